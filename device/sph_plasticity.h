/* sph_plasticity.h — J2 (von Mises) plasticity with linear isotropic
 * hardening by radial return (003 eqs. 11-14).
 *
 * The yield function is f = sqrt(2 J2) - sqrt(2/3) (kappa alpha + sigma_Y),
 * J2 = tau:tau / 2 (eq. 11).  The Jaumann update of sph_elasticity.h gives the
 * elastic trial stress; when f > 0 the stress is scaled back onto the yield
 * surface, tau = (kappa alpha + sigma_Y) / sqrt(3 J2_trial) tau_trial
 * (eq. 14), with the hardening variable (equivalent plastic strain) advanced
 * by the consistency condition of linear hardening,
 *     d alpha = sqrt(2/3) f / (2 G + 2 kappa / 3)
 * (the reference code's formula, notes §3.3), which makes the return exact
 * for proportional loading.  The plastic-flow term of the rate form (eq. 12)
 * is not added to the predictor: the return mapping enforces the
 * consistency that term expresses.  The reference code adds it whenever the
 * old stress has f > 0 and then takes d alpha from the residual f, so its
 * alpha misses the plastic strain of those substeps and it hardens less
 * than kappa: copied, it moves the square Taylor bar's observer at
 * L/dp = 8 to 4.46 mm, against our 4.20 and 003's 5.21
 * (cases/taylor_bar_square/README.md).  In 2D the in-plane model of the
 * papers is used (2 x 2 deviator), as for elasticity.
 */
#ifndef SPH_PLASTICITY_H
#define SPH_PLASTICITY_H
#include "sph_elasticity.h"
/* unconditional: the OpenCL program text holds each header once, at its
 * first #include (host/backend/opencl/opencl_runtime.c), so a guarded first include would
 * hide it from sph_artificial_stress.h */
#include "sph_eigen.h"

/* Return the trial deviatoric stress to the yield surface.  *alpha is the
 * hardening variable (updated); the result's *ratio is the scaling applied
 * (1 while elastic), which also scales the GNOG penalty (notes §3.3). */
FN mat j2_radial_return(const mat trial, CONSTANT sph_params_material *props, GLOBAL real *alpha,
                        const int i, real *ratio) {
    const real norm = sqrt(mat_ddot(trial, trial)); /* sqrt(2 J2) */
    const real kappa = props->hardening, yield = props->yield, g = props->shear_modulus;
    const real sqrt23 = sqrt(R(2) / R(3));
    const real f = norm - sqrt23 * (kappa * alpha[i] + yield);
    *ratio = R(1);
    if (!(f > R(0))) return trial;
    alpha[i] += sqrt23 * f / (R(2) * g + R(2) * kappa / R(3));
    *ratio = sqrt23 * (kappa * alpha[i] + yield) / norm;
    return mat_scale(trial, *ratio);
}

/* One substep of the stored shear stress of particle i: the Jaumann update
 * (003 eq. 8) and, for a plastic material, the return to the yield surface.
 * The trial stress is formed in the history precision (tau += dtau, hreal),
 * then scaled by the return ratio when yielding.  `alpha` may be NULL
 * (elastic); *ratio receives the return ratio (1 while elastic).  Returns
 * the new stress. */
FN_HOT mat shear_stress_advance(GLOBAL hreal *tau, const int n, const int i, const mat grad_v,
                                CONSTANT sph_params_material *props, const real dt,
                                GLOBAL real *alpha, real *ratio) {
    const mat tau_old = hsym_load(tau, n, i);
    const mat increment = jaumann_increment(tau_old, grad_v, props->shear_modulus, dt);
    hsym_add_store(tau, n, i, increment);
    mat tau_new = mat_add(tau_old, increment);
    *ratio = R(1);
#if SPH_HAS_PLASTICITY
    /* the hardening buffer exists in plastic runs only */
    if (PRESENT(alpha)) {
        tau_new = j2_radial_return(tau_new, props, alpha, i, ratio);
        if (*ratio != R(1)) hsym_scale_store(tau, n, i, *ratio);
    }
#else
    (void)alpha;
#endif
    return tau_new;
}

#if SPH_HAS_TL_PLASTICITY
/* ---- TLSPH: finite-strain J2 plasticity, F = F^e F^p -------------------
 *
 * 002 §2.1 (Taylor bar, §2.2.6) uses elastic-perfectly plastic von Mises
 * with the multiplicative split F = F^e F^p; here it is the standard
 * principal-axes return map of Simo (1992, CMAME 99:61-112; Simo & Hughes,
 * Computational Inelasticity, 1998, ch. 9), with the logarithmic (Hencky)
 * elastic law and the exponential-map flow rule of Eterovic & Bathe (1990,
 * IJNME 30:1099-1114) (the same algorithm as de Souza Neto, Peric & Owen,
 * Computational Methods for Plasticity, 2008, ch. 14), plus linear isotropic
 * hardening as in the ULSPH model above.  State per particle: the plastic
 * right Cauchy-Green inverse C_p^-1 = (F^pT F^p)^-1 (symmetric, I at the
 * start) and the equivalent plastic strain alpha.  With F at t_{n+1} and
 * (C_p^-1, alpha) at t_n:
 *   (1) trial elastic left Cauchy-Green tensor  b_e^tr = F C_p^-1 F^T;
 *   (2) spectral decomposition  b_e^tr = sum_A (lambda_A^tr)^2 n_A (x) n_A;
 *   (3) logarithmic principal elastic strains  eps_A^tr = ln lambda_A^tr;
 *   (4) Hencky elasticity in principal axes (Kirchhoff stress)
 *         tau_A = lame tr(eps) + 2 mu eps_A,  s_A = 2 mu dev(eps)_A,
 *       whose mean lame + 2 mu / 3 = K times tr(eps) = ln J;
 *   (5) yield function  f = |s^tr| - sqrt(2/3) (sigma_Y + kappa alpha_n);
 *   (6) if f > 0, radial return (exact in the log-strain space):
 *         dgamma = f / (2 mu + 2 kappa / 3),   nu_A = s_A^tr / |s^tr|,
 *         eps_A = eps_A^tr - dgamma nu_A,       s_A = s_A^tr - 2 mu dgamma nu_A,
 *         alpha_{n+1} = alpha_n + sqrt(2/3) dgamma
 *       (the flow is deviatoric, so J^p = 1 and tr(eps) keeps its trial
 *       value);
 *   (7) b_e = sum_A exp(2 eps_A) n_A (x) n_A  and  C_p^-1 = F^-1 b_e F^-T;
 *   (8) tau = sum_A tau_A n_A (x) n_A, and in tl_step.cl P = tau F^-T.
 * In the elastic range (f <= 0) C_p^-1 stays as it is (b_e = b_e^tr
 * exactly), and with C_p^-1 = I the law is Hencky elasticity, which equals
 * Saint Venant-Kirchhoff (the elastic TLSPH) to first order in the strain.
 * 2D is plane strain, as the elastic TLSPH (lame = K - 2G/3): F_zz = 1, the
 * deviator is the 3D one, and plastic flow has a zz component, so the state
 * carries (C_p^-1)_zz; the third principal direction is e_z, with
 * (b_e)_zz = (C_p^-1)_zz. */

typedef struct {
    mat cpinv_dev;     /* C_p^-1 - I, the SPH_DIM x SPH_DIM block */
    real cpinv_zz_dev; /* 2D plane strain: (C_p^-1)_zz - 1; unused in 3D */
    real alpha;        /* equivalent plastic strain */
} tl_plastic_state;

/* Steps (1)-(8) above: returns the Kirchhoff stress (SPH_DIM block) and, in
 * 2D, its out-of-plane component in *tau_zz; updates *st, and *yielded is 1
 * when the return map acted (0: state unchanged).  The state is kept as
 * C_p^-1 - I and (7) is applied as an increment,
 *   C_p^-1 - (C_p^-1)_n = F^-1 (b_e - b_e^tr) F^-T,
 *   b_e - b_e^tr = sum_A (lambda_A^tr)^2 (exp(-2 dgamma nu_A) - 1) n_A (x) n_A
 * (b_e^tr = F (C_p^-1)_n F^T), so that its round-off scales with the plastic
 * increment, not with |C_p^-1| ~ 1: rebuilding C_p^-1 from the eigenvectors
 * at every plastic step added a few ulp per step, systematically (the same
 * rotations each step), 2.6e-13 after 600 steps in 3D
 * (tests/test_plasticity.c). */
FN mat tl_j2_kirchhoff(const mat f, tl_plastic_state *st, CONSTANT sph_params *prm, real *tau_zz,
                       int *yielded) {
    const real lame = prm->materials[0].lambda, mu = prm->materials[0].shear_modulus;
    const real kappa = prm->materials[0].hardening, yield = prm->materials[0].yield;
    /* (1) b_e^tr = F F^T + F (C_p^-1 - I) F^T, (2) */
    const mat ft = mat_transpose(f);
    mat be = mat_add(mat_mul(f, ft), mat_mul(mat_mul(f, st->cpinv_dev), ft));
    be = mat_scale(mat_add(be, mat_transpose(be)), R(0.5));
    mat q;
    vec b2;
    sym_eigen(be, &q, &b2);
    /* (3): principal log strains; the third is e_z in 2D (the 1D instances,
     * fluids only, compile this unused: their lateral strains stay 0) */
    real eps[3] = {R(0), R(0), R(0)};
    UNROLL for (int a = 0; a < SPH_DIM; ++a) eps[a] = R(0.5) * log(b2.c[a]);
#    if SPH_DIM == 2
    eps[2] = R(0.5) * log1p(st->cpinv_zz_dev);
#    endif
    /* (4) */
    const real tr = eps[0] + eps[1] + eps[2];
    real s[3];
    for (int a = 0; a < 3; ++a) s[a] = R(2) * mu * (eps[a] - tr / R(3));
    const real norm = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    /* (5), (6) */
    const real sqrt23 = sqrt(R(2) / R(3));
    const real fy = norm - sqrt23 * (yield + kappa * st->alpha);
    *yielded = fy > R(0);
    real shrink[3] = {R(0), R(0), R(0)}; /* exp(-2 dgamma nu_A) - 1 */
    if (*yielded) {
        const real dgamma = fy / (R(2) * mu + R(2) * kappa / R(3));
        const real scale = R(1) - R(2) * mu * dgamma / norm;
        for (int a = 0; a < 3; ++a) {
            shrink[a] = expm1(R(-2) * dgamma * s[a] / norm);
            s[a] *= scale;
        }
        st->alpha += sqrt23 * dgamma;
    }
    const real mean = (lame + R(2) * mu / R(3)) * tr;
    /* (8) */
    mat tau = mat_zero();
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b)
        UNROLL for (int k = 0; k < SPH_DIM; ++k)
            tau.m[a][b] += (mean + s[k]) * q.m[a][k] * q.m[b][k];
    *tau_zz = mean + s[2];
    /* (7), as the increment above */
    if (*yielded) {
        mat db = mat_zero();
        UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b)
            UNROLL for (int k = 0; k < SPH_DIM; ++k)
                db.m[a][b] += b2.c[k] * shrink[k] * q.m[a][k] * q.m[b][k];
        const mat finv = mat_inverse(f);
        const mat dc = mat_mul(mat_mul(finv, db), mat_transpose(finv));
        st->cpinv_dev = mat_add(st->cpinv_dev, mat_scale(mat_add(dc, mat_transpose(dc)), R(0.5)));
#    if SPH_DIM == 2
        st->cpinv_zz_dev += (R(1) + st->cpinv_zz_dev) * shrink[2];
#    endif
    }
    return tau;
}
#endif

#endif
