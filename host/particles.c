/* particles.c — the initial particle set: lattice placement, per-body
 * ownership, initial velocity, fixed-constraint flags (see particles.h). */
#include "particles.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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

/* Visit the lattice points owned by body b, in z, y, x order (x fastest),
 * and return their number.  With `out` NULL only counts; otherwise also
 * writes them as particles start, start + 1, ... */
static long scan_body(const sph_scene *scene, int b, const double origin[3], sph_particles *out,
                      long start) {
    const int dim = scene->dim;
    const double dp = scene->dp;
    const sph_body *body = &scene->bodies[b];
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
                /* the first body in scene order owns a shared point */
                bool taken = false;
                for (int e = 0; e < b && !taken; e++)
                    taken = sph_shape_contains(scene, scene->bodies[e].shape, x);
                if (taken) continue;
                if (out) {
                    const sph_material *mat = &scene->materials[body->material];
                    double v[3];
                    sph_velocity_field_eval(scene, body, x, v);
                    for (int a = 0; a < dim; a++) {
                        out->pos[(size_t)a * (size_t)out->n + (size_t)n] = x[a];
                        out->vel[(size_t)a * (size_t)out->n + (size_t)n] = v[a];
                    }
                    out->mass[n] = mat->density * pow(dp, dim);
                    out->rho[n] = mat->density;
                    out->id[n] = (int32_t)n;
                    out->body[n] = (uint8_t)b;
                    if (out->fixed) {
                        uint8_t fixed = 0;
                        for (int c = 0; c < body->nconstraints && !fixed; c++)
                            if (body->constraints[c].type == SPH_CONSTRAINT_FIXED &&
                                sph_shape_contains(scene, body->constraints[c].region, x))
                                fixed = 1;
                        out->fixed[n] = fixed;
                        out->fixed_count += fixed;
                    }
                }
                n++;
            }
        }
    }
    return n - start;
}

sph_status sph_particles_generate(const sph_scene *scene, sph_particles *out, sph_error *err) {
    memset(out, 0, sizeof *out);
    const int dim = scene->dim;
    out->dim = dim;

    /* lattice origin: the lower corner of all bodies unless the scene sets it */
    double origin[3] = {0, 0, 0};
    if (scene->has_lattice_origin) {
        for (int a = 0; a < dim; a++) origin[a] = scene->lattice_origin[a];
    } else {
        for (int b = 0; b < scene->nbodies; b++) {
            double lo[3], hi[3];
            sph_shape_bounds(scene, scene->bodies[b].shape, lo, hi);
            for (int a = 0; a < dim; a++)
                if (b == 0 || lo[a] < origin[a]) origin[a] = lo[a];
        }
    }

    /* guard the scan itself: a tiny dp in a large box would loop for ages */
    long total = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        double lo[3], hi[3], points = 1.0;
        sph_shape_bounds(scene, scene->bodies[b].shape, lo, hi);
        for (int a = 0; a < dim; a++) points *= (hi[a] - lo[a]) / scene->dp + 1.0;
        if (points > (double)INT32_MAX)
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: bodies.%s: about %.3g lattice points in the bounding box of its "
                            "shape at dp = %g, more than this program can index (%d)",
                            scene->path, scene->bodies[b].name, points, scene->dp, INT32_MAX);
        /* lattice indices are counted from the origin and must fit a long */
        for (int a = 0; a < dim; a++) {
            double cells = fmax(fabs(lo[a] - origin[a]), fabs(hi[a] - origin[a])) / scene->dp;
            if (!(cells <= 1e15))
                return sph_fail(err, SPH_ERR_INPUT,
                                "%s: bodies.%s: the shape lies about %.3g spacings (dp = %g) "
                                "from the lattice origin along %c, too far to place particles",
                                scene->path, scene->bodies[b].name, cells, scene->dp, "xyz"[a]);
        }
    }
    for (int b = 0; b < scene->nbodies; b++) {
        long count = scan_body(scene, b, origin, NULL, 0);
        if (count == 0)
            return sph_fail(err, SPH_ERR_INPUT,
                            "%s: bodies.%s: the body has no particles: no lattice point (spacing "
                            "dp = %g) of its shape '%s' is free of earlier bodies",
                            scene->path, scene->bodies[b].name, scene->dp,
                            scene->shapes[scene->bodies[b].shape].name);
        out->body_count[b] = (int)count;
        total += count;
        if (total > INT32_MAX)
            return sph_fail(err, SPH_ERR_INPUT, "%s: more than %d particles", scene->path,
                            INT32_MAX);
    }

    bool any_constraint = false;
    for (int b = 0; b < scene->nbodies; b++) any_constraint |= scene->bodies[b].nconstraints > 0;
    size_t n = (size_t)total;
    out->n = (int)total;
    out->pos = malloc((size_t)dim * n * sizeof *out->pos);
    out->vel = malloc((size_t)dim * n * sizeof *out->vel);
    out->mass = malloc(n * sizeof *out->mass);
    out->rho = malloc(n * sizeof *out->rho);
    out->id = malloc(n * sizeof *out->id);
    out->body = malloc(n * sizeof *out->body);
    if (any_constraint) out->fixed = malloc(n * sizeof *out->fixed);
    if (!out->pos || !out->vel || !out->mass || !out->rho || !out->id || !out->body ||
        (any_constraint && !out->fixed)) {
        sph_particles_free(out);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of memory allocating %zu particles", n);
    }

    long start = 0;
    for (int b = 0; b < scene->nbodies; b++) start += scan_body(scene, b, origin, out, start);

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
                        "%s: bodies.%s: the particle at (%g, %g, %g) gets velocity (%g, %g, %g) "
                        "and mass %g (density * dp^%d): not finite (check initial_velocity, "
                        "density and the spacing)",
                        scene->path, body->name, x[0], x[1], x[2], v[0], v[1], v[2], mass, dim);
    }
    return SPH_OK;
}

void sph_particles_free(sph_particles *p) {
    if (!p) return;
    free(p->pos);
    free(p->vel);
    free(p->mass);
    free(p->rho);
    free(p->id);
    free(p->body);
    free(p->fixed);
    memset(p, 0, sizeof *p);
}
