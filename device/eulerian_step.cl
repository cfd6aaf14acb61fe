/* eulerian_step.cl — extended Eulerian SPH for fluids (004 §3.1, eqs. 9-22).
 *
 * The particles do not move: they are control volumes w_i (FIELD_VOL,
 * dp^d) carrying the conserved variables mass m_i = rho_i w_i, momentum
 * m_i v_i and, for the compressible formulation, the total energy E_i w_i
 * (FIELD_ENERGY, per particle).  The solver rebuilds the configuration once,
 * at the start (as for TLSPH): neighbour_build.cl stores the pairs within
 * 2h (across periodic axes by the nearest image), e_ij, dW/dr w_j, 1/r_ij
 * and B_i; eulerian_correct_pairs then overwrites each pair's gradient by
 * the corrected one of eq. 18, grad'W_ij = (B_i + B_j)/2 grad W_ij, once
 * (the public code's way: every later use, Riemann direction, fluxes and
 * viscous term, sees the corrected gradient).
 *
 * Conservation law, eq. 14 (e_ij from j to i, dwv = dW_ij w_j after the
 * correction; the pair sums are antisymmetric, sph_eulerian.h):
 *   dm_i/dt      = -2 w_i sum_j (rho* v*) . e_ij dwv
 *   d(m v)_i/dt  = -2 w_i sum_j (rho* v* (v* . e_ij) + p* e_ij) dwv + f_i^visc
 *   d(E w)_i/dt  = -2 w_i sum_j (E* + p*) (v* . e_ij) dwv + viscous work
 * Viscous force, eq. 13 (Morris et al. 1997's Laplacian):
 *   f_i^visc = 2 mu w_i sum_j (v_i - v_j) r_ij / (r_ij^2 + eps^2) dwv,
 * eps = 0.01 h; or as the public code discretises it, with 1 / (r_ij + eps)
 * in place of r_ij / (r_ij^2 + eps^2) (method.viscous_regularization).
 * Its work enters the energy pairwise, sum_j f_ij . (v_i + v_j)/2 with f_ij
 * the pair's viscous force, so that the total energy is conserved (the
 * public code adds f_i . v_i, which it flags "not conservative"; the kinetic
 * energy the viscous term removes becomes internal energy here).
 *
 * One step of size dt (the public code's two stages, reference §3):
 *   1. eulerian_momentum_rate: F_i = d(m v)_i/dt from the state n, kept as
 *      v' = (m v)^{n+1} / m^n = v^n + dt F / m^n (field vel_stage);
 *   2. eulerian_mass_energy_rate: dm_i/dt and d(E w)_i/dt from (rho^n,
 *      v', p^n, E^n);
 *   3. eulerian_update: m, (m v)^{n+1} = m^n v' and v = (m v) / m,
 *      rho = m / w, E w, p by the EOS (and the compressible sound speed).
 * Each pass reads only what the passes before wrote: race-free without
 * atomics.  The vorticity is no part of a step: eulerian_vorticity forms it
 * from the state a snapshot writes, when it writes one.  The native backend
 * runs steps 1 and 2, and SSP-RK's rate passes (eulerian_rates_pairs), with
 * each fluid pair summed once ("the native backend's two-stage passes sum
 * each fluid pair once", below): the same terms, summed in another order.
 */
#ifndef EULERIAN_STEP_CL
#define EULERIAN_STEP_CL
#include "sph_vec.h"
#include "sph_eulerian.h"

#if SPH_HAS_EULERIAN

#    if SPH_HAS_COMPRESSIBLE
#        define ENERGY_PARAM     , GLOBAL const real *restrict energy
#        define ENERGY_OUT_PARAM , GLOBAL real *restrict energy
#        define ENERGY_RATE_PARAMS                                                                 \
            , GLOBAL const real *restrict energy, GLOBAL real *restrict energy_rate
#        define ENERGY_UPDATE_PARAMS                                                               \
            , GLOBAL real *restrict energy, GLOBAL const real *restrict energy_rate
#        define ENERGY_ARG           , energy
#        define ENERGY_RATE_ARGS     , energy, energy_rate
#        define ENERGY_PER_VOLUME(k) (energy[k] / vol[k])
#    else
#        define ENERGY_PARAM
#        define ENERGY_OUT_PARAM
#        define ENERGY_RATE_PARAMS
#        define ENERGY_UPDATE_PARAMS
#        define ENERGY_ARG
#        define ENERGY_RATE_ARGS
#        define ENERGY_PER_VOLUME(k) R(0)
#    endif
/* (each X_PARAM(S) of this file has its X_ARG(S), the same names for a call:
 * the substep loop's, substep_loop.cl; ENERGY_UPDATE_PARAMS's are
 * ENERGY_RATE_ARGS, ENERGY_OUT_PARAM's ENERGY_ARG) */

/* Fixed-state particles (constraints of type "fixed" on a fluid body): a
 * Dirichlet buffer whose state never changes, e.g. the supersonic inflow
 * and the undisturbed gas at the ends of the Shu-Osher tube.  Their F is
 * zero (so the v^{n+1} their neighbours form is v^n) and the update leaves
 * them alone. */
#    if SPH_HAS_CLAMP
#        define FIXED_PARAM , GLOBAL const u8 *restrict fixed
#        define FIXED_ARG   , fixed
#        define IS_FIXED(k) (PRESENT(fixed) && fixed[k] != 0)
#    else
#        define FIXED_PARAM
#        define FIXED_ARG
#        define IS_FIXED(k) 0
#    endif

/* Walls and the far field (SPH_FLUID_KINDS): each particle's kind
 * (SPH_PARTICLE_*, sph_constants.h) and normal (a wall particle's into the
 * fluid, a far-field particle's outward one). */
#    if SPH_FLUID_KINDS
#        define KIND_PARAMS , GLOBAL const u8 *restrict kind, GLOBAL const real *restrict normal
#        define KIND_ARGS   , kind, normal
#        define KIND_OF(k)  (PRESENT(kind) ? (int)kind[k] : SPH_PARTICLE_FLUID)
#    else
#        define KIND_PARAMS
#        define KIND_ARGS
#        define KIND_OF(k) SPH_PARTICLE_FLUID
#    endif
/* a wall particle, whose state no step changes (a macro, also where it is a
 * constant: clang warns of a logical operator with a constant operand
 * written out, not of one from a macro) */
#    define IS_WALL(k) (KIND_OF(k) == SPH_PARTICLE_WALL)
/* A far-field particle: the far field (eulerian_far_field) sets its state
 * after every step, from the interior and the free stream; the step itself
 * leaves it alone, as a fixed-state particle.  The public code lets it
 * evolve through the step and resets it after, but with part of its support
 * outside the box its own rates are those of a truncated sum, and the
 * second stage's mass fluxes carried the v' they gave it into the interior:
 * a uniform stream through far-field faces did not stay uniform
 * (docs/fluids.md, "Boundaries"; tests/test_cylinder.py). */
#    define IS_FAR_FIELD(k)                                                                        \
        (KIND_OF(k) == SPH_PARTICLE_INFLOW || KIND_OF(k) == SPH_PARTICLE_OUTFLOW)
/* a particle whose state the step's rates do not change */
#    define HOLDS_STATE(k) (IS_FIXED(k) || IS_WALL(k) || IS_FAR_FIELD(k))

/* Gravity on the fluids (gravity_of, sph_vec.h), a body force: the momentum
 * rate of a particle that evolves gains m g and (compressible) its total
 * energy the work m v . g; the pair fluxes are untouched, so a fluid at rest
 * under gravity meets the walls that hold it through its pressure. */
/* the wall pairs' share of each fluid particle's F (pressure part, then
 * viscous part): minus their sum is the force on the walls */
#    if SPH_FLUID_WALLS
#        define WALL_FORCE_PARAM , GLOBAL real *restrict wall_force
#        define WALL_FORCE_ARG   , wall_force
#    else
#        define WALL_FORCE_PARAM
#        define WALL_FORCE_ARG
#    endif

/* The frozen pair rows: particle i's ROW_COUNT(i) pairs at the slots
 * ROW_SLOT(i, k) of nbr_j and the pair arrays, the components of e_ij
 * ROWS_STRIDE apart.  The native backend packs the rows (the pairs of
 * particle i at row_start[i] ... row_start[i + 1] - 1; host/backend/cpu/backend_cpu.c
 * packs the rebuild's rows once, before eulerian_correct_pairs): the
 * rebuild pads every row to the busiest one's length, cap, and a wall body
 * at dp/2 gives its particles and the fluid beside it two to four times the
 * 20 pairs of the fluid lattice; the pair loops then stream padded rows
 * (the cylinder at dp = 1/10: 104 steps on one thread 12.0 s padded, 5.45 s
 * packed; docs/fluids.md, "Speed on the CPU").  OpenCL devices keep the
 * padded rows: a GPU reads them column-major, where the padding is never
 * read. */
#    if !SPH_OPENCL
#        define PAIR_ROWS_PARAMS                                                                   \
            GLOBAL const int *restrict row_start, GLOBAL const int *restrict row_walls,            \
                GLOBAL const int *restrict nbr_j
#        define PAIR_ROWS_ARGS row_start, row_walls, nbr_j
#        define ROW_COUNT(i)   (row_start[(i) + 1] - row_start[i])
#        define ROW_SLOT(i, k) (row_start[i] + (k))
#        define ROWS_STRIDE    row_start[n]
/* The packing also puts a row's wall pairs last, row_walls[i] of them
 * (NULL: no walls), so the passes' lanes see fluid pairs only and sum the
 * wall pairs after them, without asking each neighbour's kind (a tenth of
 * the cylinder's step). */
#        define WALL_PAIRS_LAST   1
#        define ROW_WALL_PAIRS(i) (PRESENT(row_walls) ? row_walls[i] : 0)
#        define ROW_WALLS_UNUSED  (void)row_walls /* passes that ask each pair's kind */
#    else
#        define PAIR_ROWS_PARAMS                                                                   \
            const int cap, GLOBAL const int *restrict nbr_count, GLOBAL const int *restrict nbr_j
#        define PAIR_ROWS_ARGS    cap, nbr_count, nbr_j
#        define ROW_COUNT(i)      nbr_count[i]
#        define ROW_SLOT(i, k)    NBR_AT(i, k)
#        define ROWS_STRIDE       (n * cap)
#        define WALL_PAIRS_LAST   0
#        define ROW_WALL_PAIRS(i) 0
#        define ROW_WALLS_UNUSED  (void)0
#    endif

/* The side of particle k of pair (i, j) along e_ij. */
FN fluid_side fluid_side_make(const real rho, const real p, const vec v, const real energy,
                              const real c, const vec e_ij) {
    fluid_side s;
    s.rho = rho;
    s.p = p;
    s.v = v;
    s.u = -vec_dot(e_ij, v);
    s.energy = energy;
    s.c = c;
    return s;
}

/* The formulation's Riemann solver (sph_eulerian.h) with its constants,
 * formed once per particle: HLLC needs only eta (each side brings its own
 * sound speed, the field sound_speed), the linearised solver Z and eta/c0.
 * SOLVER_BACKGROUND(k) is the pressure p_b the momentum fluxes take from p*:
 * the ideal gas's method.background_pressure (by default the far field's
 * p_inf), so that a truncated or irregular support (next to a wall) errs by
 * p - p_b, not by p of some 70 dynamic pressures; a constant changes no
 * exact gradient and, the pair terms being antisymmetric, no total momentum.
 * The energy flux keeps p*: (E* + p*) v* is the work of the whole pressure.
 * The WC pressure is already 0 at rest (p = c0^2 (rho - rho0)): 0. */
#    if SPH_HAS_COMPRESSIBLE
typedef struct {
    real eta, background;
} fluid_solver;
FN fluid_solver fluid_solver_make(CONSTANT sph_params *prm) {
    fluid_solver k;
    k.eta = prm->riemann_limit;
    k.background = prm->background_pressure;
    return k;
}
FN fluid_state fluid_interface(const fluid_solver k, const fluid_side l, const fluid_side r,
                               const vec e_ij) {
    return riemann_hllc(l, r, e_ij, k.eta);
}
#        define SOLVER_BACKGROUND(k) ((k).background)
#        define SOUND_PARAM          , GLOBAL const real *restrict sound_speed
#        define SOUND_OUT_PARAM      , GLOBAL real *restrict sound_speed
#        define SOUND_ARG            , sound_speed
#        define SOUND_OF(k)          sound_speed[k]
#    else
typedef linearised_solver fluid_solver;
FN fluid_solver fluid_solver_make(CONSTANT sph_params *prm) {
    return linearised_solver_make(prm->materials[0].rho0, prm->materials[0].c0, prm->riemann_limit);
}
FN fluid_state fluid_interface(const fluid_solver k, const fluid_side l, const fluid_side r,
                               const vec e_ij) {
    return riemann_linearised(l, r, e_ij, k);
}
#        define SOLVER_BACKGROUND(k) R(0)
#        define SOUND_PARAM
#        define SOUND_OUT_PARAM
#        define SOUND_ARG
#        define SOUND_OF(k) R(0)
#    endif

/* A particle's state as a side of its pairs: density, pressure, velocity,
 * total energy per volume (compressible, else 0) and sound speed
 * (compressible, else 0).  FLUID_POINT(k, v) reads particle k's (with the
 * velocity v the pass uses: v^n or v'). */
typedef struct {
    real rho, p;
    vec v;
    real energy, c;
} fluid_point;
FN fluid_point fluid_point_make(const real rho, const real p, const vec v, const real energy,
                                const real c) {
    fluid_point q;
    q.rho = rho;
    q.p = p;
    q.v = v;
    q.energy = energy;
    q.c = c;
    return q;
}
#    define FLUID_POINT(k, v_k)                                                                    \
        fluid_point_make((real)rho[k], pressure[k], (v_k), ENERGY_PER_VOLUME(k), SOUND_OF(k))

/* The interface state of the pair (i, j) along e_ij (eq. 14's Riemann
 * problem). */
FN fluid_state pair_interface(const fluid_solver solver, const fluid_point a, const fluid_point b,
                              const vec e_ij) {
    return fluid_interface(solver, fluid_side_make(a.rho, a.p, a.v, a.energy, a.c, e_ij),
                           fluid_side_make(b.rho, b.p, b.v, b.energy, b.c, e_ij), e_ij);
}

#    if SPH_FLUID_KINDS
/* A fluid particle's interface with a wall particle (at rest): the Riemann
 * problem along the wall particle's normal n_j against the mirrored state
 * (rho_i, p_i, -v_i) (eulerian-sph-reference.md §1, §4). */
FN fluid_state wall_interface(const fluid_solver solver, const fluid_point a, const vec n_j) {
    fluid_point mirror = a;
    mirror.v = vec_scale(a.v, R(-1));
    return pair_interface(solver, a, mirror, n_j);
}
#    endif

/* The two-stage passes sum their fluid pairs in lanes (SPH_PAIR_LANES,
 * sph_prelude.h; sph_eulerian.h has the solver on lanes): the states of the
 * lanes' neighbours j (fluid_point_lanes), their frozen geometry (e_ij,
 * dW w_j and, for the viscous weight, pair_inv_r: pair_lanes_geometry) and
 * keep, 1 for a fluid pair and 0 for an empty lane (past the end of the
 * row, or on OpenCL a wall pair, which the passes sum one by one), whose
 * neighbour is i itself: its terms are zeros. */
typedef struct {
    lanes rho, p;
    lanes_vec v;
    lanes energy, c;
} fluid_point_lanes;
/* The neighbours' states gathered as scalars first, then built into
 * vectors (LANES_FROM); keep is 1 for a fluid pair, 0 for an empty lane. */
typedef struct {
    real rho[SPH_PAIR_LANES], p[SPH_PAIR_LANES], energy[SPH_PAIR_LANES], c[SPH_PAIR_LANES];
    real v[SPH_DIM][SPH_PAIR_LANES], keep[SPH_PAIR_LANES];
} fluid_point_gather;
FN_HOT void fluid_point_gather_set(fluid_point_gather *g, const int l, const fluid_point q,
                                   const real keep) {
    g->rho[l] = q.rho;
    g->p[l] = q.p;
    g->energy[l] = q.energy;
    g->c[l] = q.c;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) g->v[a][l] = q.v.c[a];
    g->keep[l] = keep;
}
FN_HOT fluid_point_lanes fluid_point_lanes_from(const fluid_point_gather *g, lanes *keep) {
    fluid_point_lanes q;
    q.rho = LANES_FROM(g->rho);
    q.p = LANES_FROM(g->p);
    q.energy = LANES_FROM(g->energy);
    q.c = LANES_FROM(g->c);
    UNROLL for (int a = 0; a < SPH_DIM; ++a) q.v.c[a] = LANES_FROM(g->v[a]);
    *keep = LANES_FROM(g->keep);
    return q;
}

/* The lanes from k0 of a pass's pairs k < lanes_end: PAIR_LANES_GEOMETRY
 * loads their geometry, whole vectors where the row holds all of them, else
 * lane by lane with zeros past lanes_end; lane l's neighbour
 * (LANE_PAIR_BEGIN: its slot, and j, i past lanes_end) goes into the gather
 * by fluid_point_gather_set, or LANE_PAIR_EMPTY where the lane is no fluid
 * pair. */
FN lanes lanes_load_row(GLOBAL const real *p) {
#    if SPH_PAIR_LANES > 1
    lanes v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
#    else
    return *p;
#    endif
}
/* The lanes' geometry from slot0, the slot of the first (in a packed row
 * the lanes' slots follow it; in OpenCL there is one lane), left = pairs
 * left in the row. */
FN_HOT void pair_lanes_geometry(GLOBAL const real *restrict pair_e,
                                GLOBAL const real *restrict pair_dwv,
                                GLOBAL const real *restrict pair_inv_r, const int stride,
                                const int slot0, const int left, lanes_vec *e, lanes *dwv,
                                lanes *inv_r) {
    if (left >= SPH_PAIR_LANES) {
        UNROLL for (int a = 0; a < SPH_DIM; ++a) e->c[a] =
            lanes_load_row(pair_e + a * stride + slot0);
        *dwv = lanes_load_row(pair_dwv + slot0);
        if (inv_r) *inv_r = lanes_load_row(pair_inv_r + slot0);
        return;
    }
    real e_s[SPH_DIM][SPH_PAIR_LANES], dwv_s[SPH_PAIR_LANES], inv_r_s[SPH_PAIR_LANES];
    UNROLL_LANES for (int l = 0; l < SPH_PAIR_LANES; ++l) {
        const bool live = l < left;
        const int slot = slot0 + (live ? l : 0);
        UNROLL for (int a = 0; a < SPH_DIM; ++a) e_s[a][l] =
            live ? pair_e[a * stride + slot] : R(0);
        dwv_s[l] = live ? pair_dwv[slot] : R(0);
        inv_r_s[l] = live && inv_r ? pair_inv_r[slot] : R(0);
    }
    UNROLL for (int a = 0; a < SPH_DIM; ++a) e->c[a] = LANES_FROM(e_s[a]);
    *dwv = LANES_FROM(dwv_s);
    if (inv_r) *inv_r = LANES_FROM(inv_r_s);
}
#    define PAIR_LANES_GEOMETRY(e_, dwv_, inv_r_)                                                  \
        pair_lanes_geometry(pair_e, pair_dwv, pair_inv_r, stride, ROW_SLOT(i, k0), lanes_end - k0, \
                            &(e_), &(dwv_), (inv_r_))
#    define LANE_PAIR_BEGIN(l)                                                                     \
        const int k_ = k0 + (l);                                                                   \
        const bool live_ = k_ < lanes_end;                                                         \
        const int slot = ROW_SLOT(i, live_ ? k_ : 0);                                              \
        const int j = live_ ? nbr_j[slot] : i
#    define LANE_PAIR_EMPTY(gather_, l) fluid_point_gather_set(&(gather_), (l), q_i, R(0))
/* The gather gq_ of the lanes' fluid neighbours, their velocity from the
 * field vel_ (v^n or v'); where a row's wall pairs are not last (OpenCL) a
 * wall pair gets WALL_PAIR(slot, j) and an empty lane. */
#    if SPH_FLUID_KINDS && !WALL_PAIRS_LAST
#        define LANE_WALL_PAIR(gq_, l, WALL_PAIR)                                                  \
            if (live_ && IS_WALL(j)) {                                                             \
                WALL_PAIR(slot, j);                                                                \
                LANE_PAIR_EMPTY(gq_, l);                                                           \
                continue;                                                                          \
            }
#    else
#        define LANE_WALL_PAIR(gq_, l, WALL_PAIR)
#    endif
/* A row's wall pairs after its lanes, where they come last (the native
 * backend's packed rows), each by WALL_PAIR(slot, j). */
#    if SPH_FLUID_KINDS && WALL_PAIRS_LAST
#        define WALL_PAIRS_AFTER_LANES(WALL_PAIR)                                                  \
            for (int k = lanes_end; k < count; ++k) {                                              \
                const int slot = ROW_SLOT(i, k);                                                   \
                WALL_PAIR(slot, nbr_j[slot]);                                                      \
            }
#    else
#        define WALL_PAIRS_AFTER_LANES(WALL_PAIR)
#    endif
#    define GATHER_FLUID_LANES(gq_, vel_, WALL_PAIR)                                               \
        fluid_point_gather gq_;                                                                    \
        UNROLL_LANES for (int l = 0; l < SPH_PAIR_LANES; ++l) {                                    \
            LANE_PAIR_BEGIN(l);                                                                    \
            LANE_WALL_PAIR(gq_, l, WALL_PAIR)                                                      \
            fluid_point_gather_set(&(gq_), l, FLUID_POINT(j, vec_load(vel_, n, j)), R(1));         \
        }

/* A pass's lanes from k0: their geometry e, dwv (and the viscous weight
 * into *inv_r_ptr_, where the pass wants it), the neighbours' states q
 * (their velocity from vel_) with keep, and the interface states s. */
#    define PAIR_LANES_STATES(inv_r_ptr_, vel_, WALL_PAIR)                                         \
        lanes_vec e;                                                                               \
        lanes dwv;                                                                                 \
        PAIR_LANES_GEOMETRY(e, dwv, (inv_r_ptr_));                                                 \
        GATHER_FLUID_LANES(gq, vel_, WALL_PAIR);                                                   \
        lanes keep;                                                                                \
        const fluid_point_lanes q = fluid_point_lanes_from(&gq, &keep);                            \
        const fluid_state_lanes s = pair_interface_lanes(solver, q_i, q_i_lanes, q, e)
/* The mass and energy passes' viscous weight: only the compressible
 * formulation's viscous work reads it. */
#    if SPH_HAS_COMPRESSIBLE
#        define MASS_PASS_INV_R_DECL lanes inv_r
#        define MASS_PASS_INV_R      (&inv_r)
#    else
#        define MASS_PASS_INV_R_DECL (void)0
#        define MASS_PASS_INV_R      ((lanes *)0)
#    endif

/* Particle i's side broadcast to every lane, once per row: formed inside
 * the lane loop the broadcasts were built again for every lane of four
 * (two shuffles each, the compiler did not hoist them). */
typedef struct {
    lanes rho, p;
    lanes_vec v;
} fluid_point_broadcast;
FN fluid_point_broadcast fluid_point_broadcast_make(const fluid_point a) {
    fluid_point_broadcast b;
    b.rho = lanes_broadcast(a.rho);
    b.p = lanes_broadcast(a.p);
    UNROLL for (int c = 0; c < SPH_DIM; ++c) b.v.c[c] = lanes_broadcast(a.v.c[c]);
    return b;
}

/* The interface states of lanes of pairs (i, j): the linearised solver on
 * the lanes, HLLC (its branches) lane by lane. */
FN_HOT fluid_state_lanes pair_interface_lanes(const fluid_solver solver, const fluid_point a,
                                              const fluid_point_broadcast a_lanes,
                                              const fluid_point_lanes b, const lanes_vec e_ij) {
    fluid_state_lanes s;
#    if SPH_HAS_COMPRESSIBLE
    (void)a_lanes;
    real rho_s[SPH_PAIR_LANES], p_s[SPH_PAIR_LANES], energy_s[SPH_PAIR_LANES],
        v_s[SPH_DIM][SPH_PAIR_LANES];
    UNROLL_LANES for (int l = 0; l < SPH_PAIR_LANES; ++l) {
        vec e, v_b;
        UNROLL for (int c = 0; c < SPH_DIM; ++c) {
            e.c[c] = LANE(e_ij.c[c], l);
            v_b.c[c] = LANE(b.v.c[c], l);
        }
        const fluid_state one = pair_interface(
            solver, a,
            fluid_point_make(LANE(b.rho, l), LANE(b.p, l), v_b, LANE(b.energy, l), LANE(b.c, l)),
            e);
        rho_s[l] = one.rho;
        p_s[l] = one.p;
        energy_s[l] = one.energy;
        UNROLL for (int c = 0; c < SPH_DIM; ++c) v_s[c][l] = one.v.c[c];
    }
    s.rho = LANES_FROM(rho_s);
    s.p = LANES_FROM(p_s);
    s.energy = LANES_FROM(energy_s);
    UNROLL for (int c = 0; c < SPH_DIM; ++c) s.v.c[c] = LANES_FROM(v_s[c]);
#    else
    /* fluid_side_make on lanes: the same operations */
    (void)a;
    fluid_side_lanes l, r;
    l.rho = a_lanes.rho;
    l.p = a_lanes.p;
    r.rho = b.rho;
    r.p = b.p;
    r.v = b.v;
    l.v = a_lanes.v;
    l.u = -lanes_dot(e_ij, l.v);
    r.u = -lanes_dot(e_ij, r.v);
    s = riemann_linearised_lanes(l, r, e_ij, solver);
#    endif
    return s;
}

/* The momentum rate's sums over the fluid pairs, in lanes (the first
 * two-stage pass and SSP-RK2's rates): the Riemann momentum flux times
 * dW w_j, and the viscous sum visc_w (v_i - v_j). */
FN_HOT void momentum_lanes_add(lanes *flux, lanes *visc, const fluid_state_lanes s, const real p_b,
                               const lanes vn, const lanes_vec e, const lanes dwv,
                               const lanes visc_w, const vec v_i, const lanes_vec v_j) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        flux[a] += dwv * fluid_momentum_flux_lanes(s, vn, e, a, p_b);
        visc[a] += visc_w * (v_i.c[a] - v_j.c[a]);
    }
}

/* The mass and energy rates' sums over the fluid pairs, in lanes (the
 * second two-stage pass and SSP-RK's rates): the mass flux
 * rho* (v* . e) dW w_j and, compressible, the energy flux
 * (E* + p*)(v* . e) dW w_j and the viscous work, pairwise: the pair's viscous force on i, -visc_w
 * (v_j - v_i), dotted with the pair's mean velocity (antisymmetric force, symmetric mean, so the
 * work cancels in the sum over all particles). */
typedef struct {
    lanes mass, energy, heat;
} mass_energy_lanes;
FN mass_energy_lanes mass_energy_lanes_zero(void) {
    mass_energy_lanes z;
    z.mass = z.energy = z.heat = lanes_zero();
    return z;
}
FN_HOT void mass_energy_lanes_add(mass_energy_lanes *acc, const fluid_state_lanes s, const lanes vn,
                                  const lanes dwv, const lanes visc_w, const vec v_i,
                                  const lanes_vec v_j) {
    acc->mass += s.rho * vn * dwv;
#    if SPH_HAS_COMPRESSIBLE
    acc->energy += (s.energy + s.p) * vn * dwv;
    lanes_vec dv, f_pair, v_mean;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) dv.c[a] = v_j.c[a] - v_i.c[a];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        f_pair.c[a] = dv.c[a] * (-visc_w);
        v_mean.c[a] = (v_i.c[a] + v_j.c[a]) * R(0.5);
    }
    acc->heat += lanes_dot(f_pair, v_mean);
#    else
    (void)visc_w;
    (void)v_i;
    (void)v_j;
#    endif
}
/* The lanes' sums in lane order. */
typedef struct {
    real mass, energy, heat;
} mass_energy_sums;
FN mass_energy_sums mass_energy_lanes_sum(const mass_energy_lanes acc) {
    mass_energy_sums t;
    t.mass = t.energy = t.heat = R(0);
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) {
        t.mass += LANE(acc.mass, l);
        t.energy += LANE(acc.energy, l);
        t.heat += LANE(acc.heat, l);
    }
    return t;
}
/* A wall pair that a pass skips (the mass and energy rates: no mass or
 * energy crosses a wall). */
#    define SKIP_WALL_PAIR(slot_, j_) ((void)(slot_), (void)(j_))

#    if SPH_FLUID_KINDS
/* One wall pair (i, j) of the two-stage passes, from its slot: its frozen
 * geometry and the wall particle's normal. */
typedef struct {
    vec e, n_j;
    real dwv, inv_r;
} wall_pair;
#        define WALL_PAIR_ARGS(slot, j)                                                            \
            wall_pair_load(pair_e, pair_dwv, pair_inv_r, stride, (slot), normal, n, (j))
FN wall_pair wall_pair_load(GLOBAL const real *restrict pair_e,
                            GLOBAL const real *restrict pair_dwv,
                            GLOBAL const real *restrict pair_inv_r, const int stride,
                            const int slot, GLOBAL const real *restrict normal, const int n,
                            const int j) {
    wall_pair w;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) w.e.c[a] = pair_e[a * stride + slot];
    w.dwv = pair_dwv[slot];
    w.inv_r = pair_inv_r[slot];
    w.n_j = vec_load(normal, n, j);
    return w;
}
/* The momentum pass's wall pair: its interface state, the flux along the
 * pair's corrected gradient; the no-slip viscous term (4 mu, applied by
 * the caller) from v_i against the wall at rest. */
FN void momentum_wall_pair(const fluid_solver solver, const fluid_point q_i, const wall_pair w,
                           vec *wall_flux, vec *wall_visc) {
    const fluid_state s = wall_interface(solver, q_i, w.n_j);
    *wall_flux =
        vec_axpy(*wall_flux, w.dwv, fluid_momentum_flux(s, w.e, SOLVER_BACKGROUND(solver)));
    *wall_visc = vec_axpy(*wall_visc, w.dwv * w.inv_r, q_i.v);
}
/* The wall pairs' share of F_i from their sums (momentum_wall_pair): the
 * pressure part -2 w_i wall_flux and the viscous part 4 mu w_i wall_visc,
 * each stored in wall_force where the scene measures the force on its walls,
 * blended with the force already there by `keep` (0 for the two stages and
 * SSP-RK's first stage: the new parts alone; rk_force_keep); returns their
 * sum. */
FN vec wall_pairs_force(const real keep, const vec wall_flux, const vec wall_visc, const real w_i,
                        const real mu, const int i, const int n, GLOBAL real *restrict wall_force) {
    const vec wall_p = vec_scale(wall_flux, R(-2) * w_i);
    const vec wall_v = vec_scale(wall_visc, R(4) * mu * w_i);
    if (PRESENT(wall_force)) {
        const real add = R(1) - keep;
        UNROLL for (int a = 0; a < SPH_DIM; ++a) {
            GLOBAL real *p = &wall_force[a * n + i];
            GLOBAL real *v = &wall_force[(SPH_DIM + a) * n + i];
            *p = keep == R(0) ? wall_p.c[a] : keep * *p + add * wall_p.c[a];
            *v = keep == R(0) ? wall_v.c[a] : keep * *v + add * wall_v.c[a];
        }
    }
    return vec_add(wall_p, wall_v);
}
#    endif

/* Once, before the first step: the pressure of the WC state by the EOS, or
 * the total energy and sound speed of the compressible state from its
 * pressure (both particle-local). */
/* buffers of eulerian_prepare: reads rho vel vol energy_rate; writes energy sound_speed; updates
 * pressure */
KERNEL void eulerian_prepare(ITEM_PARAM const int n, CONSTANT sph_params *prm,
                             GLOBAL const hreal *restrict rho, GLOBAL const real *restrict vel,
                             GLOBAL const real *restrict vol,
                             GLOBAL real *restrict pressure ENERGY_UPDATE_PARAMS SOUND_OUT_PARAM) {
    const int i = ITEM_ID;
    if (i >= n) return;
#    if SPH_HAS_COMPRESSIBLE
    (void)energy_rate;
    const vec v = vec_load(vel, n, i);
    const real r = (real)rho[i], gamma = prm->materials[0].gamma;
    energy[i] = vol[i] * ideal_gas_energy(pressure[i], r, v, gamma);
    sound_speed[i] = ideal_gas_sound_speed(pressure[i], r, gamma);
#    else
    (void)vel;
    (void)vol;
    pressure[i] =
        eos_weakly_compressible((real)rho[i], prm->materials[0].rho0, prm->materials[0].c0);
#    endif
}

/* Once, after the rebuild: each stored pair gradient dwv e_ij becomes
 * (B_i + B_j)/2 dwv e_ij (eq. 18): e <- g/|g|, dwv <- dwv |g| with
 * g = (B_i + B_j)/2 e; r <- r (e_old . e_new) as the public code keeps it
 * for the viscous term (floored at 0.1 r: a pair whose corrected direction
 * turned by more than 84 degrees would otherwise get a viscous denominator
 * near zero), and the slot pair_inv_r then holds the viscous weight of
 * eq. 13, r / (r^2 + eps^2) or the public code's 1 / (r + eps), eps = 0.01 h
 * (method.viscous_regularization, host/setup/scene.h): the step has no division
 * per pair.
 * g_ji = -g_ij exactly, so the pair terms stay antisymmetric. */
/* buffers of eulerian_correct_pairs: reads row_start:int*n row_walls:int*n nbr_j:int*pairs
 * nbr_count:int*n bmat kind normal; updates pair_e:real*d*pairs pair_dwv:real*pairs
 * pair_inv_r:real*pairs */
KERNEL void eulerian_correct_pairs(ITEM_PARAM const int n, CONSTANT sph_params *prm,
                                   PAIR_ROWS_PARAMS, GLOBAL const real *restrict bmat,
                                   GLOBAL real *restrict pair_e, GLOBAL real *restrict pair_dwv,
                                   GLOBAL real *restrict pair_inv_r KIND_PARAMS) {
    const int i = ITEM_ID;
    if (i >= n) return;
    ROW_WALLS_UNUSED;
#    if SPH_FLUID_KINDS
    (void)normal;
#    endif
    const int stride = ROWS_STRIDE;
    const real eps_linear = prm->viscous_eps_linear, eps_squared = prm->viscous_eps_squared;
    const mat b_i = sym_load(bmat, n, i);
    const bool far_i = IS_FAR_FIELD(i);
    const int count = ROW_COUNT(i);
    for (int k = 0; k < count; ++k) {
        const int slot = ROW_SLOT(i, k);
        const int j = nbr_j[slot];
        vec e;
        UNROLL for (int a = 0; a < SPH_DIM; ++a) e.c[a] = pair_e[a * stride + slot];
        /* (B_i + B_j) / 2; but a far-field particle's B is that of a
         * support cut by the box's face, so a pair of it with a particle
         * inside takes the inner particle's B alone: on a lattice every
         * pair of an inner particle then has the same B and its sums of a
         * uniform state vanish as in the bulk (with (B_i + B_j) / 2 a uniform
         * stream through far-field faces was disturbed within 2h of them) */
        const bool far_j = IS_FAR_FIELD(j);
        const mat b = far_i == far_j ? mat_scale(mat_add(b_i, sym_load(bmat, n, j)), R(0.5))
                      : far_j        ? b_i
                                     : sym_load(bmat, n, j);
        const vec g = mat_vec(b, e);
        const real norm = sqrt(vec_dot(g, g));
        real turn = R(1);
        if (norm > R(0)) {
            const vec e_new = vec_scale(g, R(1) / norm);
            UNROLL for (int a = 0; a < SPH_DIM; ++a) pair_e[a * stride + slot] = e_new.c[a];
            pair_dwv[slot] *= norm;
            turn = fmax(vec_dot(e, e_new), R(0.1));
        }
        const real r = turn / pair_inv_r[slot];
        pair_inv_r[slot] = r / (r * (r + eps_linear) + eps_squared);
    }
}

#    if SPH_FLUID_TWO_STAGE
/* Stage 1: the momentum rate F_i = d(m v)_i/dt (the Riemann momentum flux
 * and the viscous force, from the state n), stored as the second stage's
 * velocity v'_i = (m v)^{n+1} / m^n = v_i + dt F_i / m_i (the public code's
 * v^{n+1} = mv / m^n); fixed-state, wall and far-field particles keep v' = v. */
/* buffers of eulerian_momentum_rate: reads step_clock:small row_start:int*n row_walls:int*n
 * nbr_j:int*pairs nbr_count:int*n pair_e:real*d*pairs pair_dwv:real*pairs pair_inv_r:real*pairs
 * rho vel mass vol pressure energy sound_speed fixed kind normal; writes vel_stage; updates
 * wall_force */
KERNEL void
eulerian_momentum_rate(ITEM_PARAM const int n, STEP_DT_PARAM, CONSTANT sph_params *prm,
                       PAIR_ROWS_PARAMS, GLOBAL const real *restrict pair_e,
                       GLOBAL const real *restrict pair_dwv, GLOBAL const real *restrict pair_inv_r,
                       GLOBAL const hreal *restrict rho, GLOBAL const real *restrict vel,
                       GLOBAL const real *restrict mass, GLOBAL const real *restrict vol,
                       GLOBAL const real *restrict pressure,
                       GLOBAL real *restrict vel_stage ENERGY_PARAM SOUND_PARAM FIXED_PARAM
                           KIND_PARAMS WALL_FORCE_PARAM) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = ROWS_STRIDE;
    const real mu = prm->materials[0].viscosity;
    const fluid_solver solver = fluid_solver_make(prm);
    const vec v_i = vec_load(vel, n, i);
    const fluid_point q_i = FLUID_POINT(i, v_i);
    const fluid_point_broadcast q_i_lanes = fluid_point_broadcast_make(q_i);
    /* the fluid pairs' sums in lanes (sph_prelude.h) */
    lanes lane_flux[SPH_DIM], lane_visc[SPH_DIM];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) lane_flux[a] = lane_visc[a] = lanes_zero();
    /* wall pairs: their pressure flux and velocity sums */
    vec wall_flux = vec_zero(), wall_visc = vec_zero();
    /* fixed-state, wall and far-field particles do not evolve: F = 0 */
    const int count = HOLDS_STATE(i) ? 0 : ROW_COUNT(i);
    /* the lanes' pairs: all, or the fluid pairs before the row's walls */
    const int lanes_end = count > 0 ? count - ROW_WALL_PAIRS(i) : 0;
#        define MOMENTUM_WALL_PAIR(slot_, j_)                                                      \
            momentum_wall_pair(solver, q_i, WALL_PAIR_ARGS(slot_, j_), &wall_flux, &wall_visc)
    for (int k0 = 0; k0 < lanes_end; k0 += SPH_PAIR_LANES) {
        lanes inv_r;
        PAIR_LANES_STATES(&inv_r, vel, MOMENTUM_WALL_PAIR);
        const lanes dwv_k = dwv * keep, visc_w = dwv * inv_r * keep;
        momentum_lanes_add(lane_flux, lane_visc, s, SOLVER_BACKGROUND(solver), lanes_dot(s.v, e), e,
                           dwv_k, visc_w, v_i, q.v);
    }
    WALL_PAIRS_AFTER_LANES(MOMENTUM_WALL_PAIR)
    vec flux = vec_zero(), visc = vec_zero();
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        flux.c[a] += LANE(lane_flux[a], l);
        visc.c[a] += LANE(lane_visc[a], l);
    }
    const real w_i = vol[i];
    vec force = vec_axpy(vec_scale(flux, R(-2) * w_i), R(2) * mu * w_i, visc);
#        if SPH_FLUID_WALLS
    /* the wall pairs' share of F_i: pressure part, viscous part */
    force = vec_add(force, wall_pairs_force(R(0), wall_flux, wall_visc, w_i, mu, i, n, wall_force));
#        else
    (void)wall_flux;
    (void)wall_visc;
#        endif
    if (!HOLDS_STATE(i)) force = vec_axpy(force, mass[i], gravity_of(prm));
    vec_store(vel_stage, n, i, vec_axpy(v_i, dt / mass[i], force));
}

/* Stage 2: dm_i/dt and d(E w)_i/dt from (rho^n, v', p^n, E^n). */
/* buffers of eulerian_mass_energy_rate: reads step_clock:small row_start:int*n row_walls:int*n
 * nbr_j:int*pairs nbr_count:int*n pair_e:real*d*pairs pair_dwv:real*pairs pair_inv_r:real*pairs
 * rho vel_stage vol pressure energy sound_speed kind normal; writes mass_rate energy_rate */
KERNEL void eulerian_mass_energy_rate(
    ITEM_PARAM const int n, STEP_DT_PARAM, CONSTANT sph_params *prm, PAIR_ROWS_PARAMS,
    GLOBAL const real *restrict pair_e, GLOBAL const real *restrict pair_dwv,
    GLOBAL const real *restrict pair_inv_r, GLOBAL const hreal *restrict rho,
    GLOBAL const real *restrict vel_stage, GLOBAL const real *restrict vol,
    GLOBAL const real *restrict pressure,
    GLOBAL real *restrict mass_rate ENERGY_RATE_PARAMS SOUND_PARAM KIND_PARAMS) {
    STEP_DT_BEGIN;
    (void)dt;
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = ROWS_STRIDE;
    const fluid_solver solver = fluid_solver_make(prm);
    const vec v_i = vec_load(vel_stage, n, i);
    const fluid_point q_i = FLUID_POINT(i, v_i);
    const fluid_point_broadcast q_i_lanes = fluid_point_broadcast_make(q_i);
    /* the fluid pairs' sums in lanes (sph_prelude.h) */
    mass_energy_lanes acc = mass_energy_lanes_zero();
#        if !SPH_HAS_COMPRESSIBLE
    (void)pair_inv_r;
#        endif
#        if SPH_FLUID_KINDS
    (void)normal;
#        endif
    /* a wall particle's rates are never used (the update leaves it alone) */
    const int count = IS_WALL(i) ? 0 : ROW_COUNT(i);
    /* the lanes' pairs: the fluid pairs before the row's walls, which carry
     * no mass */
    const int lanes_end = count > 0 ? count - ROW_WALL_PAIRS(i) : 0;
    for (int k0 = 0; k0 < lanes_end; k0 += SPH_PAIR_LANES) {
        MASS_PASS_INV_R_DECL;
        PAIR_LANES_STATES(MASS_PASS_INV_R, vel_stage, SKIP_WALL_PAIR);
#        if SPH_HAS_COMPRESSIBLE
        const lanes visc_w = dwv * inv_r * keep;
#        else
        const lanes visc_w = lanes_zero();
#        endif
        mass_energy_lanes_add(&acc, s, lanes_dot(s.v, e), dwv * keep, visc_w, v_i, q.v);
    }
    const mass_energy_sums t = mass_energy_lanes_sum(acc);
    const real w_i = vol[i];
    mass_rate[i] = R(-2) * w_i * t.mass;
#        if SPH_HAS_COMPRESSIBLE
    energy_rate[i] = R(-2) * w_i * t.energy + R(2) * prm->materials[0].viscosity * w_i * t.heat;
#        endif
}

#        if !SPH_OPENCL
/* The native backend's two-stage passes sum each fluid pair once (and so
 * do its SSP-RK rate passes, eulerian_rates_pairs).
 *
 * The gather passes above (OpenCL's) solve the Riemann problem of a pair
 * (i, j) twice, once in each particle's row.  Its interface state is the
 * same from both sides (the solvers are symmetric under swapping the sides
 * and reversing e_ij; HLLC's wave speeds S_l = u_l - c_l, S_r = u_r + c_r
 * excepted where they cross, S_l > 0 > S_r: each side then takes its own
 * state, docs/fluids.md), and every term of eq. 14 and eq. 13 is antisymmetric
 * with the symmetric weight w_i w_j dW: the pair's share of particle j's
 * rate is minus its share of particle i's.  So here each fluid pair is in
 * one row only: the row of i holds its fluid pairs with j > i, except
 * those of its block that fill another row's lanes (balance_once_rows),
 * and those handed to it with j < i; padded with empty pairs (j = i, zero
 * geometry) to whole lanes, then its wall pairs, then its far pairs (below;
 * host/backend/cpu/backend_cpu.c, build_once_rows); each is solved once, its terms are
 * added to i's sums in lanes and subtracted from j's sums one by one.
 *
 * Scattering into j races with the row of j on another thread.  The rows
 * are cut into blocks of pair_block consecutive particles, at least as long
 * as the largest j - i of a pair that does not cross a periodic axis; a
 * pair whose j lies past the next block (one across a periodic axis, for
 * instance) is a "far" pair, summed on one thread afterwards.  A block then
 * writes to itself and the next block only, so the even blocks run in
 * parallel, then the odd ones: every sum gets its terms in the same order
 * whatever the number of threads (PAIRS_ONCE_THEN, host/backend/cpu/backend_cpu_kernels.c).
 * The sums of the gather passes come in another order, so the two backends
 * agree to round-off, not bit for bit (tests/test_cross_check: 1e-10).
 * Measured: docs/fluids.md, "Speed on the CPU". */

/* The rows of pairs summed once (host/backend/cpu/backend_cpu.c, build_once_rows), in
 * the names of the packed rows so that ROW_SLOT and the lanes' loads serve
 * both: row i's slots from row_start[i], its j in nbr_j. */
#            define ONCE_ROWS_PARAMS                                                               \
                GLOBAL const int *restrict row_start, GLOBAL const int *restrict nbr_j

/* A once lane's neighbour j.  Weakly compressible, every writer of the
 * pressure stores the equation of state of the density it stores
 * (eulerian_prepare, eulerian_update, eulerian_far_field: p = c0^2 (rho -
 * rho0) of the same double), so the lanes form p_j from rho_j, the same
 * operations on the same value, rather than gather it: one load fewer per
 * pair.  The compressible state is gathered whole. */
#            if SPH_HAS_COMPRESSIBLE
#                define ONCE_POINT(j, v_j) FLUID_POINT(j, v_j)
#                define ONCE_PRESSURE(q_)  (void)0
#            else
#                define ONCE_POINT(j, v_j) fluid_point_make((real)rho[j], R(0), (v_j), R(0), R(0))
#                define ONCE_PRESSURE(q_)                                                          \
                    (q_).p = prm->materials[0].c0 * prm->materials[0].c0 *                         \
                             ((q_).rho - prm->materials[0].rho0)
#            endif

/* A once row's lanes are always whole (build_once_rows pads each part to
 * whole lanes with empty pairs: j = i, zero geometry, whose terms are
 * zeros), so its lanes load their geometry as whole vectors
 * (pair_lanes_geometry with a whole lane's worth left) and gather
 * and scatter every lane without asking which are live: the same
 * operations on the same values as PAIR_LANES_STATES (whose keep is 1 on
 * every lane of a once row), without a branch per lane. */
#            define ONCE_LANES_STATES(inv_r_ptr_, vel_)                                            \
                const int slot0 = ROW_SLOT(i, k0);                                                 \
                lanes_vec e;                                                                       \
                lanes dwv;                                                                         \
                pair_lanes_geometry(pair_e, pair_dwv, pair_inv_r, stride, slot0, SPH_PAIR_LANES,   \
                                    &e, &dwv, (inv_r_ptr_));                                       \
                fluid_point_gather gq;                                                             \
                UNROLL_LANES for (int l = 0; l < SPH_PAIR_LANES; ++l) {                            \
                    const int j = nbr_j[slot0 + l];                                                \
                    fluid_point_gather_set(&gq, l, ONCE_POINT(j, vec_load(vel_, n, j)), R(1));     \
                }                                                                                  \
                lanes keep_unused;                                                                 \
                fluid_point_lanes q = fluid_point_lanes_from(&gq, &keep_unused);                   \
                (void)keep_unused;                                                                 \
                ONCE_PRESSURE(q);                                                                  \
                const fluid_state_lanes s = pair_interface_lanes(solver, q_i, q_i_lanes, q, e)

/* Row i's wall pairs k_end <= k < walls_end of the once rows summed into
 * wall_flux_ and wall_visc_ (momentum_wall_pair). */
#            define ONCE_WALL_PAIRS_SUM(wall_flux_, wall_visc_)                                    \
                for (int k = k_end; k < walls_end; ++k) {                                          \
                    const int slot = ROW_SLOT(i, k);                                               \
                    momentum_wall_pair(solver, q_i, WALL_PAIR_ARGS(slot, nbr_j[slot]),             \
                                       &(wall_flux_), &(wall_visc_));                              \
                }

/* A lane group's momentum terms of the once rows: F_i's share of each pair,
 * -2 w_i [flux - mu (v_i - v_j) / r~] dW w_j (weight = -2 w_i dW w_j). */
FN_HOT void momentum_once_terms(lanes f[SPH_DIM], const lanes weight, const fluid_state_lanes s,
                                const real p_b, const lanes vn, const lanes_vec e, const real mu,
                                const lanes inv_r, const vec v_i, const lanes_vec v_j) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) f[a] =
        weight * (fluid_momentum_flux_lanes(s, vn, e, a, p_b) - mu * inv_r * (v_i.c[a] - v_j.c[a]));
}
#            if SPH_HAS_COMPRESSIBLE
/* ... and the energy term: the energy flux and the pairwise viscous work
 * (eulerian_mass_energy_rate). */
FN_HOT lanes energy_once_term(const lanes weight, const fluid_state_lanes s, const lanes vn,
                              const real mu, const lanes inv_r, const vec v_i,
                              const lanes_vec v_j) {
    lanes_vec dv, v_mean;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) dv.c[a] = v_j.c[a] - v_i.c[a];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) v_mean.c[a] = (v_i.c[a] + v_j.c[a]) * R(0.5);
    return weight * ((s.energy + s.p) * vn + mu * inv_r * lanes_dot(dv, v_mean));
}
#            endif

/* Stage 1 on row i's fluid pairs k_begin <= k < k_end, then its wall pairs
 * k_end <= k < walls_end (none for the far pairs): the momentum rate F into
 * force_sum (i's share, and minus it for each j), the wall pairs' pressure
 * and viscous parts into wall_force (the F of a fixed-state or far-field particle is never
 * used, so it skips its wall pairs; a particle without them keeps the zeros
 * the upload wrote). */
FN_HOT void
eulerian_momentum_pairs(const int i, const int n, const int k_begin, const int k_end,
                        const int walls_end, CONSTANT sph_params *prm, const fluid_solver solver,
                        ONCE_ROWS_PARAMS, GLOBAL const real *restrict pair_e,
                        GLOBAL const real *restrict pair_dwv,
                        GLOBAL const real *restrict pair_inv_r, GLOBAL const hreal *restrict rho,
                        GLOBAL const real *restrict vel, GLOBAL const real *restrict vol,
                        GLOBAL const real *restrict pressure,
                        GLOBAL real *restrict force_sum ENERGY_PARAM SOUND_PARAM FIXED_PARAM
                            KIND_PARAMS WALL_FORCE_PARAM) {
    /* a wall particle's row holds no fluid pair it sums (build_once_rows) */
    if (IS_WALL(i)) return;
    const int stride = ROWS_STRIDE;
    const real mu = prm->materials[0].viscosity;
    const vec v_i = vec_load(vel, n, i);
    const fluid_point q_i = FLUID_POINT(i, v_i);
    const fluid_point_broadcast q_i_lanes = fluid_point_broadcast_make(q_i);
    const real w_i = vol[i];
    lanes lane_force[SPH_DIM];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) lane_force[a] = lanes_zero();
    const int lanes_end = k_end;
    for (int k0 = k_begin; k0 < lanes_end; k0 += SPH_PAIR_LANES) {
        lanes inv_r;
        ONCE_LANES_STATES(&inv_r, vel);
        const lanes vn = lanes_dot(s.v, e);
        /* -2 w_i dW w_j: F_i = -2 w_i sum_j [flux - mu (v_i - v_j) / r~] dW w_j */
        const lanes weight = R(-2) * w_i * dwv;
        lanes f[SPH_DIM];
        momentum_once_terms(f, weight, s, SOLVER_BACKGROUND(solver), vn, e, mu, inv_r, v_i, q.v);
        UNROLL for (int a = 0; a < SPH_DIM; ++a) lane_force[a] += f[a];
        UNROLL_LANES for (int l = 0; l < SPH_PAIR_LANES; ++l) {
            const int j = nbr_j[slot0 + l];
            UNROLL for (int a = 0; a < SPH_DIM; ++a) force_sum[a * n + j] -= LANE(f[a], l);
        }
    }
    vec force = vec_zero();
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) UNROLL for (int a = 0; a < SPH_DIM; ++a)
        force.c[a] += LANE(lane_force[a], l);
    if (walls_end > k_end && !HOLDS_STATE(i)) {
        /* the wall pairs' share of F_i: pressure part, viscous part */
        vec wall_flux = vec_zero(), wall_visc = vec_zero();
        ONCE_WALL_PAIRS_SUM(wall_flux, wall_visc);
        force =
            vec_add(force, wall_pairs_force(R(0), wall_flux, wall_visc, w_i, mu, i, n, wall_force));
    }
    UNROLL for (int a = 0; a < SPH_DIM; ++a) force_sum[a * n + i] += force.c[a];
}

/* Between the stages, per particle: v' = v + dt (F + m g) / m (fixed-state, wall and
 * far-field particles keep v' = v), force_sum zeroed for the next step, and the
 * second stage's sums zeroed. */
FN void eulerian_momentum_stage(const int i, const int n, const real dt, CONSTANT sph_params *prm,
                                GLOBAL const real *restrict vel, GLOBAL const real *restrict mass,
                                GLOBAL real *restrict vel_stage, GLOBAL real *restrict force_sum,
                                GLOBAL real *restrict mass_rate ENERGY_RATE_PARAMS FIXED_PARAM
                                    KIND_PARAMS) {
#            if SPH_FLUID_KINDS
    (void)normal;
#            endif
    vec v = vec_load(vel, n, i);
    if (!HOLDS_STATE(i))
        v = vec_axpy(v, dt / mass[i],
                     vec_axpy(vec_load(force_sum, n, i), mass[i], gravity_of(prm)));
    vec_store(vel_stage, n, i, v);
    vec_store(force_sum, n, i, vec_zero());
    mass_rate[i] = R(0);
#            if SPH_HAS_COMPRESSIBLE
    (void)energy;
    energy_rate[i] = R(0);
#            endif
}

/* Stage 2 on row i's fluid pairs k_begin <= k < k_end (its wall pairs
 * carry no mass): dm/dt and d(E w)/dt, i's share and j's, into the sums
 * eulerian_momentum_stage zeroed. */
FN_HOT void eulerian_mass_energy_pairs(
    const int i, const int n, const int k_begin, const int k_end, const int walls_end,
    CONSTANT sph_params *prm, const fluid_solver solver, ONCE_ROWS_PARAMS,
    GLOBAL const real *restrict pair_e, GLOBAL const real *restrict pair_dwv,
    GLOBAL const real *restrict pair_inv_r, GLOBAL const hreal *restrict rho,
    GLOBAL const real *restrict vel_stage, GLOBAL const real *restrict vol,
    GLOBAL const real *restrict pressure,
    GLOBAL real *restrict mass_rate ENERGY_RATE_PARAMS SOUND_PARAM KIND_PARAMS) {
    (void)walls_end;
    if (IS_WALL(i)) return;
#            if SPH_FLUID_KINDS
    (void)normal;
#            endif
    const int stride = ROWS_STRIDE;
    const vec v_i = vec_load(vel_stage, n, i);
    const fluid_point q_i = FLUID_POINT(i, v_i);
    const fluid_point_broadcast q_i_lanes = fluid_point_broadcast_make(q_i);
    const real w_i = vol[i];
    lanes lane_mass = lanes_zero(), lane_energy = lanes_zero();
#            if SPH_HAS_COMPRESSIBLE
    const real mu = prm->materials[0].viscosity;
#            else
    (void)pair_inv_r;
#            endif
    const int lanes_end = k_end;
    for (int k0 = k_begin; k0 < lanes_end; k0 += SPH_PAIR_LANES) {
        MASS_PASS_INV_R_DECL;
        ONCE_LANES_STATES(MASS_PASS_INV_R, vel_stage);
        const lanes vn = lanes_dot(s.v, e);
        const lanes weight = R(-2) * w_i * dwv;
        const lanes mass_term = weight * (s.rho * vn);
        lane_mass += mass_term;
#            if SPH_HAS_COMPRESSIBLE
        const lanes energy_term = energy_once_term(weight, s, vn, mu, inv_r, v_i, q.v);
        lane_energy += energy_term;
#            else
        const lanes energy_term = lanes_zero();
#            endif
        UNROLL_LANES for (int l = 0; l < SPH_PAIR_LANES; ++l) {
            const int j = nbr_j[slot0 + l];
            mass_rate[j] -= LANE(mass_term, l);
#            if SPH_HAS_COMPRESSIBLE
            energy_rate[j] -= LANE(energy_term, l);
#            endif
        }
        (void)energy_term;
    }
    real mass_sum = R(0), energy_sum = R(0);
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) {
        mass_sum += LANE(lane_mass, l);
        energy_sum += LANE(lane_energy, l);
    }
    mass_rate[i] += mass_sum;
#            if SPH_HAS_COMPRESSIBLE
    energy_rate[i] += energy_sum;
#            else
    (void)energy_sum;
#            endif
}

#        endif /* !SPH_OPENCL */

/* Stage 3, per particle: the conserved variables and the pressure.  The
 * momentum is the conserved one: (m v)^{n+1} = m^n v' (= m^n v^n + dt F),
 * then v^{n+1} = (m v)^{n+1} / m^{n+1} (the public code carries m v
 * itself; keeping v^{n+1} = v' with the new mass would create momentum
 * dt (dm/dt) v every step, and a shock tube's waves would run at the wrong
 * speeds: the Sod tube's star state came out p* = 0.189, u* = 1.21 against
 * the exact 0.303, 0.927). */
/* buffers of eulerian_update: reads step_clock:small vel_stage vol mass_rate energy_rate fixed
 * kind normal; writes rho pressure sound_speed; updates vel mass energy */
KERNEL void eulerian_update(ITEM_PARAM const int n, STEP_DT_PARAM, CONSTANT sph_params *prm,
                            GLOBAL real *restrict vel, GLOBAL const real *restrict vel_stage,
                            GLOBAL real *restrict mass, GLOBAL hreal *restrict rho,
                            GLOBAL const real *restrict vol, GLOBAL real *restrict pressure,
                            GLOBAL const real *restrict mass_rate ENERGY_UPDATE_PARAMS
                                SOUND_OUT_PARAM FIXED_PARAM KIND_PARAMS) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n || HOLDS_STATE(i)) return;
#        if SPH_FLUID_KINDS
    (void)normal;
#        endif
    const real m_old = mass[i];
    const real m = m_old + dt * mass_rate[i];
    const vec v_stage = vec_load(vel_stage, n, i);
#        if SPH_HAS_COMPRESSIBLE
    /* gravity's work over the step, m^n g . (v^n + v') / 2: with no other
     * force, exactly the kinetic energy it adds */
    const real work =
        m_old * R(0.5) * vec_dot(vec_add(vec_load(vel, n, i), v_stage), gravity_of(prm));
#        endif
    const vec v = vec_scale(v_stage, m_old / m);
    vec_store(vel, n, i, v);
    mass[i] = m;
    const real r = m / vol[i];
    rho[i] = (hreal)r;
#        if SPH_HAS_COMPRESSIBLE
    const real e = energy[i] + dt * (energy_rate[i] + work);
    energy[i] = e;
    const real gamma = prm->materials[0].gamma;
    const real p = eos_ideal_gas(e / vol[i], r, v, gamma);
    pressure[i] = p;
    sound_speed[i] = ideal_gas_sound_speed(p, r, gamma);
#        else
    pressure[i] = eos_weakly_compressible(r, prm->materials[0].rho0, prm->materials[0].c0);
#        endif
}

#    endif /* SPH_FLUID_TWO_STAGE */

#    if SPH_FLUID_RK
/* SSP-RK2 and SSP-RK3 (Shu & Osher 1988; time.integrator = "ssp-rk2",
 * "ssp-rk3"), the options to the public code's two stages.  With L(U) the
 * rates of eq. 14 (mass, momentum, energy) from one state U = (m, m v, E w),
 * every stage is U <- a U^n + (1 - a) (U + dt L(U)) from U = U^n:
 *   SSP-RK2: a = 0, 1/2:  U1 = U^n + dt L(U^n),  U^{n+1} = (U^n + U1 + dt L(U1)) / 2;
 *   SSP-RK3: a = 0, 3/4, 1/3:  U2 = 3/4 U^n + 1/4 (U1 + dt L(U1)),
 *            U^{n+1} = 1/3 U^n + 2/3 (U2 + dt L(U2)).
 * Why three: the fluxes of a stream are central (the limited dissipation
 * vanishes with the velocity jump), and a central flux under forward-Euler
 * stages amplifies short waves (the two-stage update by 1 + (u k dt)^2 per
 * step, SSP-RK2 by 1 + (u k dt)^4 / 4); SSP-RK3 damps them (by
 * 1 - (u k dt)^4 / 12 + ...) up to u k dt = sqrt(3).  A density bump carried by
 * a uniform stream grows into noise with the other two (docs/fluids.md).
 * eulerian_rates evaluates L from one state in one pair loop, one Riemann
 * problem per pair, and eulerian_rk_update takes the stage.  The wall force
 * is the step's weighted mean of the stages' (1/2, 1/2; 1/6, 1/6, 2/3: the
 * force the step applies).
 * Fixed-state, wall and far-field particles keep their state. */

/* a of the stage: the weight of U^n in the stage's new state */
FN real rk_weight_of_start(const int stages, const int stage) {
    return stage == 0 ? R(0) : stages == 2 ? R(0.5) : stage == 1 ? R(0.75) : R(1) / R(3);
}

/* the weight that the wall force summed over the earlier stages keeps at
 * this stage (the rest goes to this stage's): 1/2 at stage 1, 1/3 at
 * stage 2 give 1/2, 1/2 and 1/6, 1/6, 2/3 */
FN real rk_force_keep(const int stage) {
    return stage == 0 ? R(0) : stage == 1 ? R(0.5) : R(1) / R(3);
}

/* (a halted clock makes it a no-op, as the update: the substeps the host
 * enqueued past an output time left the stage rates and the wall forces of
 * a state that was not the step's; the time series' forces come from them) */
/* buffers of eulerian_rates: reads step_clock:small row_start:int*n row_walls:int*n
 * nbr_j:int*pairs nbr_count:int*n pair_e:real*d*pairs pair_dwv:real*pairs pair_inv_r:real*pairs
 * rho vel vol pressure energy sound_speed kind normal; writes mass_rate momentum_rate energy_rate;
 * updates wall_force */
KERNEL void eulerian_rates(ITEM_PARAM const int n, const int stage, STEP_DT_PARAM,
                           CONSTANT sph_params *prm, PAIR_ROWS_PARAMS,
                           GLOBAL const real *restrict pair_e, GLOBAL const real *restrict pair_dwv,
                           GLOBAL const real *restrict pair_inv_r, GLOBAL const hreal *restrict rho,
                           GLOBAL const real *restrict vel, GLOBAL const real *restrict vol,
                           GLOBAL const real *restrict pressure, GLOBAL real *restrict mass_rate,
                           GLOBAL real *restrict momentum_rate ENERGY_RATE_PARAMS SOUND_PARAM
                               KIND_PARAMS WALL_FORCE_PARAM) {
    STEP_DT_BEGIN;
    (void)dt;
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = ROWS_STRIDE;
    const real mu = prm->materials[0].viscosity;
    const fluid_solver solver = fluid_solver_make(prm);
    const vec v_i = vec_load(vel, n, i);
    const fluid_point q_i = FLUID_POINT(i, v_i);
    const fluid_point_broadcast q_i_lanes = fluid_point_broadcast_make(q_i);
    /* the fluid pairs' sums in lanes, as the two-stage passes' */
    lanes lane_flux[SPH_DIM], lane_visc[SPH_DIM];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) lane_flux[a] = lane_visc[a] = lanes_zero();
    mass_energy_lanes acc = mass_energy_lanes_zero();
    vec wall_flux = vec_zero(), wall_visc = vec_zero();
    /* a wall particle's rates are never used */
    const int count = IS_WALL(i) ? 0 : ROW_COUNT(i);
    const int lanes_end = count > 0 ? count - ROW_WALL_PAIRS(i) : 0;
    /* a wall pair: as the two-stage passes' (no mass or energy crosses it) */
#        define RATES_WALL_PAIR(slot_, j_)                                                         \
            momentum_wall_pair(solver, q_i, WALL_PAIR_ARGS(slot_, j_), &wall_flux, &wall_visc)
    for (int k0 = 0; k0 < lanes_end; k0 += SPH_PAIR_LANES) {
        lanes inv_r;
        PAIR_LANES_STATES(&inv_r, vel, RATES_WALL_PAIR);
        const lanes dwv_k = dwv * keep, visc_w = dwv * inv_r * keep;
        const lanes vn = lanes_dot(s.v, e);
        momentum_lanes_add(lane_flux, lane_visc, s, SOLVER_BACKGROUND(solver), vn, e, dwv_k, visc_w,
                           v_i, q.v);
        mass_energy_lanes_add(&acc, s, vn, dwv_k, visc_w, v_i, q.v);
    }
    WALL_PAIRS_AFTER_LANES(RATES_WALL_PAIR)
    vec flux = vec_zero(), visc = vec_zero();
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        flux.c[a] += LANE(lane_flux[a], l);
        visc.c[a] += LANE(lane_visc[a], l);
    }
    const mass_energy_sums t = mass_energy_lanes_sum(acc);
    const real w_i = vol[i];
    vec force = vec_axpy(vec_scale(flux, R(-2) * w_i), R(2) * mu * w_i, visc);
#        if SPH_FLUID_WALLS
    force = vec_add(force, wall_pairs_force(rk_force_keep(stage), wall_flux, wall_visc, w_i, mu, i,
                                            n, wall_force));
#        else
    (void)wall_flux;
    (void)wall_visc;
    (void)stage;
#        endif
    vec_store(momentum_rate, n, i, force);
    mass_rate[i] = R(-2) * w_i * t.mass;
#        if SPH_HAS_COMPRESSIBLE
    energy_rate[i] = R(-2) * w_i * t.energy + R(2) * mu * w_i * t.heat;
#        endif
}

/* The stage's update of the conserved variables (see eulerian_rates), then
 * rho = m / w, v = (m v) / m, p by the EOS and the ideal gas's sound speed;
 * state_saved holds U^n between the stages (m, m v, E w). */
/* buffers of eulerian_rk_update: reads step_clock:small vol mass_rate momentum_rate energy_rate
 * fixed kind normal; writes rho pressure sound_speed; updates vel mass state_saved energy */
KERNEL void eulerian_rk_update(ITEM_PARAM const int n, const int stage, const int stages,
                               STEP_DT_PARAM, CONSTANT sph_params *prm, GLOBAL real *restrict vel,
                               GLOBAL real *restrict mass, GLOBAL hreal *restrict rho,
                               GLOBAL const real *restrict vol, GLOBAL real *restrict pressure,
                               GLOBAL const real *restrict mass_rate,
                               GLOBAL const real *restrict momentum_rate,
                               GLOBAL real *restrict state_saved ENERGY_UPDATE_PARAMS
                                   SOUND_OUT_PARAM FIXED_PARAM KIND_PARAMS) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n || HOLDS_STATE(i)) return;
#        if SPH_FLUID_KINDS
    (void)normal;
#        endif
    const real m_old = mass[i];
    const vec mv_old = vec_scale(vec_load(vel, n, i), m_old);
    real m = m_old + dt * mass_rate[i];
    /* the stage's rates with gravity's: m g, and the work m v . g */
    const vec g = gravity_of(prm);
    vec mv = vec_axpy(mv_old, dt, vec_axpy(vec_load(momentum_rate, n, i), m_old, g));
#        if SPH_HAS_COMPRESSIBLE
    real e = energy[i] + dt * (energy_rate[i] + vec_dot(mv_old, g));
#        endif
    if (stage == 0) {
        state_saved[i] = m_old;
        UNROLL for (int a = 0; a < SPH_DIM; ++a) state_saved[(1 + a) * n + i] = mv_old.c[a];
#        if SPH_HAS_COMPRESSIBLE
        state_saved[(1 + SPH_DIM) * n + i] = energy[i];
#        endif
    } else {
        const real a0 = rk_weight_of_start(stages, stage), a1 = R(1) - a0;
        m = a0 * state_saved[i] + a1 * m;
        UNROLL for (int a = 0; a < SPH_DIM; ++a) mv.c[a] =
            a0 * state_saved[(1 + a) * n + i] + a1 * mv.c[a];
#        if SPH_HAS_COMPRESSIBLE
        e = a0 * state_saved[(1 + SPH_DIM) * n + i] + a1 * e;
#        endif
    }
    const vec v = vec_scale(mv, R(1) / m);
    vec_store(vel, n, i, v);
    mass[i] = m;
    const real r = m / vol[i];
    rho[i] = (hreal)r;
#        if SPH_HAS_COMPRESSIBLE
    energy[i] = e;
    const real gamma = prm->materials[0].gamma;
    const real p = eos_ideal_gas(e / vol[i], r, v, gamma);
    pressure[i] = p;
    sound_speed[i] = ideal_gas_sound_speed(p, r, gamma);
#        else
    pressure[i] = eos_weakly_compressible(r, prm->materials[0].rho0, prm->materials[0].c0);
#        endif
}
#        if !SPH_OPENCL
/* SSP-RK's rates (eulerian_rates) from row i's once pairs, as the two
 * stages' passes sum them but of one state: each fluid pair's momentum
 * term (eulerian_momentum_pairs), mass and energy terms
 * (eulerian_mass_energy_pairs) added to i's sums and subtracted from j's;
 * the wall pairs as eulerian_rates' with the stage's weights of the wall
 * force (skipped, as the two stages skip them, where i holds its state).
 * The sums start from the zeros eulerian_rates_zero left. */
FN_HOT void
eulerian_rates_pairs(const int i, const int n, const int k_begin, const int k_end,
                     const int walls_end, const int stage, CONSTANT sph_params *prm,
                     const fluid_solver solver, ONCE_ROWS_PARAMS,
                     GLOBAL const real *restrict pair_e, GLOBAL const real *restrict pair_dwv,
                     GLOBAL const real *restrict pair_inv_r, GLOBAL const hreal *restrict rho,
                     GLOBAL const real *restrict vel, GLOBAL const real *restrict vol,
                     GLOBAL const real *restrict pressure, GLOBAL real *restrict mass_rate,
                     GLOBAL real *restrict momentum_rate ENERGY_RATE_PARAMS SOUND_PARAM FIXED_PARAM
                         KIND_PARAMS WALL_FORCE_PARAM) {
    if (IS_WALL(i)) return;
    const int stride = ROWS_STRIDE;
    const real mu = prm->materials[0].viscosity;
    const vec v_i = vec_load(vel, n, i);
    const fluid_point q_i = FLUID_POINT(i, v_i);
    const fluid_point_broadcast q_i_lanes = fluid_point_broadcast_make(q_i);
    const real w_i = vol[i];
    lanes lane_force[SPH_DIM];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) lane_force[a] = lanes_zero();
    lanes lane_mass = lanes_zero(), lane_energy = lanes_zero();
    const int lanes_end = k_end;
    for (int k0 = k_begin; k0 < lanes_end; k0 += SPH_PAIR_LANES) {
        lanes inv_r;
        ONCE_LANES_STATES(&inv_r, vel);
        const lanes vn = lanes_dot(s.v, e);
        const lanes weight = R(-2) * w_i * dwv;
        lanes f[SPH_DIM];
        momentum_once_terms(f, weight, s, SOLVER_BACKGROUND(solver), vn, e, mu, inv_r, v_i, q.v);
        UNROLL for (int a = 0; a < SPH_DIM; ++a) lane_force[a] += f[a];
        const lanes mass_term = weight * (s.rho * vn);
        lane_mass += mass_term;
#            if SPH_HAS_COMPRESSIBLE
        const lanes energy_term = energy_once_term(weight, s, vn, mu, inv_r, v_i, q.v);
        lane_energy += energy_term;
#            endif
        UNROLL_LANES for (int l = 0; l < SPH_PAIR_LANES; ++l) {
            const int j = nbr_j[slot0 + l];
            UNROLL for (int a = 0; a < SPH_DIM; ++a) momentum_rate[a * n + j] -= LANE(f[a], l);
            mass_rate[j] -= LANE(mass_term, l);
#            if SPH_HAS_COMPRESSIBLE
            energy_rate[j] -= LANE(energy_term, l);
#            endif
        }
    }
    vec force = vec_zero();
    real mass_sum = R(0), energy_sum = R(0);
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) {
        UNROLL for (int a = 0; a < SPH_DIM; ++a) force.c[a] += LANE(lane_force[a], l);
        mass_sum += LANE(lane_mass, l);
        energy_sum += LANE(lane_energy, l);
    }
    if (walls_end > k_end && !HOLDS_STATE(i)) {
        vec wall_flux = vec_zero(), wall_visc = vec_zero();
        ONCE_WALL_PAIRS_SUM(wall_flux, wall_visc);
        force = vec_add(force, wall_pairs_force(rk_force_keep(stage), wall_flux, wall_visc, w_i, mu,
                                                i, n, wall_force));
    }
    UNROLL for (int a = 0; a < SPH_DIM; ++a) momentum_rate[a * n + i] += force.c[a];
    mass_rate[i] += mass_sum;
#            if SPH_HAS_COMPRESSIBLE
    energy_rate[i] += energy_sum;
#            else
    (void)energy_sum;
    (void)lane_energy;
#            endif
}

/* After a stage's update of particle i (eulerian_rk_update read its
 * rates): the zeros the next stage's eulerian_rates_pairs sums into. */
FN void eulerian_rates_zero(const int i, const int n, GLOBAL real *restrict mass_rate,
                            GLOBAL real *restrict momentum_rate ENERGY_RATE_PARAMS) {
    mass_rate[i] = R(0);
    vec_store(momentum_rate, n, i, vec_zero());
#            if SPH_HAS_COMPRESSIBLE
    (void)energy;
    energy_rate[i] = R(0);
#            endif
}
#        endif /* !SPH_OPENCL */
#    endif

#    if SPH_FAR_FIELD
/* The far field (the public code's NonReflectiveBoundaryCorrection,
 * eulerian-sph-reference.md §4), at the start and after every step: each
 * far-field particle (within 2h of a far-field face) is blended toward the
 * free stream (rho_inf, U_inf) by the kernel weight S = sum_j W_ij w_j of
 * its interior fluid neighbours j:
 *   rho = S rhobar + (1 - S) rho_inf,   v_n = S vbar_n + (1 - S) U_inf . n,
 * with plain means rhobar, vbar over those neighbours; the tangential
 * velocity is the free stream's on inflow faces and the neighbours' mean on
 * outflow faces; p by the EOS, m = rho w.  The ideal gas (compressible)
 * blends its pressure as its density, p = S pbar + (1 - S) p_inf, the
 * subsonic treatment (the scene refuses |U_inf| >= c_inf), and its total
 * energy and sound speed follow from the blended state.  It reads interior
 * particles only and writes far-field ones only: race-free. */
/* S_i = sum_j W_ij w_j over far-field particle i's interior fluid
 * neighbours j: positions, volumes and kinds are frozen, so the native
 * backend forms it once (fluid setup) and blends with it every step (the
 * pass with a kernel, an exp, per pair and step was 2-4 % of the cylinder's
 * run); OpenCL forms it in the step (eulerian_far_field). */
FN real far_field_weight(const int i, const int n, CONSTANT sph_params *prm, PAIR_ROWS_PARAMS,
                         GLOBAL const hreal *restrict pos,
                         GLOBAL const real *restrict vol KIND_PARAMS) {
    ROW_WALLS_UNUSED;
#        if SPH_FLUID_KINDS
    (void)normal;
#        endif
    real weight = R(0);
    const int count_i = ROW_COUNT(i);
    for (int k = 0; k < count_i; ++k) {
        const int j = nbr_j[ROW_SLOT(i, k)];
        if (KIND_OF(j) != SPH_PARTICLE_FLUID) continue;
        const vec d = periodic_image(prm, hvec_diff(pos, n, i, j));
        weight += kernel_w(prm, sqrt(vec_dot(d, d))) * vol[j];
    }
    return weight;
}

/* Far-field particle i's blend with its weight S_i (far_field_weight). */
FN void
far_field_blend(const int i, const int n, CONSTANT sph_params *prm, PAIR_ROWS_PARAMS,
                const real weight, GLOBAL hreal *restrict rho, GLOBAL real *restrict vel,
                GLOBAL real *restrict mass, GLOBAL const real *restrict vol,
                GLOBAL real *restrict pressure ENERGY_OUT_PARAM SOUND_OUT_PARAM KIND_PARAMS) {
    ROW_WALLS_UNUSED;
    const int kind_i = KIND_OF(i);
    real rho_sum = R(0), p_sum = R(0);
    vec v_sum = vec_zero();
    int count = 0;
    const int count_i = ROW_COUNT(i);
    for (int k = 0; k < count_i; ++k) {
        const int j = nbr_j[ROW_SLOT(i, k)];
        if (KIND_OF(j) != SPH_PARTICLE_FLUID) continue;
        rho_sum += (real)rho[j];
#        if SPH_HAS_COMPRESSIBLE
        p_sum += pressure[j];
#        endif
        v_sum = vec_add(v_sum, vec_load(vel, n, j));
        ++count;
    }
    (void)p_sum; /* WC: the pressure follows from the blended density */
    vec u_inf;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) u_inf.c[a] = prm->far_field_velocity[a];
    const real rho_inf = prm->far_field_density;
    const vec nrm = vec_load(normal, n, i);
    const real s = count > 0 ? weight : R(0);
    const real rho_bar = count > 0 ? rho_sum / (real)count : rho_inf;
    const vec v_bar = count > 0 ? vec_scale(v_sum, R(1) / (real)count) : u_inf;
    const real r = s * rho_bar + (R(1) - s) * rho_inf;
    const real vn = s * vec_dot(v_bar, nrm) + (R(1) - s) * vec_dot(u_inf, nrm);
    const vec tangential_of = kind_i == SPH_PARTICLE_INFLOW ? u_inf : v_bar;
    const vec tangential = vec_axpy(tangential_of, -vec_dot(tangential_of, nrm), nrm);
    const vec v = vec_axpy(tangential, vn, nrm);
    vec_store(vel, n, i, v);
    rho[i] = (hreal)r;
    mass[i] = r * vol[i];
#        if SPH_HAS_COMPRESSIBLE
    /* the ideal gas: its pressure blended as its density, with the plain
     * mean p-bar, toward p_inf; the total energy and sound speed follow
     * from the blended state, as eulerian_prepare forms them */
    const real p_bar = count > 0 ? p_sum / (real)count : prm->far_field_pressure;
    const real p = s * p_bar + (R(1) - s) * prm->far_field_pressure;
    const real gamma = prm->materials[0].gamma;
    pressure[i] = p;
    energy[i] = vol[i] * ideal_gas_energy(p, r, v, gamma);
    sound_speed[i] = ideal_gas_sound_speed(p, r, gamma);
#        else
    pressure[i] = eos_weakly_compressible(r, prm->materials[0].rho0, prm->materials[0].c0);
#        endif
}

/* buffers of eulerian_far_field: reads row_start:int*n row_walls:int*n nbr_j:int*pairs
 * nbr_count:int*n pos vol kind normal; writes energy sound_speed; updates rho vel mass
 * pressure */
KERNEL void
eulerian_far_field(ITEM_PARAM const int n, CONSTANT sph_params *prm, PAIR_ROWS_PARAMS,
                   GLOBAL const hreal *restrict pos, GLOBAL hreal *restrict rho,
                   GLOBAL real *restrict vel, GLOBAL real *restrict mass,
                   GLOBAL const real *restrict vol,
                   GLOBAL real *restrict pressure ENERGY_OUT_PARAM SOUND_OUT_PARAM KIND_PARAMS) {
    const int i = ITEM_ID;
    if (i >= n) return;
    if (!IS_FAR_FIELD(i)) return;
    const real weight = far_field_weight(i, n, prm, PAIR_ROWS_ARGS, pos, vol KIND_ARGS);
    far_field_blend(i, n, prm, PAIR_ROWS_ARGS, weight, rho, vel, mass, vol,
                    pressure ENERGY_ARG SOUND_ARG KIND_ARGS);
}
#    endif

#    if SPH_DIM > 1 && SPH_FLUID_VORTICITY
/* The vorticity of the current state, for a snapshot (the steps do not
 * form it): curl v_i = sum_j g_ij x (v_j - v_i), g_ij = grad'W_ij w_j
 * (e_ij dW w_j of the stored, corrected pairs), in 2D its z component, in
 * 3D all three; a wall neighbour at rest (v_j = 0), a wall particle's 0.
 * Run when the snapshot downloads the field, so it is the curl of the
 * velocity written beside it. */
/* buffers of eulerian_vorticity: reads row_start:int*n row_walls:int*n nbr_j:int*pairs
 * nbr_count:int*n pair_e:real*d*pairs pair_dwv:real*pairs vel kind normal; writes vorticity */
KERNEL void eulerian_vorticity(ITEM_PARAM const int n, PAIR_ROWS_PARAMS,
                               GLOBAL const real *restrict pair_e,
                               GLOBAL const real *restrict pair_dwv,
                               GLOBAL const real *restrict vel,
                               GLOBAL real *restrict vorticity KIND_PARAMS) {
    const int i = ITEM_ID;
    if (i >= n) return;
    ROW_WALLS_UNUSED;
#        if SPH_FLUID_KINDS
    (void)normal;
#        endif
    const int stride = ROWS_STRIDE;
    const vec v_i = vec_load(vel, n, i);
    vec curl = vec_zero();
    const int count = IS_WALL(i) ? 0 : ROW_COUNT(i);
    for (int k = 0; k < count; ++k) {
        const int slot = ROW_SLOT(i, k), j = nbr_j[slot];
        vec g;
        UNROLL for (int a = 0; a < SPH_DIM; ++a) g.c[a] =
            pair_e[a * stride + slot] * pair_dwv[slot];
        const vec v_j = IS_WALL(j) ? vec_zero() : vec_load(vel, n, j);
        curl = curl_add(curl, g, vec_sub(v_j, v_i));
    }
    UNROLL for (int a = 0; a < NSPIN; ++a) vorticity[a * n + i] = curl.c[a];
}
#    endif

/* The step clock's speed (sph_step_clock.h: dt = CFL h / (C0 + sqrt of
 * this)): WC |v|^2 with C0 = c0; compressible (c + |v|)^2 with C0 = 0, the
 * sound speed being the particle's own.  A non-finite state, a density
 * <= 0 or (compressible) a pressure <= 0 gives +inf: the host stops the run
 * and names the particle (host/run/instability.c).  The one exception is a
 * wall particle of the ideal gas, at rest with p = 0 exactly
 * (host/setup/particles.c): it carries no gas state (no pair reads it) and
 * no signal, 0. */
FN real eulerian_signal_speed2(CONSTANT sph_params *prm, const real rho, const real p,
                               const vec v) {
    const real v2 = vec_dot(v, v);
#    if SPH_HAS_COMPRESSIBLE
    if (p == R(0) && v2 == R(0) && rho > R(0)) return R(0);
    if (!(rho > R(0)) || !(p > R(0))) return INFINITY;
    const real s = ideal_gas_sound_speed(p, rho, prm->materials[0].gamma) + sqrt(v2);
    return isfinite(s) ? s * s : INFINITY;
#    else
    (void)prm;
    (void)p;
    if (!(rho > R(0))) return INFINITY;
    return isfinite(v2) ? v2 : INFINITY;
#    endif
}

/* Diagnostics, all by sum: kinetic energy, internal energy (the "strain"
 * slot: compressible E w - m |v|^2/2; WC the acoustic potential energy
 * w p^2 / (2 rho0 c0^2)), momentum (d), angular momentum (1 or 3), mass,
 * total energy. */
FN void eulerian_diagnostics_contrib(const int i, const int n, CONSTANT sph_params *prm,
                                     GLOBAL const hreal *pos, GLOBAL const real *vel,
                                     GLOBAL const real *mass, GLOBAL const real *vol,
                                     GLOBAL const real *pressure, GLOBAL const real *energy,
                                     GLOBAL const real *wall_force, real *c) {
    const vec x = hvec_load(pos, n, i), v = vec_load(vel, n, i);
    const real m = mass[i];
    const real kinetic = R(0.5) * m * vec_dot(v, v);
#    if SPH_HAS_COMPRESSIBLE
    (void)prm;
    (void)vol;
    (void)pressure;
    const real total = energy[i];
    const real internal = total - kinetic;
#    else
    (void)energy;
    const real c0 = prm->materials[0].c0;
    const real internal =
        vol[i] * pressure[i] * pressure[i] / (R(2) * prm->materials[0].rho0 * c0 * c0);
    const real total = kinetic + internal;
#    endif
    c[0] = kinetic;
    c[1] = internal;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) c[2 + a] = m * v.c[a];
#    if SPH_DIM == 1
    (void)x; /* a line has no angular momentum */
#    elif SPH_DIM == 2
    c[2 + SPH_DIM] = m * (x.c[0] * v.c[1] - x.c[1] * v.c[0]);
#    else
    c[2 + SPH_DIM + 0] = m * (x.c[1] * v.c[2] - x.c[2] * v.c[1]);
    c[2 + SPH_DIM + 1] = m * (x.c[2] * v.c[0] - x.c[0] * v.c[2]);
    c[2 + SPH_DIM + 2] = m * (x.c[0] * v.c[1] - x.c[1] * v.c[0]);
#    endif
    c[2 + SPH_DIM + NSPIN] = m;
    c[3 + SPH_DIM + NSPIN] = total;
#    if SPH_FLUID_WALLS
    /* then the wall pairs' shares of F (pressure d, viscous d): the force on
     * the walls is minus their sum */
    UNROLL for (int a = 0; a < 2 * SPH_DIM; ++a) c[4 + SPH_DIM + NSPIN + a] =
        PRESENT(wall_force) ? wall_force[a * n + i] : R(0);
#    else
    (void)wall_force;
#    endif
}

#endif
#endif
