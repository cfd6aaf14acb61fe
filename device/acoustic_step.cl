/* acoustic_step.cl — one acoustic substep of the position-Verlet scheme.
 *
 * 000 eqs. 27-29 with the order of operations of the reference code
 * (reference notes §3.8), fused into two neighbour passes:
 *
 *  acoustic_pressure (per particle i)
 *    rho^{n+1/2} = rho^n + dt/2 drho^n and p = c0^2 (rho - rho0), evaluated
 *    on the fly for i and every neighbour j (no extra pass over memory);
 *    a^s <- Rbar (a^s + da^s) for SPH-ENOG-A (003 eqs. 41-42, with Rbar and
 *    da^s from the previous substep, see below);
 *    v^{n+1} = v^n + dt [a^p + a^diss + a^s + g]   (000 eq. 28, 003 eq. 16);
 *    clamp: v = 0, x = x0 for fixed particles;
 *    x^{n+1} = x^n + dt/2 (v^n + v^{n+1})          (000 eqs. 27, 29).
 *
 *  acoustic_velocity_terms (per particle i), all from the new velocities:
 *    continuity drho/dt = rho sum u_ij dW V_j        (003 eq. 15),
 *    rho^{n+1} = rho^{n+1/2} + dt/2 drho^{n+1}       (000 eq. 29),
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

#if SPH_HAS_ROTATION_AVG
#    define ROTATION_AVG_PARAMS                                                                    \
        , GLOBAL const real *restrict dacc_shear, GLOBAL const real *restrict substep_sums
#    define ROTATION_AVG_SPIN_PARAMS , GLOBAL real *restrict dacc_shear, GLOBAL real *restrict spin
#else
#    define ROTATION_AVG_PARAMS
#    define ROTATION_AVG_SPIN_PARAMS
#endif
#if SPH_HAS_BODY_IDS
#    define BODY_PARAMS , GLOBAL const u8 *restrict body
#    define BODY_OF(i)  (PRESENT(body) ? (int)body[i] : 0)
#else
#    define BODY_PARAMS
#    define BODY_OF(i) 0
#endif
#if SPH_HAS_CLAMP
#    define CLAMP_PARAMS , GLOBAL const real *restrict pos0, GLOBAL const u8 *restrict fixed
#else
#    define CLAMP_PARAMS
#endif

FN vec pair_direction(GLOBAL const real *restrict pair_e, const int stride, const int slot) {
    vec e;
    for (int a = 0; a < SPH_DIM; ++a) e.c[a] = pair_e[a * stride + slot];
    return e;
}

/* Mean rotation of body b from the summed Rodrigues matrices (003 eq. 41). */
FN mat mean_rotation(CONSTANT real *prm, GLOBAL const real *restrict substep_sums, const int b) {
    mat r;
    const real inv_count = R(1) / prm[PRM_BODY_COUNT + b];
    for (int a = 0; a < SPH_DIM; ++a)
        for (int c = 0; c < SPH_DIM; ++c)
            r.m[a][c] = substep_sums[1 + (b * SPH_DIM + a) * SPH_DIM + c] * inv_count;
    return r;
}

KERNEL void
acoustic_pressure(ITEM_PARAM const int n, const int cap, const real dt, CONSTANT real *prm,
                  GLOBAL const int *restrict nbr_count, GLOBAL const int *restrict nbr_j,
                  GLOBAL const real *restrict pair_e, GLOBAL const real *restrict pair_dwv,
                  GLOBAL const real *restrict rho, GLOBAL const real *restrict drho,
                  GLOBAL const real *restrict mass, GLOBAL const real *restrict vol,
                  GLOBAL const real *restrict acc_diss, GLOBAL real *restrict acc_shear,
                  GLOBAL real *restrict pos,
                  GLOBAL real *restrict vel ROTATION_AVG_PARAMS BODY_PARAMS CLAMP_PARAMS) {
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = n * cap;
    const real half_dt = R(0.5) * dt;
    const real p_i = eos_pressure(prm, rho[i] + half_dt * drho[i]);

    vec sum = vec_zero();
    const int count = nbr_count[i];
    for (int k = 0; k < count; ++k) {
        const int slot = NBR_AT(i, k);
        const int j = nbr_j[slot];
        const real p_j = eos_pressure(prm, rho[j] + half_dt * drho[j]);
        sum = vec_add(sum, riemann_pressure_pair(p_i, p_j, pair_dwv[slot],
                                                 pair_direction(pair_e, stride, slot)));
    }
    const vec a_p = vec_add(vec_scale(sum, vol[i] / mass[i]), vec_load(acc_diss, n, i));

    vec a_s = vec_load(acc_shear, n, i);
#if SPH_HAS_ROTATION_AVG
    if (RUNTIME_ROTATION == ROTATION_AVERAGED && PRESENT(dacc_shear)) {
        /* 003 eq. 42 with the increment placed in the current configuration:
         * da^s was summed over the pair geometry frozen at the last rebuild,
         * one acoustic step before the configuration this update acts in, so
         * the step's mean rotation carries it along with the accumulated sum:
         * a^s <- Rbar (a^s + da^s).  On the spinning plate (CFL 0.1) this gives
         * a maximum angular-momentum error of 2.54 % (paper: 2.58 %); adding
         * da^s after the rotation gives 3.12 %, the difference being the
         * one-step lag of the increment (README, "SPH-ENOG-A rotation"). */
        const mat rbar = mean_rotation(prm, substep_sums, BODY_OF(i));
        a_s = mat_vec(rbar, vec_add(a_s, vec_load(dacc_shear, n, i)));
        vec_store(acc_shear, n, i, a_s);
    }
#endif

    const vec v_old = vec_load(vel, n, i);
    vec acc = vec_add(a_p, a_s);
    for (int a = 0; a < SPH_DIM; ++a) acc.c[a] += prm[PRM_GRAVITY + a];
    vec v_new = vec_axpy(v_old, dt, acc);
    vec x_new = vec_axpy(vec_load(pos, n, i), half_dt, vec_add(v_old, v_new));
#if SPH_HAS_CLAMP
    if (PRESENT(fixed) && fixed[i]) {
        v_new = vec_zero();
        x_new = vec_load(pos0, n, i);
    }
#endif
    vec_store(vel, n, i, v_new);
    vec_store(pos, n, i, x_new);
}

KERNEL void
acoustic_velocity_terms(ITEM_PARAM const int n, const int cap, const real dt, CONSTANT real *prm,
                        GLOBAL const int *restrict nbr_count, GLOBAL const int *restrict nbr_j,
                        GLOBAL const real *restrict pair_e, GLOBAL const real *restrict pair_dwv,
                        GLOBAL const real *restrict pair_inv_r, GLOBAL const real *restrict vel,
                        GLOBAL const real *restrict mass, GLOBAL const real *restrict vol,
                        GLOBAL const real *restrict bmat, GLOBAL real *restrict rho,
                        GLOBAL real *restrict drho, GLOBAL real *restrict acc_diss,
                        GLOBAL real *restrict tau,
                        GLOBAL real *restrict acc_shear ROTATION_AVG_SPIN_PARAMS) {
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = n * cap;
    const real half_dt = R(0.5) * dt;
    const real z = prm[PRM_RHO0] * prm[PRM_C0];
    const real c0 = prm[PRM_C0];
    const real limiter_slope = prm[PRM_RIEMANN_LIMIT];
    const vec v_i = vec_load(vel, n, i);

    real divergence = R(0);
    vec laplacian = vec_zero(), dissipation = vec_zero();
    mat grad_sum = mat_zero();
    const int count = nbr_count[i];
    for (int k = 0; k < count; ++k) {
        const int slot = NBR_AT(i, k);
        const int j = nbr_j[slot];
        const vec e = pair_direction(pair_e, stride, slot);
        const real dwv = pair_dwv[slot];
        const vec v_ij = vec_sub(v_i, vec_load(vel, n, j));
        const real u = vec_dot(v_ij, e);
        divergence += riemann_continuity_pair(u, dwv);
        dissipation = vec_add(dissipation, riemann_dissipation_pair(u, c0, limiter_slope, dwv, e));
        laplacian = vec_axpy(laplacian, u * dwv * pair_inv_r[slot], e);
        grad_sum = mat_add_outer(grad_sum, dwv, v_ij, e);
    }

    /* continuity and the second density half-step */
    const real rho_half = rho[i] + half_dt * drho[i];
    const real drho_new = rho_half * divergence;
    drho[i] = drho_new;
    rho[i] = rho_half + half_dt * drho_new;
    vec_store(acc_diss, n, i, vec_scale(dissipation, z * vol[i] / mass[i]));

    /* L_i = -sum v_ij (x) (B_i grad W) V_j = -(sum v_ij (x) e dW V_j) B_i^T, B symmetric */
    const mat grad_v = mat_scale(mat_mul(grad_sum, sym_load(bmat, n, i)), R(-1));
    const real shear_modulus = prm[PRM_G];
    sym_store(tau, n, i, jaumann_update(sym_load(tau, n, i), grad_v, shear_modulus, dt));

    /* SPH-ENOG shear-acceleration increment (000 eq. 24 / 003 eq. 28) */
    const vec da = vec_scale(laplacian, dt * R(2) * prm[PRM_XI_E] * shear_modulus / rho_half);
    const int rotation = RUNTIME_ROTATION;
    if (rotation == ROTATION_NONE) {
        vec_store(acc_shear, n, i, vec_add(vec_load(acc_shear, n, i), da));
    } else if (rotation == ROTATION_PER_PARTICLE) {
        const mat rot = rodrigues(spin_of(grad_v), dt);
        vec_store(acc_shear, n, i, vec_add(mat_vec(rot, vec_load(acc_shear, n, i)), da));
    }
#if SPH_HAS_ROTATION_AVG
    else if (PRESENT(spin)) {
        /* averaged: the increment waits for Rbar (reduced over the body,
         * applied at the start of the next acoustic_pressure) */
        real w[NSPIN];
        spin_components(spin_of(grad_v), w);
        for (int a = 0; a < NSPIN; ++a) spin[a * n + i] = w[a];
        vec_store(dacc_shear, n, i, da);
    }
#endif
}
