/* scene_materials.c — the section `materials`, and the fit of the
 * formulation and the materials the bodies use. */
#include "scene_loader.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A fluid material (no youngs_modulus) of the eulerian formulations: rho0,
 * and the weakly compressible fluid's c0 (p = c0^2 (rho - rho0), seed 004
 * eq. 11) or the ideal gas's gamma (p = (gamma - 1) rho e, eq. 11, with
 * c = sqrt(gamma p / rho), eq. 12), and the dynamic viscosity mu of eq. 13. */
static sph_status parse_fluid_material(loader *L, const config_setting_t *m, sph_material *mat) {
    const sph_formulation f = L->scene->formulation;
    const char *fname = sph_formulation_name(f);
    const config_setting_t *solid_key =
        scene_first_member(m, KEY_NAMES("poisson_ratio", "yield_stress", "hardening_modulus",
                                        "model", "exponential_b"));
    if (solid_key)
        return scene_fail_at(L, solid_key, NULL,
                             "is for solid materials; material '%s' is a fluid (it has no "
                             "youngs_modulus), as formulation \"%s\" needs",
                             m->name, fname);
    sph_status st;
    if ((st = scene_number(L, m, SK_FLUID_DENSITY, &mat->density)) ||
        (st = scene_number(L, m, SK_FLUID_VISCOSITY, &mat->viscosity)))
        return st;
    mat->fluid = true;
    mat->youngs_modulus = mat->poisson_ratio = mat->shear_modulus = 0.0;
    const config_setting_t *gamma_at = config_setting_get_member(m, "gamma");
    const config_setting_t *c_at = config_setting_get_member(m, "sound_speed");
    if (f == SPH_FORMULATION_EULERIAN_WC) {
        if (gamma_at)
            return scene_fail_at(
                L, gamma_at, NULL,
                "is the ideal gas's ratio of specific heats (formulation "
                "\"eulerian-compressible\"); the weakly compressible fluid of "
                "\"eulerian-wc\" has p = c0^2 (rho - rho0) (seed 004 eq. 11), set by "
                "sound_speed");
        if ((st = scene_require(L, m, SK_FLUID_SOUND_SPEED, &c_at)) ||
            (st = scene_number(L, m, SK_FLUID_SOUND_SPEED, &mat->sound_speed)))
            return st;
        mat->bulk_modulus = mat->density * mat->sound_speed * mat->sound_speed;
        mat->gamma = 0.0;
        if (!isfinite(mat->bulk_modulus))
            return scene_fail_at(
                L, c_at, NULL,
                "density %g and sound_speed %g give the bulk modulus rho0 c0^2 = %g: "
                "not finite",
                mat->density, mat->sound_speed, mat->bulk_modulus);
        return SPH_OK;
    }
    /* the ideal gas: its sound speed is a state variable */
    if (c_at)
        return scene_fail_at(
            L, c_at, NULL,
            "an ideal gas's sound speed follows from its state, c = sqrt(gamma p / rho) "
            "(seed 004 eq. 12); leave sound_speed out and give the bodies' "
            "initial_pressure (and initial_density)");
    mat->gamma = sph_scene_key_at(SK_FLUID_GAMMA)->def;
    if (gamma_at && (st = scene_as_float(L, gamma_at, &mat->gamma))) return st;
    /* 5/3 itself cannot be written in the 15 digits a stored scene keeps
     * (check_resolved): 1.66666666666667 and 1.666667 are accepted as 5/3 */
    if (!(mat->gamma > 1.0 && mat->gamma <= 5.0 / 3.0 + 1e-6))
        return scene_fail_at(
            L, gamma_at ? gamma_at : m, gamma_at ? NULL : "gamma",
            "an ideal gas has 1 < gamma <= 5/3 (5/3: monatomic, 7/5: diatomic such "
            "as air), got %g",
            mat->gamma);
    mat->sound_speed = 0.0;
    mat->bulk_modulus = 0.0;
    return SPH_OK;
}

/* TLSPH's elastic law (device/tl_step.cl): `model`, and the exponential
 * law's stiffening exponent `exponential_b` (1 by default, the public
 * code's bending column; eulerian-sph-reference.md §5.4).  Which
 * formulations take it is checked with the formulation (check_material_model). */
static sph_status parse_elastic_model(loader *L, const config_setting_t *m, sph_material *mat) {
    /* the schema's words follow ELASTIC_MODEL_* */
    _Static_assert(ELASTIC_MODEL_SVK == 0 && ELASTIC_MODEL_NEO_HOOKEAN == 1 &&
                       ELASTIC_MODEL_EXPONENTIAL == 2,
                   "the words of materials.model follow ELASTIC_MODEL_*");
    const config_setting_t *model_at;
    sph_status st = scene_keyword(L, m, SK_MATERIAL_MODEL, &mat->elastic_model, &model_at);
    if (st) return st;
    if (mat->plastic && model_at && mat->elastic_model != ELASTIC_MODEL_SVK)
        return scene_fail_at(
            L, model_at, NULL,
            "material '%s' is J2-plastic (it has a yield_stress), whose elastic range "
            "is Hencky's (device/sph_plasticity.h); model \"%s\" is for elastic "
            "materials",
            m->name, scene_word(SK_MATERIAL_MODEL, mat->elastic_model));
    const config_setting_t *b_at = config_setting_get_member(m, "exponential_b");
    if (b_at && mat->elastic_model != ELASTIC_MODEL_EXPONENTIAL)
        return scene_fail_at(
            L, b_at, NULL,
            "is the stiffening exponent of model \"exponential\"; material '%s' has "
            "model \"%s\"",
            m->name, scene_word(SK_MATERIAL_MODEL, mat->elastic_model));
    return scene_number(L, m, SK_MATERIAL_EXPONENTIAL_B, &mat->exponential_b);
}

sph_status scene_parse_materials(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = scene_group(L, root, SK_MATERIALS, &g);
    if (st) return st;
    int n = config_setting_length(g);
    if (n == 0) return scene_fail_at(L, g, NULL, "define at least one material");
    if (n > SPH_MAX_MATERIALS)
        return scene_fail_at(L, g, NULL, "at most %d materials, got %d", SPH_MAX_MATERIALS, n);
    const bool eulerian = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    if (eulerian && n > 1)
        return scene_fail_at(
            L, g, NULL,
            "several materials (%d) are not supported for the eulerian formulations "
            "yet: define one fluid (several bodies may share it)",
            n);
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(g, (unsigned)i);
        sph_material *mat = &sc->materials[i];
        if (!config_setting_is_group(m))
            return scene_fail_at(
                L, m, NULL, "expected a group { density; youngs_modulus; poisson_ratio; }, got %s",
                scene_type_name(config_setting_type(m)));
        char why[256];
        if (!sph_name_check(m->name, why, sizeof why)) return scene_fail_at(L, m, NULL, "%s", why);
        if ((st = scene_check_keys(L, m, SECTIONS("materials", "materials.fluid")))) return st;
        snprintf(mat->name, sizeof mat->name, "%s", m->name);
        /* a material without youngs_modulus is a fluid: the eulerian
         * formulations take fluids only, the others solids only */
        const config_setting_t *E_at = config_setting_get_member(m, "youngs_modulus");
        if (eulerian && E_at)
            return scene_fail_at(
                L, E_at, NULL,
                "material '%s' is a solid (it has a youngs_modulus), and formulation "
                "\"%s\" simulates a fluid; a fluid material has density, "
                "%s and viscosity",
                m->name, sph_formulation_name(sc->formulation),
                sc->formulation == SPH_FORMULATION_EULERIAN_WC ? "sound_speed" : "gamma");
        if (eulerian) {
            if ((st = parse_fluid_material(L, m, mat))) return st;
            continue;
        }
        if (!E_at && !config_setting_get_member(m, "poisson_ratio"))
            return scene_fail_at(
                L, m, NULL,
                "a material without youngs_modulus is a fluid, which needs "
                "method.formulation \"eulerian-wc\" or \"eulerian-compressible\", "
                "got \"%s\"; a solid material gives youngs_modulus and poisson_ratio",
                sph_formulation_name(sc->formulation));
        const config_setting_t *fluid_key = scene_first_member(m, KEY_NAMES("viscosity", "gamma"));
        if (fluid_key)
            return scene_fail_at(L, fluid_key, NULL,
                                 "is for fluid materials (formulations \"eulerian-wc\" and "
                                 "\"eulerian-compressible\"); material '%s' is a solid (it has a "
                                 "youngs_modulus)",
                                 m->name);
        if ((st = scene_number(L, m, SK_MATERIAL_DENSITY, &mat->density)) ||
            (st = scene_number(L, m, SK_MATERIAL_YOUNGS_MODULUS, &mat->youngs_modulus)) ||
            (st = scene_number(L, m, SK_MATERIAL_POISSON_RATIO, &mat->poisson_ratio)))
            return st;
        mat->plastic = config_setting_get_member(m, "yield_stress") != NULL;
        if ((st = scene_number_or(L, m, SK_MATERIAL_YIELD_STRESS, 0.0, &mat->yield_stress)) ||
            (st = scene_number(L, m, SK_MATERIAL_HARDENING_MODULUS, &mat->hardening_modulus)))
            return st;
        if (!mat->plastic && config_setting_get_member(m, "hardening_modulus"))
            return scene_fail_at(L, config_setting_get_member(m, "hardening_modulus"), NULL,
                                 "a hardening modulus needs a yield_stress (J2 plasticity)");
        if ((st = parse_elastic_model(L, m, mat))) return st;
        double E = mat->youngs_modulus, nu = mat->poisson_ratio;
        mat->bulk_modulus = E / (3.0 * (1.0 - 2.0 * nu));
        mat->shear_modulus = E / (2.0 * (1.0 + nu));
        /* 000 eq. 5: c0 = sqrt(K / rho0) */
        mat->sound_speed = sqrt(mat->bulk_modulus / mat->density);
        /* A hydrocode material (003 §5.2.3 after Mehra & Chaturvedi 2006)
         * gives its bulk sound speed beside the shear response: then the
         * equation of state takes K = rho0 c0^2 and E, nu set G alone. */
        if (config_setting_get_member(m, "sound_speed")) {
            if ((st = scene_number(L, m, SK_MATERIAL_SOUND_SPEED, &mat->sound_speed))) return st;
            mat->bulk_modulus = mat->density * mat->sound_speed * mat->sound_speed;
        }
        /* extreme but finite inputs can overflow (or underflow) the derived
         * constants the solver divides by */
        if (!(isfinite(mat->bulk_modulus) && isfinite(mat->shear_modulus) &&
              isfinite(mat->sound_speed) && mat->shear_modulus > 0 && mat->sound_speed > 0))
            return scene_fail_at(
                L, m, NULL,
                "density %g, youngs_modulus %g and poisson_ratio %.17g give bulk modulus "
                "%g, shear modulus %g and sound speed %g: not finite and positive",
                mat->density, E, nu, mat->bulk_modulus, mat->shear_modulus, mat->sound_speed);
    }
    sc->nmaterials = n;
    return SPH_OK;
}

/* The formulation and the material model must fit: ENOG and ENOG-A have no
 * stress to return to a yield surface (003 §4.2), so they are elastic only
 * (TLSPH takes J2 materials: the finite-strain return map of
 * device/sph_plasticity.h with 002's hourglass switch).
 * Resolves the default xi_G: GNOG 4.0 elastic / 0.2 plastic (the reference
 * code's values), GNOG-A 2.0 for every material (003 §4.3). */
sph_status scene_check_material_model(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *method = config_setting_get_member(root, "method");
    const config_setting_t *form_at = config_setting_get_member(method, "formulation");
    bool plastic = false;
    const char *plastic_material = "";
    /* every material a body or a region uses */
    int row_of[SPH_MAX_MATERIALS];
    const int rows = sph_scene_material_rows(sc, row_of);
    for (int k = 0; k < sc->nmaterials; ++k) {
        const sph_material *m = &sc->materials[k];
        if (row_of[k] < 0) continue;
        if (m->plastic) {
            plastic = true;
            plastic_material = m->name;
        }
        if (m->elastic_model != ELASTIC_MODEL_SVK && sc->formulation != SPH_FORMULATION_TLSPH)
            return scene_fail_at(L, form_at, NULL,
                                 "material '%s' has a hyperelastic model (neo-Hookean or "
                                 "exponential), which \"tlsph\" implements; formulation \"%s\" is "
                                 "hypoelastic (Jaumann stress rate): use \"tlsph\", or leave the "
                                 "material's model out",
                                 m->name, sph_formulation_name(sc->formulation));
    }
    /* several materials: the interface terms of device/sph_materials.h are
     * those of the updated-Lagrangian solids */
    if (rows > 1 && (sc->formulation == SPH_FORMULATION_TLSPH ||
                     SPH_FORMULATION_IS_EULERIAN(sc->formulation))) {
        const char *names[2] = {"", ""};
        for (int k = 0; k < sc->nmaterials; ++k)
            if (row_of[k] >= 0 && row_of[k] < 2) names[row_of[k]] = sc->materials[k].name;
        return scene_fail_at(
            L, form_at, NULL,
            "the bodies and regions of this scene use %d materials ('%s', '%s', ...); "
            "formulation \"%s\" runs one material: several materials are "
            "implemented for the updated-Lagrangian solids (\"enog\", \"enog-a\", "
            "\"og\", \"oas\", \"gnog\", \"gnog-a\")",
            rows, names[0], names[1], sph_formulation_name(sc->formulation));
    }
    if (plastic && FORM_IS_ENOG(sc->formulation))
        return scene_fail_at(L, form_at, NULL,
                             "formulation \"%s\" is for elastic materials, but material '%s' is "
                             "plastic (it has a yield_stress); use \"gnog-a\", \"gnog\", \"og\", "
                             "\"oas\" or \"tlsph\"",
                             sph_formulation_name(sc->formulation), plastic_material);
    if (isnan(sc->xi_g))
        sc->xi_g = sc->formulation == SPH_FORMULATION_GNOG ? (plastic ? 0.2 : 4.0) : 2.0;
    return SPH_OK;
}
