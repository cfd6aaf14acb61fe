/* sph_constants.h — constants shared by the host and the device code: the
 * discrete feature values and the layout of the parameter block.  Plain
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
/* What a formulation computes (f: a FORMULATION_* value). */
#define FORM_IS_ENOG(f)        ((f) == FORMULATION_ENOG || (f) == FORMULATION_ENOG_A)
#define FORM_HAS_STRESS_DIV(f) ((f) >= FORMULATION_OG && (f) <= FORMULATION_GNOG_A)
#define FORM_HAS_PENALTY(f)    ((f) == FORMULATION_GNOG || (f) == FORMULATION_GNOG_A)

/* Layout of the scalar parameter block `prm` (one real array, same on both
 * backends, filled by sph_params_fill in host/feature_set.c). */
#define PRM_H                 0  /* smoothing length h */
#define PRM_CUTOFF            1  /* support radius 2h */
#define PRM_RHO0              2  /* reference density */
#define PRM_C0                3  /* artificial sound speed */
#define PRM_G                 4  /* shear modulus */
#define PRM_K                 5  /* bulk modulus rho0 c0^2 */
#define PRM_XI_E              6  /* ENOG coefficient xi_E (000 eq. 24) */
#define PRM_GRAVITY           7  /* 3 components */
#define PRM_ROTATION          10 /* CPU backend: run-time copy of SPH_ROTATION */
#define PRM_KERNEL            11 /* CPU backend: run-time copy of SPH_KERNEL */
#define PRM_RIEMANN_LIMIT     12 /* >0: truncated-linear limiter slope; 0: unlimited */
#define PRM_NBODIES           13 /* CPU backend: run-time copy of SPH_NBODIES */
#define PRM_DP                14 /* initial particle spacing */
#define PRM_FORMULATION       15 /* CPU backend: run-time copy of SPH_FORMULATION */
#define PRM_PLASTIC           16 /* CPU backend: run-time copy of SPH_PLASTIC */
#define PRM_XI_G              17 /* GNOG penalty coefficient xi_G (003 eqs. 43, 46) */
#define PRM_YIELD             18 /* J2 initial yield stress sigma_Y (003 eq. 11) */
#define PRM_HARDENING         19 /* J2 linear isotropic hardening modulus kappa */
#define PRM_ART_EPS           20 /* OAS artificial-stress coefficient epsilon */
#define PRM_ART_N             21 /* OAS exponent n of f = W(r)/W(dp) */
#define PRM_ART_WDP           22 /* W(dp) of the kernel in use */
#define PRM_HOURGLASS         23 /* TLSPH hourglass-control coefficient alpha (002) */
#define PRM_LAMBDA            24 /* Lame's first parameter (TLSPH Saint Venant-Kirchhoff) */
#define PRM_TORQUE_PROJECTION 26 /* CPU backend: run-time copy of SPH_TORQUE_PROJECTION */
#define PRM_BODY_COUNT        32 /* particles per body, SPH_MAX_BODIES entries */
#define SPH_MAX_BODIES        8
/* Moments per body of the torque projection (device/sph_torque_projection.h,
 * TORQUE_NCOMP), for the host's buffer sizes: 18 in 2D, 34 in 3D. */
#define SPH_TORQUE_NCOMP(d) (3 * (d) + 1 + 2 * (d) * (d) + (d) * ((d) + 1) / 2)
/* the constraint table: constraint k (particles whose `fixed` is k + 1)
 * holds PRM_CONSTRAINT_STRIDE values from PRM_CONSTRAINT + k * stride: the
 * mask of its constrained axes (bit a: axis a) and the velocity prescribed
 * along them (3 values; 0 for a fixed constraint) */
#define PRM_CONSTRAINT        (PRM_BODY_COUNT + SPH_MAX_BODIES)
#define PRM_CONSTRAINT_STRIDE 4
#define SPH_MAX_CONSTRAINTS   16
/* the wall table (device/sph_wall.h): PRM_WALL_COUNT walls, wall w holds
 * PRM_WALL_STRIDE values from PRM_WALL + w * stride: a point of its plane
 * (3 values) and its unit normal into the solid (3 values) */
#define PRM_WALL_COUNT  25
#define PRM_WALL        (PRM_CONSTRAINT + SPH_MAX_CONSTRAINTS * PRM_CONSTRAINT_STRIDE)
#define PRM_WALL_STRIDE 6
#define SPH_MAX_WALLS   6
#define PRM_COUNT       (PRM_WALL + SPH_MAX_WALLS * PRM_WALL_STRIDE)

/* Layout of the instability monitor's reduction (device/monitor.cl), all
 * components combined by max. */
#define SPH_MONITOR_NEG_MIN_DIST 0 /* -min_j r_ij / dp */
#define SPH_MONITOR_MISMATCH     1 /* max_i m_i, the velocity mismatch */
#define SPH_MONITOR_GRADV        2 /* max_i |L_i| */
#define SPH_MONITOR_NONFINITE    3 /* 1: some position or velocity is NaN/Inf */
#define SPH_MONITOR_MAX_X        4 /* max x (dim), then max -x (dim) */
#define SPH_MONITOR_NCOMP(dim)   (SPH_MONITOR_MAX_X + 2 * (dim))
#define SPH_MONITOR_NCOMP_MAX    SPH_MONITOR_NCOMP(3)

/* Contact between bodies (device/sph_contact.h), in free slots of the
 * parameter block below PRM_BODY_COUNT: the factors of the impedance term
 * (x 1/2 rho0 c0) and of the penalty (x rho0 c0^2); 1 and 1 by default. */
#define PRM_CONTACT_IMPEDANCE 30
#define PRM_CONTACT_PENALTY   31

#endif
