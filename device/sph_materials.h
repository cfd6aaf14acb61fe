/* sph_materials.h — the material of a particle, and the coefficients of a
 * pair of particles of two materials (docs/method.md, "Several materials").
 *
 * A scene of one material has no material-id buffer: every particle reads
 * row 0 of the material table (in OpenCL a compile-time 0, so the
 * arithmetic is that of a one-material program).  With several materials
 * (OpenCL: -DSPH_MATERIALS=k, k > 1; the native backend: whenever the
 * buffer is present) particle i reads row material[i].
 *
 * A pair of two materials, i and j, takes:
 *  - the acoustic Riemann dissipation with each side's impedance
 *    Z = rho0 c0: the linearised Riemann problem of two acoustic media has
 *    the interface pressure
 *        P* = (Z_j p_i + Z_i p_j)/(Z_i + Z_j) - Z_i Z_j/(Z_i + Z_j) u_ij
 *    (Toro, Riemann Solvers and Numerical Methods for Fluid Dynamics, 3rd
 *    ed. 2009, §9.3; the interface state of Rezavand, Zhang & Hu, J. Comput.
 *    Phys. 402 (2020) 109092), so the dissipation coefficient Z/2 of one
 *    material (sph_riemann.h) becomes Z_i Z_j/(Z_i + Z_j), half the harmonic
 *    mean of the impedances.  The non-dissipative part keeps the sum form
 *    (p_i + p_j, tau_i + tau_j): it gives no force where the stress is
 *    uniform across the interface, which a bonded interface in equilibrium
 *    has (traction continuity), and it is momentum exact;
 *  - the harmonic mean 2 G_i G_j/(G_i + G_j) of the shear moduli in the
 *    Laplacian-type shear terms (ENOG's eq. 24 of 000, GNOG's penalty, 003
 *    eq. 43): the flux of a diffusion operator is continuous across a jump
 *    of its coefficient with the harmonic mean (Cleary & Monaghan, J.
 *    Comput. Phys. 148 (1999) 227, their k_ij);
 *  - contact: the impedance part with Z_i Z_j/(Z_i + Z_j) (the share of the
 *    approach speed each side takes up, 1/2 for one material) and the
 *    penalty with the harmonic mean of the bulk moduli (two springs in
 *    series);
 *  - the limiter's sound speed (c_i + c_j)/2.
 * Each coefficient is formed as a_i times a ratio that is exactly 1 for two
 * particles of one material (2a/(a + a) = 1 in floating point), so pairs of
 * one material keep the bits of a one-material scene.  J2 plasticity is
 * per particle: each reads its own yield stress and hardening, and an
 * elastic material in a scene with a plastic one has the yield stress
 * SPH_NEVER_YIELDS (sph_constants.h). */
#ifndef SPH_MATERIALS_H
#define SPH_MATERIALS_H

#if SPH_HAS_MATERIAL_IDS
#    define MATERIAL_PARAMS , GLOBAL const u8 *restrict material
#    define MATERIAL_ARG    , material
#    define MATERIAL_OF(i)  (PRESENT(material) ? (int)material[i] : 0)
/* 1 when this run's particles carry material ids */
#    define MATERIALS_VARY PRESENT(material)
#else
#    define MATERIAL_PARAMS
#    define MATERIAL_ARG
#    define MATERIAL_OF(i) 0
#    define MATERIALS_VARY 0
#endif
/* The table row of material m (prm in scope). */
#define MATERIAL_ROW(m) (&prm->materials[(m)])

/* a_ij / a_i for the harmonic mean a_ij = 2 a_i a_j / (a_i + a_j): exactly
 * 1 when a_i = a_j */
FN real harmonic_ratio(const real a_i, const real a_j) {
    return R(2) * a_j / (a_i + a_j);
}

/* Z_i Z_j/(Z_i + Z_j) / (Z_i / 2) = harmonic_ratio(Z_i, Z_j): the pair's
 * dissipation over the one-material dissipation of i */
FN real impedance_ratio(CONSTANT sph_params_material *mi, CONSTANT sph_params_material *mj) {
    return harmonic_ratio(mi->rho0 * mi->c0, mj->rho0 * mj->c0);
}

#endif
