#include "feature_set.h"

#include "backend_cpu.h"
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
    /* bodies do not merge: they meet through the contact force (TLSPH runs
     * one body, scene.c) */
    out->contact = scene->nbodies > 1 && scene->formulation != SPH_FORMULATION_TLSPH;
    out->walls = scene->nwalls;
    out->torque_projection = scene->torque_projection;
    for (int b = 0; b < scene->nbodies; ++b)
        if (scene->materials[scene->bodies[b].material].plastic) out->plastic = true;
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
    snprintf(buf, len,
             "-DSPH_DIM=%d -DSPH_DOUBLE=%d -DSPH_MIXED=%d -DSPH_KERNEL=%d -DSPH_FORMULATION=%d "
             "-DSPH_PLASTIC=%d -DSPH_ROTATION=%d -DSPH_HAS_CLAMP=%d -DSPH_NBODIES=%d "
             "-DSPH_CONTACT=%d -DSPH_WALLS=%d -DSPH_NBR_ROW_MAJOR=%d -DSPH_PAIR_RECOMPUTE=%d "
             "-DSPH_TORQUE_PROJECTION=%d -DSPH_WG=%d "
             "-DSORT_WG=%d",
             f->dim, f->double_precision ? 1 : 0, f->mixed_precision ? 1 : 0, (int)f->kernel,
             (int)f->formulation, f->plastic ? 1 : 0, (int)f->rotation, f->has_clamp ? 1 : 0,
             f->nbodies, f->contact ? 1 : 0, f->walls, nbr_row_major ? 1 : 0,
             pair_recompute ? 1 : 0, f->torque_projection ? 1 : 0, reduce_wg, sort_wg);
}

int sph_substep_ncomp(const sph_features *f) {
    if (f->rotation != SPH_ROTATION_AVERAGED) return 1;
    const int torque = f->torque_projection ? SPH_TORQUE_NCOMP(f->dim) : 0;
    return 1 + f->nbodies * (f->dim * f->dim + torque);
}

int sph_partial_ncomp(const sph_features *f) {
    /* rebuild 2d + 2, diagnostics 2 + d + (1 or 3), monitor 4 + 2d */
    const int others = SPH_MONITOR_NCOMP(f->dim);
    const int substep = sph_substep_ncomp(f);
    return substep > others ? substep : others;
}

sph_status sph_params_fill(const sph_scene *scene, const sph_particles *particles,
                           const sph_features *f, double *prm, sph_error *err) {
    /* One material per run: pairs of different materials need the
     * multi-material Riemann states and contact of the benchmark library. */
    const int material = scene->bodies[0].material;
    for (int b = 1; b < scene->nbodies; ++b)
        if (scene->bodies[b].material != material)
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: bodies '%s' and '%s' use different materials; this version "
                            "runs scenes whose bodies share one material",
                            scene->path, scene->bodies[0].name, scene->bodies[b].name);
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
    const sph_material *m = &scene->materials[material];
    for (int k = 0; k < PRM_COUNT; ++k) prm[k] = 0.0;
    const double h = scene->smoothing_ratio * scene->dp;
    prm[PRM_H] = h;
    prm[PRM_CUTOFF] = 2.0 * h;
    prm[PRM_RHO0] = m->density;
    prm[PRM_C0] = m->sound_speed;
    prm[PRM_G] = m->shear_modulus;
    prm[PRM_K] = m->density * m->sound_speed * m->sound_speed;
    prm[PRM_XI_E] = scene->xi_e;
    for (int a = 0; a < 3; ++a) prm[PRM_GRAVITY + a] = a < scene->dim ? scene->gravity[a] : 0.0;
    prm[PRM_ROTATION] = (double)f->rotation;
    prm[PRM_KERNEL] = (double)f->kernel;
    prm[PRM_RIEMANN_LIMIT] = scene->riemann_limiter_slope;
    prm[PRM_NBODIES] = (double)f->nbodies;
    prm[PRM_DP] = scene->dp;
    prm[PRM_FORMULATION] = (double)f->formulation;
    prm[PRM_PLASTIC] = f->plastic ? 1.0 : 0.0;
    prm[PRM_TORQUE_PROJECTION] = f->torque_projection ? 1.0 : 0.0;
    prm[PRM_XI_G] = scene->xi_g;
    prm[PRM_YIELD] = m->yield_stress;
    prm[PRM_HARDENING] = m->hardening_modulus;
    prm[PRM_ART_EPS] = scene->art_epsilon;
    prm[PRM_ART_N] = scene->art_exponent;
    prm[PRM_ART_WDP] = 0.0; /* set by the backend from the kernel (sph_smoothing_kernel.h) */
    prm[PRM_HOURGLASS] = scene->hourglass_alpha;
    /* Lame's first parameter of TLSPH's Saint Venant-Kirchhoff model:
     * lambda = K - 2G/3 = E nu / ((1 + nu)(1 - 2 nu)) in 2D too (plane
     * strain, the material constants of 004 and of the reference code's
     * elastic solid).  The in-plane K - G of the updated-Lagrangian 2D model
     * makes the plate 0.6 % (nu = 0.4) to 4 % (nu = 0.22) too soft in
     * bending against 004 Table 6 (bench-results/tlsph-kernels.json). */
    prm[PRM_LAMBDA] = m->bulk_modulus - 2.0 / 3.0 * m->shear_modulus;
    /* contact between bodies (device/sph_contact.h) */
    prm[PRM_CONTACT_IMPEDANCE] = scene->contact_impedance;
    prm[PRM_CONTACT_PENALTY] = scene->contact_penalty;
    for (int b = 0; b < f->nbodies; ++b) prm[PRM_BODY_COUNT + b] = (double)particles->body_count[b];
    /* the constraint table (device/sph_constraints.h) */
    for (int k = 0; k < sph_constraint_count(scene) && k < SPH_MAX_CONSTRAINTS; ++k) {
        const sph_constraint *c = sph_constraint_at(scene, k);
        double *row = prm + PRM_CONSTRAINT + k * PRM_CONSTRAINT_STRIDE;
        row[0] = (double)c->axis_mask;
        for (int a = 0; a < scene->dim; ++a) row[1 + a] = c->velocity[a];
    }
    /* the wall table (device/sph_wall.h) */
    prm[PRM_WALL_COUNT] = (double)scene->nwalls;
    for (int w = 0; w < scene->nwalls && w < SPH_MAX_WALLS; ++w) {
        double *row = prm + PRM_WALL + w * PRM_WALL_STRIDE;
        for (int a = 0; a < scene->dim; ++a) {
            row[a] = scene->walls[w].point[a];
            row[3 + a] = scene->walls[w].normal[a];
        }
    }
    /* W(dp) normalises the artificial-stress weight f = W(r)/W(dp) */
    prm[PRM_ART_WDP] = cpu_kernels_for(f->dim, true)->kernel_w(prm, scene->dp);
    return SPH_OK;
}
