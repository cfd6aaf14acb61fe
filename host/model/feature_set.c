#include "feature_set.h"

#include "physics.h"
#include "sph_constants.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void sph_features_from_scene(const sph_scene *scene, const sph_particles *particles,
                             sph_precision precision, sph_features *out) {
    memset(out, 0, sizeof *out);
    out->dim = scene->dim;
    out->double_precision = precision == SPH_PRECISION_DOUBLE;
    out->mixed_precision = precision == SPH_PRECISION_MIXED;
    out->formulation = scene->formulation;
    out->rotation = scene->rotation;
    out->kernel = scene->kernel;
    out->stepping = scene->stepping;
    out->has_clamp = particles->fixed != NULL && particles->fixed_count > 0;
    out->nbodies = scene->nbodies;
    int row_of[SPH_MAX_MATERIALS];
    out->materials = sph_scene_material_rows(scene, row_of);
    /* bodies do not merge: they meet through the contact force (TLSPH runs
     * one body, scene.c) */
    out->contact = scene->nbodies > 1 && scene->formulation != SPH_FORMULATION_TLSPH &&
                   !SPH_FORMULATION_IS_EULERIAN(scene->formulation);
    out->walls = scene->nwalls;
    out->torque_projection = scene->torque_projection;
    for (int k = 0; k < scene->nmaterials && k < SPH_MAX_MATERIALS; ++k) {
        if (row_of[k] < 0) continue;
        const sph_material *m = &scene->materials[k];
        if (m->plastic) out->plastic = true;
        if (scene->formulation == SPH_FORMULATION_TLSPH) out->elastic_model = m->elastic_model;
    }
    out->tl_damping = scene->formulation == SPH_FORMULATION_TLSPH && scene->pairwise_damping > 0;
    if (SPH_FORMULATION_IS_EULERIAN(scene->formulation)) {
        for (int b = 0; b < scene->nbodies; ++b)
            if (scene->bodies[b].role == SPH_BODY_WALL) out->fluid_walls = true;
        out->far_field = scene->has_far_field;
        out->fluid_vorticity = scene->dim > 1 && scene->output_field[SPH_OUT_VORTICITY];
        out->fluid_kinds = particles->kind != NULL;
        out->fluid_rk = scene->fluid_integrator != SPH_FLUID_TWO_STAGE;
        out->fluid_rk_stages = scene->fluid_integrator == SPH_FLUID_SSP_RK3   ? 3
                               : scene->fluid_integrator == SPH_FLUID_SSP_RK2 ? 2
                                                                              : 0;
    }
}

const char *sph_precision_name(const sph_features *f) {
    return f->double_precision ? "double" : (f->mixed_precision ? "mixed" : "single");
}

bool sph_precision_parse(const char *name, sph_precision *out) {
    static const char *const names[] = {"double", "single", "mixed"};
    for (int k = 0; k < 3; ++k)
        if (strcmp(name, names[k]) == 0) {
            *out = (sph_precision)k;
            return true;
        }
    return false;
}

bool sph_history_double(const sph_features *f) {
    return f->double_precision || f->mixed_precision;
}

void sph_features_build_options(const sph_features *f, int reduce_wg, int sort_wg,
                                bool nbr_row_major, bool pair_recompute, char *buf, size_t len) {
    char elastic_model[32] = "", materials[32] = ""; /* the defaults: SVK, one material */
    if (f->materials > 1)
        snprintf(materials, sizeof materials, " -DSPH_MATERIALS=%d", f->materials);
    if (f->elastic_model != ELASTIC_MODEL_SVK)
        snprintf(elastic_model, sizeof elastic_model, " -DSPH_ELASTIC_MODEL=%d", f->elastic_model);
    snprintf(buf, len,
             "-DSPH_DIM=%d -DSPH_DOUBLE=%d -DSPH_MIXED=%d -DSPH_KERNEL=%d -DSPH_FORMULATION=%d "
             "-DSPH_PLASTIC=%d -DSPH_ROTATION=%d -DSPH_HAS_CLAMP=%d -DSPH_NBODIES=%d "
             "-DSPH_CONTACT=%d -DSPH_WALLS=%d -DSPH_NBR_ROW_MAJOR=%d -DSPH_PAIR_RECOMPUTE=%d "
             "-DSPH_TORQUE_PROJECTION=%d -DSPH_WG=%d "
             "-DSORT_WG=%d -DSPH_PARAMS_SIZE=%zu%s%s%s%s%s%s%s%s",
             f->dim, f->double_precision ? 1 : 0, f->mixed_precision ? 1 : 0, (int)f->kernel,
             (int)f->formulation, f->plastic ? 1 : 0, (int)f->rotation, f->has_clamp ? 1 : 0,
             f->nbodies, f->contact ? 1 : 0, f->walls, nbr_row_major ? 1 : 0,
             pair_recompute ? 1 : 0, f->torque_projection ? 1 : 0, reduce_wg, sort_wg,
             /* the host's size of the block, which the program checks
              * (device/sph_params.h) */
             f->double_precision ? sizeof(sph_params_f64) : sizeof(sph_params_f32),
             /* fluids: walls and far field (device/sph_prelude.h) */
             f->fluid_kinds ? " -DSPH_FLUID_KINDS=1" : "",
             f->fluid_walls ? " -DSPH_FLUID_WALLS=1" : "", f->far_field ? " -DSPH_FAR_FIELD=1" : "",
             f->fluid_rk ? " -DSPH_FLUID_RK=1" : "",
             f->fluid_vorticity ? " -DSPH_FLUID_VORTICITY=1" : "",
             /* TLSPH: a hyperelastic law, the pairwise damping (tl_step.cl) */
             elastic_model, f->tl_damping ? " -DSPH_TL_DAMPING=1" : "",
             /* several materials (device/sph_materials.h) */
             materials);
}

int sph_substep_ncomp(const sph_features *f) {
    if (f->rotation != SPH_ROTATION_AVERAGED) return 1;
    const int torque = f->torque_projection ? SPH_TORQUE_NCOMP(f->dim) : 0;
    return 1 + f->nbodies * (f->dim * f->dim + torque);
}

int sph_partial_ncomp(const sph_features *f) {
    /* rebuild 2d + 2, diagnostics 2 + d + (1 or 3), monitor 4 + 2d */
    int others = SPH_MONITOR_NCOMP(f->dim);
    /* fluid diagnostics with walls: 4 + d + spins + 2d (reduction.cl;
     * the native fluid instances always have the wall components) */
    const int fluid_diag = 4 + f->dim + sph_spin_components(f->dim) + 2 * f->dim;
    if (SPH_FORMULATION_IS_EULERIAN(f->formulation) && fluid_diag > others) others = fluid_diag;
    const int substep = sph_substep_ncomp(f);
    return substep > others ? substep : others;
}

sph_status sph_params_fill(const sph_scene *scene, const sph_particles *particles,
                           const sph_features *f, sph_params_f64 *prm, sph_error *err) {
    /* the projection turns a body's surplus torque into a rigid angular
     * acceleration: right for a free body, whose rigid spin it is, but a
     * clamp or a driven region would have to hold that rigid field back and
     * the body would bend (the 2D plate's period 0.65 % shorter) */
    if (f->torque_projection && f->has_clamp)
        return sph_fail(err, SPH_ERR_INPUT,
                        "%s: method.torque_projection keeps the net torque of free bodies; "
                        "this scene constrains %d particles (clamp, rollers or a driven "
                        "region), so leave it false",
                        scene->path, particles->fixed_count);
    if (f->nbodies > SPH_MAX_BODIES)
        return sph_fail(err, SPH_ERR_INPUT, "%s: %d bodies, at most %d are supported", scene->path,
                        f->nbodies, SPH_MAX_BODIES);
    memset(prm, 0, sizeof *prm);
    const double h = scene->smoothing_ratio * scene->dp;
    prm->h = h;
    prm->cutoff = 2.0 * h;
    prm->dp = scene->dp;
    for (int a = 0; a < 3; ++a) prm->gravity[a] = a < scene->dim ? scene->gravity[a] : 0.0;
    prm->xi_e = scene->xi_e;
    prm->xi_g = scene->xi_g;
    prm->riemann_limit = scene->riemann_limiter_slope;
    /* the viscous term's eps = 0.01 h (004 eq. 13; host/setup/scene/scene.h) */
    const double visc_eps = 0.01 * h;
    prm->viscous_eps_linear = scene->viscous_regularization == SPH_VISCOUS_LINEAR ? visc_eps : 0;
    prm->viscous_eps_squared =
        scene->viscous_regularization == SPH_VISCOUS_SQUARED ? visc_eps * visc_eps : 0;
    prm->art_eps = scene->art_epsilon;
    prm->art_n = scene->art_exponent;
    prm->hourglass = scene->hourglass_alpha;
    prm->pair_damping = f->tl_damping ? scene->pairwise_damping : 0.0;
    /* contact between bodies (device/sph_contact.h) */
    prm->contact_impedance = scene->contact_impedance;
    prm->contact_penalty = scene->contact_penalty;
    /* the material table: row r holds the r-th material the bodies and
     * regions use (sph_scene_material_rows; particles carry their row when
     * there are several) */
    int row_of[SPH_MAX_MATERIALS];
    sph_scene_material_rows(scene, row_of);
    for (int k = 0; k < scene->nmaterials && k < SPH_MAX_MATERIALS; ++k) {
        if (row_of[k] < 0) continue;
        const sph_material *m = &scene->materials[k];
        sph_params_material_f64 *row = &prm->materials[row_of[k]];
        row->rho0 = m->density;
        row->c0 = m->sound_speed;
        row->shear_modulus = m->shear_modulus;
        row->bulk_modulus = m->density * m->sound_speed * m->sound_speed;
        /* Lame's first parameter of TLSPH's Saint Venant-Kirchhoff model:
         * lambda = K - 2G/3 = E nu / ((1 + nu)(1 - 2 nu)) in 2D too (plane
         * strain, the material constants of 004 and of the reference code's
         * elastic solid).  The in-plane K - G of the updated-Lagrangian 2D
         * model makes the plate 0.6 % (nu = 0.4) to 4 % (nu = 0.22) too soft
         * in bending against 004 Table 6 (bench-results/tlsph-kernels.json). */
        row->lambda = m->bulk_modulus - 2.0 / 3.0 * m->shear_modulus;
        /* an elastic material beside a plastic one never yields
         * (device/sph_materials.h) */
        row->yield = f->plastic && !m->plastic ? SPH_NEVER_YIELDS : m->yield_stress;
        row->hardening = m->hardening_modulus;
        row->exponential_b = m->exponential_b;
        /* fluids (device/eulerian_step.cl) */
        row->viscosity = m->viscosity;
        row->gamma = m->gamma;
    }
    prm->periodic_mask = scene->periodic_mask;
    prm->far_field_density = scene->far_field_density;
    prm->far_field_pressure = scene->far_field_pressure;
    prm->background_pressure = scene->background_pressure;
    for (int a = 0; a < scene->dim; ++a) prm->far_field_velocity[a] = scene->far_field_velocity[a];
    for (int a = 0; a < scene->dim; ++a)
        if (scene->periodic_mask & (1 << a))
            prm->period[a] = scene->periodic_upper[a] - scene->periodic_lower[a];
    if (SPH_FORMULATION_IS_EULERIAN(scene->formulation) && !f->double_precision)
        return sph_fail(err, SPH_ERR_INPUT,
                        "%s: formulation \"%s\" runs in double precision only (its conserved "
                        "sums and the step clock's signal speeds); drop --precision %s",
                        scene->path, sph_formulation_name(scene->formulation),
                        sph_precision_name(f));
    for (int b = 0; b < f->nbodies; ++b) prm->body_count[b] = particles->body_count[b];
    /* the constraint table (device/sph_constraints.h) */
    for (int k = 0; k < sph_constraint_count(scene) && k < SPH_MAX_CONSTRAINTS; ++k) {
        const sph_constraint *c = sph_constraint_at(scene, k);
        prm->constraints[k].axis_mask = c->axis_mask;
        for (int a = 0; a < scene->dim; ++a) prm->constraints[k].velocity[a] = c->velocity[a];
    }
    /* the wall table (device/sph_wall.h) */
    prm->nwalls = scene->nwalls;
    for (int w = 0; w < scene->nwalls && w < SPH_MAX_WALLS; ++w)
        for (int a = 0; a < scene->dim; ++a) {
            prm->walls[w].point[a] = scene->walls[w].point[a];
            prm->walls[w].normal[a] = scene->walls[w].normal[a];
        }
    /* the native backend's run-time selections (sph_params.h) */
    prm->smoothing_kernel = (int)f->kernel;
    prm->rotation = (int)f->rotation;
    prm->nbodies = f->nbodies;
    prm->plastic = f->plastic ? 1 : 0;
    prm->torque_projection = f->torque_projection ? 1 : 0;
    prm->elastic_model = f->elastic_model;
    /* W(dp) normalises the artificial-stress weight f = W(r)/W(dp) */
    prm->art_wdp = sph_physics_for(f->dim, true)->kernel_w(prm, scene->dp);
    return SPH_OK;
}
