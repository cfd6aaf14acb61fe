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
#include "sph_vec.h"

/* Eigen-decomposition of a symmetric matrix by cyclic Jacobi rotations:
 * a = q diag(lambda) q^T.  Exact after one rotation in 2D; a handful of
 * sweeps reach round-off in 3D. */
FN void sym_eigen(const mat a_in, mat *q_out, vec *lambda) {
    mat a = a_in, q = mat_identity();
    for (int sweep = 0; sweep < (SPH_DIM == 2 ? 1 : 8); ++sweep) {
        for (int p = 0; p < SPH_DIM - 1; ++p)
            for (int r = p + 1; r < SPH_DIM; ++r) {
                const real apr = a.m[p][r];
                if (apr == R(0)) continue;
                const real theta = (a.m[r][r] - a.m[p][p]) / (R(2) * apr);
                const real t =
                    (theta >= R(0) ? R(1) : R(-1)) / (fabs(theta) + sqrt(theta * theta + R(1)));
                const real c = R(1) / sqrt(t * t + R(1)), s = t * c;
                for (int k = 0; k < SPH_DIM; ++k) { /* a <- a J */
                    const real akp = a.m[k][p], akr = a.m[k][r];
                    a.m[k][p] = c * akp - s * akr;
                    a.m[k][r] = s * akp + c * akr;
                }
                for (int k = 0; k < SPH_DIM; ++k) { /* a <- J^T a */
                    const real apk = a.m[p][k], ark = a.m[r][k];
                    a.m[p][k] = c * apk - s * ark;
                    a.m[r][k] = s * apk + c * ark;
                }
                for (int k = 0; k < SPH_DIM; ++k) { /* q <- q J */
                    const real qkp = q.m[k][p], qkr = q.m[k][r];
                    q.m[k][p] = c * qkp - s * qkr;
                    q.m[k][r] = s * qkp + c * qkr;
                }
            }
    }
    for (int k = 0; k < SPH_DIM; ++k) lambda->c[k] = a.m[k][k];
    *q_out = q;
}

/* R of one particle from its deviatoric stress, pressure and density. */
FN mat artificial_stress(const mat tau, const real p, const real rho, const real epsilon) {
    mat sigma = tau;
    for (int a = 0; a < SPH_DIM; ++a) sigma.m[a][a] -= p;
    mat q;
    vec lambda;
    sym_eigen(sigma, &q, &lambda);
    mat r = mat_zero();
    const real inv_rho2 = R(1) / (rho * rho);
    for (int k = 0; k < SPH_DIM; ++k) {
        if (!(lambda.c[k] > R(0))) continue;
        const real rk = -epsilon * lambda.c[k] * inv_rho2;
        for (int a = 0; a < SPH_DIM; ++a)
            for (int b = 0; b < SPH_DIM; ++b) r.m[a][b] += rk * q.m[a][k] * q.m[b][k];
    }
    return r;
}

#endif
