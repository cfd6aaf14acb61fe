/* fields.h — the registry of per-particle fields.
 *
 * One table says which per-particle arrays exist for a feature set, their
 * element type and component count.  Backends allocate from it (and only what
 * is present), the rebuild permutes every present field into the cell order,
 * output and tests download by field, and summary.json reports the bytes of
 * each buffer.  A field's name is also the name of the kernel parameter it is
 * bound to (see opencl_runtime.c).
 */
#ifndef SPH_FIELDS_H
#define SPH_FIELDS_H

#include "feature_set.h"

#include <stdbool.h>
#include <stddef.h>

typedef enum {
    FIELD_POS,            /* position x */
    FIELD_VEL,            /* velocity v */
    FIELD_RHO,            /* density */
    FIELD_DRHO,           /* density rate from the continuity equation */
    FIELD_MASS,           /* mass (constant) */
    FIELD_VOL,            /* volume m/rho, refreshed at each rebuild */
    FIELD_ACC_DISS,       /* Riemann dissipation acceleration (lags one substep) */
    FIELD_ACC_SHEAR,      /* accumulated shear acceleration a^s */
    FIELD_DACC_SHEAR,     /* pending increment da^s (averaged rotation only) */
    FIELD_SPIN,           /* spin components (averaged rotation only) */
    FIELD_TAU,            /* deviatoric (shear) stress, symmetric */
    FIELD_BMAT,           /* kernel-gradient correction matrix B, symmetric */
    FIELD_ID,             /* particle id: its index in the initial set */
    FIELD_BODY,           /* body index (scenes with several bodies) */
    FIELD_MATERIAL,       /* row of the material table (scenes with several materials) */
    FIELD_FIXED,          /* constraint of the particle + 1 (0: free; sph_constraints.h) */
    FIELD_ACC_STRESS,     /* stress-divergence acceleration (OG, OAS, GNOG, GNOG-A) */
    FIELD_GRADV,          /* velocity gradient L, full d x d (GNOG, GNOG-A: L_j in eq. 44) */
    FIELD_ART_STRESS,     /* artificial stress R, symmetric (OAS) */
    FIELD_PLASTIC_STRAIN, /* J2 hardening variable alpha: equivalent plastic strain */
    FIELD_PENALTY_SCALE,  /* per-particle penalty coefficient s_i (plastic GNOG family) */
    FIELD_PK1,            /* first Piola-Kirchhoff stress P, full d x d (TLSPH) */
    FIELD_DEFGRAD,        /* deformation gradient F, full d x d (TLSPH) */
    FIELD_PLASTIC_CINV,   /* plastic TLSPH: C_p^-1 - I, symmetric, then (2D) its zz component */
    FIELD_CONTACT_COUNT,  /* contact neighbours (other bodies) of the last rebuild (contact) */
    /* fluids (device/eulerian_step.cl): FIELD_MASS is the conserved mass
     * rho w there, FIELD_VOL the fixed volume w */
    FIELD_PRESSURE,    /* pressure p, by the EOS */
    FIELD_VEL_STAGE,   /* the second stage's velocity v + dt F / m (F = d(m v)/dt) */
    FIELD_MASS_RATE,   /* dm/dt */
    FIELD_ENERGY,      /* total energy of the particle, E w (compressible) */
    FIELD_ENERGY_RATE, /* d(E w)/dt (compressible) */
    FIELD_SOUND_SPEED, /* sqrt(gamma p / rho) (compressible) */
    FIELD_VORTICITY,   /* curl v (2D: its z component) */
    FIELD_KIND,        /* SPH_PARTICLE_* (walls or a far field) */
    FIELD_NORMAL,      /* wall particles: normal into the fluid; far field: outward */
    FIELD_WALL_FORCE,  /* the wall pairs' share of d(m v)/dt: pressure (d), viscous (d) */
    /* fluids with time.integrator = "ssp-rk2" or "ssp-rk3" (eulerian_rates) */
    FIELD_MOMENTUM_RATE, /* d(m v)/dt */
    FIELD_STATE_SAVED,   /* the step's start: m, m v (d), E w (compressible) */
    FIELD_COUNT
} sph_field;

/* REAL: in the run's arithmetic precision; HREAL: a history field (device/
 * sph_prelude.h), double in double and mixed precision, float in single. */
typedef enum { FIELD_TYPE_REAL, FIELD_TYPE_HREAL, FIELD_TYPE_INT32, FIELD_TYPE_U8 } sph_field_type;

typedef struct {
    const char *name;
    sph_field_type type;
    int components;
    bool present;
} sph_field_info;

/* Fill the registry for a feature set. */
void sph_fields_layout(const sph_features *f, sph_field_info out[FIELD_COUNT]);

/* Bytes of one element of a field of this type in a run of this feature set. */
size_t sph_field_element_size(sph_field_type type, const sph_features *f);

/* A floating-point field (REAL or HREAL): transferred to the host as double. */
bool sph_field_is_real(sph_field_type type);
/* A field the steps do not keep: the backend forms it from the state when
 * it is downloaded (the fluids' vorticity, eulerian_vorticity); no part of
 * the state, so checkpoints leave it out. */
bool sph_field_is_derived(sph_field f);

#endif
