/* tl_step.cl — one acoustic substep of total-Lagrangian SPH (TLSPH).
 *
 * The reference configuration is the particle configuration at t = 0: the
 * solver rebuilds the configuration once, at the start, and never again, so
 * the frozen pair geometry of neighbour_build.cl IS the reference geometry:
 * e_ij = X_ij / |X_ij| (from j to i), dW/dR(|X_ij|) V0_j, 1/|X_ij|, and the
 * correction matrix B0_i (001: kernel computed once on the undeformed
 * configuration; 002 §2.1 / 004 eq. 25: B0 on the initial configuration).
 * FIELD_VOL keeps V0 = m / rho0 (it is refreshed only at a rebuild).
 *
 * Time integration: position Verlet (drift-kick-drift), the project's scheme
 * (000 eqs. 27-29) and, for TLSPH, equivalent to the SPHinXsys half-step
 * integration of 004 (seed digest §3.1: x and F advanced by half steps with
 * velocities of the two ends of the step):
 *   x^{n+1/2} = x^n + dt/2 v^n,
 *   F, P, a at x^{n+1/2},
 *   v^{n+1} = v^n + dt a,   x^{n+1} = x^{n+1/2} + dt/2 v^{n+1}.
 * F is computed from the half-step positions rather than integrated from
 * dF/dt (004 eq. 26): since (26) is linear in v, integrating it with the same
 * half steps gives the same F up to round-off, and the direct form keeps F and
 * x consistent for the hourglass term.  001 uses a leap-frog of the same order.
 *
 * Three passes, race-free without atomics (each pass only reads what the
 * others write):
 *  tl_deformation (per particle, neighbours' x^{n+1/2}):
 *    F_i = sum_j V0_j (x_j - x_i) (x) (B0_i grad0 W_ij)     (002 §2.1 [R]),
 *    E = (F^T F - I)/2, S = lambda tr(E) I + 2 mu E, P = F S (004 eq. 24),
 *    rho = rho0 / det F (004 eq. 23) and the deviatoric Cauchy stress
 *    dev(J^-1 P F^T) into tau, for outputs and the energy diagnostic;
 *  tl_acceleration (per particle, neighbours' P, B, F, x^{n+1/2}):
 *    m_i a_i = sum_j V0_i V0_j (P_i B0_i + P_j B0_j) grad0 W_ij   (004 eq. 25,
 *              002's corrected anti-symmetric force)
 *            + f_i^HG (002 hourglass control, below);
 *  tl_update (per particle): gravity, the velocity and position update and
 *    the clamp, as acoustic_pressure does.
 *
 * Kernel-gradient convention (as acoustic_step.cl): grad_i W_ij V_j =
 * pair_dwv * e_ij with e_ij pointing from j to i; so for a uniform stretch
 * x_j - x_i = F (X_j - X_i) = -F e_ij |X_ij| and F_i = F A_i B_i = F, where
 * A_i = -sum_j |X_ij| dW V_j e (x) e is the moment B inverts.
 *
 * Hourglass control (002 §2.1, reconstructed in the seed digest and checked
 * against TrixiParticles.jl's PenaltyForceGanzenmueller; here X_ij = X_i - X_j,
 * x_ij = x_i - x_j, hat = unit vector):
 *   f_i^HG = alpha/2 sum_j V0_i V0_j W(|X_ij|) / |X_ij|^2 E
 *            [(F_i + F_j) X_ij - 2 x_ij] . hat(x_ij) hat(x_ij),
 * the sum of the two particles' error vectors eps = F X - x projected on the
 * current bond: a spring along the bond that pulls the pair back to the
 * locally linear map.  Each pair term is anti-symmetric and along x_ij, so it
 * conserves linear and angular momentum; E is the material's Young's modulus
 * E = 9 K G / (3 K + G).
 *
 * Hyperelastic laws (SPH_HAS_HYPERELASTIC: materials.X.model "neo-hookean"
 * or "exponential"; tl_hyperelastic_pk1 below) replace SVK's P = F S in
 * tl_deformation; an SVK program has none of their code.
 *
 * Pairwise numerical damping (SPH_HAS_TL_DAMPING: method.pairwise_damping
 * c_d > 0; the public code's TLSPH first half step, which its bending
 * column runs with c_d = 0.25; eulerian-sph-reference.md §5.4): a viscous
 * pair stress along the bond's strain rate, added to the pair's P B terms,
 *   m_i a_i += sum_j V0_i V0_j c_d (W(X_ij)/W(0)) 1/2 (F_i + F_j)
 *              (1/2 rho0 c0 h eps_ij) grad0 W_ij,
 *   eps_ij = (d / |X_ij|)^2 (x_ij . v_ij)
 * with x_ij the half-step separation and v_ij = v_i - v_j.  The pair term
 * is anti-symmetric (linear momentum is conserved), vanishes for a rigid
 * translation or rotation (x_ij . v_ij = 0) and opposes a bond's stretching
 * rate, so it only dissipates.
 *
 * Plastic materials (SPH_HAS_TL_PLASTICITY: TLSPH and a yield_stress; none
 * of this is in the elastic program):
 *  - tl_deformation replaces SVK by the finite-strain J2 return map of
 *    sph_plasticity.h (F = F^e F^p, Hencky elasticity, radial return in the
 *    principal log-strain space; Simo 1992), P = tau F^-T, carrying
 *    C_p^-1 - I (field plastic_cinv; zero at the start like every field, so
 *    C_p^-1 = I) and the equivalent plastic strain alpha (plastic_strain);
 *  - the 002 plasticity switch in tl_acceleration: a particle with non-zero
 *    plastic strain uses its current yield stress sigma_Y + kappa alpha
 *    instead of E in the hourglass force (002 §2.1: "E is replaced by the
 *    yield strength"; without it plastic flow is suppressed, 002 §2.2.6).
 *    Each particle's modulus weights its own error vector,
 *      f_i^HG = alpha/2 sum_j V0_i V0_j W(|X_ij|) / |X_ij|^2
 *               [E_i (F_i X_ij - x_ij) + E_j (F_j X_ij - x_ij)] . hat(x_ij) hat(x_ij),
 *    which is 002's (E_i + E_j) form resolved per side, is symmetric in
 *    (i, j) up to the sign of hat(x_ij), so every pair term stays
 *    anti-symmetric, and equals the elastic formula when E_i = E_j = E.
 */
#include "sph_vec.h"
#include "sph_smoothing_kernel.h"
#include "sph_elasticity.h"
#include "sph_constraints.h"
#include "sph_plasticity.h"
#include "sph_hyperelastic.h"

#if SPH_HAS_TLSPH

/* the optional parameters, each X_PARAMS with its X_ARGS, the same names
 * for a call (the substep loop's, substep_loop.cl) */
#    if SPH_HAS_CLAMP
#        define TL_CLAMP_PARAMS , GLOBAL const u8 *restrict fixed
#        define TL_CLAMP_ARGS   , fixed
#        define TL_CLAMP_ARG    fixed
#    else
#        define TL_CLAMP_PARAMS
#        define TL_CLAMP_ARGS
#        define TL_CLAMP_ARG 0
#    endif
#    if SPH_HAS_TL_PLASTICITY
#        define TL_PLASTIC_STATE_PARAMS                                                            \
            , GLOBAL real *restrict plastic_strain, GLOBAL real *restrict plastic_cinv
#        define TL_PLASTIC_SWITCH_PARAMS , GLOBAL const real *restrict plastic_strain
#        define TL_PLASTIC_STATE_ARGS    , plastic_strain, plastic_cinv
#        define TL_PLASTIC_SWITCH_ARGS   , plastic_strain
#    else
#        define TL_PLASTIC_STATE_PARAMS
#        define TL_PLASTIC_SWITCH_PARAMS
#        define TL_PLASTIC_STATE_ARGS
#        define TL_PLASTIC_SWITCH_ARGS
#    endif

FN vec tl_pair_direction(GLOBAL const real *restrict pair_e, const int stride, const int slot) {
    vec e;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) e.c[a] = pair_e[a * stride + slot];
    return e;
}

/* x_i - x_j at the half step, x^{n+1/2} = x^n + dt/2 v^n, evaluated where
 * needed so that no pass writes what its neighbours read; the difference of
 * the positions is taken in their (history) precision. */
FN vec tl_half_separation(GLOBAL const hreal *restrict pos, GLOBAL const real *restrict vel,
                          const int n, const int i, const int j, const real half_dt) {
    return vec_axpy(hvec_diff(pos, n, i, j), half_dt,
                    vec_sub(vec_load(vel, n, i), vec_load(vel, n, j)));
}

/* Young's modulus from the bulk and shear moduli of the parameter block. */
FN real tl_youngs_modulus(CONSTANT sph_params *prm) {
    const real k = prm->materials[0].bulk_modulus, g = prm->materials[0].shear_modulus;
    return R(9) * k * g / (R(3) * k + g);
}

#    if SPH_HAS_TL_PLASTICITY
/* The plastic state of particle i; plastic_cinv holds C_p^-1 - I: the
 * symmetric block (sph_vec.h order), then in 2D the zz component. */
FN tl_plastic_state tl_plastic_load(GLOBAL const real *restrict plastic_strain,
                                    GLOBAL const real *restrict plastic_cinv, const int n,
                                    const int i) {
    tl_plastic_state st;
    st.cpinv_dev = sym_load(plastic_cinv, n, i);
#        if SPH_DIM == 2
    st.cpinv_zz_dev = plastic_cinv[NSYM * n + i];
#        else
    st.cpinv_zz_dev = R(0);
#        endif
    st.alpha = plastic_strain[i];
    return st;
}

FN void tl_plastic_store(GLOBAL real *restrict plastic_strain, GLOBAL real *restrict plastic_cinv,
                         const int n, const int i, const tl_plastic_state st) {
    sym_store(plastic_cinv, n, i, st.cpinv_dev);
#        if SPH_DIM == 2
    plastic_cinv[NSYM * n + i] = st.cpinv_zz_dev;
#        endif
    plastic_strain[i] = st.alpha;
}

/* 002 plasticity switch: the modulus of a particle in the hourglass force,
 * E while it has not yielded, then its current yield stress. */
FN real tl_hourglass_modulus(CONSTANT sph_params *prm, const real plastic_strain,
                             const real youngs) {
    return plastic_strain > R(0)
               ? prm->materials[0].yield + prm->materials[0].hardening * plastic_strain
               : youngs;
}
#    endif

/* buffers of tl_deformation: reads step_clock:small nbr_count:int*n nbr_j:int*pairs
 * pair_e:real*d*pairs pair_dwv:real*pairs pos vel bmat; writes defgrad pk1 rho tau; updates
 * plastic_strain plastic_cinv */
KERNEL void tl_deformation(ITEM_PARAM const int n, const int cap, STEP_DT_PARAM,
                           CONSTANT sph_params *prm, GLOBAL const int *restrict nbr_count,
                           GLOBAL const int *restrict nbr_j, GLOBAL const real *restrict pair_e,
                           GLOBAL const real *restrict pair_dwv, GLOBAL const hreal *restrict pos,
                           GLOBAL const real *restrict vel, GLOBAL const real *restrict bmat,
                           GLOBAL real *restrict defgrad, GLOBAL real *restrict pk1,
                           GLOBAL hreal *restrict rho,
                           GLOBAL hreal *restrict tau TL_PLASTIC_STATE_PARAMS) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = n * cap;
    const real half_dt = R(0.5) * dt;

    /* sum_j dW V0_j (x_j - x_i) (x) e_ij; F = that times B0_i (B symmetric) */
    mat g = mat_zero();
    const int count = nbr_count[i];
    for (int k = 0; k < count; ++k) {
        const int slot = NBR_AT(i, k);
        const int j = nbr_j[slot];
        const vec x_ji = tl_half_separation(pos, vel, n, j, i, half_dt);
        g = mat_add_outer(g, pair_dwv[slot], x_ji, tl_pair_direction(pair_e, stride, slot));
    }
    const mat f = mat_mul(g, sym_load(bmat, n, i));
    const real det = mat_det(f);
    mat p, sigma;
#    if SPH_HAS_TL_PLASTICITY
    if (RUNTIME_PLASTIC && PRESENT(plastic_cinv)) {
        /* finite-strain J2 (sph_plasticity.h): Kirchhoff tau, P = tau F^-T */
        tl_plastic_state st = tl_plastic_load(plastic_strain, plastic_cinv, n, i);
        real tau_zz;
        int yielded;
        const mat kirchhoff = tl_j2_kirchhoff(f, &st, prm, &tau_zz, &yielded);
        (void)tau_zz;
        if (yielded) tl_plastic_store(plastic_strain, plastic_cinv, n, i, st);
        p = mat_mul(kirchhoff, mat_transpose(mat_inverse(f)));
        sigma = mat_scale(kirchhoff, R(1) / det);
    } else
#    endif
    {
#    if SPH_HAS_HYPERELASTIC
        if (RUNTIME_ELASTIC_MODEL != ELASTIC_MODEL_SVK)
            p = tl_hyperelastic_pk1(f, prm);
        else
#    endif
            p = tl_svk_pk1(f, prm->materials[0].lambda, prm->materials[0].shear_modulus);
        sigma = mat_scale(mat_mul(p, mat_transpose(f)), R(1) / det);
    }
    mat_store(defgrad, n, i, f);
    mat_store(pk1, n, i, p);

    /* Outputs: rho = rho0 / J (004 eq. 23) and tau = dev(sigma), sigma =
     * J^-1 P F^T.  The snapshots' pressure is then c0^2 (rho - rho0) =
     * K (1/J - 1), which equals -tr(sigma)/d to first order in the strain
     * (exactly so only for linear elasticity), and the strain-energy
     * diagnostic V (tau:tau/4G + p^2/2K) is the SVK energy to second order
     * (for a plastic material the same small-strain, in-plane estimate of
     * the stored elastic energy: the plastic work is not in it). */
    rho[i] = prm->materials[0].rho0 / det;
    const real mean = mat_trace(sigma) / R(SPH_DIM);
    UNROLL for (int a = 0; a < SPH_DIM; ++a) sigma.m[a][a] -= mean;
    hsym_store(tau, n, i, sigma);
}

/* buffers of tl_acceleration: reads step_clock:small nbr_count:int*n nbr_j:int*pairs
 * pair_e:real*d*pairs pair_dwv:real*pairs pair_inv_r:real*pairs pos vel mass vol bmat defgrad
 * pk1 pair_w:real*pairs plastic_strain; writes acc_shear */
KERNEL void tl_acceleration(ITEM_PARAM const int n, const int cap, STEP_DT_PARAM,
                            CONSTANT sph_params *prm, GLOBAL const int *restrict nbr_count,
                            GLOBAL const int *restrict nbr_j, GLOBAL const real *restrict pair_e,
                            GLOBAL const real *restrict pair_dwv,
                            GLOBAL const real *restrict pair_inv_r,
                            GLOBAL const hreal *restrict pos, GLOBAL const real *restrict vel,
                            GLOBAL const real *restrict mass, GLOBAL const real *restrict vol,
                            GLOBAL const real *restrict bmat, GLOBAL const real *restrict defgrad,
                            GLOBAL const real *restrict pk1, GLOBAL hreal *restrict acc_shear,
                            GLOBAL const real *restrict pair_w TL_PLASTIC_SWITCH_PARAMS) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = n * cap;
    const real half_dt = R(0.5) * dt;
    const mat f_i = mat_load(defgrad, n, i);
    const real alpha = prm->hourglass;
    const real youngs = tl_youngs_modulus(prm);
#    if SPH_HAS_TL_PLASTICITY
    /* the plasticity switch: per-particle moduli inside the pair term */
    const int switched = RUNTIME_PLASTIC && PRESENT(plastic_strain);
    const real e_i = switched ? tl_hourglass_modulus(prm, plastic_strain[i], youngs) : youngs;
    const real hourglass_scale = R(0.5) * alpha * (switched ? R(1) : youngs);
#    else
    const real hourglass_scale = R(0.5) * alpha * youngs;
#    endif

#    if SPH_HAS_TL_DAMPING
    /* the pairwise damping of the header: its coefficient, 1/W(0), v_i */
    const real damping = prm->pair_damping;
    const real inv_w0 = damping > R(0) ? R(1) / kernel_w(prm, R(0)) : R(0);
    const vec v_i = vec_load(vel, n, i);
    vec sum_damp = vec_zero();
#    endif
    /* sum_j (P_i B_i + P_j B_j) grad W V0_j = P_i B_i sum_j g_ij + sum_j P_j B_j g_ij */
    vec sum_g = vec_zero(), sum_j = vec_zero(), sum_hg = vec_zero();
    const int count = nbr_count[i];
    for (int k = 0; k < count; ++k) {
        const int slot = NBR_AT(i, k);
        const int j = nbr_j[slot];
        const vec e = tl_pair_direction(pair_e, stride, slot);
        const vec g = vec_scale(e, pair_dwv[slot]);
        sum_g = vec_add(sum_g, g);
        sum_j = vec_add(sum_j, mat_vec(mat_load(pk1, n, j), mat_vec(sym_load(bmat, n, j), g)));
#    if SPH_HAS_TL_DAMPING
        if (damping > R(0)) {
            /* (W_ij / W0) eps_ij (F_i + F_j) g_ij, W_ij from the stored
             * W(X_ij) V0_j / X_ij^2 */
            const real inv_r0 = pair_inv_r[slot];
            const vec x_ij = tl_half_separation(pos, vel, n, i, j, half_dt);
            const real rate = R(SPH_DIM * SPH_DIM) * inv_r0 * inv_r0 *
                              vec_dot(x_ij, vec_sub(v_i, vec_load(vel, n, j)));
            const real weight = pair_w[slot] / (inv_r0 * inv_r0 * vol[j]) * inv_w0;
            sum_damp = vec_axpy(sum_damp, weight * rate,
                                mat_vec(mat_add(f_i, mat_load(defgrad, n, j)), g));
        }
#    endif
        if (alpha > R(0)) {
            /* 002 hourglass control, pair term of the header */
            const real r0 = R(1) / pair_inv_r[slot];
            const vec big_x = vec_scale(e, r0);
            const vec x_ij = tl_half_separation(pos, vel, n, i, j, half_dt);
            const real r2 = vec_dot(x_ij, x_ij);
            if (r2 > R(0)) {
                const vec hat = vec_scale(x_ij, R(1) / sqrt(r2));
                real delta;
#    if SPH_HAS_TL_PLASTICITY
                if (switched) {
                    /* E_i (F_i X_ij - x_ij).hat + E_j (F_j X_ij - x_ij).hat */
                    const real e_j = tl_hourglass_modulus(prm, plastic_strain[j], youngs);
                    const vec err_i = vec_sub(mat_vec(f_i, big_x), x_ij);
                    const vec err_j = vec_sub(mat_vec(mat_load(defgrad, n, j), big_x), x_ij);
                    delta = e_i * vec_dot(err_i, hat) + e_j * vec_dot(err_j, hat);
                } else
#    endif
                {
                    const vec predicted = mat_vec(mat_add(f_i, mat_load(defgrad, n, j)), big_x);
                    delta = vec_dot(vec_axpy(predicted, R(-2), x_ij), hat);
                }
                const real w = pair_w[slot]; /* W(X_ij) V0_j / X_ij^2 */
                sum_hg = vec_axpy(sum_hg, w * delta, hat);
            }
        }
    }
    const mat pb_i = mat_mul(mat_load(pk1, n, i), sym_load(bmat, n, i));
    vec force = vec_add(mat_vec(pb_i, sum_g), sum_j); /* per V0_i */
#    if SPH_HAS_TL_DAMPING
    /* c_d x 1/2 (F_i + F_j) x 1/2 rho0 c0 h eps_ij */
    force =
        vec_axpy(force, damping * R(0.25) * prm->materials[0].rho0 * prm->materials[0].c0 * prm->h,
                 sum_damp);
#    endif
    const real v_over_m = vol[i] / mass[i];
    vec acc = vec_scale(force, v_over_m);
    acc = vec_axpy(acc, hourglass_scale * v_over_m, sum_hg);
    /* the acceleration goes to the acc_shear buffer, which TLSPH does not
     * otherwise use, for tl_update */
    hvec_store(acc_shear, n, i, acc);
}

/* buffers of tl_update: reads step_clock:small acc_shear fixed; updates pos vel */
KERNEL void tl_update(ITEM_PARAM const int n, STEP_DT_PARAM, CONSTANT sph_params *prm,
                      GLOBAL const hreal *restrict acc_shear, GLOBAL hreal *restrict pos,
                      GLOBAL real *restrict vel TL_CLAMP_PARAMS) {
    STEP_DT_BEGIN;
    const int i = ITEM_ID;
    if (i >= n) return;
    verlet_advance(prm, n, i, dt, hvec_load(acc_shear, n, i), pos, vel, TL_CLAMP_ARG);
}

#endif
