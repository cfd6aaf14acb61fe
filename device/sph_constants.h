/* sph_constants.h — constants shared by the host and the device code: the
 * discrete feature values and the layout of the parameter block.  Plain
 * macros only, so host C can include it without the device dialect. */
#ifndef SPH_CONSTANTS_H
#define SPH_CONSTANTS_H

/* Discrete feature values, shared by host and device. */
#define KERNEL_WENDLAND_C2 0

#define ROTATION_NONE         0 /* SPH-ENOG: a^s accumulates unrotated (000 eq. 24) */
#define ROTATION_AVERAGED     1 /* SPH-ENOG-A: a^s <- Rbar (a^s + da) (003 eqs. 41-42) */
#define ROTATION_PER_PARTICLE 2 /* reference code: a^s <- R_i a^s + da (003 eq. 34) */

#define FORMULATION_ENOG   0
#define FORMULATION_ENOG_A 1

/* Layout of the scalar parameter block `prm` (one real array, same on both
 * backends, filled by sph_params_fill in host/feature_set.c). */
#define PRM_H             0  /* smoothing length h */
#define PRM_CUTOFF        1  /* support radius 2h */
#define PRM_RHO0          2  /* reference density */
#define PRM_C0            3  /* artificial sound speed */
#define PRM_G             4  /* shear modulus */
#define PRM_K             5  /* bulk modulus rho0 c0^2 */
#define PRM_XI_E          6  /* ENOG coefficient xi_E (000 eq. 24) */
#define PRM_GRAVITY       7  /* 3 components */
#define PRM_ROTATION      10 /* CPU backend: run-time copy of SPH_ROTATION */
#define PRM_KERNEL        11 /* CPU backend: run-time copy of SPH_KERNEL */
#define PRM_RIEMANN_LIMIT 12 /* >0: truncated-linear limiter slope; 0: unlimited */
#define PRM_NBODIES       13 /* CPU backend: run-time copy of SPH_NBODIES */
#define PRM_DP            14 /* initial particle spacing */
#define PRM_BODY_COUNT    16 /* particles per body, SPH_MAX_BODIES entries */
#define SPH_MAX_BODIES    8
#define PRM_COUNT         (PRM_BODY_COUNT + SPH_MAX_BODIES)

#endif
