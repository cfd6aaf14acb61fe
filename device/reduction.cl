/* reduction.cl — the global reductions, done on the device.
 *
 * Each reduction has a per-particle contribution (shared by both backends)
 * and runs in two stages: work-groups of SPH_WG particles reduce into one
 * partial row each, then reduce_finalize combines the rows.  Components
 * [0, nmax) combine by max, [nmax, ncomp) by sum.  The fixed grouping makes
 * every reduction deterministic (no atomics, no order that depends on
 * timing).
 *
 *  rebuild:     bounding box and the advection-step criteria, once per
 *               configuration rebuild (also refreshes V = m/rho);
 *  substep:     max |v|^2 for the acoustic step and, for SPH-ENOG-A, the sum
 *               of the Rodrigues matrices of each body (003 eq. 41), and
 *               with method.torque_projection each body's moments of the
 *               accumulated shear acceleration (sph_torque_projection.h);
 *  diagnostics: kinetic and strain energy, linear and angular momentum.
 */
#include "sph_vec.h"
#include "sph_rotation.h"
#include "sph_elasticity.h"
#include "sph_materials.h"
#include "sph_hyperelastic.h"
#include "sph_torque_projection.h"
#include "eulerian_step.cl"

#define REBUILD_NCOMP (2 * SPH_DIM + 2)
#define SUBSTEP_NCOMP_MAX                                                                          \
    (1 + SPH_NBODIES * (SPH_DIM * SPH_DIM + (SPH_HAS_TORQUE_PROJECTION ? TORQUE_NCOMP : 0)))
/* fluids add the total mass and energy (eulerian_step.cl) */
#if SPH_HAS_EULERIAN
/* and, with walls, the wall pairs' shares of F (pressure, viscous) */
#    define DIAG_NCOMP (4 + SPH_DIM + NSPIN + (SPH_FLUID_WALLS ? 2 * SPH_DIM : 0))
#else
#    define DIAG_NCOMP (2 + SPH_DIM + NSPIN)
#endif
#define DIAG_KINETIC  0
#define DIAG_STRAIN   1
#define DIAG_MOMENTUM 2
#define DIAG_ANGULAR  (2 + SPH_DIM)

FN void reduce_identity(real *c, const int nmax, const int ncomp) {
    for (int k = 0; k < ncomp; ++k) c[k] = k < nmax ? REAL_LOWEST : R(0);
}
/* fmax(a, b) as a comparison: the same value, NaN included (a NaN a gives b,
 * a NaN b gives a), without the library call fmax is in the native build
 * (sph_riemann.h; 1 % of a cylinder run went to it, a call per particle per
 * substep). */
FN real reduce_max(const real a, const real b) {
    return (b > a || a != a) ? b : a;
}
FN void reduce_combine(real *acc, const real *c, const int nmax, const int ncomp) {
    for (int k = 0; k < ncomp; ++k) acc[k] = k < nmax ? reduce_max(acc[k], c[k]) : acc[k] + c[k];
}

/* Block g of SPH_WG particles: CONTRIB (which writes particle i's
 * contribution into c) combined in particle order, stored as row g of
 * partials.  The native backend's reductions and, on OpenCL CPU devices,
 * one work-item's share (SPH_REDUCE_BLOCKS); the rows are then combined in
 * order. */
#define REDUCE_BLOCK(g, n, NMAX, NCOMP, NCOMP_MAX, partials, CONTRIB)                              \
    do {                                                                                           \
        real acc_[NCOMP_MAX], c[NCOMP_MAX];                                                        \
        reduce_identity(acc_, (NMAX), (NCOMP));                                                    \
        const int end_ = ((g) + 1) * SPH_WG < (n) ? ((g) + 1) * SPH_WG : (n);                      \
        for (int i = (g)*SPH_WG; i < end_; ++i) {                                                  \
            CONTRIB;                                                                               \
            reduce_combine(acc_, c, (NMAX), (NCOMP));                                              \
        }                                                                                          \
        for (int k_ = 0; k_ < (NCOMP); ++k_) (partials)[(g) * (NCOMP) + k_] = acc_[k_];            \
    } while (0)

/* The partial rows combined in row order, component by component: the
 * native backend's second stage, and on CPU devices one work-item's
 * (finalize_rows, substep_reduce_finish). */
FN void combine_rows(const int ngroups, const int nmax, const int ncomp,
                     GLOBAL const real *restrict partials, GLOBAL real *restrict result) {
    for (int k = 0; k < ncomp; ++k) {
        real acc = k < nmax ? REAL_LOWEST : R(0);
        for (int g = 0; g < ngroups; ++g) {
            const real x = partials[g * ncomp + k];
            acc = k < nmax ? reduce_max(acc, x) : acc + x;
        }
        result[k] = acc;
    }
}

/* Components: -min x (d), max x (d), max |v|^2, max 4 h |a| (all by max).
 * The acceleration of the advection criterion is the dissipation plus the
 * external acceleration: what the reference code's force array holds at the
 * start of an advection step (its density half-step resets it to the
 * dissipative force; reference notes §3.7, §4). */
/* `state`: the dissipation acceleration (solids) or the pressure (fluids,
 * whose initial pressure the upload holds) */
#if SPH_HAS_EULERIAN
#    define REBUILD_STATE_PARAM GLOBAL const real *restrict pressure
#    define REBUILD_STATE_ARG   pressure
#else
#    define REBUILD_STATE_PARAM GLOBAL const real *restrict acc_diss
#    define REBUILD_STATE_ARG   acc_diss
#endif
FN void rebuild_contrib(const int i, const int n, CONSTANT sph_params *prm, GLOBAL const hreal *pos,
                        GLOBAL const real *vel, GLOBAL const real *mass, GLOBAL const hreal *rho,
                        GLOBAL real *vol, GLOBAL const real *state, real *c) {
    const vec x = hvec_load(pos, n, i), v = vec_load(vel, n, i);
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        c[a] = -x.c[a];
        c[SPH_DIM + a] = x.c[a];
    }
#if SPH_HAS_EULERIAN
    /* fluids: the volumes w_i are fixed (eulerian_step.cl); the first
     * step's speed is the step clock's (eulerian_signal_speed2: the
     * compressible pressure is the uploaded initial one, the WC speed does
     * not need it) */
    (void)mass;
    (void)vol;
    c[2 * SPH_DIM] = eulerian_signal_speed2(prm, (real)rho[i], state[i], v);
    c[2 * SPH_DIM + 1] = R(0);
#else
    const GLOBAL real *acc_diss = state;
    /* ContinuumVolumeUpdate of the reference: V = m / rho at each rebuild */
    vol[i] = (real)(mass[i] / rho[i]);
    c[2 * SPH_DIM] = vec_dot(v, v);
    const vec a = vec_add(vec_load(acc_diss, n, i), gravity_of(prm));
    c[2 * SPH_DIM + 1] = R(4) * prm->h * sqrt(vec_dot(a, a));
#endif
}

FN int substep_ncomp(CONSTANT sph_params *prm) {
    (void)prm;
    if (RUNTIME_ROTATION != ROTATION_AVERAGED) return 1;
    const int torque = SPH_HAS_TORQUE_PROJECTION && RUNTIME_TORQUE_PROJECTION ? TORQUE_NCOMP : 0;
    return 1 + RUNTIME_NBODIES * (SPH_DIM * SPH_DIM + torque);
}
/* Components: max |v|^2; then per body the summed R_i (d*d, by sum); then,
 * with the torque projection, per body the moments of
 * sph_torque_projection.h (TORQUE_NCOMP, by sum; at torque_offset). */
FN void substep_contrib(const int i, const int n, const real dt, CONSTANT sph_params *prm,
                        GLOBAL const real *vel, GLOBAL const real *spin, GLOBAL const u8 *body,
                        GLOBAL const hreal *pos, GLOBAL const real *mass,
                        GLOBAL const hreal *acc_shear, GLOBAL const real *dacc_shear,
                        GLOBAL const hreal *rho, GLOBAL const real *pressure, real *c) {
    const vec v = vec_load(vel, n, i);
#if SPH_HAS_EULERIAN
    /* fluids: the step clock's signal speed, +inf for a state that cannot go on */
    (void)dt, (void)spin, (void)body, (void)pos, (void)mass, (void)acc_shear, (void)dacc_shear;
    c[0] = eulerian_signal_speed2(prm, (real)rho[i], pressure[i], v);
    return;
#else
    (void)rho, (void)pressure;
#endif
    const real v2 = vec_dot(v, v);
    /* the max reduction (fmax) would drop a NaN: make it the largest value,
     * so that the host sees a non-finite speed and stops (host/run/solver.c) */
    c[0] = isfinite(v2) ? v2 : INFINITY;
    if (RUNTIME_ROTATION != ROTATION_AVERAGED) return;
    const int ncomp = substep_ncomp(prm);
    for (int k = 1; k < ncomp; ++k) c[k] = R(0);
    real w[NSPIN];
    UNROLL for (int a = 0; a < NSPIN; ++a) w[a] = spin[a * n + i];
    const mat rot = rodrigues(spin_matrix(w), dt);
    const int b = (SPH_HAS_BODY_IDS && PRESENT(body)) ? (int)body[i] : 0;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int e = 0; e < SPH_DIM; ++e)
        c[1 + (b * SPH_DIM + a) * SPH_DIM + e] = rot.m[a][e];
#if SPH_HAS_TORQUE_PROJECTION
    /* (the buffers exist in programs with the projection only) y = x^{n+1}, w = v^{n+1}, b = a^s +
     * da^s: what the next substep's acoustic_pressure turns by Rbar and applies at y + dt/2 w */
    if (RUNTIME_TORQUE_PROJECTION && PRESENT(dacc_shear))
        torque_moments(mass[i], hvec_load(pos, n, i), v,
                       vec_add(hvec_load(acc_shear, n, i), vec_load(dacc_shear, n, i)),
                       c + torque_offset(prm, b));
#endif
}

/* Components (all by sum): kinetic energy, strain energy, momentum (d),
 * angular momentum about the origin (1 in 2D, 3 in 3D). */
FN void diagnostics_contrib(const int i, const int n, CONSTANT sph_params *prm,
                            GLOBAL const hreal *pos, GLOBAL const real *vel,
                            GLOBAL const real *mass, GLOBAL const hreal *rho,
                            GLOBAL const hreal *tau, GLOBAL const real *defgrad MATERIAL_PARAMS,
                            real *c) {
    const vec x = hvec_load(pos, n, i), v = vec_load(vel, n, i);
    const real m = mass[i];
    c[DIAG_KINETIC] = R(0.5) * m * vec_dot(v, v);
    /* elastic TLSPH: its law's own strain energy V0 psi(F) (sph_hyperelastic.h);
     * F is that of the substep's half-step positions.  (OpenCL decides at
     * compile time: its RUNTIME_* are constants.) */
#if SPH_HAS_TLSPH && (!SPH_OPENCL || !SPH_PLASTIC)
#    if SPH_OPENCL
    if (PRESENT(defgrad))
#    else
    if (RUNTIME_FORMULATION == FORMULATION_TLSPH && !RUNTIME_PLASTIC && PRESENT(defgrad))
#    endif
        c[DIAG_STRAIN] =
            m / prm->materials[0].rho0 * tl_strain_energy(mat_load(defgrad, n, i), prm);
    else
#else
    (void)defgrad;
#endif
    {
        /* the linear-elastic estimate from the density and the deviatoric stress */
        const real volume = (real)(m / rho[i]);
        CONSTANT sph_params_material *props = MATERIAL_ROW(MATERIAL_OF(i));
        c[DIAG_STRAIN] =
            volume * strain_energy_density(hsym_load(tau, n, i), eos_pressure(props, rho[i]),
                                           props->shear_modulus, props->bulk_modulus);
    }
    UNROLL for (int a = 0; a < SPH_DIM; ++a) c[DIAG_MOMENTUM + a] = m * v.c[a];
#if SPH_DIM == 1
    (void)x; /* a line has no angular momentum */
#elif SPH_DIM == 2
    c[DIAG_ANGULAR] = m * (x.c[0] * v.c[1] - x.c[1] * v.c[0]);
#else
    c[DIAG_ANGULAR + 0] = m * (x.c[1] * v.c[2] - x.c[2] * v.c[1]);
    c[DIAG_ANGULAR + 1] = m * (x.c[2] * v.c[0] - x.c[0] * v.c[2]);
    c[DIAG_ANGULAR + 2] = m * (x.c[0] * v.c[1] - x.c[1] * v.c[0]);
#endif
}

#if SPH_OPENCL
/* Tree-combine `value` over a segment of SPH_WG work-items (by max or by
 * sum), `lane` this item's place in it; the result is in segment[0] for
 * every item after the call, which every item of the work-group makes (the
 * barriers).  A reduction's work-group is one segment; the substep loop's
 * (substep_loop.cl) holds several, combined in the same order. */
FN void segment_tree(__local real *segment, const int lane, const real value, const int by_max) {
    segment[lane] = value;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int s = SPH_WG / 2; s > 0; s >>= 1) {
        if (lane < s)
            segment[lane] =
                by_max ? fmax(segment[lane], segment[lane + s]) : segment[lane] + segment[lane + s];
        barrier(CLK_LOCAL_MEM_FENCE);
    }
}

FN void group_tree(__local real *scratch, const real value, const int by_max) {
    segment_tree(scratch, get_local_id(0), value, by_max);
}

/* Reduce each component over a segment (see segment_tree); its lane 0 writes
 * the segment's row `row` when it is one (row >= 0). */
FN void segment_reduce_store(__local real *segment, const int lane, const int row, const real *c,
                             const int nmax, const int ncomp, __global real *partials) {
    for (int k = 0; k < ncomp; ++k) {
        segment_tree(segment, lane, c[k], k < nmax);
        if (lane == 0 && row >= 0) partials[row * ncomp + k] = segment[0];
        barrier(CLK_LOCAL_MEM_FENCE);
    }
}

/* Reduce each component over the work-group; item 0 writes the group's row. */
FN void group_reduce_store(__local real *scratch, const real *c, const int nmax, const int ncomp,
                           __global real *partials) {
    segment_reduce_store(scratch, get_local_id(0), get_group_id(0), c, nmax, ncomp, partials);
}

#    if SPH_REDUCE_BLOCKS
/* CPU devices: each work-item reduces a block of SPH_WG particles in order
 * into the block's partial row, without barriers: pocl runs the code between
 * two barriers as a loop over the group's work-items, and the tree over 16
 * items took 20 us per substep for the 1612 particles of the H/dp = 10
 * plate, 11 % of its run (docs/benchmarks.md, "pocl").  Launched with one
 * work-item per block (reduce_items, backend_opencl.c). */
#        define REDUCE_SCRATCH
#        define REDUCE_PARTICLES(NMAX, NCOMP, NCOMP_MAX, CONTRIB)                                  \
            do {                                                                                   \
                const int g_ = get_global_id(0);                                                   \
                if (g_ * SPH_WG < n)                                                               \
                    REDUCE_BLOCK(g_, n, NMAX, NCOMP, NCOMP_MAX, partials, CONTRIB);                \
            } while (0)
#    else
/* GPUs: one particle per work-item, combined over the group by a tree. */
#        define REDUCE_SCRATCH __local real scratch[SPH_WG]
#        define REDUCE_PARTICLES(NMAX, NCOMP, NCOMP_MAX, CONTRIB)                                  \
            do {                                                                                   \
                real c[NCOMP_MAX];                                                                 \
                const int i = get_global_id(0);                                                    \
                reduce_identity(c, (NMAX), (NCOMP));                                               \
                if (i < n) CONTRIB;                                                                \
                group_reduce_store(scratch, c, (NMAX), (NCOMP), partials);                         \
            } while (0)
#    endif

/* buffers of rebuild_reduce: reads pos vel mass rho pressure acc_diss; writes vol partials:small */
__kernel __attribute__((reqd_work_group_size(SPH_WG, 1, 1))) void
rebuild_reduce(const int n, CONSTANT sph_params *prm, GLOBAL const hreal *restrict pos,
               GLOBAL const real *restrict vel, GLOBAL const real *restrict mass,
               GLOBAL const hreal *restrict rho, GLOBAL real *restrict vol, REBUILD_STATE_PARAM,
               GLOBAL real *restrict partials) {
    REDUCE_SCRATCH;
    REDUCE_PARTICLES(REBUILD_NCOMP, REBUILD_NCOMP, REBUILD_NCOMP,
                     rebuild_contrib(i, n, prm, pos, vel, mass, rho, vol, REBUILD_STATE_ARG, c));
}

#    if SPH_HAS_ROTATION_AVG
#        define SPIN_ARG           spin
#        define REDUCE_SPIN_PARAMS , GLOBAL const real *restrict spin
#    else
#        define SPIN_ARG 0
#        define REDUCE_SPIN_PARAMS
#    endif
#    if SPH_HAS_BODY_IDS
#        define BODY_ARG           body
#        define REDUCE_BODY_PARAMS , GLOBAL const u8 *restrict body
#    else
#        define BODY_ARG 0
#        define REDUCE_BODY_PARAMS
#    endif
#    if SPH_HAS_EULERIAN
#        define FLUID_ARGS rho, pressure
#        define REDUCE_FLUID_PARAMS                                                                \
            , GLOBAL const hreal *restrict rho, GLOBAL const real *restrict pressure
#    else
#        define FLUID_ARGS 0, 0
#        define REDUCE_FLUID_PARAMS
#    endif
#    if SPH_HAS_TORQUE_PROJECTION
#        define TORQUE_ARGS pos, mass, acc_shear, dacc_shear
#        define REDUCE_TORQUE_PARAMS                                                               \
            , GLOBAL const hreal *restrict pos, GLOBAL const real *restrict mass,                  \
                GLOBAL const hreal *restrict acc_shear, GLOBAL const real *restrict dacc_shear
#    else
#        define TORQUE_ARGS 0, 0, 0, 0
#        define REDUCE_TORQUE_PARAMS
#    endif
/* buffers of substep_reduce: reads step_clock:small vel spin body pos mass acc_shear dacc_shear
 * rho pressure; writes partials:small */
__kernel __attribute__((reqd_work_group_size(SPH_WG, 1, 1))) void
substep_reduce(const int n, STEP_DT_PARAM, CONSTANT sph_params *prm,
               GLOBAL const real *restrict vel,
               GLOBAL real *restrict partials REDUCE_SPIN_PARAMS REDUCE_BODY_PARAMS
                   REDUCE_TORQUE_PARAMS REDUCE_FLUID_PARAMS) {
    REDUCE_SCRATCH;
    STEP_DT_BEGIN;
    const int ncomp = substep_ncomp(prm);
    REDUCE_PARTICLES(
        1, ncomp, SUBSTEP_NCOMP_MAX,
        substep_contrib(i, n, dt, prm, vel, SPIN_ARG, BODY_ARG, TORQUE_ARGS, FLUID_ARGS, c));
}

#    if SPH_HAS_EULERIAN
#        if SPH_HAS_COMPRESSIBLE
#            define DIAG_ENERGY_PARAM , GLOBAL const real *restrict energy
#            define DIAG_ENERGY_ARG   energy
#        else
#            define DIAG_ENERGY_PARAM
#            define DIAG_ENERGY_ARG 0
#        endif
#        if SPH_FLUID_WALLS
#            define DIAG_WALL_PARAM , GLOBAL const real *restrict wall_force
#            define DIAG_WALL_ARG   wall_force
#        else
#            define DIAG_WALL_PARAM
#            define DIAG_WALL_ARG 0
#        endif
/* buffers of diagnostics_reduce: reads pos vel mass vol pressure energy wall_force; writes
 * partials:small */
__kernel __attribute__((reqd_work_group_size(SPH_WG, 1, 1))) void
diagnostics_reduce(const int n, CONSTANT sph_params *prm, GLOBAL const hreal *restrict pos,
                   GLOBAL const real *restrict vel, GLOBAL const real *restrict mass,
                   GLOBAL const real *restrict vol, GLOBAL const real *restrict pressure,
                   GLOBAL real *restrict partials DIAG_ENERGY_PARAM DIAG_WALL_PARAM) {
    REDUCE_SCRATCH;
    REDUCE_PARTICLES(0, DIAG_NCOMP, DIAG_NCOMP,
                     eulerian_diagnostics_contrib(i, n, prm, pos, vel, mass, vol, pressure,
                                                  DIAG_ENERGY_ARG, DIAG_WALL_ARG, c));
}
#    else
/* TLSPH: the deformation gradient for its strain energy */
#        if SPH_HAS_TLSPH
#            define DIAG_DEFGRAD_PARAM , GLOBAL const real *restrict defgrad
#            define DIAG_DEFGRAD_ARG   defgrad
#        else
#            define DIAG_DEFGRAD_PARAM
#            define DIAG_DEFGRAD_ARG 0
#        endif
/* buffers of diagnostics_reduce: reads pos vel mass rho tau defgrad material; writes
 * partials:small */
__kernel __attribute__((reqd_work_group_size(SPH_WG, 1, 1))) void
diagnostics_reduce(const int n, CONSTANT sph_params *prm, GLOBAL const hreal *restrict pos,
                   GLOBAL const real *restrict vel, GLOBAL const real *restrict mass,
                   GLOBAL const hreal *restrict rho, GLOBAL const hreal *restrict tau,
                   GLOBAL real *restrict partials DIAG_DEFGRAD_PARAM MATERIAL_PARAMS) {
    REDUCE_SCRATCH;
    REDUCE_PARTICLES(
        0, DIAG_NCOMP, DIAG_NCOMP,
        diagnostics_contrib(i, n, prm, pos, vel, mass, rho, tau, DIAG_DEFGRAD_ARG MATERIAL_ARG, c));
}
#    endif

/* Second stage, one work-group: row-wise combine of `ngroups` partial rows. */
FN void finalize_rows(__local real *scratch, const int ngroups, const int nmax, const int ncomp,
                      GLOBAL const real *restrict partials, GLOBAL real *restrict result) {
    const int lid = get_local_id(0);
#    if SPH_REDUCE_BLOCKS
    /* one work-item, the rows in order (no barriers, see REDUCE_PARTICLES) */
    (void)scratch;
    if (lid == 0) combine_rows(ngroups, nmax, ncomp, partials, result);
#    else
    for (int k = 0; k < ncomp; ++k) {
        real acc = k < nmax ? REAL_LOWEST : R(0);
        for (int g = lid; g < ngroups; g += SPH_WG) {
            const real x = partials[g * ncomp + k];
            acc = k < nmax ? reduce_max(acc, x) : acc + x;
        }
        group_tree(scratch, acc, k < nmax);
        if (lid == 0) result[k] = scratch[0];
        barrier(CLK_LOCAL_MEM_FENCE);
    }
#    endif
}

/* buffers of reduce_finalize: reads partials:small; writes result:small */
__kernel __attribute__((reqd_work_group_size(SPH_WG, 1, 1))) void
reduce_finalize(const int ngroups, const int nmax, const int ncomp,
                GLOBAL const real *restrict partials, GLOBAL real *restrict result) {
    __local real scratch[SPH_WG];
    finalize_rows(scratch, ngroups, nmax, ncomp, partials, result);
}

#    if SPH_STEP_CLOCK
/* The substep reduction's second stage (max |v|^2, then the sums that give
 * R-bar) and the step clock's advance on that max |v|^2 (sph_step_clock.h):
 * the next substep's size, or the end of the advection step, decided on the
 * device so that the host need not read max |v|^2 after every substep. */
/* buffers of substep_finalize: reads partials:small; writes result:small; updates
 * step_clock:small */
__kernel __attribute__((reqd_work_group_size(SPH_WG, 1, 1))) void
substep_finalize(const int ngroups, const int ncomp, GLOBAL const real *restrict partials,
                 GLOBAL real *restrict result, GLOBAL double *restrict step_clock) {
    __local real scratch[SPH_WG];
    if (step_clock[CLOCK_HALTED] != 0.0) return;
    finalize_rows(scratch, ngroups, 1, ncomp, partials, result);
    if (get_local_id(0) == 0) step_clock_finish(step_clock, (double)result[0]);
}

#        if SPH_REDUCE_BLOCKS
/* CPU devices: substep_reduce and substep_finalize in one launch (a launch
 * costs 5-8 us on pocl, against 13 us for this reduction of the H/dp = 10
 * plate).  Each work-item reduces its block; the one that counts itself
 * last (atomic_inc on blocks_done, after a fence on its partial row)
 * combines the rows in order, the same sums as substep_finalize whoever
 * does them, advances the clock and resets the counter.  The others read
 * the clock before they count, so they never see it change mid-launch. */
/* buffers of substep_reduce_finish: reads vel spin body pos mass acc_shear dacc_shear rho
 * pressure; writes partials:small result:small; updates step_clock:small blocks_done:small */
__kernel __attribute__((reqd_work_group_size(SPH_WG, 1, 1))) void
substep_reduce_finish(const int n, const int ngroups, CONSTANT sph_params *prm,
                      GLOBAL const real *restrict vel, GLOBAL real *partials,
                      GLOBAL real *restrict result, GLOBAL double *step_clock,
                      volatile GLOBAL int *blocks_done REDUCE_SPIN_PARAMS REDUCE_BODY_PARAMS
                          REDUCE_TORQUE_PARAMS REDUCE_FLUID_PARAMS) {
    if (step_clock[CLOCK_HALTED] != 0.0) return;
    const real dt = (real)step_clock[CLOCK_DT];
    const int ncomp = substep_ncomp(prm);
    const int g = get_global_id(0);
    if (g >= ngroups) return;
    REDUCE_BLOCK(
        g, n, 1, ncomp, SUBSTEP_NCOMP_MAX, partials,
        substep_contrib(i, n, dt, prm, vel, SPIN_ARG, BODY_ARG, TORQUE_ARGS, FLUID_ARGS, c));
    mem_fence(CLK_GLOBAL_MEM_FENCE);
    if (atomic_inc(blocks_done) != ngroups - 1) return;
    mem_fence(CLK_GLOBAL_MEM_FENCE);
    *blocks_done = 0;
    combine_rows(ngroups, 1, ncomp, partials, result);
    step_clock_finish(step_clock, (double)result[0]);
}
#        endif
#    endif
#endif
