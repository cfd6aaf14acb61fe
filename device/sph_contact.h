/* sph_contact.h — the contact force between particles of different bodies.
 *
 * In a scene with several bodies (SPH_HAS_CONTACT) bodies do not merge: the
 * rebuild keeps two lists per particle (neighbour_build.cl), its own body's
 * neighbours, which every continuum term sums over (continuity, Riemann
 * pressure and dissipation, velocity gradient and B, shear terms, the body's
 * mean rotation), and its contact neighbours: the particles of other bodies
 * within the cut-off 2h.  Between those acts only this force, frictionless
 * and along the line of centres, from the current positions and velocities
 * of the pair (x_ij = x_i - x_j, r = |x_ij|, e_ij = x_ij / r from j to i,
 * u_ij = (v_i - v_j).e_ij, negative while the pair approaches):
 *
 *   m_i a_i = -2 sum_j p_ij min(dW(r), 0) V_i V_j e_ij,
 *   p_ij    = c_Z (1/2) rho0 c0 max(0, -u_ij)  +  c_K rho0 c0^2 max(0, 1 - r/dp)^2,
 *
 * the public reference code's contact of solids against walls (its Taylor
 * bar, reference notes §6.5: an impedance term proportional to the
 * approaching normal velocity plus a penalty that switches on at a
 * particle-scale gap, stiffness rho0 c0^2, applied like a pressure) written
 * for two deformable bodies, with e_ij as the normal:
 *
 *  - impedance: (1/2) rho0 c0 |u| is the interface pressure of the acoustic
 *    Riemann problem of two equal media that meet at the relative speed |u|
 *    (000 eqs. 11-14 with p_L = p_R = 0), so the surfaces stop the way two
 *    colliding elastic bodies do; it acts only while the pair approaches
 *    (no adhesion) and its power, sum over pairs of
 *    2 p dW V_i V_j u = -c_Z rho0 c0 |dW| V_i V_j u^2 (u < 0), is never
 *    positive: it only dissipates;
 *  - penalty: particles of two bodies whose lattice cells overlap (r < dp;
 *    lattice neighbours across a touching face sit at r = dp and feel none)
 *    repel with the pressure K (1 - r/dp)^2, K = rho0 c0^2 the contact
 *    stiffness of the reference (its material's bulk modulus), with the
 *    reference's quadratic ramp.  The reference's wall contact switches on
 *    when a particle's centre comes within half a wall spacing of a wall
 *    particle's centre, i.e. once it has crossed the wall's surface, and
 *    scales the ramp by 0.1 |overlap|; between two deformable bodies of
 *    equal spacing the switch is the touching distance dp itself, and the
 *    full stiffness K keeps a pressed contact to a fraction of a spacing.
 *    The penalty depends on r alone: it is the force of the pair potential
 *    phi(r) = int_r^dp 2 p(s) |dW(s)| V_i V_j ds and creates no energy.
 *    The quadratic ramp makes the force smooth (C1) at r = dp, which keeps
 *    the time integration's energy error small: a pair bouncing at 0.05 c0
 *    keeps its kinetic energy to 1.3e-4 at the acoustic CFL 0.4, where a
 *    linear ramp K (1 - r/dp) (a kink in the force) gained 2.3 % (linear:
 *    +2.9 % to -4.7 % over 0.02 to 0.1 c0; quadratic: within 7e-4).
 *
 * Every pair term is antisymmetric (e_ji = -e_ij exactly, u and p symmetric,
 * and the contact lists are symmetric), so linear momentum is conserved to
 * round-off; a central force also conserves angular momentum.  Time
 * integration: acoustic_contact evaluates the force at the half-step
 * positions x^{n+1/2} = x^n + dt/2 v^n of both particles (with the
 * velocities v^n in u), which is where position Verlet (000 eqs. 27-29)
 * takes a force that depends on the positions, and adds it to the
 * acceleration of the velocity update.  (Taken at x^n instead, the update
 * v^{n+1} = v^n + dt a(x^n), x^{n+1} = x^n + dt/2 (v^n + v^{n+1}) multiplies
 * the energy of a spring by 1 + (omega dt)^2 / 2 per step.)
 * c_Z = contact.impedance and c_K = contact.penalty (1, 1 by default;
 * docs/scene-format.md).
 *
 * Between bodies of two materials (sph_materials.h) the impedance part is
 * c_Z Z_i Z_j/(Z_i + Z_j) max(0, -u_ij), the interface pressure of the
 * acoustic Riemann problem of the two media, and the penalty's K the
 * harmonic mean of the two bulk moduli; both are the same for i and j up to
 * round-off, so momentum stays exact to round-off (cases/impact_two_materials:
 * 2e-15).
 */
#ifndef SPH_CONTACT_H
#define SPH_CONTACT_H

#include "sph_vec.h"
#include "sph_smoothing_kernel.h"
#include "sph_materials.h"

/* The two parts of a contact pressure, shared with the rigid walls
 * (sph_wall.h), for a particle of the material `props`.  Impedance: c_Z rho0 c0
 * times the share of the normal velocity u_n (< 0: approaching) that the
 * interface takes up (1/2 between two bodies of one material, Z_j/(Z_i +
 * Z_j) between two materials, 1 against a rigid wall). */
FN real contact_impedance_pressure(CONSTANT sph_params *prm, CONSTANT sph_params_material *props,
                                   const real share, const real u_n) {
    return u_n < R(0) ? -share * prm->contact_impedance * props->rho0 * props->c0 * u_n : R(0);
}
/* Penalty: c_K K (1 - gap / reach)^2 once the gap is below its reach, with
 * K the bulk modulus times `stiffness` (1 for one material, the harmonic
 * mean's ratio between two, sph_materials.h). */
FN real contact_penalty_pressure(CONSTANT sph_params *prm, CONSTANT sph_params_material *props,
                                 const real stiffness, const real gap, const real reach) {
    if (!(gap < reach)) return R(0);
    const real overlap = R(1) - gap / reach;
    return prm->contact_penalty * (props->bulk_modulus * stiffness) * overlap * overlap;
}

/* Contact pressure p_ij of a pair at distance r approaching at -u; mi and
 * mj the materials of i and j (the same row for one material). */
FN real contact_pair_pressure(CONSTANT sph_params *prm, CONSTANT sph_params_material *mi,
                              CONSTANT sph_params_material *mj, const real r, const real u) {
    if (mi == mj)
        return contact_impedance_pressure(prm, mi, R(0.5), u) +
               contact_penalty_pressure(prm, mi, R(1), r, prm->dp);
    /* two materials: Z_i Z_j/(Z_i + Z_j) = (Z_j/(Z_i + Z_j)) Z_i, the
     * harmonic mean of K (sph_materials.h) */
    const real z_i = mi->rho0 * mi->c0, z_j = mj->rho0 * mj->c0;
    return contact_impedance_pressure(prm, mi, z_j / (z_i + z_j), u) +
           contact_penalty_pressure(prm, mi, harmonic_ratio(mi->bulk_modulus, mj->bulk_modulus), r,
                                    prm->dp);
}

#if SPH_HAS_CONTACT
/* Contact acceleration of particle i: its contact neighbours fill the top
 * of its neighbour row, slots cap - 1, cap - 2, ... (neighbour_build.cl). */
FN vec contact_acceleration(const int i, const int n, const int cap, const real half_dt,
                            CONSTANT sph_params *prm, GLOBAL const int *restrict nbr_j,
                            GLOBAL const int *restrict contact_count,
                            GLOBAL const hreal *restrict pos, GLOBAL const real *restrict vel,
                            GLOBAL const real *restrict mass,
                            GLOBAL const real *restrict vol MATERIAL_PARAMS) {
    const vec v_i = vec_load(vel, n, i);
    CONSTANT sph_params_material *mat_i = MATERIAL_ROW(MATERIAL_OF(i));
    const real cutoff = prm->cutoff;
    vec sum = vec_zero();
    const int count = contact_count[i];
    for (int k = 0; k < count; ++k) {
        const int j = nbr_j[NBR_AT(i, cap - 1 - k)];
        const vec v_j = vec_load(vel, n, j);
        /* at the half step, (x_i - x_j) + dt/2 (v_i - v_j): d_ji = -d_ij */
        const vec d = vec_axpy(hvec_diff(pos, n, i, j), half_dt, vec_sub(v_i, v_j));
        const real r2 = vec_dot(d, d);
        if (r2 >= cutoff * cutoff || r2 <= R(0)) continue;
        const real r = sqrt(r2);
        const vec e = vec_scale(d, R(1) / r);
        const real u = vec_dot(vec_sub(v_i, v_j), e);
        const real p = contact_pair_pressure(prm, mat_i, MATERIAL_ROW(MATERIAL_OF(j)), r, u);
        /* the Laguerre kernels' dW turns positive beyond r = 1.41 h: a
         * contact only pushes, so those pairs do not count */
        const real dw = fmin(kernel_dw(prm, r), R(0));
        sum = vec_axpy(sum, R(-2) * p * dw * vol[j], e);
    }
    return vec_scale(sum, vol[i] / mass[i]);
}
#endif

#endif
