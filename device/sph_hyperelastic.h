/* sph_hyperelastic.h — the elastic laws of total-Lagrangian SPH
 * (tl_step.cl) as strain energies psi(F) per reference volume and their
 * first Piola-Kirchhoff stresses P = F S, S = 2 d psi / d C (docs/method.md,
 * "TLSPH"): Saint Venant-Kirchhoff (004 eq. 24, the default), and, compiled
 * in only for scenes that choose them (SPH_HAS_HYPERELASTIC), neo-Hookean
 * and exponential.  The energies serve the strain-energy diagnostic
 * (reduction.cl). */
#ifndef SPH_HYPERELASTIC_H
#define SPH_HYPERELASTIC_H
#include "sph_vec.h"

#if SPH_HAS_TLSPH

/* Saint Venant-Kirchhoff (004 eq. 24): P = F S, S = lambda tr(E) I + 2 mu E,
 * E = (F^T F - I)/2, lambda = K - 2G/3 also in 2D (plane strain, as 004;
 * host/model/feature_set.c). */
FN mat tl_svk_pk1(const mat f, const real lambda, const real mu) {
    mat e = mat_scale(mat_mul(mat_transpose(f), f), R(0.5));
    UNROLL for (int a = 0; a < SPH_DIM; ++a) e.m[a][a] -= R(0.5);
    mat s = mat_scale(e, R(2) * mu);
    const real tr = mat_trace(e);
    UNROLL for (int a = 0; a < SPH_DIM; ++a) s.m[a][a] += lambda * tr;
    return mat_mul(f, s);
}

#    if SPH_HAS_HYPERELASTIC
/* The hyperelastic laws of materials.X.model, as the second Piola-Kirchhoff
 * stress S = 2 d psi / d C, with C = F^T F, J = det F, I1 = tr C (in 2D
 * plane strain C_zz = 1, so I1 = tr C + 1), lambda = K - 2G/3 and mu = G:
 *  - "neo-hookean", compressible (Bonet & Wood, Nonlinear Continuum
 *    Mechanics for Finite Element Analysis, 2nd ed. 2008, eqs. 6.27-6.28;
 *    the rubber of 002 §2.2, seed digest §2):
 *      psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2,
 *      S = mu (I - C^-1) + lambda ln J C^-1,
 *    linear elasticity with (lambda, mu) at small strain;
 *  - "exponential": the isotropic term of Holzapfel & Ogden's (2009)
 *    myocardium law, a exp(b (I1 - 3)), with the public code's volumetric
 *    part (its Muscle material with a = G, which its bending column of 004
 *    §4.6 uses; eulerian-sph-reference.md §5.4):
 *      psi = a/(2b) (exp(b (I1 - 3)) - 1) - a (J - 1) + lambda/2 (J - 1)^2,
 *      S = a exp(b (I1 - 3)) I + (lambda (J - 1) - a) J C^-1,
 *    at small strain linear elasticity with mu = a and lambda + a (2b - 1)
 *    (the column, b = 1: K + G in place of K, E 17.05 MPa for 17.0).
 * P = F S.  A particle turned inside out (J <= 0) gives NaN (ln J) or
 * forces that the monitor reports (docs/stability.md). */
FN mat tl_hyperelastic_pk1(const mat f, CONSTANT sph_params *prm) {
    const mat c = mat_mul(mat_transpose(f), f);
    const mat c_inv = mat_inverse(c);
    const real det = mat_det(f);
    const real lambda = prm->materials[0].lambda, mu = prm->materials[0].shear_modulus;
    mat s;
    if (RUNTIME_ELASTIC_MODEL == ELASTIC_MODEL_NEO_HOOKEAN) {
        s = mat_scale(c_inv, lambda * log(det) - mu);
        UNROLL for (int a = 0; a < SPH_DIM; ++a) s.m[a][a] += mu;
    } else {
        /* as a (e^x - 1) I + a (I - J C^-1) + lambda (J - 1) J C^-1, x = b (I1 - 3):
         * expm1 keeps e^x - 1 accurate (to its own ulps, not 1's) at the small
         * strains of most particles, in single precision too */
        const real x = prm->materials[0].exponential_b * (mat_trace(c) - R(SPH_DIM));
        s = mat_scale(c_inv, (lambda * (det - R(1)) - mu) * det);
        const real iso = mu * expm1(x) + mu;
        UNROLL for (int a = 0; a < SPH_DIM; ++a) s.m[a][a] += iso;
    }
    return mat_mul(f, s);
}
#    endif

/* psi(F), the strain energy per reference volume of the material's law
 * (the laws above, lambda = K - 2G/3, mu = G); J <= 0 gives NaN. */
FN real tl_strain_energy(const mat f, CONSTANT sph_params *prm) {
    const mat c = mat_mul(mat_transpose(f), f);
    const real lambda = prm->materials[0].lambda, mu = prm->materials[0].shear_modulus;
#    if SPH_HAS_HYPERELASTIC
    const real det = mat_det(f);
    /* I1 - 3 = tr C - d in plane strain (C_zz = 1) and in 3D */
    const real i1_3 = mat_trace(c) - R(SPH_DIM);
    if (RUNTIME_ELASTIC_MODEL == ELASTIC_MODEL_NEO_HOOKEAN) {
        const real ln_j = log(det);
        return R(0.5) * mu * i1_3 - mu * ln_j + R(0.5) * lambda * ln_j * ln_j;
    }
    if (RUNTIME_ELASTIC_MODEL == ELASTIC_MODEL_EXPONENTIAL) {
        const real b = prm->materials[0].exponential_b;
        return mu / (R(2) * b) * expm1(b * i1_3) - mu * (det - R(1)) +
               R(0.5) * lambda * (det - R(1)) * (det - R(1));
    }
#    endif
    /* Saint Venant-Kirchhoff: lambda/2 (tr E)^2 + mu E:E */
    mat e = mat_scale(c, R(0.5));
    UNROLL for (int a = 0; a < SPH_DIM; ++a) e.m[a][a] -= R(0.5);
    const real tr = mat_trace(e);
    return R(0.5) * lambda * tr * tr + mu * mat_ddot(e, e);
}

#endif
#endif
