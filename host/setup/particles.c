/* particles.c — the initial particle set: lattice placement, per-body
 * ownership, initial velocity, fixed-constraint flags (see particles.h). */
#include "particles.h"

#include "relax.h"
#include "shape_sdf.h"
#include "sph_constants.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

/* 003 eq. 51: the first bending mode of a clamped-free plate,
 * f(s) = (sin kL + sinh kL)(cos ks - cosh ks) - (cos kL + cosh kL)(sin ks - sinh ks). */
static double cantilever_mode_shape(double kl, double ks) {
    return (sin(kl) + sinh(kl)) * (cos(ks) - cosh(ks)) -
           (cos(kl) + cosh(kl)) * (sin(ks) - sinh(ks));
}

void sph_velocity_field_eval(const sph_scene *scene, const sph_body *body, const double x[3],
                             double v[3]) {
    const sph_velocity_field *f = &body->velocity;
    v[0] = v[1] = v[2] = 0.0;
    switch (f->type) {
    case SPH_VELOCITY_ZERO:
        break;
    case SPH_VELOCITY_UNIFORM:
        for (int a = 0; a < scene->dim; a++) v[a] = f->vector[a];
        break;
    case SPH_VELOCITY_RIGID_ROTATION: {
        double r[3] = {0, 0, 0};
        for (int a = 0; a < scene->dim; a++) r[a] = x[a] - f->centre[a];
        if (scene->dim == 2) {
            /* omega = omega_z e_z: v = omega_z (-r_y, r_x) */
            v[0] = -f->omega[2] * r[1];
            v[1] = f->omega[2] * r[0];
        } else {
            v[0] = f->omega[1] * r[2] - f->omega[2] * r[1];
            v[1] = f->omega[2] * r[0] - f->omega[0] * r[2];
            v[2] = f->omega[0] * r[1] - f->omega[1] * r[0];
        }
        break;
    }
    case SPH_VELOCITY_CANTILEVER_MODE: {
        /* 003 eq. 50: v = v_f c0 f(s) / f(L), s measured from the clamp along x;
         * the clamped part (s <= 0) starts at rest */
        double s = x[0] - f->clamp_x;
        if (s > 0.0) {
            double c0 = scene->materials[body->material].sound_speed;
            double k = f->kl / f->length;
            v[f->axis] = f->amplitude_c0 * c0 * cantilever_mode_shape(f->kl, k * s) /
                         cantilever_mode_shape(f->kl, f->kl);
        }
        break;
    }
    case SPH_VELOCITY_PLATE_MODE: {
        /* 000 eq. 35 */
        const double pi = 3.14159265358979323846;
        v[f->axis] = f->amplitude * sin(f->modes[0] * pi * (x[0] - f->lower[0]) / f->size[0]) *
                     sin(f->modes[1] * pi * (x[1] - f->lower[1]) / f->size[1]);
        break;
    }
    case SPH_VELOCITY_EXPRESSION:
        /* compiled once per body by apply_velocity_expressions, not per call */
        break;
    }
}

/* Lattice index range [first, last] of the cell centres
 * origin + (i + 1/2) dp that lie in [lo, hi]; the half-cell offset keeps
 * centres half a spacing away from box faces placed on the lattice, so
 * rounding cannot move a face onto a centre. */
static void index_range(double lo, double hi, double origin, double dp, long *first, long *last) {
    *first = (long)ceil((lo - origin) / dp - 0.5);
    *last = (long)floor((hi - origin) / dp - 0.5);
}

/* The particle spacing of body b: dp for matter, spacing_ratio dp for a
 * wall body (scene.h; a scene filled by hand may leave the ratio 0: dp). */
static double body_spacing(const sph_scene *scene, int b) {
    const double ratio = scene->bodies[b].spacing_ratio;
    return ratio > 0.0 && ratio <= 1.0 ? ratio * scene->dp : scene->dp;
}

static bool is_wall(const sph_scene *scene, int b) {
    return scene->bodies[b].role == SPH_BODY_WALL;
}

static bool any_wall_body(const sph_scene *scene) {
    for (int b = 0; b < scene->nbodies; b++)
        if (is_wall(scene, b)) return true;
    return false;
}

/* Are the points around x (a small step along every axis, both ways) in
 * both shapes?  A lattice point that two bodies share only because it lies
 * on a face where they touch is not; one inside a common volume is. */
static bool shared_volume(const sph_scene *scene, int s1, int s2, const double x[3]) {
    for (int a = 0; a < scene->dim; a++) {
        const double eps = fmax(1e-6 * scene->dp, 1e-12 * fabs(x[a]));
        for (int sign = -1; sign <= 1; sign += 2) {
            double y[3] = {x[0], x[1], x[2]};
            y[a] += sign * eps;
            if (!sph_shape_contains(scene, s1, y) || !sph_shape_contains(scene, s2, y))
                return false;
        }
    }
    return true;
}

/* What follows from particle n's position x in body b: velocity, mass,
 * density and the constraint flag (placed or relaxed). */
static void set_point_data(const sph_scene *scene, int b, sph_particles *out, long n,
                           const double x[3]) {
    const int dim = scene->dim;
    const sph_body *body = &scene->bodies[b];
    /* the body's material, or that of its first region holding x */
    const int material = sph_body_material_at(scene, b, x);
    const sph_material *mat = &scene->materials[material];
    if (out->material) {
        int row_of[SPH_MAX_MATERIALS];
        sph_scene_material_rows(scene, row_of);
        out->material[n] = (uint8_t)row_of[material];
    }
    double v[3];
    sph_velocity_field_eval(scene, body, x, v);
    for (int a = 0; a < dim; a++) out->vel[(size_t)a * (size_t)out->n + (size_t)n] = v[a];
    out->mass[n] = mat->density * pow(body_spacing(scene, b), dim);
    out->rho[n] = mat->density;
    if (out->fixed) {
        /* the first of the body's constraints whose region holds the
         * particle; its index in the scene's constraint table
         * (sph_constraint_index) + 1 */
        uint8_t fixed = 0;
        for (int c = 0; c < body->nconstraints && !fixed; c++)
            if (sph_shape_contains(scene, body->constraints[c].region, x))
                fixed = (uint8_t)(sph_constraint_index(scene, b, c) + 1);
        out->fixed[n] = fixed;
    }
}

/* Replace the lattice particles of every body with placement = "relaxed"
 * by their relaxed positions (relax.h), then their velocities and
 * constraint flags by those at the new positions. */
static sph_status relax_bodies(const sph_scene *scene, const double origin[3], bool force,
                               sph_particles *out, sph_error *err) {
    const int dim = scene->dim;
    const size_t n = (size_t)out->n;
    long start = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        const long count = out->body_count[b];
        if (scene->bodies[b].placement != SPH_PLACEMENT_RELAXED) {
            start += count;
            continue;
        }
        double *x = malloc((size_t)dim * (size_t)count * sizeof *x);
        if (!x)
            return sph_fail(err, SPH_ERR_RUNTIME, "out of memory relaxing body '%s'",
                            scene->bodies[b].name);
        for (int a = 0; a < dim; a++)
            memcpy(x + (size_t)a * (size_t)count, out->pos + (size_t)a * n + (size_t)start,
                   (size_t)count * sizeof *x);
        /* what each constraint region holds on the lattice and after */
        const sph_body *body = &scene->bodies[b];
        long held[SPH_SCENE_MAX_CONSTRAINTS] = {0}, kept[SPH_SCENE_MAX_CONSTRAINTS] = {0};
        for (long i = 0; i < count; i++) {
            double y[3] = {0, 0, 0};
            for (int a = 0; a < dim; a++) y[a] = x[(size_t)a * (size_t)count + (size_t)i];
            for (int k = 0; k < body->nconstraints; k++)
                held[k] += sph_shape_contains(scene, body->constraints[k].region, y);
        }
        sph_status st = sph_relax_body(scene, b, origin, (int)count, x, force, &out->relax[b], err);
        if (!st) {
            for (long i = 0; i < count; i++) {
                double y[3] = {0, 0, 0};
                for (int a = 0; a < dim; a++) {
                    y[a] = x[(size_t)a * (size_t)count + (size_t)i];
                    out->pos[(size_t)a * n + (size_t)(start + i)] = y[a];
                }
                set_point_data(scene, b, out, start + i, y);
                for (int k = 0; k < body->nconstraints; k++)
                    kept[k] += sph_shape_contains(scene, body->constraints[k].region, y);
            }
        }
        free(x);
        if (st) return st;
        /* relaxed particles keep dp/2 from the body's surface: a region
         * thinner than that along the surface may lose every particle */
        for (int k = 0; k < body->nconstraints; k++)
            if (held[k] > 0 && kept[k] == 0)
                return sph_fail(
                    err, SPH_ERR_INPUT,
                    "%s: constraint %d (region '%s') holds %ld of the lattice particles but "
                    "none of the relaxed ones, which keep dp/2 = %g inside the "
                    "body's surface; make the region reach deeper into the body",
                    body->where, k, scene->shapes[body->constraints[k].region].name, held[k],
                    0.5 * body_spacing(scene, b));
        start += count;
    }
    out->fixed_count = 0;
    for (size_t i = 0; out->fixed && i < n; i++) out->fixed_count += out->fixed[i] != 0;
    return SPH_OK;
}

/* The first point where a body overlaps an earlier one, and the first of
 * its shape's points that a wall body takes. */
typedef struct {
    int other; /* the earlier body, -1: none */
    double x[3];
    int wall; /* the wall body, -1: none */
    double wall_x[3];
} overlap_info;

/* Visit the lattice points owned by body b, in z, y, x order (x fastest),
 * and return their number.  With `out` NULL only counts, and stops with -1
 * at the first point inside the volume of an earlier body (`overlap`);
 * otherwise also writes them as particles start, start + 1, ...  A point on
 * a face two bodies share belongs to the earlier one.  Matter bodies share
 * the scene's lattice (spacing dp) and wall bodies have their own, of
 * spacing spacing_ratio dp anchored at the same origin: bodies of the two
 * kinds are compared apart, and a matter point inside any wall body's
 * shape is not placed (the wall takes that volume, without an overlap). */
static long scan_body(const sph_scene *scene, int b, const double origin[3], sph_particles *out,
                      long start, overlap_info *overlap) {
    const int dim = scene->dim;
    const double dp = body_spacing(scene, b);
    const sph_body *body = &scene->bodies[b];
    const bool wall = is_wall(scene, b);
    double lo[3], hi[3];
    sph_shape_bounds(scene, body->shape, lo, hi);
    long first[3] = {0, 0, 0}, last[3] = {0, 0, 0};
    for (int a = 0; a < dim; a++) index_range(lo[a], hi[a], origin[a], dp, &first[a], &last[a]);

    long n = start;
    for (long k = first[2]; k <= last[2]; k++) {
        for (long j = first[1]; j <= last[1]; j++) {
            for (long i = first[0]; i <= last[0]; i++) {
                const long idx[3] = {i, j, k};
                double x[3] = {0, 0, 0};
                for (int a = 0; a < dim; a++) x[a] = origin[a] + ((double)idx[a] + 0.5) * dp;
                if (!sph_shape_contains(scene, body->shape, x)) continue;
                bool taken = false;
                for (int e = 0; !wall && e < scene->nbodies && !taken; e++) {
                    taken =
                        is_wall(scene, e) && sph_shape_contains(scene, scene->bodies[e].shape, x);
                    if (taken && overlap && overlap->wall < 0) {
                        overlap->wall = e;
                        for (int a = 0; a < 3; a++) overlap->wall_x[a] = x[a];
                    }
                }
                for (int e = 0; e < b && !taken; e++) {
                    if (is_wall(scene, e) != wall) continue;
                    taken = sph_shape_contains(scene, scene->bodies[e].shape, x);
                    if (taken && overlap &&
                        shared_volume(scene, body->shape, scene->bodies[e].shape, x)) {
                        overlap->other = e;
                        for (int a = 0; a < 3; a++) overlap->x[a] = x[a];
                        return -1;
                    }
                }
                if (taken) continue;
                if (out) {
                    for (int a = 0; a < dim; a++)
                        out->pos[(size_t)a * (size_t)out->n + (size_t)n] = x[a];
                    out->id[n] = (int32_t)n;
                    out->body[n] = (uint8_t)b;
                    set_point_data(scene, b, out, n, x);
                }
                n++;
            }
        }
    }
    return n - start;
}

/* "(x, y)" or "(x, y, z)" */
static void format_point(const double x[3], int dim, char *buf, size_t len) {
    if (dim == 1)
        snprintf(buf, len, "(%g)", x[0]);
    else if (dim == 2)
        snprintf(buf, len, "(%g, %g)", x[0], x[1]);
    else
        snprintf(buf, len, "(%g, %g, %g)", x[0], x[1], x[2]);
}

/* The position of particle i of p, as format_point writes it. */
static void format_particle(const sph_particles *p, int dim, size_t i, char *buf, size_t len) {
    double x[3] = {0, 0, 0};
    for (int a = 0; a < dim; a++) x[a] = p->pos[(size_t)a * (size_t)p->n + i];
    format_point(x, dim, buf, len);
}

/* "(x, y) to (x, y)": a box, for the messages that say where a region, a
 * domain or a body's particles lie */
static void format_span(const double lo[3], const double hi[3], int dim, char *buf, size_t len) {
    char l[96], h[96];
    format_point(lo, dim, l, sizeof l);
    format_point(hi, dim, h, sizeof h);
    snprintf(buf, len, "%s to %s", l, h);
}

/* The velocities of the bodies whose initial_velocity is an expression
 * (set_point_data left them 0): the body's expressions are compiled once
 * and evaluated at every particle of the body, placed or relaxed.  A value
 * that is not finite is an input error naming the expression's key and the
 * particle. */
static sph_status apply_velocity_expressions(const sph_scene *scene, sph_particles *out,
                                             sph_error *err) {
    const int dim = scene->dim;
    const size_t n = (size_t)out->n;
    const char *vars[3], *names[SPH_SCENE_MAX_CONSTANTS];
    const int nvars = sph_scene_expression_variables(dim, vars);
    const sph_expression_constants constants = sph_scene_expression_constants(scene, names);
    size_t start = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        const size_t count = (size_t)out->body_count[b];
        const sph_body *body = &scene->bodies[b];
        const sph_velocity_field *f = &body->velocity;
        if (f->type != SPH_VELOCITY_EXPRESSION) {
            start += count;
            continue;
        }
        const char *texts[3] = {f->expression[0], f->expression[1], f->expression[2]};
        sph_expression_field field;
        int bad = -1;
        char why[768];
        /* the scene loader compiled the same texts: a failure here is a
         * scene built around it (a test, a caller filling sph_scene) */
        if (!sph_expression_field_compile(&field, texts, dim, vars, nvars, &constants, &bad, why,
                                          sizeof why))
            return sph_fail(err, SPH_ERR_INPUT, "%s: %s",
                            bad >= 0 && f->expression_where[bad][0] ? f->expression_where[bad]
                                                                    : body->where,
                            why);
        for (size_t i = start; i < start + count; i++) {
            double x[3] = {0, 0, 0}, v[3] = {0, 0, 0};
            for (int a = 0; a < dim; a++) x[a] = out->pos[(size_t)a * n + i];
            if (!sph_expression_field_eval(&field, x, false, v, &bad, why, sizeof why)) {
                char point[96];
                format_point(x, dim, point, sizeof point);
                sph_expression_field_free(&field);
                return sph_fail(err, SPH_ERR_INPUT,
                                "%s: the expression \"%.200s\" %s at the particle at %s of body "
                                "'%s': initial velocities must be finite",
                                f->expression_where[bad], f->expression[bad], why, point,
                                body->name);
            }
            for (int a = 0; a < dim; a++) out->vel[(size_t)a * n + i] = v[a];
        }
        sph_expression_field_free(&field);
        start += count;
    }
    return SPH_OK;
}

/* The initial state of the fluid bodies (the eulerian formulations): rho
 * from bodies.X.initial_density (else the material's rho0), the mass
 * rho w with the lattice volume w = dp^d (a wall body's (spacing_ratio
 * dp)^d; seed 004 eq. 14 carries w_i rho_i),
 * and for the ideal gas the pressure from bodies.X.initial_pressure.  A value
 * that is not finite, a density <= 0 or a pressure <= 0 is an input error
 * naming the key and the particle. */
static sph_status apply_fluid_state(const sph_scene *scene, sph_particles *out, sph_error *err) {
    if (!SPH_FORMULATION_IS_EULERIAN(scene->formulation)) return SPH_OK;
    const bool compressible = scene->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE;
    const int dim = scene->dim;
    const size_t n = (size_t)out->n;
    const char *vars[3], *names[SPH_SCENE_MAX_CONSTANTS];
    const int nvars = sph_scene_expression_variables(dim, vars);
    const sph_expression_constants constants = sph_scene_expression_constants(scene, names);
    size_t start = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        const size_t count = (size_t)out->body_count[b];
        const sph_body *body = &scene->bodies[b];
        const sph_material *mat = &scene->materials[body->material];
        /* the particle's volume: dp^d, a wall's (spacing_ratio dp)^d */
        const double volume = pow(body_spacing(scene, b), dim);
        /* a wall particle of the ideal gas carries p = 0 (and so E = 0,
         * c = 0): no pair reads a wall particle's state, the fluid
         * particle's mirrored one is the other side of its Riemann problem
         * (device/eulerian_step.cl, wall_interface) */
        const bool gas = compressible && !is_wall(scene, b);
        if (gas && !body->initial_pressure[0])
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s.initial_pressure: missing: the ideal gas of formulation "
                            "\"eulerian-compressible\" starts from a pressure",
                            body->where);
        /* entry 0 the density, 1 the pressure; "" is 0 everywhere */
        const char *texts[2] = {body->initial_density, gas ? body->initial_pressure : ""};
        const char *wheres[2] = {
            body->initial_density_where[0] ? body->initial_density_where : body->where,
            body->initial_pressure_where[0] ? body->initial_pressure_where : body->where};
        static const char *const what[2] = {"densities", "pressures"};
        sph_expression_field field;
        int bad = -1;
        char why[768];
        /* the scene loader compiled the same texts: a failure here is a
         * scene built around it (a test, a caller filling sph_scene) */
        if (!sph_expression_field_compile(&field, texts, 2, vars, nvars, &constants, &bad, why,
                                          sizeof why))
            return sph_fail(err, SPH_ERR_INPUT, "%s: %s", bad >= 0 ? wheres[bad] : body->where,
                            why);
        for (size_t i = start; i < start + count; i++) {
            double x[3] = {0, 0, 0}, v[2] = {0, 0};
            for (int a = 0; a < dim; a++) x[a] = out->pos[(size_t)a * n + i];
            /* a library error or a value that is not finite: `why` says which */
            bool ok = sph_expression_field_eval(&field, x, false, v, &bad, why, sizeof why);
            if (ok && !body->initial_density[0]) v[0] = mat->density;
            if (ok && (!(v[0] > 0.0) || (gas && !(v[1] > 0.0)))) {
                ok = false;
                bad = v[0] > 0.0 ? 1 : 0;
                snprintf(why, sizeof why, "gives %g", v[bad]);
            }
            if (!ok) {
                char point[96];
                format_point(x, dim, point, sizeof point);
                sph_expression_field_free(&field);
                return sph_fail(err, SPH_ERR_INPUT,
                                "%s: the expression \"%.200s\" %s at the particle at %s of body "
                                "'%s': initial %s must be finite and > 0",
                                wheres[bad], texts[bad], why, point, body->name, what[bad]);
            }
            out->rho[i] = v[0];
            out->mass[i] = v[0] * volume;
            if (gas) out->pressure[i] = v[1];
        }
        sph_expression_field_free(&field);
        start += count;
    }
    return SPH_OK;
}

/* Along a periodic axis (scene.h, boundary) every particle must lie in
 * [lower, upper) and on the lattice lower + (i + 1/2) dp: the particles next
 * to the seam are then dp from their neighbours' images, as everywhere else
 * (a lattice anchored elsewhere would put a gap or an overlap there). */
static sph_status check_periodic_lattice(const sph_scene *scene, const sph_particles *p,
                                         sph_error *err) {
    if (!scene->periodic_mask) return SPH_OK;
    const int dim = scene->dim;
    const size_t n = (size_t)p->n;
    for (int a = 0; a < dim; a++) {
        if (!(scene->periodic_mask & (1 << a))) continue;
        const double lo = scene->periodic_lower[a], hi = scene->periodic_upper[a];
        for (size_t i = 0; i < n; i++) {
            /* a wall body's particles: on its own lattice, spacing_ratio dp */
            const double dp = body_spacing(scene, p->body[i]);
            const double xa = p->pos[(size_t)a * n + i];
            const double s = (xa - lo) / dp - 0.5, off = s - round(s);
            const bool inside = xa >= lo && xa < hi;
            if (inside && fabs(off) <= 1e-6) continue;
            char point[96];
            format_particle(p, dim, i, point, sizeof point);
            const sph_body *body = &scene->bodies[p->body[i]];
            if (!inside)
                return sph_fail(err, SPH_ERR_INPUT,
                                "%s: the lattice does not fit the periodic axis %c: the particle "
                                "at %s of body '%s' (%s) lies outside the period [%g, %g); "
                                "every body must lie within boundary.lower and boundary.upper "
                                "along it",
                                scene->periodic_where, "xyz"[a], point, body -> name, body -> where,
                                lo, hi);
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: the lattice does not fit the periodic axis %c: the particle at "
                            "%s of body '%s' (%s) lies %.3g dp off the lattice boundary.lower + "
                            "(i + 1/2) dp, so the particles across the seam would not be dp "
                            "apart; leave lattice_origin out (it is then anchored at "
                            "boundary.lower) or put it on that lattice",
                            scene->periodic_where, "xyz"[a], point, body -> name, body -> where,
                            off);
        }
    }
    return SPH_OK;
}

/* A far-field scene (boundary.far_field): the far field acts on the faces
 * of the box [boundary.lower, boundary.upper], so every matter particle must
 * lie inside it (a wall body may reach beyond it). */
static sph_status check_far_field_box(const sph_scene *scene, const sph_particles *p,
                                      sph_error *err) {
    if (!scene->has_far_field) return SPH_OK;
    const int dim = scene->dim;
    const size_t n = (size_t)p->n;
    const double *lower = scene->periodic_lower, *upper = scene->periodic_upper;
    for (size_t i = 0; i < n; i++) {
        if (is_wall(scene, p->body[i])) continue;
        bool in = true;
        for (int a = 0; a < dim; a++) {
            const double x = p->pos[(size_t)a * n + i];
            in = in && x >= lower[a] && x <= upper[a];
        }
        if (in) continue;
        char point[96], box[200];
        format_particle(p, dim, i, point, sizeof point);
        format_span(lower, upper, dim, box, sizeof box);
        const sph_body *body = &scene->bodies[p->body[i]];
        return sph_fail(err, SPH_ERR_INPUT,
                        "%s: the particle at %s of body '%s' (%s) lies outside the far field's "
                        "box boundary.lower to boundary.upper, %s; every matter body must lie "
                        "within it (the far field acts on its faces)",
                        scene->periodic_where, point, body->name, body->where, box);
    }
    return SPH_OK;
}

/* Scenes with wall bodies or a far field: each particle's kind and normal
 * (particles.h).  A wall particle's normal is the outward normal of its
 * body's shape at it (the gradient of the signed distance, shape_sdf.h:
 * out of the wall, into the fluid).  A fluid particle within one cut-off
 * 2h of a far-field face (a face of the boundary box across an axis that is
 * not periodic) takes that face's outward normal n, the nearest face's
 * (ties: the first axis, the lower face), and is outflow where
 * U_inf . n > 0, else inflow (the public code's rule: the left, top and
 * bottom of a flow along x are inflow). */
static void assign_kinds(const sph_scene *scene, sph_particles *p) {
    if (!p->kind) return;
    const int dim = scene->dim;
    const size_t n = (size_t)p->n;
    const double cutoff = 2.0 * scene->smoothing_ratio * scene->dp;
    for (size_t i = 0; i < n; i++) {
        double x[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
        for (int a = 0; a < dim; a++) x[a] = p->pos[(size_t)a * n + i];
        const int b = p->body[i];
        uint8_t kind = SPH_PARTICLE_FLUID;
        if (is_wall(scene, b)) {
            kind = SPH_PARTICLE_WALL;
            sph_shape_sdf(scene, scene->bodies[b].shape, x, normal);
            double norm = 0.0;
            for (int a = 0; a < dim; a++) norm += normal[a] * normal[a];
            norm = sqrt(norm);
            /* 2D: the shape's normal has no z part; keep it a unit vector
             * (x where the distance function gives none) */
            for (int a = 0; a < dim; a++)
                normal[a] = norm > 0.0 ? normal[a] / norm : (a == 0 ? 1.0 : 0.0);
        } else if (scene->has_far_field) {
            /* distances equal to rounding (a corner's diagonal) are ties */
            const double tie = 1e-9 * scene->dp;
            double nearest = INFINITY;
            int face_axis = -1, face_side = 0;
            for (int a = 0; a < dim; a++) {
                if (scene->periodic_mask & (1 << a)) continue;
                for (int side = -1; side <= 1; side += 2) {
                    const double d = side < 0 ? x[a] - scene->periodic_lower[a]
                                              : scene->periodic_upper[a] - x[a];
                    if (d < cutoff && d < nearest - tie)
                        nearest = d, face_axis = a, face_side = side;
                }
            }
            if (face_axis >= 0) {
                normal[face_axis] = (double)face_side;
                const double un = scene->far_field_velocity[face_axis] * face_side;
                kind = un > 0.0 ? SPH_PARTICLE_OUTFLOW : SPH_PARTICLE_INFLOW;
            }
        }
        p->kind[i] = kind;
        for (int a = 0; a < dim; a++) p->normal[(size_t)a * n + i] = normal[a];
    }
}

/* The bounding box of body b's particles [start, start + count). */
static void body_span(const sph_particles *p, long start, long count, double lo[3], double hi[3]) {
    const size_t n = (size_t)p->n;
    for (int a = 0; a < 3; a++) lo[a] = hi[a] = 0.0;
    for (int a = 0; a < p->dim; a++) {
        lo[a] = INFINITY;
        hi[a] = -INFINITY;
        for (long i = start; i < start + count; i++) {
            const double x = p->pos[(size_t)a * n + (size_t)i];
            lo[a] = fmin(lo[a], x);
            hi[a] = fmax(hi[a], x);
        }
    }
}

/* Every constraint must select particles of its body: a region that holds
 * none (a typo in its coordinates, a region of another body, one thinner
 * than dp between lattice points), or whose particles all take a constraint
 * listed before it, would leave the body silently unconstrained there.
 * Checked on the lattice; relax_bodies checks the relaxed positions. */
/* The box of shape `shape` and that of the body's particles [start, start +
 * count), as text for messages. */
#define SPAN_TEXT 200
static void region_and_body_spans(const sph_scene *scene, const sph_particles *p, int shape,
                                  long start, long count, char rs[SPAN_TEXT], char bs[SPAN_TEXT]) {
    double rlo[3], rhi[3], blo[3], bhi[3];
    sph_shape_bounds(scene, shape, rlo, rhi);
    body_span(p, start, count, blo, bhi);
    format_span(rlo, rhi, scene->dim, rs, SPAN_TEXT);
    format_span(blo, bhi, scene->dim, bs, SPAN_TEXT);
}

/* Every region of a body must give its material to some of the body's
 * particles: a region outside the body, or inside an earlier region of it,
 * would change nothing. */
static sph_status check_material_regions(const sph_scene *scene, const sph_particles *p,
                                         sph_error *err) {
    const int dim = scene->dim;
    const size_t n = (size_t)p->n;
    long start = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        const sph_body *body = &scene->bodies[b];
        const long count = p->body_count[b];
        long given[SPH_SCENE_MAX_REGIONS] = {0};
        for (long i = start; i < start + count && body->nregions > 0; i++) {
            double x[3] = {0, 0, 0};
            for (int a = 0; a < dim; a++) x[a] = p->pos[(size_t)a * n + (size_t)i];
            for (int k = 0; k < body->nregions; k++)
                if (sph_shape_contains(scene, body->regions[k].shape, x)) {
                    given[k]++;
                    break;
                }
        }
        for (int k = 0; k < body->nregions; k++) {
            if (given[k] > 0) continue;
            const sph_region *r = &body->regions[k];
            char rs[SPAN_TEXT], bs[SPAN_TEXT];
            region_and_body_spans(scene, p, r->shape, start, count, rs, bs);
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: region '%s' (within %s) gives material '%s' to none of the "
                            "%ld particles of body '%s' (%s, spacing dp = %g): it lies outside "
                            "the body or inside an earlier region of it; make it overlap the "
                            "part of that material",
                            r->where, scene->shapes[r->shape].name, rs,
                            scene->materials[r->material].name, count, body->name, bs, scene->dp);
        }
        start += count;
    }
    return SPH_OK;
}

static sph_status check_constraint_regions(const sph_scene *scene, const sph_particles *p,
                                           sph_error *err) {
    const int dim = scene->dim;
    const size_t n = (size_t)p->n;
    long start = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        const sph_body *body = &scene->bodies[b];
        const long count = p->body_count[b];
        long held[SPH_SCENE_MAX_CONSTRAINTS] = {0}, taken[SPH_SCENE_MAX_CONSTRAINTS] = {0};
        for (long i = start; i < start + count && body->nconstraints > 0; i++) {
            double x[3] = {0, 0, 0};
            for (int a = 0; a < dim; a++) x[a] = p->pos[(size_t)a * n + (size_t)i];
            for (int k = 0; k < body->nconstraints; k++)
                held[k] += sph_shape_contains(scene, body->constraints[k].region, x);
            const int f = p->fixed[i];
            if (f > 0) taken[f - 1 - sph_constraint_index(scene, b, 0)]++;
        }
        for (int k = 0; k < body->nconstraints; k++) {
            const sph_constraint *con = &body->constraints[k];
            const char *region = scene->shapes[con->region].name;
            if (held[k] == 0) {
                char rs[SPAN_TEXT], bs[SPAN_TEXT];
                region_and_body_spans(scene, p, con->region, start, count, rs, bs);
                return sph_fail(err, SPH_ERR_INPUT,
                                "%s: region '%s' (within %s) holds none of the %ld particles "
                                "of body '%s' (%s, spacing dp = %g), so the constraint "
                                "would do nothing; make the region cover the particles to "
                                "constrain",
                                con->where, region, rs, count, body->name, bs, scene->dp);
            }
            if (taken[k] == 0) {
                int first = 0;
                for (int j = 0; j < k; j++) {
                    double x[3] = {0, 0, 0};
                    bool shared = false;
                    for (long i = start; i < start + count && !shared; i++) {
                        for (int a = 0; a < dim; a++) x[a] = p->pos[(size_t)a * n + (size_t)i];
                        shared = sph_shape_contains(scene, con->region, x) &&
                                 sph_shape_contains(scene, body->constraints[j].region, x);
                    }
                    if (shared) {
                        first = j;
                        break;
                    }
                }
                return sph_fail(err, SPH_ERR_INPUT,
                                "%s: every one of the %ld particles of body '%s' in region '%s' "
                                "takes an earlier constraint (a particle takes the first listed "
                                "whose region holds it; constraint [%d], region '%s'), so this "
                                "one would do nothing",
                                con->where, held[k], body->name, region, first,
                                scene->shapes[body->constraints[first].region].name);
            }
        }
        start += count;
    }
    return SPH_OK;
}

/* A given monitor.domain must hold every particle at the start: the
 * monitor would otherwise stop the run at t = 0 as an instability. */
static sph_status check_monitor_domain(const sph_scene *scene, const sph_particles *p,
                                       sph_error *err) {
    if (!scene->monitor_has_domain || scene->monitor_action == SPH_MONITOR_OFF) return SPH_OK;
    const int dim = scene->dim;
    const size_t n = (size_t)p->n;
    const double *lower = scene->monitor_domain_lower, *upper = scene->monitor_domain_upper;
    long start = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        const long count = p->body_count[b];
        long outside = 0, first = -1;
        for (long i = start; i < start + count; i++) {
            bool in = true;
            for (int a = 0; a < dim; a++) {
                const double x = p->pos[(size_t)a * n + (size_t)i];
                in = in && x >= lower[a] && x <= upper[a];
            }
            if (!in && first < 0) first = i;
            outside += !in;
        }
        if (outside > 0) {
            const sph_body *body = &scene->bodies[b];
            double blo[3], bhi[3];
            body_span(p, start, count, blo, bhi);
            char pt[96], ds[200], bs[200];
            format_particle(p, dim, (size_t)first, pt, sizeof pt);
            format_span(lower, upper, dim, ds, sizeof ds);
            format_span(blo, bhi, dim, bs, sizeof bs);
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: %ld of the %ld particles of body '%s' (%s) start outside the "
                            "domain %s, the first at %s; the body's particles span %s, and the "
                            "domain must contain them all",
                            scene->monitor_domain_where, outside, count, body->name, body->where,
                            ds, pt, bs);
        }
        start += count;
    }
    return SPH_OK;
}

void sph_format_bytes(double bytes, char *buf, size_t len) {
    static const char *const units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 6) {
        bytes /= 1024.0;
        u++;
    }
    if (u == 0)
        snprintf(buf, len, "%.0f bytes", bytes);
    else
        snprintf(buf, len, "%.1f %s", bytes, units[u]);
}

double sph_host_memory_available(char *describe, size_t len) {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    const double physical = pages > 0 && page > 0 ? (double)pages * (double)page : INFINITY;
    double limit = physical;
    const char *which = NULL;
    struct rlimit rl;
    if (getrlimit(RLIMIT_DATA, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        (double)rl.rlim_cur < limit) {
        limit = (double)rl.rlim_cur;
        which = "its data-size limit, ulimit -d";
    }
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        (double)rl.rlim_cur < limit) {
        limit = (double)rl.rlim_cur;
        which = "its address-space limit, ulimit -v";
    }
    char phys[32], lim[32];
    sph_format_bytes(physical, phys, sizeof phys);
    sph_format_bytes(limit, lim, sizeof lim);
    if (!isfinite(physical))
        snprintf(describe, len, "the size of this machine's memory is unknown");
    else if (which)
        snprintf(describe, len,
                 "this process may use %s (%s; the machine has %s of physical memory)", lim, which,
                 phys);
    else
        snprintf(describe, len, "this machine has %s of physical memory", phys);
    return limit;
}

size_t sph_particles_bytes_each(int dim, bool constrained) {
    return 2 * (size_t)dim * sizeof(double) /* pos, vel */ + 2 * sizeof(double) /* mass, rho */ +
           sizeof(int32_t) + sizeof(uint8_t) + (constrained ? sizeof(uint8_t) : 0);
}

sph_status sph_particles_generate(const sph_scene *scene, sph_particles *out, sph_error *err) {
    return sph_particles_generate_ex(scene, out, false, err);
}

sph_status sph_particles_generate_ex(const sph_scene *scene, sph_particles *out, bool force_relax,
                                     sph_error *err) {
    memset(out, 0, sizeof *out);
    const int dim = scene->dim;
    out->dim = dim;

    /* lattice origin: the lower corner of all matter bodies unless the scene
     * sets it; along a periodic axis boundary.lower, so that a body filling the
     * period holds L/dp particles and the lattice continues across the seam
     * (check_periodic_lattice) */
    double origin[3] = {0, 0, 0};
    if (scene->has_lattice_origin) {
        for (int a = 0; a < dim; a++) origin[a] = scene->lattice_origin[a];
    } else {
        /* the matter bodies' corner: a wall body (on its own lattice from
         * the same origin) does not move the fluid's lattice */
        bool first = true;
        for (int b = 0; b < scene->nbodies; b++) {
            if (is_wall(scene, b)) continue;
            double lo[3], hi[3];
            sph_shape_bounds(scene, scene->bodies[b].shape, lo, hi);
            for (int a = 0; a < dim; a++)
                if (first || lo[a] < origin[a]) origin[a] = lo[a];
            first = false;
        }
        for (int a = 0; a < dim; a++)
            if (scene->periodic_mask & (1 << a)) origin[a] = scene->periodic_lower[a];
    }

    bool any_constraint = false;
    for (int b = 0; b < scene->nbodies; b++) any_constraint |= scene->bodies[b].nconstraints > 0;
    /* several materials: each particle's row of the material table */
    int row_of[SPH_MAX_MATERIALS];
    const bool with_materials = sph_scene_material_rows(scene, row_of) > 1;
    /* the ideal gas's initial pressure: one more double a particle */
    const bool with_pressure = scene->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE;
    /* fluid scenes with wall bodies or a far field: each particle's kind and
     * normal (assign_kinds) */
    const bool with_kinds = SPH_FORMULATION_IS_EULERIAN(scene->formulation) &&
                            (scene->has_far_field || any_wall_body(scene));
    const double each =
        (double)sph_particles_bytes_each(dim, any_constraint) +
        (with_pressure ? (double)sizeof(double) : 0.0) +
        (with_materials ? (double)sizeof(uint8_t) : 0.0) +
        (with_kinds ? (double)(sizeof(uint8_t) + (size_t)dim * sizeof(double)) : 0.0);
    char available[256], need[32];

    /* guard the scan itself: a tiny dp in a large box would loop for ages,
     * and more particles than fit the memory or an int32 index cannot run */
    long total = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        double lo[3], hi[3], points = 1.0;
        /* a wall body's lattice: spacing_ratio dp */
        const double spacing = body_spacing(scene, b);
        sph_shape_bounds(scene, scene->bodies[b].shape, lo, hi);
        for (int a = 0; a < dim; a++) points *= (hi[a] - lo[a]) / spacing + 1.0;
        if (!(points <= (double)INT32_MAX)) {
            const double limit = sph_host_memory_available(available, sizeof available);
            sph_format_bytes(points * each, need, sizeof need);
            if (points * each > limit)
                return sph_fail(err, SPH_ERR_RUNTIME,
                                "%s: at dp = %g the shape of body '%s' spans about %.3g lattice "
                                "points, and that many particles need at least %s of memory for "
                                "their initial arrays alone, but %s; lower the resolution",
                                scene->path, spacing, scene->bodies[b].name, points, need,
                                available);
            return sph_fail(err, SPH_ERR_RUNTIME,
                            "%s: at dp = %g the shape of body '%s' spans about %.3g lattice "
                            "points, more particles than this program can index (%d); lower the "
                            "resolution",
                            scene->path, spacing, scene->bodies[b].name, points, INT32_MAX);
        }
        /* lattice indices are counted from the origin and must fit a long */
        for (int a = 0; a < dim; a++) {
            double cells = fmax(fabs(lo[a] - origin[a]), fabs(hi[a] - origin[a])) / spacing;
            if (!(cells <= 1e15))
                return sph_fail(err, SPH_ERR_INPUT,
                                "%s: the shape lies about %.3g spacings (dp = %g) from the "
                                "lattice origin along %c, too far to place particles",
                                scene->bodies[b].where, cells, spacing, "xyz"[a]);
        }
    }
    for (int b = 0; b < scene->nbodies; b++) {
        overlap_info ov = {-1, {0, 0, 0}, -1, {0, 0, 0}};
        long count = scan_body(scene, b, origin, NULL, 0, &ov);
        if (count < 0) {
            const sph_body *body = &scene->bodies[b], *other = &scene->bodies[ov.other];
            char point[96];
            format_point(ov.x, dim, point, sizeof point);
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: overlaps body '%s' (%s): its shape '%s' and shape '%s' both "
                            "contain the point %s; bodies may touch but must not overlap",
                            body->where, other->name, other->where, scene->shapes[body->shape].name,
                            scene->shapes[other->shape].name, point);
        }
        if (count > 0 && ov.wall >= 0 && scene->bodies[b].placement == SPH_PLACEMENT_RELAXED) {
            /* the relaxation keeps a body within its own shape only */
            const sph_body *body = &scene->bodies[b], *w = &scene->bodies[ov.wall];
            char point[96];
            format_point(ov.wall_x, dim, point, sizeof point);
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: the body is relaxed (placement = \"relaxed\") within its shape "
                            "'%s', which reaches into wall body '%s' (%s) at %s: the relaxation "
                            "would move its particles into the wall; give the body its shape "
                            "without the wall's (a \"difference\" shape of the two, as "
                            "cases/cylinder_flow_2d/scene.cfg's flow = box minus disc)",
                            body->where, scene->shapes[body->shape].name, w->name, w->where, point);
        }
        if (count == 0)
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: the body has no particles: no lattice point (spacing %s = %g) "
                            "of its shape '%s' is free of earlier bodies%s",
                            scene->bodies[b].where, is_wall(scene, b) ? "spacing * dp" : "dp",
                            body_spacing(scene, b), scene->shapes[scene->bodies[b].shape].name,
                            with_kinds && !is_wall(scene, b) && any_wall_body(scene)
                                ? " and outside the wall bodies"
                                : "");
        out->body_count[b] = (int)count;
        total += count;
        if (total > INT32_MAX)
            return sph_fail(err, SPH_ERR_RUNTIME,
                            "%s: more than %d particles, more than this program can index; "
                            "lower the resolution",
                            scene->path, INT32_MAX);
    }
    /* before allocating: the particle arrays must fit in the memory */
    const double limit = sph_host_memory_available(available, sizeof available);
    if ((double)total * each > limit) {
        sph_format_bytes((double)total * each, need, sizeof need);
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "%s: %ld particles at dp = %g need %s of memory for their initial arrays "
                        "alone, but %s; lower the resolution",
                        scene->path, total, scene->dp, need, available);
    }

    size_t n = (size_t)total;
    out->n = (int)total;
    out->pos = malloc((size_t)dim * n * sizeof *out->pos);
    out->vel = malloc((size_t)dim * n * sizeof *out->vel);
    out->mass = malloc(n * sizeof *out->mass);
    out->rho = malloc(n * sizeof *out->rho);
    out->id = malloc(n * sizeof *out->id);
    out->body = malloc(n * sizeof *out->body);
    if (any_constraint) out->fixed = malloc(n * sizeof *out->fixed);
    if (with_materials) out->material = malloc(n * sizeof *out->material);
    if (with_pressure) out->pressure = calloc(n, sizeof *out->pressure);
    if (with_kinds) {
        out->kind = calloc(n, sizeof *out->kind);
        out->normal = calloc((size_t)dim * n, sizeof *out->normal);
    }
    if (!out->pos || !out->vel || !out->mass || !out->rho || !out->id || !out->body ||
        (any_constraint && !out->fixed) || (with_materials && !out->material) ||
        (with_pressure && !out->pressure) || (with_kinds && (!out->kind || !out->normal))) {
        sph_particles_free(out);
        sph_format_bytes((double)total * each, need, sizeof need);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of memory allocating %zu particles (%s); %s", n,
                        need, available);
    }

    long start = 0;
    for (int b = 0; b < scene->nbodies; b++) start += scan_body(scene, b, origin, out, start, NULL);
    out->fixed_count = 0;
    for (size_t i = 0; out->fixed && i < n; i++) out->fixed_count += out->fixed[i] != 0;
    sph_status rst = check_constraint_regions(scene, out, err);
    if (!rst) rst = check_material_regions(scene, out, err);
    if (!rst) rst = relax_bodies(scene, origin, force_relax, out, err);
    if (!rst) rst = apply_velocity_expressions(scene, out, err);
    if (!rst) rst = apply_fluid_state(scene, out, err);
    if (!rst) rst = check_periodic_lattice(scene, out, err);
    if (!rst) rst = check_far_field_box(scene, out, err);
    if (!rst) rst = check_monitor_domain(scene, out, err);
    if (!rst) assign_kinds(scene, out);
    if (rst) {
        sph_particles_free(out);
        return rst;
    }

    /* a body may touch a wall (its particles' cells end on the wall's
     * surface, centres dp/2 in front) but not cross it */
    for (int w = 0; w < scene->nwalls; w++) {
        const sph_wall *wall = &scene->walls[w];
        for (size_t i = 0; i < n; i++) {
            double d = 0.0;
            for (int a = 0; a < dim; a++)
                d += (out->pos[(size_t)a * n + i] - wall->point[a]) * wall->normal[a];
            if (d >= 0.5 * scene->dp * (1.0 - 1e-9)) continue;
            char point[96];
            format_particle(out, dim, i, point, sizeof point);
            const sph_body *body = &scene->bodies[out->body[i]];
            sph_particles_free(out);
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: wall '%s' cuts body '%s' (%s): its particle at %s lies %g from "
                            "the wall's surface, less than dp/2 = %g in front of it; a body may "
                            "touch a wall but not cross it",
                            wall->where, wall->name, body->name, body->where, point, d,
                            0.5 * scene->dp);
        }
    }

    /* extreme but finite inputs can overflow the initial velocity (a rigid
     * rotation far from its centre, a cantilever mode with a large kl) or the
     * mass rho0 dp^d */
    for (size_t i = 0; i < n; i++) {
        bool finite = isfinite(out->mass[i]) && out->mass[i] > 0.0;
        for (int a = 0; a < dim; a++) finite = finite && isfinite(out->vel[(size_t)a * n + i]);
        if (finite) continue;
        const sph_body *body = &scene->bodies[out->body[i]];
        double x[3] = {0, 0, 0}, v[3] = {0, 0, 0};
        for (int a = 0; a < dim; a++) {
            x[a] = out->pos[(size_t)a * n + i];
            v[a] = out->vel[(size_t)a * n + i];
        }
        double mass = out->mass[i];
        sph_particles_free(out);
        return sph_fail(err, SPH_ERR_INPUT,
                        "%s: the particle at (%g, %g, %g) gets velocity (%g, %g, %g) and mass %g "
                        "(density * dp^%d): not finite (check initial_velocity, density and the "
                        "spacing)",
                        body->where, x[0], x[1], x[2], v[0], v[1], v[2], mass, dim);
    }

    /* every observer needs particles within the kernel support to follow
     * (the interpolation of observers.c) */
    const double cutoff = 2.0 * scene->smoothing_ratio * scene->dp;
    for (int o = 0; o < scene->nobservers; o++) {
        const double *xo = scene->observers[o].position;
        bool near = false;
        for (size_t i = 0; i < n && !near; i++) {
            double r2 = 0.0;
            for (int a = 0; a < dim; a++) {
                const double d = out->pos[(size_t)a * n + i] - xo[a];
                r2 += d * d;
            }
            near = r2 < cutoff * cutoff;
        }
        if (near) continue;
        char point[96];
        format_point(xo, dim, point, sizeof point);
        sph_particles_free(out);
        return sph_fail(err, SPH_ERR_INPUT,
                        "%s: %s is outside every body: no particle lies within the kernel "
                        "support 2h = %g m of it; place the observer inside a body",
                        scene->observers[o].where, point, cutoff);
    }
    return SPH_OK;
}

void sph_particles_free(sph_particles *p) {
    if (!p) return;
    free(p->pos);
    free(p->vel);
    free(p->mass);
    free(p->rho);
    free(p->pressure);
    free(p->id);
    free(p->body);
    free(p->fixed);
    free(p->material);
    free(p->kind);
    free(p->normal);
    memset(p, 0, sizeof *p);
}
