/* acoustic_step.cl — one acoustic substep of the position-Verlet scheme.
 *
 * 000 eqs. 27-29 with the order of operations of the reference code
 * (reference notes §3.8), fused into two neighbour passes:
 *
 *  acoustic_contact (per particle i; scenes with several bodies only)
 *    a^diss += contact acceleration at the half-step positions
 *    x^{n+1/2} = x^n + dt/2 v^n of the pair (sph_contact.h);
 *
 *  acoustic_pressure (per particle i)
 *    rho^{n+1/2} = rho^n + dt/2 drho^n and p = c0^2 (rho - rho0), evaluated
 *    on the fly for i and every neighbour j (no extra pass over memory);
 *    a^s <- Rbar (a^s + da^s) for SPH-ENOG-A (003 eqs. 41-42, with Rbar and
 *    da^s from the previous substep, see below);
 *    v^{n+1} = v^n + dt [a^p + a^diss + a^s + g]   (000 eq. 28, 003 eq. 16),
 *    plus the rigid walls' contact at x^n + dt/2 v^n (sph_wall.h);
 *    constraints: prescribed v (0: clamp, roller) along the constrained
 *    axes, x <- x + dt v there (sph_constraints.h);
 *    x^{n+1} = x^n + dt/2 (v^n + v^{n+1})          (000 eqs. 27, 29).
 *
 *  acoustic_velocity_terms (per particle i), all from the new velocities:
 *    continuity drho/dt = rho sum u_ij dW V_j        (003 eq. 15),
 *      plus the rigid walls' mirror images (sph_wall.h),
 *    rho^{n+1} = rho^{n+1/2} + dt/2 drho^{n+1}       (000 eq. 29; in single
 *      precision summed as in density_advance, sph_elasticity.h),
 *    Riemann dissipation acceleration for the next update (sph_riemann.h),
 *    velocity gradient with the kernel-gradient correction (003 eq. 20),
 *    Jaumann update of the shear stress (003 eq. 8),
 *    ENOG shear-acceleration increment
 *      da^s = dt 2 xi_E G / rho sum (e.v_ij / r) dW V_j e   (000 eq. 24,
 *      003 eqs. 25-28), rotated as selected by SPH_ROTATION.
 *
 * Between the two passes neighbours only read what the other pass writes, so
 * each pass is race-free without atomics.  The pair geometry (e_ij, dW V_j,
 * 1/r) is the one frozen at the last configuration rebuild.
 */
#include "sph_vec.h"
#include "sph_riemann.h"
#include "sph_rotation.h"
#include "sph_elasticity.h"
#include "sph_materials.h"
#include "sph_plasticity.h"
#include "sph_artificial_stress.h"
#include "sph_smoothing_kernel.h"
#include "sph_constraints.h"
#include "sph_contact.h"
#include "sph_wall.h"
#include "sph_pair_geometry.h"
#include "sph_torque_projection.h"

/* The optional parameters of the kernels below, by feature; each X_PARAMS
 * has its X_ARGS, the same names for a call (the substep loop's,
 * substep_loop.cl). */
#if SPH_HAS_ROTATION_AVG
#    define ROTATION_AVG_PARAMS                                                                    \
        , GLOBAL const real *restrict dacc_shear, GLOBAL const real *restrict substep_sums
#    define ROTATION_AVG_SPIN_PARAMS , GLOBAL real *restrict dacc_shear, GLOBAL real *restrict spin
#    define ROTATION_AVG_ARGS        , dacc_shear, substep_sums
#    define ROTATION_AVG_SPIN_ARGS   , dacc_shear, spin
#else
#    define ROTATION_AVG_PARAMS
#    define ROTATION_AVG_SPIN_PARAMS
#    define ROTATION_AVG_ARGS
#    define ROTATION_AVG_SPIN_ARGS
#endif
#if SPH_HAS_BODY_IDS
#    define BODY_PARAMS , GLOBAL const u8 *restrict body
#    define BODY_ARGS   , body
#    define BODY_OF(i)  (PRESENT(body) ? (int)body[i] : 0)
#else
#    define BODY_PARAMS
#    define BODY_ARGS
#    define BODY_OF(i) 0
#endif
#if SPH_HAS_CLAMP
#    define CLAMP_PARAMS , GLOBAL const u8 *restrict fixed
#    define CLAMP_ARGS   , fixed
#    define CLAMP_ARG    fixed
#else
#    define CLAMP_PARAMS
#    define CLAMP_ARGS
#    define CLAMP_ARG 0
#endif
/* buffers of the stress-divergence formulations (OG, OAS, GNOG, GNOG-A) */
#if SPH_HAS_STRESS_DIV
#    define STRESS_DIV_PARAMS , GLOBAL const real *restrict acc_stress
#    define STRESS_DIV_ARGS   , acc_stress
#else
#    define STRESS_DIV_PARAMS
#    define STRESS_DIV_ARGS
#endif
#if SPH_HAS_PENALTY
#    define GRADV_OUT_PARAMS , GLOBAL real *restrict gradv
#    define GRADV_OUT_ARGS   , gradv
#else
#    define GRADV_OUT_PARAMS
#    define GRADV_OUT_ARGS
#endif
#if SPH_HAS_ART_STRESS
#    define ART_OUT_PARAMS , GLOBAL real *restrict art_stress
#    define ART_OUT_ARGS   , art_stress
#else
#    define ART_OUT_PARAMS
#    define ART_OUT_ARGS
#endif
#if SPH_HAS_WALLS
#    define WALL_POS_PARAMS , GLOBAL const hreal *restrict pos
#    define WALL_POS_ARGS   , pos
#else
#    define WALL_POS_PARAMS
#    define WALL_POS_ARGS
#endif
#if SPH_HAS_PLASTICITY
#    define PLASTIC_OUT_PARAMS                                                                     \
        , GLOBAL real *restrict plastic_strain, GLOBAL real *restrict penalty_scale
#    define PLASTIC_OUT_ARGS , plastic_strain, penalty_scale
#else
#    define PLASTIC_OUT_PARAMS
#    define PLASTIC_OUT_ARGS
#endif

/* Mean rotation of body b from the summed Rodrigues matrices (003 eq. 41). */
FN mat mean_rotation(CONSTANT sph_params *prm, GLOBAL const real *restrict substep_sums,
                     const int b) {
    mat r;
    const real inv_count = R(1) / prm->body_count[b];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int c = 0; c < SPH_DIM; ++c) r.m[a][c] =
        substep_sums[1 + (b * SPH_DIM + a) * SPH_DIM + c] * inv_count;
    return r;
}

#if SPH_HAS_ROTATION_AVG
#    define DACC_ARG dacc_shear
#else
#    define DACC_ARG 0
#endif
/* Add this substep's increment da to an accumulated acceleration a (the
 * ENOG shear acceleration, 000 eq. 24, or the GNOG penalty, 003 eq. 47):
 * a += da unrotated; a = R_i a + da with the particle's own Rodrigues matrix
 * (003 eq. 34); or, averaged, da waits in dacc for R-bar, applied as
 * a = R-bar (a + da) at the next acoustic_pressure (003 eqs. 41-42). */
FN void accumulate_increment(GLOBAL hreal *restrict acc, GLOBAL real *restrict dacc, const int n,
                             const int i, const vec da, const mat grad_v, const int rotation,
                             const real dt) {
    if (rotation == ROTATION_NONE) {
        hvec_add_store(acc, n, i, da);
    } else if (rotation == ROTATION_PER_PARTICLE) {
        hvec_rotate(acc, n, i, rodrigues(spin_of(grad_v), dt), vec_zero(), da);
    } else if (PRESENT(dacc)) {
        vec_store(dacc, n, i, da);
    }
}

#if SPH_HAS_CONTACT
/* Contact between bodies (sph_contact.h), before the velocity update: the
 * force at the half-step positions, as position Verlet evaluates a force of
 * the positions (000 eqs. 27-29), added to the dissipation acceleration the
 * update applies.  Reads positions and velocities only, so it runs
 * race-free before acoustic_pressure moves them. */
/* buffers of acoustic_contact: reads step_clock:small nbr_j:int*pairs contact_count pos vel mass
 * vol material; updates acc_diss */
KERNEL void acoustic_contact(ITEM_PARAM const int n, const int cap, STEP_DT_PARAM,
                             CONSTANT sph_params *prm, GLOBAL const int *restrict nbr_j,
                             GLOBAL const int *restrict contact_count,
                             GLOBAL const hreal *restrict pos, GLOBAL const real *restrict vel,
                             GLOBAL const real *restrict mass, GLOBAL const real *restrict vol,
                             GLOBAL real *restrict acc_diss MATERIAL_PARAMS) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n || contact_count[i] == 0) return;
    const vec a = contact_acceleration(i, n, cap, R(0.5) * dt, prm, nbr_j, contact_count, pos, vel,
                                       mass, vol MATERIAL_ARG);
    vec_store(acc_diss, n, i, vec_add(vec_load(acc_diss, n, i), a));
}
#endif

/* acoustic_pressure's neighbour sum, e_ij (-(p_i + p_j) dW V_j) in
 * SPH_PAIR_LANES lanes (sph_prelude.h; see acoustic_velocity_terms) with
 * its factor, RIEMANN_PRESSURE_FACTOR (sph_riemann.h).  `vary`: read each
 * neighbour's material row (several materials); else every neighbour's is
 * row 0. */
FN_HOT vec pressure_pair_sum(const int i, const int n, const int cap, const real half_dt,
                             const real p_i, const bool vary, CONSTANT sph_params *prm,
                             GLOBAL const int *restrict nbr_count, GLOBAL const int *restrict nbr_j,
                             PAIR_DIR_PARAMS, GLOBAL const real *restrict vol,
                             GLOBAL const hreal *restrict rho,
                             GLOBAL const real *restrict drho MATERIAL_PARAMS) {
    const int stride = n * cap; /* the stored pair arrays (PAIR_DIR) */
    (void)stride;
    (void)vol; /* the recomputed geometry's */
    (void)vary;
    CONSTANT sph_params_material *row0 = MATERIAL_ROW(0);
    lanes lane_sum[SPH_DIM];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) lane_sum[a] = lanes_zero();
    const int count = nbr_count[i];
    for (int k0 = 0; k0 < count; k0 += SPH_PAIR_LANES) {
        lanes e[SPH_DIM], dwv = lanes_zero(), p_j = lanes_zero();
        UNROLL for (int a = 0; a < SPH_DIM; ++a) e[a] = lanes_zero();
#if PAIR_LANES_DIRECT
        if (k0 + SPH_PAIR_LANES <= count) {
            const int slot = NBR_AT(i, k0);
            dwv = lanes_load(pair_dwv + slot);
            UNROLL for (int a = 0; a < SPH_DIM; ++a) e[a] = lanes_load(pair_e + a * stride + slot);
            UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) {
                const int j = nbr_j[slot + l];
                LANE(p_j, l) = half_step_pressure(vary ? MATERIAL_ROW(MATERIAL_OF(j)) : row0,
                                                  rho[j], drho[j], half_dt);
            }
        } else
#endif
            UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) {
                int j;
                const int slot = lane_pair(nbr_j, n, cap, i, k0 + l, count, &j);
                LANE(p_j, l) = half_step_pressure(vary ? MATERIAL_ROW(MATERIAL_OF(j)) : row0,
                                                  rho[j], drho[j], half_dt);
                lane_set_geometry(PAIR_DIR(slot, j), k0 + l < count, l, e, &dwv, 0);
            }
        const lanes f = RIEMANN_PRESSURE_FACTOR(p_i, p_j, dwv);
        UNROLL for (int a = 0; a < SPH_DIM; ++a) lane_sum[a] += e[a] * f;
    }
    vec sum = vec_zero();
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) UNROLL for (int a = 0; a < SPH_DIM; ++a)
        sum.c[a] += LANE(lane_sum[a], l);
    return sum;
}

/* buffers of acoustic_pressure: reads step_clock:small nbr_count:int*n nbr_j:int*pairs
 * pair_pos:hreal*d*n pair_e:real*d*pairs pair_dwv:real*pairs rho drho mass vol acc_diss
 * dacc_shear substep_sums:small body fixed acc_stress material; updates acc_shear pos vel */
KERNEL void acoustic_pressure(ITEM_PARAM const int n, const int cap, STEP_DT_PARAM,
                              CONSTANT sph_params *prm, GLOBAL const int *restrict nbr_count,
                              GLOBAL const int *restrict nbr_j, PAIR_DIR_PARAMS,
                              GLOBAL const hreal *restrict rho, GLOBAL const real *restrict drho,
                              GLOBAL const real *restrict mass, GLOBAL const real *restrict vol,
                              GLOBAL const real *restrict acc_diss,
                              GLOBAL hreal *restrict acc_shear, GLOBAL hreal *restrict pos,
                              GLOBAL real *restrict vel ROTATION_AVG_PARAMS BODY_PARAMS CLAMP_PARAMS
                                  STRESS_DIV_PARAMS MATERIAL_PARAMS) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = n * cap; /* the stored pair arrays (PAIR_DIR, PAIR_GEOMETRY) */
    (void)stride;
    const real half_dt = R(0.5) * dt;
    CONSTANT sph_params_material *mat_i = MATERIAL_ROW(MATERIAL_OF(i));
    const real p_i = half_step_pressure(mat_i, rho[i], drho[i], half_dt);

    /* a one-material run's lanes are those of a program without material
     * ids: `vary` is a constant of each inlined copy */
    const vec sum = MATERIALS_VARY
                        ? pressure_pair_sum(i, n, cap, half_dt, p_i, true, prm, nbr_count, nbr_j,
                                            PAIR_DIR_ARGS, vol, rho, drho MATERIAL_ARG)
                        : pressure_pair_sum(i, n, cap, half_dt, p_i, false, prm, nbr_count, nbr_j,
                                            PAIR_DIR_ARGS, vol, rho, drho MATERIAL_ARG);
    const vec a_p = vec_add(vec_scale(sum, vol[i] / mass[i]), vec_load(acc_diss, n, i));

    vec a_s = hvec_load(acc_shear, n, i);
#if SPH_HAS_ROTATION_AVG
    /* the body's mean rotation over the last substep (reduction.cl), which
     * turns both the accumulated acceleration and the stress divergence */
    const bool averaged = RUNTIME_ROTATION == ROTATION_AVERAGED && PRESENT(dacc_shear);
    const mat rbar = averaged ? mean_rotation(prm, substep_sums, BODY_OF(i)) : mat_identity();
    if (averaged) {
        /* 003 eq. 42 with the increment placed in the current configuration:
         * da^s was summed over the pair geometry frozen at the last rebuild,
         * one acoustic step before the configuration this update acts in, so
         * the step's mean rotation carries it along with the accumulated sum:
         * a^s <- Rbar (a^s + da^s).  On the spinning plate (CFL 0.1, the
         * geometry frozen at the start of the step) this gave a maximum
         * angular-momentum error of 2.54 % (paper: 2.58 %) against 3.12 % with
         * da^s added after the rotation, the difference being the one-step
         * lag of the increment; 1.05 % with the mid-interval geometry
         * (docs/method.md, "SPH-ENOG-A rotation"). */
        vec post = vec_zero();
#    if SPH_HAS_TORQUE_PROJECTION
        if (RUNTIME_TORQUE_PROJECTION) {
            /* less the rigid field that carries the turned sum's net torque
             * at this substep's kick positions (sph_torque_projection.h);
             * alpha and c are the body's, formed here from its sums as
             * Rbar is by mean_rotation */
            real alpha[NSPIN];
            vec centre;
            torque_field(substep_sums + torque_offset(prm, BODY_OF(i)), rbar, dt, alpha, &centre);
            const vec x_half = vec_axpy(hvec_load(pos, n, i), half_dt, vec_load(vel, n, i));
            post = vec_scale(torque_field_at(alpha, centre, x_half), R(-1));
        }
#    endif
        a_s = hvec_rotate(acc_shear, n, i, rbar, vec_load(dacc_shear, n, i), post);
    }
#endif

#if SPH_HAS_STRESS_DIV
    /* stress divergence of the last substep (000 eq. 17, 003 eq. 45) */
    if (PRESENT(acc_stress)) {
        /* computed after the last velocity update in that substep's
         * configuration, it acts one step later: with the averaged rotation
         * it turns with the body by Rbar, as the accumulated penalty does.
         * Unturned, the one-step lag tilts a spinning solid's centripetal
         * shear forces forward and spins it up: on the spinning cube
         * (nu = 0.3) SPH-GNOG-A's angular momentum grew 0.37 % in 0.1 s,
         * 0.025 % with the turn. */
        vec a_sigma = vec_load(acc_stress, n, i);
#    if SPH_HAS_ROTATION_AVG
        if (averaged) a_sigma = mat_vec(rbar, a_sigma);
#    endif
        a_s = vec_add(a_s, a_sigma);
    }
#endif
#if SPH_HAS_WALLS
    /* rigid walls at the half-step position (sph_wall.h) */
    if (prm->nwalls > 0) {
        const vec v_i = vec_load(vel, n, i);
        const vec x_half = vec_axpy(hvec_load(pos, n, i), half_dt, v_i);
        a_s = vec_add(a_s, wall_acceleration(prm, mat_i, x_half, v_i, p_i, vol[i] / mass[i]));
    }
#endif
    verlet_advance(prm, n, i, dt, vec_add(a_p, a_s), pos, vel, CLAMP_ARG);
}

#if SPH_HAS_MATERIAL_IDS
/* The two-material corrections of acoustic_velocity_terms' sums: for each
 * neighbour j of another material than i, dissipation += (ratio_Z
 * beta(c_ij) - beta(c_i)) u dW V_j e_ij and laplacian += (ratio_G - 1)
 * u dW V_j / r e_ij, which turn the one-material pair terms the lanes summed
 * into the pair's two-material ones (sph_materials.h). */
FN void interface_velocity_terms(const int i, const int n, const int cap, CONSTANT sph_params *prm,
                                 GLOBAL const int *restrict nbr_count,
                                 GLOBAL const int *restrict nbr_j, PAIR_GEOMETRY_PARAMS,
                                 GLOBAL const real *restrict vel, GLOBAL const real *restrict vol,
                                 GLOBAL const u8 *restrict material, vec *dissipation,
                                 vec *laplacian) {
    const int stride = n * cap; /* the stored pair arrays (PAIR_GEOMETRY) */
    (void)stride;
    (void)vol; /* the recomputed geometry's */
    const int m_i = material[i];
    CONSTANT sph_params_material *mat_i = MATERIAL_ROW(m_i);
    const real slope = prm->riemann_limit;
    const vec v_i = vec_load(vel, n, i);
    const int count = nbr_count[i];
    for (int k = 0; k < count; ++k) {
        const int slot = NBR_AT(i, k);
        const int j = nbr_j[slot];
        if ((int)material[j] == m_i) continue;
        CONSTANT sph_params_material *mat_j = MATERIAL_ROW(material[j]);
        const pair_geometry g = PAIR_GEOMETRY(slot, j);
        const real u = vec_dot(vec_sub(v_i, vec_load(vel, n, j)), g.e);
        const real u_dwv = RIEMANN_CONTINUITY_FACTOR(u, g.dwv);
        const real own = riemann_dissipation_factor(u, mat_i->c0, slope, g.dwv);
        const real pair =
            riemann_dissipation_factor(u, R(0.5) * (mat_i->c0 + mat_j->c0), slope, g.dwv) *
            impedance_ratio(mat_i, mat_j);
        *dissipation = vec_axpy(*dissipation, pair - own, g.e);
        *laplacian = vec_axpy(*laplacian,
                              (harmonic_ratio(mat_i->shear_modulus, mat_j->shear_modulus) - R(1)) *
                                  u_dwv * g.inv_r,
                              g.e);
    }
}
#endif

/* buffers of acoustic_velocity_terms: reads step_clock:small nbr_count:int*n nbr_j:int*pairs
 * pair_pos:hreal*d*n pair_e:real*d*pairs pair_dwv:real*pairs pair_inv_r:real*pairs vel mass vol
 * bmat pos material; writes acc_diss dacc_shear spin gradv art_stress penalty_scale; updates rho
 * drho tau acc_shear plastic_strain */
KERNEL void acoustic_velocity_terms(
    ITEM_PARAM const int n, const int cap, STEP_DT_PARAM, CONSTANT sph_params *prm,
    GLOBAL const int *restrict nbr_count, GLOBAL const int *restrict nbr_j, PAIR_GEOMETRY_PARAMS,
    GLOBAL const real *restrict vel, GLOBAL const real *restrict mass,
    GLOBAL const real *restrict vol, GLOBAL const real *restrict bmat, GLOBAL hreal *restrict rho,
    GLOBAL real *restrict drho, GLOBAL real *restrict acc_diss, GLOBAL hreal *restrict tau,
    GLOBAL hreal *restrict acc_shear ROTATION_AVG_SPIN_PARAMS GRADV_OUT_PARAMS ART_OUT_PARAMS
        PLASTIC_OUT_PARAMS WALL_POS_PARAMS MATERIAL_PARAMS) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = n * cap; /* the stored pair arrays (PAIR_DIR, PAIR_GEOMETRY) */
    (void)stride;
    const real half_dt = R(0.5) * dt;
    const int m_i = MATERIAL_OF(i);
    CONSTANT sph_params_material *mat_i = MATERIAL_ROW(m_i);
    const real z = mat_i->rho0 * mat_i->c0;
    const real c0 = mat_i->c0;
    const real limiter_slope = prm->riemann_limit;
    const vec v_i = vec_load(vel, n, i);

    /* The neighbour sums in SPH_PAIR_LANES lanes (sph_prelude.h): lane l
     * takes the neighbours k = l, l + lanes, ..., the lanes are added in
     * order at the end.  Per pair, with u = v_ij . e_ij:
     *   continuity   u dW V_j                 (riemann_continuity_pair)
     *   dissipation  beta u dW V_j e_ij       (riemann_dissipation_pair)
     *   ENOG Laplacian  u dW V_j / r_ij e_ij  (000 eq. 24)
     *   velocity gradient  dW V_j v_ij (x) e_ij  (mat_add_outer) */
    lanes lane_div = lanes_zero(), lane_lap[SPH_DIM], lane_diss[SPH_DIM],
          lane_grad[SPH_DIM][SPH_DIM];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        lane_lap[a] = lane_diss[a] = lanes_zero();
        UNROLL for (int b = 0; b < SPH_DIM; ++b) lane_grad[a][b] = lanes_zero();
    }
    const bool limited = limiter_slope > R(0);
    const int count = nbr_count[i];
    for (int k0 = 0; k0 < count; k0 += SPH_PAIR_LANES) {
        lanes e[SPH_DIM], v_ij[SPH_DIM], dwv = lanes_zero(), inv_r = lanes_zero();
        UNROLL for (int a = 0; a < SPH_DIM; ++a) e[a] = v_ij[a] = lanes_zero();
#if PAIR_LANES_DIRECT
        if (k0 + SPH_PAIR_LANES <= count) {
            const int slot = NBR_AT(i, k0);
            dwv = lanes_load(pair_dwv + slot);
            inv_r = lanes_load(pair_inv_r + slot);
            UNROLL for (int a = 0; a < SPH_DIM; ++a) e[a] = lanes_load(pair_e + a * stride + slot);
            UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) {
                const int j = nbr_j[slot + l];
                UNROLL for (int a = 0; a < SPH_DIM; ++a) LANE(v_ij[a], l) =
                    v_i.c[a] - vel[a * n + j];
            }
        } else
#endif
            UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) {
                int j;
                const int slot = lane_pair(nbr_j, n, cap, i, k0 + l, count, &j);
                lane_set_geometry(PAIR_GEOMETRY(slot, j), k0 + l < count, l, e, &dwv, &inv_r);
                UNROLL for (int a = 0; a < SPH_DIM; ++a) LANE(v_ij[a], l) =
                    v_i.c[a] - vel[a * n + j];
            }
        lanes u = lanes_zero();
        UNROLL for (int a = 0; a < SPH_DIM; ++a) u += v_ij[a] * e[a];
        const lanes u_dwv = RIEMANN_CONTINUITY_FACTOR(u, dwv);
        lane_div += u_dwv;
        /* riemann_dissipation_factor: u dW V_j itself (beta = 1) unless the
         * scene limits the dissipation */
        lanes diss = u_dwv;
        if (limited)
            UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) LANE(diss, l) =
                riemann_dissipation_factor(LANE(u, l), c0, limiter_slope, LANE(dwv, l));
        const lanes lap = u_dwv * inv_r;
        UNROLL for (int a = 0; a < SPH_DIM; ++a) {
            lane_diss[a] += e[a] * diss;
            lane_lap[a] += lap * e[a];
            UNROLL for (int b = 0; b < SPH_DIM; ++b) lane_grad[a][b] += dwv * v_ij[a] * e[b];
        }
    }
    real divergence = R(0);
    vec laplacian = vec_zero(), dissipation = vec_zero();
    mat grad_sum = mat_zero();
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) {
        divergence += LANE(lane_div, l);
        UNROLL for (int a = 0; a < SPH_DIM; ++a) {
            laplacian.c[a] += LANE(lane_lap[a], l);
            dissipation.c[a] += LANE(lane_diss[a], l);
            UNROLL for (int b = 0; b < SPH_DIM; ++b) grad_sum.m[a][b] += LANE(lane_grad[a][b], l);
        }
    }
#if SPH_HAS_MATERIAL_IDS
    /* pairs of two materials (sph_materials.h): their dissipation and
     * Laplacian terms scaled by the impedances' and the shear moduli's
     * harmonic means over i's own, the limiter at the mean sound speed; a
     * pass of its own over the neighbours, so the lanes above stay those of
     * a one-material run */
    if (MATERIALS_VARY)
        interface_velocity_terms(i, n, cap, prm, nbr_count, nbr_j, PAIR_GEOMETRY_ARGS, vel, vol,
                                 material, &dissipation, &laplacian);
#endif

    /* continuity and the second density half-step */
    const hreal rho_half = rho[i] + half_dt * drho[i];
    real drho_new = (real)rho_half * divergence;
#if SPH_HAS_WALLS
    /* the rigid walls' mirror images at the new position (sph_wall.h) */
    if (prm->nwalls > 0) {
        const real wall_rate =
            (real)rho_half * wall_divergence(prm, hvec_load(pos, n, i), v_i,
                                             half_step_pressure(mat_i, rho[i], drho[i], half_dt));
        /* a particle leaving the wall gives back its compression and no
         * more in one step: the free surface it becomes has p = 0 */
        drho_new += fmax(wall_rate, fmin(R(0), (mat_i->rho0 - (real)rho_half) / dt));
    }
#endif
    rho[i] = density_advance(rho[i], drho[i], drho_new, half_dt);
    drho[i] = drho_new;
    vec_store(acc_diss, n, i, vec_scale(dissipation, z * vol[i] / mass[i]));

    /* L_i = -sum v_ij (x) (B_i grad W) V_j = -(sum v_ij (x) e dW V_j) B_i^T, B symmetric */
    const mat grad_v = mat_scale(mat_mul(grad_sum, sym_load(bmat, n, i)), R(-1));
    const real shear_modulus = mat_i->shear_modulus;
    const int formulation = RUNTIME_FORMULATION;
    (void)shear_modulus; /* used by the features compiled in below */
    (void)formulation;
    real ratio;
#if SPH_HAS_PLASTICITY
    const mat tau_new = shear_stress_advance(tau, n, i, grad_v, mat_i, dt, plastic_strain, &ratio);
    /* only GNOG(-A) scale their penalty by the return ratio: OG and OAS have
     * no such buffer (an OpenCL program's PRESENT is 1) */
#    if SPH_HAS_PENALTY
    if (PRESENT(penalty_scale)) penalty_scale[i] = ratio;
#    else
    (void)penalty_scale;
#    endif
#else
    const mat tau_new = shear_stress_advance(tau, n, i, grad_v, mat_i, dt, 0, &ratio);
    (void)ratio;
#endif
#if SPH_HAS_ART_STRESS
    if (formulation == FORMULATION_OAS && PRESENT(art_stress))
        sym_store(
            art_stress, n, i,
            artificial_stress(tau_new, eos_pressure(mat_i, rho[i]), (real)rho[i], prm->art_eps));
#endif
#if SPH_HAS_PENALTY
    /* GNOG(-A): L_j enters the linear velocity prediction of the pair (003 eq. 44) */
    if (FORM_HAS_PENALTY(formulation) && PRESENT(gradv)) mat_store(gradv, n, i, grad_v);
#endif
    const int rotation = RUNTIME_ROTATION;
    (void)rotation;
#if SPH_HAS_ROTATION_AVG
    if (rotation == ROTATION_AVERAGED && PRESENT(spin)) {
        /* the spin of this substep: its Rodrigues matrices are summed over
         * the body into Rbar (reduction.cl), applied at the start of the next
         * acoustic_pressure to the accumulated a^s plus the increment */
        real w[NSPIN];
        spin_components(spin_of(grad_v), w);
        UNROLL for (int a = 0; a < NSPIN; ++a) spin[a * n + i] = w[a];
    }
#endif
#if SPH_HAS_ENOG
    if (FORM_IS_ENOG(formulation)) {
        /* SPH-ENOG shear-acceleration increment (000 eq. 24 / 003 eq. 28).
         * 1/rho_i is taken as V_i/m_i, the volume of the last rebuild that
         * the pair terms' V_j are: m_i da_i = c V_i V_j f_ij is then
         * antisymmetric and momentum exact.  With the current rho_i (which
         * drifts from m_i/V_i between rebuilds) the colliding rings' momentum
         * drifted by 2.8e-6 once the geometry was frozen at mid-interval. */
        const vec da =
            vec_scale(laplacian, dt * R(2) * prm->xi_e * shear_modulus * vol[i] / mass[i]);
        accumulate_increment(acc_shear, DACC_ARG, n, i, da, grad_v, rotation, dt);
    }
#endif
}

#if SPH_HAS_STRESS_DIV
#    if SPH_HAS_PENALTY
#        define PENALTY_PARAMS                                                                     \
            , GLOBAL const real *restrict vel, GLOBAL const real *restrict gradv,                  \
                GLOBAL hreal *restrict acc_shear
#        define PENALTY_ARGS , vel, gradv, acc_shear
#    else
#        define PENALTY_PARAMS
#        define PENALTY_ARGS
#    endif
#    if SPH_HAS_ART_STRESS
#        define ART_IN_PARAMS , GLOBAL const real *restrict art_stress
#        define ART_IN_ARGS   , art_stress
#    else
#        define ART_IN_PARAMS
#        define ART_IN_ARGS
#    endif
#    if SPH_HAS_PLASTICITY && SPH_HAS_PENALTY
#        define PENALTY_SCALE_PARAMS , GLOBAL const real *restrict penalty_scale
#        define PENALTY_SCALE_ARGS   , penalty_scale
#    else
#        define PENALTY_SCALE_PARAMS
#        define PENALTY_SCALE_ARGS
#    endif
#    if SPH_HAS_ROTATION_AVG && SPH_HAS_PENALTY
#        define PENALTY_AVG_PARAMS , GLOBAL real *restrict dacc_shear
#        define PENALTY_AVG_ARGS   , dacc_shear
#    else
#        define PENALTY_AVG_PARAMS
#        define PENALTY_AVG_ARGS
#    endif
/* Third pass of the stress-divergence formulations, after the stress update
 * of acoustic_velocity_terms (neighbours read the updated tau and L):
 *   a^sigma_i = 1/rho_i sum_j (tau_i + tau_j) . grad_i W_ij V_j
 *     (000 eq. 17, 003 eq. 45; used by the next substep's velocity update),
 *   SPH-OAS: + sum_j m_j f_ij^n (R_i + R_j) . grad_i W_ij (Gray et al. 2001),
 *   SPH-GNOG: penalty increment
 *     da = dt xi_G G / rho_i sum_j s_ij vhat_ij / r_ij dW_ij V_j   (003 eq. 43)
 *   SPH-GNOG-A: the projected form (003 eqs. 46, 48-49)
 *     da = dt xi_G G / rho_i sum_j s_ij (vhat_ij . e_ij) / r_ij dW_ij V_j e_ij
 *   with vhat_ij = v_ij - (L_i + L_j) r_ij / 2 (eq. 44) and s_ij the mean of
 *   the particles' penalty scales (1, or the J2 return ratio when yielding),
 *   accumulated as a^ = a^ + da (GNOG), R_i a^ + da (per-particle rotation)
 *   or, averaged, Rbar (a^ + da) at the next acoustic_pressure (eq. 47). */
/* buffers of acoustic_shear_force: reads step_clock:small nbr_count:int*n nbr_j:int*pairs
 * pair_pos:hreal*d*n pair_e:real*d*pairs pair_dwv:real*pairs pair_inv_r:real*pairs mass vol rho
 * tau vel gradv art_stress penalty_scale material; writes acc_stress dacc_shear; updates
 * acc_shear */
KERNEL void acoustic_shear_force(ITEM_PARAM const int n, const int cap, STEP_DT_PARAM,
                                 CONSTANT sph_params *prm, GLOBAL const int *restrict nbr_count,
                                 GLOBAL const int *restrict nbr_j, PAIR_GEOMETRY_PARAMS,
                                 GLOBAL const real *restrict mass, GLOBAL const real *restrict vol,
                                 GLOBAL const hreal *restrict rho, GLOBAL const hreal *restrict tau,
                                 GLOBAL real *restrict acc_stress PENALTY_PARAMS ART_IN_PARAMS
                                     PENALTY_SCALE_PARAMS PENALTY_AVG_PARAMS MATERIAL_PARAMS) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = n * cap; /* the stored pair arrays (PAIR_DIR, PAIR_GEOMETRY) */
    (void)stride;
    const int formulation = RUNTIME_FORMULATION;
    (void)formulation; /* OG compiles in neither the artificial stress nor the penalty */
    const mat tau_i = hsym_load(tau, n, i);
    vec stress = vec_zero();
#    if SPH_HAS_ART_STRESS
    const bool art = formulation == FORMULATION_OAS && PRESENT(art_stress);
    const mat art_i = art ? sym_load(art_stress, n, i) : mat_zero();
    vec art_sum = vec_zero();
    const real inv_wdp = R(1) / prm->art_wdp, art_n = prm->art_n;
#    endif
#    if SPH_HAS_PENALTY
    const bool penalty = FORM_HAS_PENALTY(formulation) && PRESENT(gradv);
    const bool projected = formulation == FORMULATION_GNOG_A;
    const vec v_i = penalty ? vec_load(vel, n, i) : vec_zero();
    const mat l_i = penalty ? mat_load(gradv, n, i) : mat_zero();
    real s_i = R(1);
#        if SPH_HAS_PLASTICITY
    if (PRESENT(penalty_scale)) s_i = penalty_scale[i];
#        endif
    vec pen_sum = vec_zero();
    CONSTANT sph_params_material *mat_i = MATERIAL_ROW(MATERIAL_OF(i));
#    endif
    const int count = nbr_count[i];
    for (int k = 0; k < count; ++k) {
        const int slot = NBR_AT(i, k);
        const int j = nbr_j[slot];
        const pair_geometry g = PAIR_GEOMETRY(slot, j);
        const vec e = g.e;
        const real dwv = g.dwv;
        /* (tau_i + tau_j) . grad_i W V_j, grad_i W V_j = dW V_j e_ij */
        stress = vec_axpy(stress, dwv, mat_vec(mat_add(tau_i, hsym_load(tau, n, j)), e));
#    if SPH_HAS_ART_STRESS
        if (art) {
            const real w = kernel_w(prm, R(1) / g.inv_r) * inv_wdp;
            real fn = R(1);
            for (int m = 0; m < (int)art_n; ++m) fn *= w; /* n is a whole number (4) */
            art_sum = vec_axpy(art_sum, (real)rho[j] * fn * dwv,
                               mat_vec(mat_add(art_i, sym_load(art_stress, n, j)), e));
        }
#    endif
#    if SPH_HAS_PENALTY
        if (penalty) {
            /* eq. 44 over r_ij, vhat_ij / r = v_ij / r - (L_i + L_j) e_ij / 2,
             * with r_ij = r e_ij: no division per pair */
            const vec v_hat_over_r =
                vec_sub(vec_scale(vec_sub(v_i, vec_load(vel, n, j)), g.inv_r),
                        vec_scale(mat_vec(mat_add(l_i, mat_load(gradv, n, j)), e), R(0.5)));
            real s_ij = s_i;
#        if SPH_HAS_PLASTICITY
            if (PRESENT(penalty_scale)) s_ij = R(0.5) * (s_i + penalty_scale[j]);
#        endif
            real weight = s_ij * dwv;
#        if SPH_HAS_MATERIAL_IDS
            /* two materials: the shear moduli's harmonic mean
             * (sph_materials.h); the test is a load and a compare where
             * the penalty's own terms are some forty operations */
            if (MATERIALS_VARY && material[j] != material[i])
                weight *=
                    harmonic_ratio(mat_i->shear_modulus, MATERIAL_ROW(material[j])->shear_modulus);
#        endif
            pen_sum = projected ? vec_axpy(pen_sum, weight * vec_dot(v_hat_over_r, e), e)
                                : vec_axpy(pen_sum, weight, v_hat_over_r);
        }
#    endif
    }
    const real inv_rho = vol[i] / mass[i];
    vec a_sigma = vec_scale(stress, inv_rho);
#    if SPH_HAS_ART_STRESS
    if (art) a_sigma = vec_add(a_sigma, art_sum);
#    endif
    vec_store(acc_stress, n, i, a_sigma);
#    if SPH_HAS_PENALTY
    if (penalty) {
        /* 1/rho_i as V_i/m_i, as for ENOG above: momentum exact */
        const vec da = vec_scale(pen_sum, dt * prm->xi_g * mat_i->shear_modulus * inv_rho);
        accumulate_increment(acc_shear, DACC_ARG, n, i, da, l_i, RUNTIME_ROTATION, dt);
    }
#    endif
}
#endif
