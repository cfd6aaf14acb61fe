/* sph_artificial_stress.h — the artificial stress of Gray, Monaghan & Swift
 * (2001), the "AS" of the SPH-OAS baseline (000 §6, 003 §5).
 *
 * In the principal frame of sigma = tau - p I, each tensile principal stress
 * s_a > 0 gets R_a = -epsilon s_a / rho^2 (compressive ones none); R rotated
 * back to the global frame is added to the momentum equation as
 *     dv_i/dt += sum_j m_j f_ij^n (R_i + R_j) . grad_i W_ij,
 *     f_ij = W(r_ij) / W(dp),
 * a short-range repulsion that counters the tensile instability.  Parameters
 * epsilon = 0.3, n = 4, the values Gray et al. derive for elastic solids and
 * that the SPH-OAS runs use (scene method.artificial_stress).
 */
#ifndef SPH_ARTIFICIAL_STRESS_H
#define SPH_ARTIFICIAL_STRESS_H
#include "sph_eigen.h"

/* R of one particle from its deviatoric stress, pressure and density. */
FN mat artificial_stress(const mat tau, const real p, const real rho, const real epsilon) {
    mat sigma = tau;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) sigma.m[a][a] -= p;
    mat q;
    vec lambda;
    sym_eigen(sigma, &q, &lambda);
    mat r = mat_zero();
    const real inv_rho2 = R(1) / (rho * rho);
    UNROLL for (int k = 0; k < SPH_DIM; ++k) {
        if (!(lambda.c[k] > R(0))) continue;
        const real rk = -epsilon * lambda.c[k] * inv_rho2;
        UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b)
            r.m[a][b] += rk * q.m[a][k] * q.m[b][k];
    }
    return r;
}

#endif
