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
FN real eos_pressure(CONSTANT sph_params_material *props, const hreal rho) {
    const real c0 = props->c0;
    return c0 * c0 * (real)(rho - (hreal)props->rho0);
}

/* The pressure at the density half-step, p(rho + dt/2 drho), which the
 * pressure pass evaluates for every neighbour.  In double it is taken as
 * written.  In single and mixed precision the excess over rho0 is taken
 * first, exactly (in single by Sterbenz's lemma, for rho0/2 <= rho <= 2
 * rho0; in mixed it is the one double operation per pair), and the small
 * half-step increment is added to it in real: rho + dt/2 drho rounded to
 * float would quantise the density in steps of ulp(rho0) (6.1e-5 for rho0 =
 * 1000), and the pressure in steps of c0^2 ulp(rho0), while a substep
 * changes the density by only a few such steps (see density_advance).  That
 * rounding moved single precision's first period of the plate (H/dp = 20,
 * v_f = 0.05) by +0.084 % of the +0.223 % it was off double
 * (docs/benchmarks.md, "Precision modes").  (GPUs without full-rate double
 * run mixed precision's one operation per pair slowly.) */
FN real half_step_pressure(CONSTANT sph_params_material *props, const hreal rho, const real drho,
                           const real half_dt) {
#if SPH_DOUBLE
    return eos_pressure(props, rho + half_dt * drho);
#else
    const real c0 = props->c0;
    return c0 * c0 * ((real)(rho - (hreal)props->rho0) + half_dt * drho);
#endif
}

/* The density at the end of a substep, rho^{n+1} = rho^{n+1/2} + dt/2 drho^{n+1}
 * (000 eq. 29) with rho^{n+1/2} = rho^n + dt/2 drho^n, from rho^n and the two
 * rates.  In single precision (the history fields in float) the two half-step
 * increments are summed first, rho^n + dt/2 (drho^n + drho^{n+1}), so that the
 * density rounds once per substep, not twice: on the plate (v_f = 0.05) the
 * median particle's density changes by about 3 ulp(rho0) per substep at
 * H/dp = 10 (1.6 kg/m^3 in 0.1 s, 5 662 substeps; the acoustic step, and so
 * the change per substep, shrinks as dp), so each rounding is a large part
 * of the increment.  Measured with half_step_pressure above: the
 * plate's first period at H/dp = 20 in single went from +0.139 % to +0.024 %
 * off double (docs/benchmarks.md, "Precision modes").  Double and mixed (rho
 * in double) take the two half-steps as written. */
FN hreal density_advance(const hreal rho, const real drho_old, const real drho_new,
                         const real half_dt) {
#if SPH_DOUBLE || SPH_MIXED
    return (rho + half_dt * drho_old) + half_dt * drho_new;
#else
    return rho + half_dt * (drho_old + drho_new);
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
    UNROLL for (int a = 0; a < SPH_DIM; ++a) dev.m[a][a] -= tr;
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
    UNROLL for (int a = 0; a < SPH_DIM; ++a) s.m[a][a] -= p;
#if SPH_DIM == 1
    return fabs(s.m[0][0]); /* uniaxial stress */
#elif SPH_DIM == 2
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
