/* sph_eigen.h — the symmetric eigen-solver shared by the artificial stress
 * of SPH-OAS (sph_artificial_stress.h) and the finite-strain J2 return map
 * of TLSPH (sph_plasticity.h, principal stretches of b_e). */
#ifndef SPH_EIGEN_H
#define SPH_EIGEN_H
#include "sph_vec.h"

/* Eigen-decomposition of a symmetric matrix by cyclic Jacobi rotations:
 * a = q diag(lambda) q^T.  Exact after one rotation in 2D; a handful of
 * sweeps reach round-off in 3D. */
FN void sym_eigen(const mat a_in, mat *q_out, vec *lambda) {
    mat a = a_in, q = mat_identity();
    for (int sweep = 0; sweep < (SPH_DIM == 2 ? 1 : 8); ++sweep) {
        UNROLL for (int p = 0; p < SPH_DIM - 1; ++p) UNROLL for (int r = p + 1; r < SPH_DIM; ++r) {
            const real apr = a.m[p][r];
            if (apr == R(0)) continue;
            const real theta = (a.m[r][r] - a.m[p][p]) / (R(2) * apr);
            const real t =
                (theta >= R(0) ? R(1) : R(-1)) / (fabs(theta) + sqrt(theta * theta + R(1)));
            const real c = R(1) / sqrt(t * t + R(1)), s = t * c;
            UNROLL for (int k = 0; k < SPH_DIM; ++k) { /* a <- a J */
                const real akp = a.m[k][p], akr = a.m[k][r];
                a.m[k][p] = c * akp - s * akr;
                a.m[k][r] = s * akp + c * akr;
            }
            UNROLL for (int k = 0; k < SPH_DIM; ++k) { /* a <- J^T a */
                const real apk = a.m[p][k], ark = a.m[r][k];
                a.m[p][k] = c * apk - s * ark;
                a.m[r][k] = s * apk + c * ark;
            }
            UNROLL for (int k = 0; k < SPH_DIM; ++k) { /* q <- q J */
                const real qkp = q.m[k][p], qkr = q.m[k][r];
                q.m[k][p] = c * qkp - s * qkr;
                q.m[k][r] = s * qkp + c * qkr;
            }
        }
    }
    UNROLL for (int k = 0; k < SPH_DIM; ++k) lambda->c[k] = a.m[k][k];
    *q_out = q;
}

#endif
