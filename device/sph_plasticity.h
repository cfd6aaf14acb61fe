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
 * (the same increment the reference code uses, notes §3.3), which makes
 * the return exact for proportional loading.  The plastic-flow term of the
 * rate form (eq. 12) is not added to the predictor: the return mapping
 * enforces the consistency that term expresses.  In 2D the in-plane model of
 * the papers is used (2 x 2 deviator), as for elasticity.
 */
#ifndef SPH_PLASTICITY_H
#define SPH_PLASTICITY_H
#include "sph_elasticity.h"

/* Return the trial deviatoric stress to the yield surface.  *alpha is the
 * hardening variable (updated); the result's *ratio is the scaling applied
 * (1 while elastic), which also scales the GNOG penalty (notes §3.3). */
FN mat j2_radial_return(const mat trial, CONSTANT real *prm, GLOBAL real *alpha, const int i,
                        real *ratio) {
    const real norm = sqrt(mat_ddot(trial, trial)); /* sqrt(2 J2) */
    const real kappa = prm[PRM_HARDENING], yield = prm[PRM_YIELD], g = prm[PRM_G];
    const real sqrt23 = sqrt(R(2) / R(3));
    const real f = norm - sqrt23 * (kappa * alpha[i] + yield);
    *ratio = R(1);
    if (!(f > R(0))) return trial;
    alpha[i] += sqrt23 * f / (R(2) * g + R(2) * kappa / R(3));
    *ratio = sqrt23 * (kappa * alpha[i] + yield) / norm;
    return mat_scale(trial, *ratio);
}

/* One substep of the shear stress: the Jaumann update (003 eq. 8) and, for
 * a plastic material, the return to the yield surface.  `alpha` may be NULL
 * (elastic); *ratio receives the return ratio (1 while elastic). */
FN mat shear_stress_update(const mat tau, const mat grad_v, CONSTANT real *prm, const real dt,
                           GLOBAL real *alpha, const int i, real *ratio) {
    const mat trial = jaumann_update(tau, grad_v, prm[PRM_G], dt);
    *ratio = R(1);
    if (RUNTIME_PLASTIC) {
        if (PRESENT(alpha)) return j2_radial_return(trial, prm, alpha, i, ratio);
    }
    return trial;
}

#endif
