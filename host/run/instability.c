#include "instability.h"

#include "physics.h"
#include "sph_constants.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Host copies of what locating needs; every pointer owned here. */
typedef struct {
    int n, dim;
    double *pos, *vel, *vol, *bmat;
    int32_t *id;
    uint8_t *body;
    sph_neighbour_lists nbr;
} host_state;

static void host_state_free(host_state *h) {
    free(h->pos);
    free(h->vel);
    free(h->vol);
    free(h->bmat);
    free(h->id);
    free(h->body);
    sph_neighbour_lists_free(&h->nbr);
}

static double *alloc_field(const sph_backend *be, sph_field f) {
    return malloc((size_t)be->fields[f].components * (size_t)be->n * sizeof(double));
}

/* The first field (registry order) with a non-finite value, and among its
 * non-finite particles the one of lowest id. */
static sph_status find_nonfinite(sph_backend *be, host_state *h, int *slot, sph_trip_location *out,
                                 sph_error *err) {
    const int n = h->n;
    for (int f = 0; f < FIELD_COUNT && *slot < 0; ++f) {
        const sph_field_info *info = &be->fields[f];
        if (!info->present || !sph_field_is_real(info->type)) continue;
        /* derived from the pressure: a negative one makes it NaN, and
         * find_nonpositive names the pressure itself */
        if (f == FIELD_SOUND_SPEED) continue;
        double *x = alloc_field(be, (sph_field)f);
        if (!x) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
        const sph_status st = be->ops->download(be, (sph_field)f, x, err);
        if (st) {
            free(x);
            return st;
        }
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < info->components; ++c)
                if (!isfinite(x[(size_t)c * (size_t)n + (size_t)i]) &&
                    (*slot < 0 || h->id[i] < h->id[*slot])) {
                    *slot = i;
                    snprintf(out->field, sizeof out->field, "%s", info->name);
                }
        free(x);
    }
    return SPH_OK;
}

/* The particle with the largest monitor measure `component`, evaluated by
 * the physics source (device/monitor.cl) on the host copies. */
static sph_status find_monitor_max(sph_backend *be, const sph_params_f64 *prm, host_state *h,
                                   int component, int *slot, sph_error *err) {
    const sph_physics *k = sph_physics_for(h->dim, true);
    h->vel = alloc_field(be, FIELD_VEL);
    h->vol = alloc_field(be, FIELD_VOL);
    h->bmat = alloc_field(be, FIELD_BMAT);
    if (!h->vel || !h->vol || !h->bmat) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    sph_status st = be->ops->download(be, FIELD_VEL, h->vel, err);
    if (!st) st = be->ops->download(be, FIELD_VOL, h->vol, err);
    if (!st) st = be->ops->download(be, FIELD_BMAT, h->bmat, err);
    if (!st) st = be->ops->download_neighbours(be, &h->nbr, err);
    if (st) return st;
    double best = -INFINITY;
    for (int i = 0; i < h->n; ++i) {
        double c[SPH_MONITOR_NCOMP_MAX];
        k->monitor_particle(prm, h->n, h->nbr.cap, h->nbr.count, h->nbr.j, h->pos, h->vel, h->vol,
                            h->bmat, i, c);
        if (c[component] > best) {
            best = c[component];
            *slot = i;
        }
    }
    return SPH_OK;
}

/* Fluids: the first (lowest id) particle whose density, or compressible
 * pressure, is not positive (the step clock's signal speed is then +inf,
 * device/eulerian_step.cl).  A wall particle of the ideal gas carries p = 0
 * (host/setup/particles.c): its pressure is not looked at. */
static sph_status find_nonpositive(sph_backend *be, host_state *h, int *slot,
                                   sph_trip_location *out, sph_error *err) {
    const sph_field fields[] = {FIELD_RHO, FIELD_PRESSURE};
    const char *names[] = {"density", "pressure"};
    const bool compressible = be->features.formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE;
    uint8_t *kind = NULL;
    if (compressible && be->fields[FIELD_KIND].present) {
        kind = malloc((size_t)h->n);
        if (!kind) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
        const sph_status st = be->ops->download(be, FIELD_KIND, kind, err);
        if (st) {
            free(kind);
            return st;
        }
    }
    for (int f = 0; f < (compressible ? 2 : 1); ++f) {
        double *x = alloc_field(be, fields[f]);
        if (!x) {
            free(kind);
            return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
        }
        const sph_status st = be->ops->download(be, fields[f], x, err);
        if (st) {
            free(x);
            free(kind);
            return st;
        }
        for (int i = 0; i < h->n; ++i)
            if (!(x[i] > 0.0) && !(f == 1 && kind && kind[i] == SPH_PARTICLE_WALL) &&
                (*slot < 0 || h->id[i] < h->id[*slot])) {
                *slot = i;
                snprintf(out->field, sizeof out->field, "%s", names[f]);
                out->nonpositive = true;
            }
        free(x);
        if (*slot >= 0) break;
    }
    free(kind);
    return SPH_OK;
}

static sph_status find_fastest(sph_backend *be, host_state *h, int *slot, sph_error *err) {
    h->vel = alloc_field(be, FIELD_VEL);
    if (!h->vel) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    const sph_status st = be->ops->download(be, FIELD_VEL, h->vel, err);
    if (st) return st;
    double best = -1.0;
    for (int i = 0; i < h->n; ++i) {
        double v2 = 0.0;
        for (int a = 0; a < h->dim; ++a)
            v2 += h->vel[(size_t)a * h->n + i] * h->vel[(size_t)a * h->n + i];
        if (v2 > best) {
            best = v2;
            *slot = i;
        }
    }
    return SPH_OK;
}

static void find_outside(const host_state *h, const double lower[3], const double upper[3],
                         int *slot) {
    double best = -INFINITY;
    for (int i = 0; i < h->n; ++i) {
        double outside = -INFINITY;
        for (int a = 0; a < h->dim; ++a) {
            const double x = h->pos[(size_t)a * h->n + i];
            outside = fmax(outside, fmax(x - upper[a], lower[a] - x));
        }
        if (outside > best) {
            best = outside;
            *slot = i;
        }
    }
}

sph_status sph_instability_locate(sph_backend *be, const sph_params_f64 *prm, sph_trip_kind kind,
                                  const double lower[3], const double upper[3],
                                  sph_trip_location *out, sph_error *err) {
    memset(out, 0, sizeof *out);
    out->particle = -1;
    host_state h = {.n = be->n, .dim = be->features.dim};
    h.pos = alloc_field(be, FIELD_POS);
    h.id = malloc((size_t)h.n * sizeof(int32_t));
    if (!h.pos || !h.id) {
        host_state_free(&h);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    sph_status st = be->ops->download(be, FIELD_POS, h.pos, err);
    if (!st) st = be->ops->download(be, FIELD_ID, h.id, err);
    if (!st && be->fields[FIELD_BODY].present) {
        h.body = malloc((size_t)h.n);
        st = h.body ? be->ops->download(be, FIELD_BODY, h.body, err)
                    : sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    int slot = -1;
    if (!st) {
        switch (kind) {
        case SPH_TRIP_NONFINITE:
            st = find_nonfinite(be, &h, &slot, out, err);
            if (!st && slot < 0 && FORM_IS_EULERIAN((int)be->features.formulation))
                st = find_nonpositive(be, &h, &slot, out, err);
            /* every field finite: the energy sums overflowed; the fastest
             * particle is the one to look at */
            if (!st && slot < 0) st = find_fastest(be, &h, &slot, err);
            break;
        case SPH_TRIP_ZIGZAG:
            st = find_monitor_max(be, prm, &h, SPH_MONITOR_MISMATCH, &slot, err);
            break;
        case SPH_TRIP_CLUSTERING:
            st = find_monitor_max(be, prm, &h, SPH_MONITOR_NEG_MIN_DIST, &slot, err);
            break;
        case SPH_TRIP_ENERGY:
        case SPH_TRIP_SPEED:
            st = find_fastest(be, &h, &slot, err);
            break;
        case SPH_TRIP_DOMAIN:
            find_outside(&h, lower, upper, &slot);
            break;
        }
    }
    if (!st && slot >= 0) {
        out->particle = h.id[slot];
        out->body = h.body ? h.body[slot] : 0;
        for (int a = 0; a < h.dim; ++a) out->position[a] = h.pos[(size_t)a * h.n + slot];
    }
    host_state_free(&h);
    return st;
}
