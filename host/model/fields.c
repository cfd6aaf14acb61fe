#include "fields.h"

#include "sph_constants.h"

#include <stdint.h>

void sph_fields_layout(const sph_features *f, sph_field_info out[FIELD_COUNT]) {
    const int d = f->dim;
    const int nsym = d * (d + 1) / 2;
    const int nspin = sph_spin_components(d);
    const bool averaged = f->rotation == SPH_ROTATION_AVERAGED;
    const int form = (int)f->formulation;
    /* fluids have neither the solid's stresses nor its acoustic terms */
    const bool fluid = FORM_IS_EULERIAN(form), solid = !fluid;
    const bool compressible = form == FORMULATION_EULERIAN_COMPRESSIBLE;
    const sph_field_info table[FIELD_COUNT] = {
        [FIELD_POS] = {"pos", FIELD_TYPE_HREAL, d, true},
        [FIELD_VEL] = {"vel", FIELD_TYPE_REAL, d, true},
        [FIELD_RHO] = {"rho", FIELD_TYPE_HREAL, 1, true},
        [FIELD_DRHO] = {"drho", FIELD_TYPE_REAL, 1, solid},
        [FIELD_MASS] = {"mass", FIELD_TYPE_REAL, 1, true},
        [FIELD_VOL] = {"vol", FIELD_TYPE_REAL, 1, true},
        [FIELD_ACC_DISS] = {"acc_diss", FIELD_TYPE_REAL, d, solid},
        [FIELD_ACC_SHEAR] = {"acc_shear", FIELD_TYPE_HREAL, d, solid},
        [FIELD_DACC_SHEAR] = {"dacc_shear", FIELD_TYPE_REAL, d, averaged},
        [FIELD_SPIN] = {"spin", FIELD_TYPE_REAL, nspin, averaged},
        [FIELD_TAU] = {"tau", FIELD_TYPE_HREAL, nsym, solid},
        [FIELD_BMAT] = {"bmat", FIELD_TYPE_REAL, nsym, true},
        [FIELD_ID] = {"id", FIELD_TYPE_INT32, 1, true},
        [FIELD_BODY] = {"body", FIELD_TYPE_U8, 1, f->nbodies > 1},
        [FIELD_MATERIAL] = {"material", FIELD_TYPE_U8, 1, f->materials > 1},
        [FIELD_FIXED] = {"fixed", FIELD_TYPE_U8, 1, f->has_clamp},
        [FIELD_ACC_STRESS] = {"acc_stress", FIELD_TYPE_REAL, d, FORM_HAS_STRESS_DIV(form)},
        [FIELD_GRADV] = {"gradv", FIELD_TYPE_REAL, d * d, FORM_HAS_PENALTY(form)},
        [FIELD_ART_STRESS] = {"art_stress", FIELD_TYPE_REAL, nsym, form == FORMULATION_OAS},
        [FIELD_PLASTIC_STRAIN] = {"plastic_strain", FIELD_TYPE_REAL, 1, f->plastic},
        [FIELD_PENALTY_SCALE] = {"penalty_scale", FIELD_TYPE_REAL, 1,
                                 f->plastic && FORM_HAS_PENALTY(form)},
        [FIELD_PK1] = {"pk1", FIELD_TYPE_REAL, d * d, form == FORMULATION_TLSPH},
        [FIELD_DEFGRAD] = {"defgrad", FIELD_TYPE_REAL, d * d, form == FORMULATION_TLSPH},
        /* finite-strain J2 of TLSPH (device/sph_plasticity.h): C_p^-1 stored
         * as C_p^-1 - I, so that the zero fill of the upload is C_p^-1 = I;
         * 2D is plane strain, which adds (C_p^-1)_zz */
        [FIELD_PLASTIC_CINV] = {"plastic_cinv", FIELD_TYPE_REAL, d == 2 ? nsym + 1 : nsym,
                                f->plastic && form == FORMULATION_TLSPH},
        /* bodies that do not merge: the contact neighbours of each particle
         * sit at the top of its neighbour row (device/sph_contact.h) */
        [FIELD_CONTACT_COUNT] = {"contact_count", FIELD_TYPE_INT32, 1, f->contact},
        [FIELD_PRESSURE] = {"pressure", FIELD_TYPE_REAL, 1, fluid},
        [FIELD_VEL_STAGE] = {"vel_stage", FIELD_TYPE_REAL, d, fluid && !f->fluid_rk},
        [FIELD_MASS_RATE] = {"mass_rate", FIELD_TYPE_REAL, 1, fluid},
        [FIELD_ENERGY] = {"energy", FIELD_TYPE_REAL, 1, compressible},
        [FIELD_ENERGY_RATE] = {"energy_rate", FIELD_TYPE_REAL, 1, compressible},
        [FIELD_SOUND_SPEED] = {"sound_speed", FIELD_TYPE_REAL, 1, compressible},
        [FIELD_VORTICITY] = {"vorticity", FIELD_TYPE_REAL, nspin, fluid && f->fluid_vorticity},
        [FIELD_KIND] = {"kind", FIELD_TYPE_U8, 1, fluid && f->fluid_kinds},
        [FIELD_NORMAL] = {"normal", FIELD_TYPE_REAL, d, fluid && f->fluid_kinds},
        [FIELD_WALL_FORCE] = {"wall_force", FIELD_TYPE_REAL, 2 * d, fluid && f->fluid_walls},
        [FIELD_MOMENTUM_RATE] = {"momentum_rate", FIELD_TYPE_REAL, d, fluid && f->fluid_rk},
        [FIELD_STATE_SAVED] = {"state_saved", FIELD_TYPE_REAL, 1 + d + (compressible ? 1 : 0),
                               fluid && f->fluid_rk},
    };
    for (int k = 0; k < FIELD_COUNT; ++k) out[k] = table[k];
}

size_t sph_field_element_size(sph_field_type type, const sph_features *f) {
    switch (type) {
    case FIELD_TYPE_REAL:
        return f->double_precision ? sizeof(double) : sizeof(float);
    case FIELD_TYPE_HREAL:
        return sph_history_double(f) ? sizeof(double) : sizeof(float);
    case FIELD_TYPE_INT32:
        return sizeof(int32_t);
    case FIELD_TYPE_U8:
        return sizeof(uint8_t);
    }
    return 0;
}

bool sph_field_is_derived(sph_field f) {
    return f == FIELD_VORTICITY;
}

bool sph_field_is_real(sph_field_type type) {
    return type == FIELD_TYPE_REAL || type == FIELD_TYPE_HREAL;
}
