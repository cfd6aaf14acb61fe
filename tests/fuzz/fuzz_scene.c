/* fuzz_scene.c — libFuzzer harness over the scene parser, the validator and
 * the particle generator (the input convention is in fuzz_scene.h).
 *
 * Besides "no crash, no leak, no undefined behaviour, no hang", every input
 * must end in one of two ways, checked here so that the fuzzer reports a
 * violation as a crash:
 *   - rejected with SPH_ERR_INPUT and a message that names the input (its
 *     origin) or the override (`--set ...`);
 *   - accepted, with the validator's promises kept: names that keep the
 *     name rule (sph_name_check), finite positive spacing,
 *     finite box corners with lower < upper, finite positive material
 *     constants, indices in range, and resolved text that loads again (a
 *     restart reloads it from the checkpoint).
 * An accepted scene within FUZZ_SCENE_PARTICLE_BUDGET lattice points also
 * goes through sph_particles_generate, which must either fail the same way
 * or give every body particles inside its shape, with finite values.
 *
 * Build: cmake -DCMAKE_C_COMPILER=clang -DSPHSOLID_FUZZ=ON (docs/tests.md, "Fuzzing"). */
#include "fuzz_scene.h"

#include "particles.h"
#include "scene.h"
#include "sph_constants.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

__attribute__((format(printf, 2, 3))) static void violate(fuzz_scene_result *res, const char *fmt,
                                                          ...) {
    if (res->violation[0]) return; /* keep the first */
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(res->violation, sizeof res->violation, fmt, ap);
    va_end(ap);
}

static bool finite_positive(double x) {
    return isfinite(x) && x > 0.0;
}

/* A failure must be an input error whose message names where it came from. */
static void check_failure(fuzz_scene_result *res, const char *stage, sph_status st,
                          const sph_error *err, const char *origin) {
    if (st != SPH_ERR_INPUT)
        violate(res, "%s: status %d, expected SPH_ERR_INPUT: %s", stage, (int)st, err->msg);
    else if (!strstr(err->msg, origin) && strncmp(err->msg, "--set ", 6) != 0)
        violate(res, "%s: the message names neither '%s' nor an override: %s", stage, origin,
                err->msg);
}

static void check_scene(fuzz_scene_result *res, const sph_scene *sc) {
    if (sc->dim < 1 || sc->dim > 3 ||
        (sc->dim == 1 && !SPH_FORMULATION_IS_EULERIAN(sc->formulation)))
        violate(res, "dim %d with formulation %d", sc->dim, (int)sc->formulation);
    if (!finite_positive(sc->dp)) violate(res, "dp %g", sc->dp);
    if (!finite_positive(sc->end_time) || !finite_positive(sc->output_interval))
        violate(res, "end %g, output_interval %g", sc->end_time, sc->output_interval);
    if (!isfinite(sc->snapshot_interval) || sc->snapshot_every < 0)
        violate(res, "snapshot_interval %g, every %d", sc->snapshot_interval, sc->snapshot_every);
    if (!sc->resolved_text) violate(res, "no resolved text");
    if (sc->nmaterials < 1 || sc->nmaterials > SPH_MAX_MATERIALS || sc->nshapes < 1 ||
        sc->nshapes > SPH_SCENE_MAX_SHAPES || sc->nbodies < 1 || sc->nbodies > SPH_MAX_BODIES ||
        sc->nobservers < 0 || sc->nobservers > SPH_SCENE_MAX_OBSERVERS) {
        violate(res, "table sizes %d materials, %d shapes, %d bodies, %d observers", sc->nmaterials,
                sc->nshapes, sc->nbodies, sc->nobservers);
        return;
    }
    const bool eulerian = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    const bool compressible = sc->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE;
    for (int m = 0; m < sc->nmaterials; m++) {
        const sph_material *mat = &sc->materials[m];
        if (mat->fluid != eulerian)
            violate(res, "material '%s': fluid %d in formulation %d", mat->name, mat->fluid,
                    (int)sc->formulation);
        if (!mat->fluid) {
            if (!finite_positive(mat->density) || !finite_positive(mat->sound_speed) ||
                !finite_positive(mat->bulk_modulus) || !finite_positive(mat->shear_modulus))
                violate(res, "material '%s': rho %g, c0 %g, K %g, G %g", mat->name, mat->density,
                        mat->sound_speed, mat->bulk_modulus, mat->shear_modulus);
            continue;
        }
        /* a fluid has no shear modulus; the weakly compressible one has c0
         * and K = rho0 c0^2, the ideal gas neither (its c follows from its
         * state) but a gamma in (1, 5/3] */
        const bool state_ok =
            compressible ? mat->sound_speed == 0.0 && mat->bulk_modulus == 0.0 &&
                               mat->gamma > 1.0 && mat->gamma <= 5.0 / 3.0 + 1e-6
                         : finite_positive(mat->sound_speed) && finite_positive(mat->bulk_modulus);
        if (!finite_positive(mat->density) || mat->shear_modulus != 0.0 || !state_ok ||
            !isfinite(mat->viscosity) || mat->viscosity < 0.0)
            violate(res, "fluid material '%s': rho %g, c0 %g, K %g, G %g, gamma %g, mu %g",
                    mat->name, mat->density, mat->sound_speed, mat->bulk_modulus,
                    mat->shear_modulus, mat->gamma, mat->viscosity);
    }
    /* the flow around a cylinder's keys: walls at rest on their own lattice,
     * at least one matter body, a far field and forces with finite positive
     * references */
    int matter = 0, walls = 0;
    for (int b = 0; b < sc->nbodies; b++) {
        const sph_body *body = &sc->bodies[b];
        const bool wall = body->role == SPH_BODY_WALL;
        matter += body->role == SPH_BODY_MATTER;
        walls += wall;
        if ((body->role != SPH_BODY_MATTER && !wall) || !(body->spacing_ratio > 0.0) ||
            body->spacing_ratio > 1.0 || (!wall && body->spacing_ratio != 1.0) ||
            (wall &&
             (!eulerian || body->nconstraints != 0 || body->velocity.type != SPH_VELOCITY_ZERO ||
              body->initial_density[0] || body->initial_pressure[0])))
            violate(res, "body %d: role %d, spacing %g, %d constraints, velocity type %d", b,
                    (int)body->role, body->spacing_ratio, body->nconstraints,
                    (int)body->velocity.type);
    }
    if (matter < 1) violate(res, "no matter body");
    /* regions: shapes and materials of the tables; several materials only
     * with the updated-Lagrangian solids */
    for (int b = 0; b < sc->nbodies; b++) {
        const sph_body *body = &sc->bodies[b];
        if (body->nregions < 0 || body->nregions > SPH_SCENE_MAX_REGIONS ||
            (body->nregions > 0 && body->role == SPH_BODY_WALL)) {
            violate(res, "body %d: %d regions, role %d", b, body->nregions, (int)body->role);
            continue;
        }
        for (int k = 0; k < body->nregions; k++)
            if (body->regions[k].shape < 0 || body->regions[k].shape >= sc->nshapes ||
                body->regions[k].material < 0 || body->regions[k].material >= sc->nmaterials)
                violate(res, "body %d region %d: shape %d, material %d", b, k,
                        body->regions[k].shape, body->regions[k].material);
    }
    int row_of[SPH_MAX_MATERIALS];
    const int rows = sph_scene_material_rows(sc, row_of);
    if (rows < 1 || (rows > 1 && (eulerian || sc->formulation == SPH_FORMULATION_TLSPH)))
        violate(res, "%d materials in use with formulation %d", rows, (int)sc->formulation);
    /* observers: a traction has a unit normal; the wave analysis two
     * distinct traction observers */
    for (int o = 0; o < sc->nobservers; o++) {
        const sph_observer *obs = &sc->observers[o];
        double n2 = 0.0;
        for (int a = 0; a < sc->dim; a++) n2 += obs->normal[a] * obs->normal[a];
        if (obs->quantity == SPH_OBSERVE_TRACTION ? fabs(n2 - 1.0) > 1e-9 : n2 != 0.0)
            violate(res, "observer %d: quantity %d, |n|^2 %g", o, (int)obs->quantity, n2);
    }
    if ((sc->wave_incident >= 0) != (sc->wave_transmitted >= 0) ||
        (sc->wave_incident >= 0 &&
         (sc->wave_incident == sc->wave_transmitted || sc->wave_incident >= sc->nobservers ||
          sc->wave_transmitted >= sc->nobservers ||
          sc->observers[sc->wave_incident].quantity != SPH_OBSERVE_TRACTION ||
          sc->observers[sc->wave_transmitted].quantity != SPH_OBSERVE_TRACTION)))
        violate(res, "wave analysis: observers %d, %d", sc->wave_incident, sc->wave_transmitted);
    if (sc->has_far_field) {
        double u2 = 0.0;
        for (int a = 0; a < sc->dim; a++) {
            u2 += sc->far_field_velocity[a] * sc->far_field_velocity[a];
            if (!(sc->periodic_upper[a] > sc->periodic_lower[a]) ||
                !isfinite(sc->periodic_upper[a] - sc->periodic_lower[a]))
                violate(res, "far field box axis %d: [%g, %g]", a, sc->periodic_lower[a],
                        sc->periodic_upper[a]);
        }
        /* the gas: p_inf given, the stream subsonic; the WC fluid: no p_inf */
        const bool gas_ok =
            compressible
                ? finite_positive(sc->far_field_pressure) &&
                      u2 < sc->materials[0].gamma * sc->far_field_pressure / sc->far_field_density
                : sc->far_field_pressure == 0.0;
        if (!eulerian || !gas_ok || !finite_positive(sc->far_field_density) || !isfinite(u2) ||
            sc->periodic_mask == (1 << sc->dim) - 1)
            violate(res, "far field: rho %g, |U|^2 %g, p %g, periodic mask %d",
                    sc->far_field_density, u2, sc->far_field_pressure, sc->periodic_mask);
    }
    /* the gas's background pressure: finite, >= 0, given where walls bound
     * the gas without a far field; none in the other formulations */
    if (!(isfinite(sc->background_pressure) && sc->background_pressure >= 0.0) ||
        (!compressible && (sc->background_pressure != 0.0 || sc->background_pressure_given)) ||
        (compressible && walls > 0 && !sc->has_far_field && !sc->background_pressure_given))
        violate(res, "background pressure %g (given %d, walls %d)", sc->background_pressure,
                (int)sc->background_pressure_given, walls);
    if (sc->has_forces && (walls < 1 || !finite_positive(sc->force_reference_density) ||
                           !finite_positive(sc->force_reference_speed) ||
                           !finite_positive(sc->force_reference_length) ||
                           !isfinite(sc->force_window) || sc->force_window < 0.0))
        violate(res, "forces: %d walls, rho %g, U %g, L %g, window %g", walls,
                sc->force_reference_density, sc->force_reference_speed, sc->force_reference_length,
                sc->force_window);
    for (int s = 0; s < sc->nshapes; s++) {
        const sph_shape *sh = &sc->shapes[s];
        if (sh->type == SPH_SHAPE_BOX) {
            for (int a = 0; a < sc->dim; a++)
                if (!isfinite(sh->lower[a]) || !isfinite(sh->upper[a]) ||
                    !(sh->lower[a] < sh->upper[a]))
                    violate(res, "shape %d: axis %d: [%g, %g]", s, a, sh->lower[a], sh->upper[a]);
        } else if (sh->type == SPH_SHAPE_SPHERE || sh->type == SPH_SHAPE_CYLINDER) {
            /* round shapes: positive radii, inner < outer, a unit axis, and
             * a finite bounding box */
            const double axis2 =
                sh->axis[0] * sh->axis[0] + sh->axis[1] * sh->axis[1] + sh->axis[2] * sh->axis[2];
            if (!finite_positive(sh->outer_radius) || !(sh->inner_radius >= 0.0) ||
                !(sh->inner_radius < sh->outer_radius) ||
                (sh->type == SPH_SHAPE_CYLINDER &&
                 (!finite_positive(sh->length) || fabs(axis2 - 1.0) > 1e-12)))
                violate(res, "shape %d: radii %g, %g, length %g, |axis|^2 %g", s, sh->inner_radius,
                        sh->outer_radius, sh->length, axis2);
            for (int a = 0; a < sc->dim; a++)
                if (!isfinite(sh->lower[a]) || !isfinite(sh->upper[a]) ||
                    !(sh->lower[a] < sh->upper[a]))
                    violate(res, "shape %d: axis %d: [%g, %g]", s, a, sh->lower[a], sh->upper[a]);
        } else if (sh->nparts < 1 || sh->nparts > SPH_SCENE_MAX_SHAPE_PARTS) {
            violate(res, "shape %d: %d parts", s, sh->nparts);
        } else {
            for (int i = 0; i < sh->nparts; i++)
                if (sh->parts[i] < 0 || sh->parts[i] >= sc->nshapes)
                    violate(res, "shape %d: part %d", s, sh->parts[i]);
        }
    }
    /* every name keeps the rule (timeseries.csv columns, JSON, --set keys) */
    char why[256];
    for (int m = 0; m < sc->nmaterials; m++)
        if (!sph_name_check(sc->materials[m].name, why, sizeof why))
            violate(res, "material %d: %s", m, why);
    for (int s = 0; s < sc->nshapes; s++)
        if (sc->shapes[s].name[0] && !sph_name_check(sc->shapes[s].name, why, sizeof why))
            violate(res, "shape %d: %s", s, why);
    for (int b = 0; b < sc->nbodies; b++)
        if (!sph_name_check(sc->bodies[b].name, why, sizeof why))
            violate(res, "body %d: %s", b, why);
    for (int o = 0; o < sc->nobservers; o++)
        if (!sph_name_check(sc->observers[o].name, why, sizeof why) ||
            sph_observer_name_reserved(sc->observers[o].name))
            violate(res, "observer %d: '%s' breaks the name rule or is reserved", o,
                    sc->observers[o].name);
    for (int w = 0; w < sc->nwalls; w++)
        if (!sph_name_check(sc->walls[w].name, why, sizeof why))
            violate(res, "wall %d: %s", w, why);
    for (int b = 0; b < sc->nbodies; b++) {
        const sph_body *body = &sc->bodies[b];
        if (body->material < 0 || body->material >= sc->nmaterials || body->shape < 0 ||
            body->shape >= sc->nshapes)
            violate(res, "body %d: material %d, shape %d", b, body->material, body->shape);
        for (int c = 0; c < body->nconstraints; c++)
            if (body->constraints[c].region < 0 || body->constraints[c].region >= sc->nshapes)
                violate(res, "body %d: constraint region %d", b, body->constraints[c].region);
    }
}

/* Lattice points in the bodies' bounding boxes: what sph_particles_generate
 * scans.  NaN compares false, so "not within budget". */
static bool within_budget(const sph_scene *sc) {
    double total = 0.0;
    for (int b = 0; b < sc->nbodies; b++) {
        double lo[3], hi[3], points = 1.0;
        /* a wall body's lattice: spacing_ratio dp */
        const double ratio = sc->bodies[b].spacing_ratio > 0.0 ? sc->bodies[b].spacing_ratio : 1.0;
        sph_shape_bounds(sc, sc->bodies[b].shape, lo, hi);
        for (int a = 0; a < sc->dim; a++) points *= (hi[a] - lo[a]) / (ratio * sc->dp) + 1.0;
        total += points;
    }
    return total <= FUZZ_SCENE_PARTICLE_BUDGET;
}

static void check_particles(fuzz_scene_result *res, const sph_scene *sc, const sph_particles *p) {
    int per_body[SPH_MAX_BODIES] = {0};
    for (int i = 0; i < p->n; i++) {
        double x[3] = {0, 0, 0};
        for (int a = 0; a < p->dim; a++) {
            x[a] = p->pos[(size_t)a * (size_t)p->n + (size_t)i];
            if (!isfinite(x[a]) || !isfinite(p->vel[(size_t)a * (size_t)p->n + (size_t)i])) {
                violate(res, "particle %d: position or velocity not finite", i);
                return;
            }
        }
        if (p->body[i] >= sc->nbodies) {
            violate(res, "particle %d: body %d", i, p->body[i]);
            return;
        }
        per_body[p->body[i]]++;
        if (!finite_positive(p->mass[i]) || p->id[i] != i ||
            !sph_shape_contains(sc, sc->bodies[p->body[i]].shape, x)) {
            violate(res, "particle %d: mass %g, id %d, or outside its body's shape", i, p->mass[i],
                    (int)p->id[i]);
            return;
        }
    }
    for (int b = 0; b < sc->nbodies; b++)
        if (per_body[b] < 1 || per_body[b] != p->body_count[b])
            violate(res, "body %d: %d particles, body_count %d", b, per_body[b], p->body_count[b]);
    /* fluid scenes with walls or a far field: every particle's kind, a wall
     * particle's unit normal, a far-field particle's axis-aligned one */
    bool any_wall = false;
    for (int b = 0; b < sc->nbodies; b++) any_wall |= sc->bodies[b].role == SPH_BODY_WALL;
    const bool kinds =
        SPH_FORMULATION_IS_EULERIAN(sc->formulation) && (any_wall || sc->has_far_field);
    if (kinds != (p->kind != NULL) || kinds != (p->normal != NULL)) {
        violate(res, "kind %p, normal %p, expected %s", (void *)p->kind, (void *)p->normal,
                kinds ? "both" : "neither");
        return;
    }
    for (int i = 0; kinds && i < p->n; i++) {
        const bool wall = sc->bodies[p->body[i]].role == SPH_BODY_WALL;
        double n2 = 0.0;
        for (int a = 0; a < p->dim; a++) {
            const double c = p->normal[(size_t)a * (size_t)p->n + (size_t)i];
            n2 += c * c;
        }
        const uint8_t k = p->kind[i];
        const bool ok = wall ? k == SPH_PARTICLE_WALL && fabs(n2 - 1.0) < 1e-9
                        : k == SPH_PARTICLE_FLUID
                            ? n2 == 0.0
                            : (k == SPH_PARTICLE_INFLOW || k == SPH_PARTICLE_OUTFLOW) &&
                                  sc->has_far_field && n2 == 1.0;
        if (!ok) {
            violate(res, "particle %d: kind %d, |normal|^2 %g (body %d)", i, k, n2, p->body[i]);
            return;
        }
    }
}

void fuzz_scene_run(const uint8_t *data, size_t size, const char *origin, fuzz_scene_result *res) {
    memset(res, 0, sizeof *res);
    /* the text, NUL-terminated (libconfig reads up to the first NUL) */
    char *text = malloc(size + 1);
    if (!text) abort();
    memcpy(text, data, size);
    text[size] = '\0';
    if (strstr(text, "@include")) {
        res->skipped = true;
        free(text);
        return;
    }

    /* "#set key=value" lines: overrides, in order */
    char *overrides[FUZZ_SCENE_MAX_OVERRIDES];
    int noverrides = 0;
    for (const char *line = text; line && noverrides < FUZZ_SCENE_MAX_OVERRIDES;) {
        const char *end = strchr(line, '\n');
        size_t len = end ? (size_t)(end - line) : strlen(line);
        if (len >= 5 && strncmp(line, "#set ", 5) == 0) {
            char *ov = malloc(len - 4);
            if (!ov) abort();
            memcpy(ov, line + 5, len - 5);
            ov[len - 5] = '\0';
            overrides[noverrides++] = ov;
        }
        line = end ? end + 1 : NULL;
    }

    sph_scene scene;
    res->load = sph_scene_load_text(&scene, origin, text, (const char *const *)overrides,
                                    noverrides, &res->err);
    if (res->load != SPH_OK) {
        check_failure(res, "load", res->load, &res->err, origin);
    } else {
        check_scene(res, &scene);
        /* the resolved text is what a checkpoint stores: it must load again */
        sph_scene again;
        sph_error err2 = {0};
        sph_status st = sph_scene_load_text(&again, origin, scene.resolved_text, NULL, 0, &err2);
        if (st != SPH_OK)
            violate(res, "the resolved text does not load again: %s", err2.msg);
        else if (again.dim != scene.dim || again.nbodies != scene.nbodies ||
                 again.nshapes != scene.nshapes || again.nmaterials != scene.nmaterials ||
                 again.formulation != scene.formulation)
            violate(res, "the resolved text loads as a different scene");
        sph_scene_free(&again);

        if (!res->violation[0] && within_budget(&scene)) {
            /* relaxed bodies: in memory only (a fuzz input writes no
             * files) and a few steps, enough to run every path; in 2D
             * only: a 3D body's boundary mesh (relax.c) takes 20 s for
             * a hollow ball of 700 lattice points under the sanitizers,
             * past the fuzzer's timeout (3D relaxation: tests/test_relax.c) */
            for (int b = 0; b < scene.nbodies; b++) {
                scene.bodies[b].relaxation.file[0] = '\0';
                if (scene.bodies[b].relaxation.steps > 5) scene.bodies[b].relaxation.steps = 5;
                if (scene.dim == 3) scene.bodies[b].placement = SPH_PLACEMENT_LATTICE;
            }
            sph_particles p;
            res->generated = true;
            res->particles = sph_particles_generate(&scene, &p, &res->err);
            if (res->particles != SPH_OK) {
                check_failure(res, "particles", res->particles, &res->err, origin);
            } else {
                res->nparticles = p.n;
                check_particles(res, &scene, &p);
                sph_particles_free(&p);
            }
        }
        sph_scene_free(&scene);
    }
    for (int i = 0; i < noverrides; i++) free(overrides[i]);
    free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fuzz_scene_result res;
    fuzz_scene_run(data, size, "fuzz-input.cfg", &res);
    if (res.violation[0]) {
        fprintf(stderr, "fuzz_scene: invariant violated: %s\n", res.violation);
        abort();
    }
    return res.skipped ? -1 : 0;
}
