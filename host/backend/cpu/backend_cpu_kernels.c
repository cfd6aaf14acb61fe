/* backend_cpu_kernels.c — the device/ physics compiled as C for the native
 * backend.  CMake builds this file once per dimension (SPH_DIM), precision
 * mode (SPH_DOUBLE, SPH_MIXED) and formulation (SPH_CPU_FORMULATION);
 * CPU_VARIANT names the exported table.  The per-item kernels of
 * device/ become loop bodies of OpenMP loops; the reductions use the same
 * per-particle contributions and the same fixed blocks of SPH_WG particles
 * as the OpenCL work-groups.
 */
#include "backend_cpu.h"

#include "sph_step_clock.h"

#include <omp.h>

#include "neighbour_build.cl"
#include "acoustic_step.cl"
#include "tl_step.cl"
#include "eulerian_step.cl"
#include "reduction.cl"
#include "monitor.cl"

/* Components of the largest reduction */
#define MAX2_(a, b) ((a) > (b) ? (a) : (b))
#define BLOCK_NCOMP_MAX                                                                            \
    MAX2_(MAX2_(SUBSTEP_NCOMP_MAX, REBUILD_NCOMP), MAX2_(DIAG_NCOMP, MONITOR_NCOMP))

/* Reduce CONTRIB(i, c) over all particles in blocks of SPH_WG: each block
 * combines its particles in order, then the blocks are combined in order, so
 * the result does not depend on the number of threads. */
#define BLOCK_REDUCE(b, nmax, ncomp, result, CONTRIB)                                              \
    do {                                                                                           \
        real *partials_ = (real *)(b)->partials;                                                   \
        const int n_ = (b)->n;                                                                     \
        const int ngroups_ = (n_ + SPH_WG - 1) / SPH_WG;                                           \
        _Pragma("omp for schedule(static)") for (int g_ = 0; g_ < ngroups_; ++g_)                  \
            REDUCE_BLOCK(g_, n_, (nmax), (ncomp), BLOCK_NCOMP_MAX, partials_, CONTRIB);            \
        _Pragma("omp single") combine_rows(ngroups_, (nmax), (ncomp), partials_, (result));        \
    } while (0)

#define F_REAL(b, f)  ((real *)(b)->field[f])
#define F_HREAL(b, f) ((hreal *)(b)->field[f]) /* history fields (fields.c) */
#define F_U8(b, f)    ((u8 *)(b)->field[f])
#define F_INT(b, f)   ((int *)(b)->field[f])

static void rebuild_reduce_impl(cpu_buffers *b, double *out) {
    real result[REBUILD_NCOMP];
    CONSTANT sph_params *prm = (const sph_params *)b->prm;
    /* the dissipation acceleration of solids, the pressure of fluids */
    const real *state = F_REAL(b, SPH_HAS_EULERIAN ? FIELD_PRESSURE : FIELD_ACC_DISS);
#pragma omp parallel if (b->parallel)
    BLOCK_REDUCE(b, REBUILD_NCOMP, REBUILD_NCOMP, result,
                 rebuild_contrib(i, n_, prm, F_HREAL(b, FIELD_POS), F_REAL(b, FIELD_VEL),
                                 F_REAL(b, FIELD_MASS), F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_VOL),
                                 state, c));
    for (int k = 0; k < REBUILD_NCOMP; ++k) out[k] = (double)result[k];
}

static void store_grid(cpu_buffers *b, const sph_grid *g) {
    real *geom = (real *)b->grid_geom;
    for (int a = 0; a < 3; ++a) geom[a] = (real)g->origin[a];
    geom[GRID_INV_CELL] = (real)(1.0 / g->cell);
}

static void cell_keys_impl(cpu_buffers *b, const sph_grid *g, double geometry_shift) {
    store_grid(b, g);
    const int n = b->n;
#pragma omp parallel for schedule(static) if (b->parallel)
    for (int i = 0; i < n; ++i)
        cell_keys(i, n, n, F_HREAL(b, FIELD_POS), F_REAL(b, FIELD_VEL), (real)geometry_shift,
                  (const real *)b->grid_geom, g->dims[0], g->dims[1], g->dims[2], b->keys);
}

static void sort_by_cell_impl(const cpu_buffers *b, long ncells, uint64_t *sorted) {
    counting_sort_by_cell(b->n, (int)ncells, b->keys, sorted, b->cell_start, b->cell_end);
}

static int build_neighbours_impl(cpu_buffers *b, const sph_grid *g, double geometry_shift) {
    store_grid(b, g);
    const int n = b->n;
    int overflow = 0;
#pragma omp parallel for schedule(static) if (b->parallel)
    for (int i = 0; i < n; ++i)
        build_neighbours(i, n, b->cap, (const sph_params *)b->prm, F_HREAL(b, FIELD_POS),
                         F_REAL(b, FIELD_VEL), (real)geometry_shift, F_REAL(b, FIELD_VOL),
                         g->dims[0], g->dims[1], g->dims[2], (const ulong *)b->keys, b->cell_start,
                         b->cell_end, b->nbr_count, b->nbr_j, (real *)b->pair_e,
                         (real *)b->pair_dwv, (real *)b->pair_inv_r, F_REAL(b, FIELD_BMAT),
                         &overflow, (real *)b->pair_w, F_REAL(b, FIELD_DEFGRAD),
                         F_U8(b, FIELD_BODY), F_INT(b, FIELD_CONTACT_COUNT));
    return overflow;
}

/* A team of the calling parallel region (cpu_team.h). */
#define TEAM_ENTER(b) cpu_team_enter(&(b)->team, omp_get_num_threads())

/* One TLSPH substep (tl_step.cl) as orphaned loops of the caller's parallel
 * region, team t: the deformation pass, the acceleration pass, then the
 * update over fixed blocks of SPH_WG particles, each block reducing max
 * |v|^2 into its partial row (the same grouping as substep_reduce on the
 * device). */
static void tl_substep_passes(cpu_buffers *b, real dt, cpu_team *t) {
    const int n = b->n, cap = b->cap;
    CONSTANT sph_params *prm = (const sph_params *)b->prm;
    real *partials = (real *)b->partials;
    const int ncomp = substep_ncomp(prm);
    const int ngroups = (n + SPH_WG - 1) / SPH_WG;
    {
#pragma omp for schedule(static) nowait
        for (int i = 0; i < n; ++i)
            tl_deformation(i, n, cap, dt, prm, b->nbr_count, b->nbr_j, (const real *)b->pair_e,
                           (const real *)b->pair_dwv, F_HREAL(b, FIELD_POS), F_REAL(b, FIELD_VEL),
                           F_REAL(b, FIELD_BMAT), F_REAL(b, FIELD_DEFGRAD), F_REAL(b, FIELD_PK1),
                           F_HREAL(b, FIELD_RHO), F_HREAL(b, FIELD_TAU),
                           F_REAL(b, FIELD_PLASTIC_STRAIN), F_REAL(b, FIELD_PLASTIC_CINV));
        cpu_team_sync(t);
#pragma omp for schedule(static) nowait
        for (int i = 0; i < n; ++i)
            tl_acceleration(i, n, cap, dt, prm, b->nbr_count, b->nbr_j, (const real *)b->pair_e,
                            (const real *)b->pair_dwv, (const real *)b->pair_inv_r,
                            F_HREAL(b, FIELD_POS), F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_MASS),
                            F_REAL(b, FIELD_VOL), F_REAL(b, FIELD_BMAT), F_REAL(b, FIELD_DEFGRAD),
                            F_REAL(b, FIELD_PK1), F_HREAL(b, FIELD_ACC_SHEAR),
                            (const real *)b->pair_w, F_REAL(b, FIELD_PLASTIC_STRAIN));
        cpu_team_sync(t);
#pragma omp for schedule(static) nowait
        for (int g = 0; g < ngroups; ++g)
            REDUCE_BLOCK(
                g, n, 1, ncomp, SUBSTEP_NCOMP_MAX, partials,
                (tl_update(i, n, dt, prm, F_HREAL(b, FIELD_ACC_SHEAR), F_HREAL(b, FIELD_POS),
                           F_REAL(b, FIELD_VEL), F_U8(b, FIELD_FIXED)),
                 substep_contrib(i, n, dt, prm, F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_SPIN),
                                 F_U8(b, FIELD_BODY), F_HREAL(b, FIELD_POS), F_REAL(b, FIELD_MASS),
                                 F_HREAL(b, FIELD_ACC_SHEAR), F_REAL(b, FIELD_DACC_SHEAR),
                                 F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_PRESSURE), c)));
        cpu_team_sync(t);
    }
}

#if SPH_HAS_EULERIAN
#    if SPH_HAS_COMPRESSIBLE
#        define ENERGY_FIELD_ARG       , F_REAL(b, FIELD_ENERGY)
#        define ENERGY_RATE_FIELD_ARGS , F_REAL(b, FIELD_ENERGY), F_REAL(b, FIELD_ENERGY_RATE)
#        define SOUND_FIELD_ARG        , F_REAL(b, FIELD_SOUND_SPEED)
#    else
#        define ENERGY_FIELD_ARG
#        define ENERGY_RATE_FIELD_ARGS
#        define SOUND_FIELD_ARG
#    endif
/* the packed pair rows (eulerian_step.cl, host/backend/cpu/backend_cpu.c) */
#    define FLUID_ROWS(b) (b)->row_start, (b)->row_walls, (b)->row_j
/* walls and the far field (NULL buffers when the scene has neither) */
#    define KIND_FIELD_ARGS , F_U8(b, FIELD_KIND), F_REAL(b, FIELD_NORMAL)

/* The far field's pass (eulerian_step.cl), as an orphaned loop of the
 * caller's parallel region, team t, over the far-field particles with their
 * frozen weights; nothing without them. */
static void far_field_pass(cpu_buffers *b, cpu_team *t) {
    if (!b->nfar_field) return;
    const int n = b->n;
    CONSTANT sph_params *prm = (const sph_params *)b->prm;
    const real *weight = (const real *)b->far_field_weight;
#    pragma omp for schedule(static) nowait
    for (int r = 0; r < b->nfar_field; ++r)
        far_field_blend(b->far_field[r], n, prm, FLUID_ROWS(b), weight[r], F_HREAL(b, FIELD_RHO),
                        F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_MASS), F_REAL(b, FIELD_VOL),
                        F_REAL(b, FIELD_PRESSURE) ENERGY_FIELD_ARG SOUND_FIELD_ARG KIND_FIELD_ARGS);
    cpu_team_sync(t);
}

/* Once after the rebuild of a fluid run (eulerian_step.cl): the pressure
 * (WC) or total energy and sound speed (compressible) of the initial state,
 * the corrected pair gradients of eq. 18, and the far field's first blend. */
static void fluid_setup_impl(cpu_buffers *b) {
    const int n = b->n;
    CONSTANT sph_params *prm = (const sph_params *)b->prm;
#    pragma omp parallel if (b->parallel)
    {
        cpu_team t = TEAM_ENTER(b);
#    pragma omp for schedule(static)
        for (int i = 0; i < n; ++i)
            eulerian_prepare(i, n, prm, F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_VEL),
                             F_REAL(b, FIELD_VOL),
                             F_REAL(b, FIELD_PRESSURE) ENERGY_RATE_FIELD_ARGS SOUND_FIELD_ARG);
#    pragma omp for schedule(static)
        for (int i = 0; i < n; ++i)
            eulerian_correct_pairs(i, n, prm, FLUID_ROWS(b), F_REAL(b, FIELD_BMAT),
                                   (real *)b->pair_e, (real *)b->pair_dwv,
                                   (real *)b->pair_inv_r KIND_FIELD_ARGS);
        /* the far field's weights, once: its geometry is frozen */
        real *weight = (real *)b->far_field_weight;
#    pragma omp for schedule(static)
        for (int r = 0; r < b->nfar_field; ++r)
            weight[r] =
                far_field_weight(b->far_field[r], n, prm, FLUID_ROWS(b), F_HREAL(b, FIELD_POS),
                                 F_REAL(b, FIELD_VOL) KIND_FIELD_ARGS);
        far_field_pass(b, &t);
    }
}

/* The pairs summed once of a two-stage pass (eulerian_step.cl), ROW(i,
 * k_begin, k_end, walls_end) per row as orphaned loops of the caller's
 * parallel region, team T: the even blocks of pair_block particles, then the odd
 * ones (a block writes to itself and the next one only), each row with its
 * wall pairs, then the far pairs on one thread.  The blocks go to the
 * threads as they free up (schedule dynamic): one thread sums a block's
 * rows in order, so which thread it is changes no sum.
 *
 * Then PARTICLE(i), the pass's per-particle work that needs the pass's sums
 * of i complete (v' after the momentum rates, the update after the mass
 * rates), for every particle.  A block's sums are complete once its own rows
 * and those of the block before it are summed, so without far pairs the
 * blocks' threads do it as they go, on the data they just wrote: block 0
 * after its rows (no block writes to it but itself), and odd block b after
 * its rows for blocks b and b + 1 (block b + 1 was summed in the even round).
 * The particle work of block b + 1 reads and writes only particles of that
 * block, which no other block's rows read in this pass (a row reads its own
 * block and the next).  Each particle gets the same operations on the same
 * values as in a loop of its own after the pass, so the result is the same
 * bit for bit and does not depend on the number of threads; the loop and a
 * barrier per pass are saved.  With far pairs, a loop after them. */
#    define ONCE_ROWS(b) (b)->once_start, (b)->once_j
#    define ONCE_GEOMETRY(b)                                                                       \
        (const real *)(b)->once_e, (const real *)(b)->once_dwv, (const real *)(b)->once_inv_r
#    define PAIRS_ONCE_THEN(b, T, ROW, PARTICLE)                                                   \
        do {                                                                                       \
            const int block_ = (b)->pair_block, nblocks_ = (n + block_ - 1) / block_;              \
            const bool as_they_go_ = (b)->nfar_rows == 0;                                          \
            for (int parity_ = 0; parity_ < 2; ++parity_) {                                        \
                _Pragma("omp for schedule(dynamic, 1) nowait") for (int q_ = 0;                    \
                                                                    q_ <                           \
                                                                    (nblocks_ - parity_ + 1) / 2;  \
                                                                    ++q_) {                        \
                    const int first_ = (2 * q_ + parity_) * block_;                                \
                    const int last_ = first_ + block_ < n ? first_ + block_ : n;                   \
                    for (int i = first_; i < last_; ++i) {                                         \
                        const int k_begin = 0, k_end = (b)->once_count[i];                         \
                        const int walls_end = k_end + (b)->once_walls[i];                          \
                        ROW;                                                                       \
                    }                                                                              \
                    if (as_they_go_ && (parity_ == 1 || first_ == 0)) {                            \
                        int done_ = last_; /* block 0: itself; odd b: b and b + 1 */               \
                        if (parity_ == 1) done_ = last_ + block_ < n ? last_ + block_ : n;         \
                        for (int i = first_; i < done_; ++i) PARTICLE;                             \
                    }                                                                              \
                }                                                                                  \
                cpu_team_sync(T);                                                                  \
            }                                                                                      \
            if (!as_they_go_) { /* the same for every thread: all or none sync */                  \
                _Pragma("omp single nowait") for (int r_ = 0; r_ < (b)->nfar_rows; ++r_) {         \
                    const int i = (b)->far_rows[r_];                                               \
                    const int k_begin = (b)->once_count[i] + (b)->once_walls[i];                   \
                    const int k_end = k_begin + (b)->once_far[i], walls_end = k_end;               \
                    ROW;                                                                           \
                }                                                                                  \
                cpu_team_sync(T);                                                                  \
                _Pragma("omp for schedule(static) nowait") for (int i = 0; i < n; ++i) PARTICLE;   \
                cpu_team_sync(T);                                                                  \
            }                                                                                      \
        } while (0)

/* One step of a fluid run (eulerian_step.cl) in one parallel region: the
 * momentum rate, the mass and energy rates, the update (or SSP-RK's rate
 * pass and stage update per stage), the far field, then the step clock's
 * signal speed over fixed blocks of SPH_WG particles. */
static void fluid_substep_passes(cpu_buffers *b, real dt, cpu_team *t) {
    const int n = b->n;
    CONSTANT sph_params *prm = (const sph_params *)b->prm;
    real *partials = (real *)b->partials;
    const int ngroups = (n + SPH_WG - 1) / SPH_WG;
    {
        if (b->field[FIELD_MOMENTUM_RATE]) {
            /* SSP-RK (time.integrator): per stage the rates of its state,
             * each fluid pair summed once as in the two stages, then its
             * update, per block as the blocks finish, which zeroes the rates
             * for the next stage's sums */
            const fluid_solver solver = fluid_solver_make(prm);
            const int stages = b->rk_stages;
            for (int stage = 0; stage < stages; ++stage)
                PAIRS_ONCE_THEN(
                    b, t,
                    eulerian_rates_pairs(
                        i, n, k_begin, k_end, walls_end, stage, prm, solver, ONCE_ROWS(b),
                        ONCE_GEOMETRY(b), F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_VEL),
                        F_REAL(b, FIELD_VOL), F_REAL(b, FIELD_PRESSURE), F_REAL(b, FIELD_MASS_RATE),
                        F_REAL(b, FIELD_MOMENTUM_RATE) ENERGY_RATE_FIELD_ARGS SOUND_FIELD_ARG,
                        F_U8(b, FIELD_FIXED) KIND_FIELD_ARGS, F_REAL(b, FIELD_WALL_FORCE)),
                    {
                        eulerian_rk_update(
                            i, n, stage, stages, dt, prm, F_REAL(b, FIELD_VEL),
                            F_REAL(b, FIELD_MASS), F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_VOL),
                            F_REAL(b, FIELD_PRESSURE), F_REAL(b, FIELD_MASS_RATE),
                            F_REAL(b, FIELD_MOMENTUM_RATE),
                            F_REAL(b, FIELD_STATE_SAVED) ENERGY_RATE_FIELD_ARGS SOUND_FIELD_ARG,
                            F_U8(b, FIELD_FIXED) KIND_FIELD_ARGS);
                        eulerian_rates_zero(i, n, F_REAL(b, FIELD_MASS_RATE),
                                            F_REAL(b, FIELD_MOMENTUM_RATE) ENERGY_RATE_FIELD_ARGS);
                    });
        } else {
            /* the two stages, each fluid pair summed once (eulerian_step.cl);
             * the solver's constants formed once per step, not per row (two
             * divisions) */
            const fluid_solver solver = fluid_solver_make(prm);
            PAIRS_ONCE_THEN(
                b, t,
                eulerian_momentum_pairs(
                    i, n, k_begin, k_end, walls_end, prm, solver, ONCE_ROWS(b), ONCE_GEOMETRY(b),
                    F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_VOL),
                    F_REAL(b, FIELD_PRESSURE),
                    (real *)b->force_sum ENERGY_FIELD_ARG SOUND_FIELD_ARG,
                    F_U8(b, FIELD_FIXED) KIND_FIELD_ARGS, F_REAL(b, FIELD_WALL_FORCE)),
                eulerian_momentum_stage(i, n, dt, prm, F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_MASS),
                                        F_REAL(b, FIELD_VEL_STAGE), (real *)b->force_sum,
                                        F_REAL(b, FIELD_MASS_RATE) ENERGY_RATE_FIELD_ARGS,
                                        F_U8(b, FIELD_FIXED) KIND_FIELD_ARGS));
            PAIRS_ONCE_THEN(
                b, t,
                eulerian_mass_energy_pairs(
                    i, n, k_begin, k_end, walls_end, prm, solver, ONCE_ROWS(b), ONCE_GEOMETRY(b),
                    F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_VEL_STAGE), F_REAL(b, FIELD_VOL),
                    F_REAL(b, FIELD_PRESSURE),
                    F_REAL(b, FIELD_MASS_RATE)
                        ENERGY_RATE_FIELD_ARGS SOUND_FIELD_ARG KIND_FIELD_ARGS),
                eulerian_update(i, n, dt, prm, F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_VEL_STAGE),
                                F_REAL(b, FIELD_MASS), F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_VOL),
                                F_REAL(b, FIELD_PRESSURE),
                                F_REAL(b, FIELD_MASS_RATE) ENERGY_RATE_FIELD_ARGS SOUND_FIELD_ARG,
                                F_U8(b, FIELD_FIXED) KIND_FIELD_ARGS));
        }
        far_field_pass(b, t);
#    pragma omp for schedule(static) nowait
        for (int g = 0; g < ngroups; ++g)
            REDUCE_BLOCK(g, n, 1, 1, SUBSTEP_NCOMP_MAX, partials,
                         c[0] = eulerian_signal_speed2(prm, (real)F_HREAL(b, FIELD_RHO)[i],
                                                       F_REAL(b, FIELD_PRESSURE)[i],
                                                       vec_load(F_REAL(b, FIELD_VEL), n, i)));
        cpu_team_sync(t);
    }
}
#    define FLUID_SETUP fluid_setup_impl
#    if SPH_DIM > 1
/* The vorticity of the current state (eulerian_step.cl), for a snapshot. */
static void fluid_vorticity_impl(cpu_buffers *b) {
    const int n = b->n;
#        pragma omp parallel for schedule(static) if (b->parallel)
    for (int i = 0; i < n; ++i)
        eulerian_vorticity(i, n, FLUID_ROWS(b), (const real *)b->pair_e, (const real *)b->pair_dwv,
                           F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_VORTICITY) KIND_FIELD_ARGS);
}
#        define FLUID_VORTICITY fluid_vorticity_impl
#    else
#        define FLUID_VORTICITY NULL
#    endif
#else
#    define FLUID_SETUP     NULL
#    define FLUID_VORTICITY NULL
#endif

/* One substep of the updated-Lagrangian solids as orphaned loops of the
 * caller's parallel region, team t: the pressure pass, the velocity-terms
 * pass, each in equal shares of the particles, then the reduction over fixed
 * blocks of SPH_WG particles of their contributions (|v|^2, Rodrigues
 * matrices) into the blocks' partial rows (combined in block order by the
 * caller).  (Running the velocity-terms pass by blocks of SPH_WG too gave
 * the 1612 particles of the H/dp = 10 plate as 4 blocks to one thread and 3
 * to the other.) */
static void solid_substep_passes(cpu_buffers *b, real dt, cpu_team *t) {
    const int n = b->n, cap = b->cap;
    CONSTANT sph_params *prm = (const sph_params *)b->prm;
    real *sums = (real *)b->substep_sums;
    real *partials = (real *)b->partials;
    const int ncomp = substep_ncomp(prm);
    const int ngroups = (n + SPH_WG - 1) / SPH_WG;
    const bool stress_div = FORM_HAS_STRESS_DIV(RUNTIME_FORMULATION);
    const int *contact_count = F_INT(b, FIELD_CONTACT_COUNT);
    {
        /* bodies that do not merge: the contact force first (sph_contact.h) */
        if (contact_count) {
#pragma omp for schedule(static) nowait
            for (int i = 0; i < n; ++i)
                acoustic_contact(i, n, cap, dt, prm, b->nbr_j, contact_count, F_HREAL(b, FIELD_POS),
                                 F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_MASS), F_REAL(b, FIELD_VOL),
                                 F_REAL(b, FIELD_ACC_DISS), F_U8(b, FIELD_MATERIAL));
            cpu_team_sync(t);
        }
#pragma omp for schedule(static) nowait
        for (int i = 0; i < n; ++i)
            acoustic_pressure(
                i, n, cap, dt, prm, b->nbr_count, b->nbr_j, (const real *)b->pair_e,
                (const real *)b->pair_dwv, F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_DRHO),
                F_REAL(b, FIELD_MASS), F_REAL(b, FIELD_VOL), F_REAL(b, FIELD_ACC_DISS),
                F_HREAL(b, FIELD_ACC_SHEAR), F_HREAL(b, FIELD_POS), F_REAL(b, FIELD_VEL),
                F_REAL(b, FIELD_DACC_SHEAR), sums, F_U8(b, FIELD_BODY), F_U8(b, FIELD_FIXED),
                F_REAL(b, FIELD_ACC_STRESS), F_U8(b, FIELD_MATERIAL));
        cpu_team_sync(t);

#pragma omp for schedule(static) nowait
        for (int i = 0; i < n; ++i)
            acoustic_velocity_terms(
                i, n, cap, dt, prm, b->nbr_count, b->nbr_j, (const real *)b->pair_e,
                (const real *)b->pair_dwv, (const real *)b->pair_inv_r, F_REAL(b, FIELD_VEL),
                F_REAL(b, FIELD_MASS), F_REAL(b, FIELD_VOL), F_REAL(b, FIELD_BMAT),
                F_HREAL(b, FIELD_RHO), F_REAL(b, FIELD_DRHO), F_REAL(b, FIELD_ACC_DISS),
                F_HREAL(b, FIELD_TAU), F_HREAL(b, FIELD_ACC_SHEAR), F_REAL(b, FIELD_DACC_SHEAR),
                F_REAL(b, FIELD_SPIN), F_REAL(b, FIELD_GRADV), F_REAL(b, FIELD_ART_STRESS),
                F_REAL(b, FIELD_PLASTIC_STRAIN), F_REAL(b, FIELD_PENALTY_SCALE),
                F_HREAL(b, FIELD_POS), F_U8(b, FIELD_MATERIAL));
        cpu_team_sync(t);
#pragma omp for schedule(static) nowait
        for (int g = 0; g < ngroups; ++g)
            REDUCE_BLOCK(g, n, 1, ncomp, SUBSTEP_NCOMP_MAX, partials,
                         substep_contrib(i, n, dt, prm, F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_SPIN),
                                         F_U8(b, FIELD_BODY), F_HREAL(b, FIELD_POS),
                                         F_REAL(b, FIELD_MASS), F_HREAL(b, FIELD_ACC_SHEAR),
                                         F_REAL(b, FIELD_DACC_SHEAR), F_HREAL(b, FIELD_RHO),
                                         F_REAL(b, FIELD_PRESSURE), c));
        cpu_team_sync(t);
        /* third pass of the stress-divergence formulations: reads the tau
         * and L of the neighbours written above */
        if (stress_div) {
#pragma omp for schedule(static) nowait
            for (int i = 0; i < n; ++i)
                acoustic_shear_force(
                    i, n, cap, dt, prm, b->nbr_count, b->nbr_j, (const real *)b->pair_e,
                    (const real *)b->pair_dwv, (const real *)b->pair_inv_r, F_REAL(b, FIELD_MASS),
                    F_REAL(b, FIELD_VOL), F_HREAL(b, FIELD_RHO), F_HREAL(b, FIELD_TAU),
                    F_REAL(b, FIELD_ACC_STRESS), F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_GRADV),
                    F_HREAL(b, FIELD_ACC_SHEAR), F_REAL(b, FIELD_ART_STRESS),
                    F_REAL(b, FIELD_PENALTY_SCALE), F_REAL(b, FIELD_DACC_SHEAR),
                    F_U8(b, FIELD_MATERIAL));
            cpu_team_sync(t);
        }
    }
}

/* One substep of this instance's formulation in the caller's parallel
 * region: its passes, ending in a sync of the team. */
static void substep_passes(cpu_buffers *b, real dt, cpu_team *t) {
#if SPH_HAS_EULERIAN
    fluid_substep_passes(b, dt, t);
    return;
#endif
    if (RUNTIME_FORMULATION == FORMULATION_TLSPH) /* a constant of this instance */
        tl_substep_passes(b, dt, t);
    else
        solid_substep_passes(b, dt, t);
}

/* max |v|^2 (or the fluids' signal speed squared) of the substep just
 * taken: the blocks' partial rows combined in block order. */
static double substep_max_speed2(cpu_buffers *b) {
    CONSTANT sph_params *prm = (const sph_params *)b->prm;
    const int ngroups = (b->n + SPH_WG - 1) / SPH_WG;
    real *sums = (real *)b->substep_sums;
    combine_rows(ngroups, 1, SPH_HAS_EULERIAN ? 1 : substep_ncomp(prm), (real *)b->partials, sums);
    return (double)sums[0];
}

static void substep_impl(cpu_buffers *b, double dt, double *max_speed2) {
#pragma omp parallel if (b->parallel)
    {
        cpu_team t = TEAM_ENTER(b);
        substep_passes(b, (real)dt, &t);
    }
    *max_speed2 = substep_max_speed2(b);
}

/* The substeps of an advection step (sph_backend_advance) in one parallel
 * region: after each, thread 0 combines the reduction rows and advances the
 * step clock (device/sph_step_clock.h, as the host would), then the team
 * reads the clock together.  The same substeps, the same bits, as one
 * substep_impl call and one host clock advance at a time, without a fork
 * and join of the team per substep. */
static void advance_impl(cpu_buffers *b, double *clock, long limit) {
#pragma omp parallel if (b->parallel)
    {
        cpu_team t = TEAM_ENTER(b);
        while (clock[CLOCK_HALTED] == CLOCK_RUNNING && clock[CLOCK_COUNT] < (double)limit) {
            substep_passes(b, (real)clock[CLOCK_DT], &t);
            if (omp_get_thread_num() == 0) step_clock_finish(clock, substep_max_speed2(b));
            cpu_team_sync(&t);
        }
    }
}

static void diagnostics_impl(cpu_buffers *b, double *out) {
    CONSTANT sph_params *prm = (const sph_params *)b->prm;
    real result[DIAG_NCOMP];
#if SPH_HAS_EULERIAN
#    pragma omp parallel if (b->parallel)
    BLOCK_REDUCE(b, 0, DIAG_NCOMP, result,
                 eulerian_diagnostics_contrib(
                     i, n_, prm, F_HREAL(b, FIELD_POS), F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_MASS),
                     F_REAL(b, FIELD_VOL), F_REAL(b, FIELD_PRESSURE), F_REAL(b, FIELD_ENERGY),
                     F_REAL(b, FIELD_WALL_FORCE), c));
#else
#    pragma omp parallel if (b->parallel)
    BLOCK_REDUCE(b, 0, DIAG_NCOMP, result,
                 diagnostics_contrib(i, n_, prm, F_HREAL(b, FIELD_POS), F_REAL(b, FIELD_VEL),
                                     F_REAL(b, FIELD_MASS), F_HREAL(b, FIELD_RHO),
                                     F_HREAL(b, FIELD_TAU), F_REAL(b, FIELD_DEFGRAD),
                                     F_U8(b, FIELD_MATERIAL), c));
#endif
    for (int k = 0; k < DIAG_NCOMP; ++k) out[k] = (double)result[k];
}

/* ---- physics probes ---------------------------------------------------- */

/* the host's double block in this variant's precision */
static void params_to_real(const sph_params_f64 *prm_in, sph_params *prm_out) {
#if SPH_DOUBLE
    *prm_out = *prm_in;
#else
    sph_params_to_f32(prm_in, prm_out);
#endif
}
static double probe_kernel_w(const sph_params_f64 *prm_in, double r) {
    sph_params prm[1];
    params_to_real(prm_in, prm);
    return (double)kernel_w(prm, (real)r);
}
static double probe_kernel_dw(const sph_params_f64 *prm_in, double r) {
    sph_params prm[1];
    params_to_real(prm_in, prm);
    return (double)kernel_dw(prm, (real)r);
}
static double probe_wall_plane_kernel(const sph_params_f64 *prm_in, double d) {
    sph_params prm[1];
    params_to_real(prm_in, prm);
    return (double)wall_plane_kernel(prm, (real)d);
}
static double probe_ideal_gas_sound_speed(double p, double rho, double gamma) {
    return (double)ideal_gas_sound_speed((real)p, (real)rho, (real)gamma);
}
static void probe_rodrigues(const double *w_in, double dt, double *rot) {
#if SPH_DIM == 1
    /* a line does not turn (the 1D instances are the fluids') */
    (void)w_in;
    const mat r = rodrigues(mat_zero(), (real)dt);
#else
    real w[NSPIN];
    for (int a = 0; a < NSPIN; ++a) w[a] = (real)w_in[a];
    const mat r = rodrigues(spin_matrix(w), (real)dt);
#endif
    for (int a = 0; a < SPH_DIM; ++a)
        for (int c = 0; c < SPH_DIM; ++c) rot[a * SPH_DIM + c] = (double)r.m[a][c];
}
static vec vec_from(const double *x) {
    vec v;
    for (int a = 0; a < SPH_DIM; ++a) v.c[a] = (real)x[a];
    return v;
}
static void probe_riemann_pair(const double *v_i, const double *v_j, double p_i, double p_j,
                               double z, double dw, const double *e_ij, double *pressure,
                               double *dissipation, double *continuity) {
    const vec e = vec_from(e_ij);
    const real u = vec_dot(vec_sub(vec_from(v_i), vec_from(v_j)), e);
    const vec fp = riemann_pressure_pair((real)p_i, (real)p_j, (real)dw, e);
    const vec fd = vec_scale(riemann_dissipation_pair(u, R(1), R(0), (real)dw, e), (real)z);
    for (int a = 0; a < SPH_DIM; ++a) {
        pressure[a] = (double)fp.c[a];
        dissipation[a] = (double)fd.c[a];
    }
    *continuity = (double)riemann_continuity_pair(u, (real)dw);
}

/* One substep of a material point's shear stress (Jaumann + J2 return),
 * tau and grad_v row-major d x d; alpha NULL for an elastic material. */
static void probe_stress_update(const sph_params_f64 *prm_in, const double *grad_v_in, double dt,
                                double *tau_io, double *alpha_io) {
    sph_params prm[1];
    params_to_real(prm_in, prm);
    /* the stress as the field of a one-particle set (sym_index layout) */
    hreal stored[NSYM];
    mat grad_v;
    for (int a = 0; a < SPH_DIM; ++a)
        for (int c = 0; c < SPH_DIM; ++c) {
            stored[sym_index(a, c)] = (hreal)tau_io[a * SPH_DIM + c];
            grad_v.m[a][c] = (real)grad_v_in[a * SPH_DIM + c];
        }
    real alpha = alpha_io ? (real)*alpha_io : R(0), ratio;
    const mat out = shear_stress_advance(stored, 1, 0, grad_v, &prm->materials[0], (real)dt,
                                         alpha_io ? &alpha : NULL, &ratio);
    for (int a = 0; a < SPH_DIM; ++a)
        for (int c = 0; c < SPH_DIM; ++c) tau_io[a * SPH_DIM + c] = (double)out.m[a][c];
    if (alpha_io) *alpha_io = (double)alpha;
}

/* Artificial stress R of Gray et al. (2001) for one particle (row-major). */
static void probe_artificial_stress(const double *tau_in, double p, double rho, double epsilon,
                                    double *r_out) {
    mat tau;
    for (int a = 0; a < SPH_DIM; ++a)
        for (int c = 0; c < SPH_DIM; ++c) tau.m[a][c] = (real)tau_in[a * SPH_DIM + c];
    const mat r = artificial_stress(tau, (real)p, (real)rho, (real)epsilon);
    for (int a = 0; a < SPH_DIM; ++a)
        for (int c = 0; c < SPH_DIM; ++c) r_out[a * SPH_DIM + c] = (double)r.m[a][c];
}

/* The TLSPH finite-strain J2 update of one material point (sph_plasticity.h,
 * tl_j2_kirchhoff): f row-major d x d; state[] = C_p^-1 (row-major d x d),
 * then (C_p^-1)_zz, then alpha, updated; tau_out = the Kirchhoff stress,
 * row-major d x d, then tau_zz.  Returns 1 when the return map acted. */
static int probe_tl_j2_update(const sph_params_f64 *prm_in, const double *f_in, double *state,
                              double *tau_out) {
    sph_params prm[1];
    params_to_real(prm_in, prm);
    const int dd = SPH_DIM * SPH_DIM;
    mat f;
    tl_plastic_state st;
    for (int a = 0; a < SPH_DIM; ++a)
        for (int c = 0; c < SPH_DIM; ++c) {
            f.m[a][c] = (real)f_in[a * SPH_DIM + c];
            st.cpinv_dev.m[a][c] = (real)(state[a * SPH_DIM + c] - (a == c ? 1.0 : 0.0));
        }
    st.cpinv_zz_dev = (real)(state[dd] - 1.0);
    st.alpha = (real)state[dd + 1];
    real tau_zz;
    int yielded;
    const mat tau = tl_j2_kirchhoff(f, &st, prm, &tau_zz, &yielded);
    for (int a = 0; a < SPH_DIM; ++a)
        for (int c = 0; c < SPH_DIM; ++c) {
            tau_out[a * SPH_DIM + c] = (double)tau.m[a][c];
            state[a * SPH_DIM + c] = (double)st.cpinv_dev.m[a][c] + (a == c ? 1.0 : 0.0);
        }
    tau_out[dd] = (double)tau_zz;
    state[dd] = (double)st.cpinv_zz_dev + 1.0;
    state[dd + 1] = (double)st.alpha;
    return yielded;
}

static void monitor_impl(cpu_buffers *b, double *out) {
    CONSTANT sph_params *prm = (const sph_params *)b->prm;
    real result[MONITOR_NCOMP];
    const int cap = b->cap;
#pragma omp parallel if (b->parallel)
    BLOCK_REDUCE(b, MONITOR_NCOMP, MONITOR_NCOMP, result,
                 monitor_contrib(i, n_, cap, prm, b->nbr_count, b->nbr_j, F_HREAL(b, FIELD_POS),
                                 F_REAL(b, FIELD_VEL), F_REAL(b, FIELD_VOL), F_REAL(b, FIELD_BMAT),
                                 c));
    for (int k = 0; k < MONITOR_NCOMP; ++k) out[k] = (double)result[k];
}

#if SPH_DOUBLE
/* One particle's monitor measures (the f64 instance: real is double). */
static void monitor_particle_impl(const sph_params_f64 *prm_in, int n, int cap,
                                  const int32_t *nbr_count, const int32_t *nbr_j, const double *pos,
                                  const double *vel, const double *vol, const double *bmat, int i,
                                  double *out) {
    sph_params prm[1];
    params_to_real(prm_in, prm);
    monitor_contrib(i, n, cap, prm, nbr_count, nbr_j, pos, vel, vol, bmat, out);
}
#    define MONITOR_PARTICLE monitor_particle_impl
#else
#    define MONITOR_PARTICLE NULL
#endif

/* Derived output fields from the state, for snapshots: pressure by the EOS,
 * von Mises stress of tau - p I, and tau in VTK's symmetric-tensor order
 * (xx, yy, zz, xy, yz, xz; zero out of plane in 2D).  tau is in the field
 * layout (component-major, stride n). */
static void stress_output_impl(const sph_params_f64 *prm_in, int n, const double *rho,
                               const double *tau, const uint8_t *material, double *pressure,
                               double *von_mises_out, double *tensor6) {
    sph_params prm[1];
    params_to_real(prm_in, prm);
    static const int vtk_a[6] = {0, 1, 2, 0, 1, 0}, vtk_b[6] = {0, 1, 2, 1, 2, 2};
    for (int i = 0; i < n; ++i) {
        mat t;
        for (int a = 0; a < SPH_DIM; ++a)
            for (int b = 0; b < SPH_DIM; ++b) t.m[a][b] = (real)tau[sym_index(a, b) * n + i];
        const real p = eos_pressure(&prm->materials[material ? material[i] : 0], (real)rho[i]);
        if (pressure) pressure[i] = (double)p;
        if (von_mises_out) von_mises_out[i] = (double)von_mises(t, p);
        if (tensor6)
            for (int k = 0; k < 6; ++k)
                tensor6[(size_t)i * 6 + (size_t)k] = vtk_a[k] < SPH_DIM && vtk_b[k] < SPH_DIM
                                                         ? (double)t.m[vtk_a[k]][vtk_b[k]]
                                                         : 0.0;
    }
}

const cpu_kernels CPU_VARIANT = {
    .dim = SPH_DIM,
    .double_precision = SPH_DOUBLE,
    .mixed_precision = SPH_MIXED,
    .formulation = SPH_CPU_FORMULATION,
    .pair_lanes = SPH_PAIR_LANES,
    .rebuild_reduce = rebuild_reduce_impl,
    .cell_keys = cell_keys_impl,
    .sort_by_cell = sort_by_cell_impl,
    .build_neighbours = build_neighbours_impl,
    .substep = substep_impl,
    .advance = advance_impl,
    .fluid_setup = FLUID_SETUP,
    .fluid_vorticity = FLUID_VORTICITY,
    .diagnostics = diagnostics_impl,
    .monitor = monitor_impl,
    .physics =
        {
            .dim = SPH_DIM,
            .double_precision = SPH_DOUBLE,
            .monitor_particle = MONITOR_PARTICLE,
            .kernel_w = probe_kernel_w,
            .kernel_dw = probe_kernel_dw,
            .wall_plane_kernel = probe_wall_plane_kernel,
            .rodrigues = probe_rodrigues,
            .ideal_gas_sound_speed = probe_ideal_gas_sound_speed,
            .riemann_pair = probe_riemann_pair,
            .stress_output = stress_output_impl,
            .stress_update = probe_stress_update,
            .artificial_stress = probe_artificial_stress,
            .tl_j2_update = probe_tl_j2_update,
        },
};
