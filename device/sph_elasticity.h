/* sph_elasticity.h — constitutive relations of the elastic solid.
 *
 * Pressure from the artificial equation of state (000 eq. 4, 003 eq. 4),
 * deviatoric (shear) stress from the Jaumann rate (003 eq. 8), and the derived
 * output quantities: von Mises stress and the elastic energy density.
 */
#ifndef SPH_ELASTICITY_H
#define SPH_ELASTICITY_H
#include "sph_vec.h"

/* p = c0^2 (rho - rho0); rho - rho0 is taken in the density's (history)
 * precision, before it rounds to real */
FN real eos_pressure(CONSTANT real *prm, const hreal rho) {
    const real c0 = prm[PRM_C0];
    return c0 * c0 * (real)(rho - (hreal)prm[PRM_RHO0]);
}

/* The pressure at the density half-step, p(rho + dt/2 drho), which the
 * pressure pass evaluates for every neighbour.  In mixed precision the
 * history density costs one double operation there, the excess over rho0;
 * the half-step increment is small beside it and added in single.  (GPUs
 * without full-rate double run that one operation per pair slowly.) */
FN real half_step_pressure(CONSTANT real *prm, const hreal rho, const real drho,
                           const real half_dt) {
#if SPH_MIXED && !SPH_DOUBLE
    const real c0 = prm[PRM_C0];
    return c0 * c0 * ((real)(rho - (hreal)prm[PRM_RHO0]) + half_dt * drho);
#else
    return eos_pressure(prm, rho + half_dt * drho);
#endif
}

/* The increment of one explicit Euler step of the Jaumann rate, 003 eq. 8:
 *   dtau/dt = 2G D' + tau Omega^T + Omega tau,
 * D = (L + L^T)/2, D' = D - tr(D)/d I, Omega = (L - L^T)/2,
 * with L_ab = dv_a/dx_b (003 eqs. 9-10).  In 2D the model is the in-plane
 * one of the papers (d = 2 in the deviator; no out-of-plane component). */
FN_HOT mat jaumann_increment(const mat tau, const mat grad_v, const real shear_modulus,
                             const real dt) {
    const mat lt = mat_transpose(grad_v);
    const mat d = mat_scale(mat_add(grad_v, lt), R(0.5));
    const mat omega = mat_scale(mat_add(grad_v, mat_scale(lt, R(-1))), R(0.5));
    mat dev = d;
    const real tr = mat_trace(d) / R(SPH_DIM);
    for (int a = 0; a < SPH_DIM; ++a) dev.m[a][a] -= tr;
    const mat rate = mat_add(mat_scale(dev, R(2) * shear_modulus),
                             mat_add(mat_mul(tau, mat_transpose(omega)), mat_mul(omega, tau)));
    return mat_scale(rate, dt);
}

/* The Jaumann step itself: tau + dtau */
FN mat jaumann_update(const mat tau, const mat grad_v, const real shear_modulus, const real dt) {
    return mat_add(tau, jaumann_increment(tau, grad_v, shear_modulus, dt));
}

/* Spin tensor of a velocity gradient. */
FN mat spin_of(const mat grad_v) {
    return mat_scale(mat_add(grad_v, mat_scale(mat_transpose(grad_v), R(-1))), R(0.5));
}

/* von Mises stress of sigma = tau - p I (reference notes §3.9): in 2D the
 * plane formula with sigma_zz = 0, in 3D the full one. */
FN real von_mises(const mat tau, const real p) {
    mat s = tau;
    for (int a = 0; a < SPH_DIM; ++a) s.m[a][a] -= p;
#if SPH_DIM == 2
    return sqrt(fmax(s.m[0][0] * s.m[0][0] + s.m[1][1] * s.m[1][1] - s.m[0][0] * s.m[1][1] +
                         R(3) * s.m[0][1] * s.m[0][1],
                     R(0)));
#else
    const real xx = s.m[0][0], yy = s.m[1][1], zz = s.m[2][2];
    return sqrt(
        fmax(xx * xx + yy * yy + zz * zz - xx * yy - xx * zz - yy * zz +
                 R(3) * (s.m[0][1] * s.m[0][1] + s.m[0][2] * s.m[0][2] + s.m[1][2] * s.m[1][2]),
             R(0)));
#endif
}

/* Elastic energy per unit volume of linear isotropic elasticity split into
 * its deviatoric and volumetric parts: tau:tau/(4G) + p^2/(2K). */
FN real strain_energy_density(const mat tau, const real p, const real shear_modulus,
                              const real bulk_modulus) {
    return mat_ddot(tau, tau) / (R(4) * shear_modulus) + p * p / (R(2) * bulk_modulus);
}

#endif
