/* sph_constants.h — constants shared by the host and the device code: the
 * discrete feature values and the layout of the monitor's reduction (the
 * parameter block is sph_params.h).  Plain
 * macros only, so host C can include it without the device dialect. */
#ifndef SPH_CONSTANTS_H
#define SPH_CONSTANTS_H

/* Discrete feature values, shared by host and device. */
#define KERNEL_WENDLAND_C2       0 /* 000, 003: h = 1.3 dp, cut-off 2h */
#define KERNEL_LAGUERRE_GAUSS    1 /* 004 eq. 8, truncated at 2h */
#define KERNEL_LAGUERRE_WENDLAND 2 /* Litvinov et al. 2015 */
#define KERNEL_CUBIC_BSPLINE     3 /* Monaghan & Lattanzio 1985 */

#define ROTATION_NONE         0 /* SPH-ENOG: a^s accumulates unrotated (000 eq. 24) */
#define ROTATION_AVERAGED     1 /* SPH-ENOG-A: a^s <- Rbar (a^s + da) (003 eqs. 41-42) */
#define ROTATION_PER_PARTICLE 2 /* reference code: a^s <- R_i a^s + da (003 eq. 34) */

#define FORMULATION_ENOG   0 /* 000: Laplacian shear acceleration, eq. 24 */
#define FORMULATION_ENOG_A 1 /* 003: ENOG with the rotation, eqs. 38-42 */
#define FORMULATION_OG     2 /* 000 eqs. 17-18: nested stress divergence */
#define FORMULATION_OAS    3 /* OG + artificial stress (Gray, Monaghan & Swift 2001) */
#define FORMULATION_GNOG   4 /* 003 eqs. 43-45: stress divergence + penalty */
#define FORMULATION_GNOG_A 5 /* 003 eqs. 46-49, Algorithm 2 */
#define FORMULATION_TLSPH  6 /* total Lagrangian (001, 004 §3; hourglass control 002) */
/* 004 §3.1: extended Eulerian SPH for fluids, fixed particles (eulerian_step.cl) */
#define FORMULATION_EULERIAN_WC           7 /* weakly compressible, linearised Riemann solver */
#define FORMULATION_EULERIAN_COMPRESSIBLE 8 /* ideal gas, HLLC, energy equation */
/* The elastic law of TLSPH (materials.X.model; device/tl_step.cl).  The
 * updated-Lagrangian formulations are hypoelastic (Jaumann rate). */
#define ELASTIC_MODEL_SVK         0 /* Saint Venant-Kirchhoff, 004 eq. 24 (the default) */
#define ELASTIC_MODEL_NEO_HOOKEAN 1 /* compressible neo-Hookean (Bonet & Wood; 002) */
#define ELASTIC_MODEL_EXPONENTIAL 2 /* isotropic exponential (the public code's column) */
/* The yield stress (Pa) of an elastic material in a scene that also has a
 * plastic one (sph_materials.h): finite in single precision, and beyond any
 * stress a solid of this code reaches, so the J2 return never acts. */
#define SPH_NEVER_YIELDS 1e30
/* What a formulation computes (f: a FORMULATION_* value). */
#define FORM_IS_ENOG(f)        ((f) == FORMULATION_ENOG || (f) == FORMULATION_ENOG_A)
#define FORM_HAS_STRESS_DIV(f) ((f) >= FORMULATION_OG && (f) <= FORMULATION_GNOG_A)
#define FORM_HAS_PENALTY(f)    ((f) == FORMULATION_GNOG || (f) == FORMULATION_GNOG_A)
#define FORM_IS_EULERIAN(f)                                                                        \
    ((f) == FORMULATION_EULERIAN_WC || (f) == FORMULATION_EULERIAN_COMPRESSIBLE)

/* Particle kinds of fluid scenes with walls or a far field (field `kind`,
 * device/eulerian_step.cl; host/setup/particles.h) */
#define SPH_PARTICLE_FLUID   0 /* fluid */
#define SPH_PARTICLE_WALL    1 /* a particle of a wall body: at rest, bounds the fluid */
#define SPH_PARTICLE_INFLOW  2 /* far-field fluid, inflow face: free stream blended in */
#define SPH_PARTICLE_OUTFLOW 3 /* far-field fluid, outflow face */

/* Moments per body of the torque projection (device/sph_torque_projection.h,
 * TORQUE_NCOMP), for the host's buffer sizes: 18 in 2D, 34 in 3D. */
#define SPH_TORQUE_NCOMP(d) (3 * (d) + 1 + 2 * (d) * (d) + (d) * ((d) + 1) / 2)
/* Layout of the instability monitor's reduction (device/monitor.cl), all
 * components combined by max. */
#define SPH_MONITOR_NEG_MIN_DIST 0 /* -min_j r_ij / dp */
#define SPH_MONITOR_MISMATCH     1 /* max_i m_i, the velocity mismatch */
#define SPH_MONITOR_GRADV        2 /* max_i |L_i| */
#define SPH_MONITOR_NONFINITE    3 /* 1: some position or velocity is NaN/Inf */
#define SPH_MONITOR_MAX_X        4 /* max x (dim), then max -x (dim) */
#define SPH_MONITOR_NCOMP(dim)   (SPH_MONITOR_MAX_X + 2 * (dim))
#define SPH_MONITOR_NCOMP_MAX    SPH_MONITOR_NCOMP(3)

#endif
