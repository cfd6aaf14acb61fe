#include "observers.h"

#include "physics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sph_status sph_observers_init(const sph_scene *scene, const sph_particles *p,
                              const sph_params_f64 *prm, sph_observer_set *set, sph_error *err) {
    memset(set, 0, sizeof *set);
    set->count = scene->nobservers;
    set->dim = scene->dim;
    set->offset = calloc((size_t)set->count + 1, sizeof(int));
    set->normals = calloc((size_t)set->count * 3 + 1, sizeof(double));
    if (!set->offset || !set->normals) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    for (int o = 0; o < set->count; ++o) {
        if (scene->observers[o].quantity != SPH_OBSERVE_TRACTION) continue;
        set->traction = true;
        for (int a = 0; a < 3; ++a) set->normals[o * 3 + a] = scene->observers[o].normal[a];
    }
    if (set->count == 0) return SPH_OK;
    const sph_physics *k = sph_physics_for(scene->dim, true);
    const double cutoff = prm->cutoff;
    /* two passes: count, then fill */
    for (int pass = 0; pass < 2; ++pass) {
        int total = 0;
        for (int o = 0; o < set->count; ++o) {
            const double *xo = scene->observers[o].position;
            double wsum = 0.0;
            const int first = total;
            for (int i = 0; i < p->n; ++i) {
                double r2 = 0.0;
                for (int a = 0; a < p->dim; ++a) {
                    const double dx = p->pos[(size_t)a * p->n + i] - xo[a];
                    r2 += dx * dx;
                }
                if (r2 >= cutoff * cutoff) continue;
                if (pass == 1) {
                    const double w = k->kernel_w(prm, sqrt(r2)) * p->mass[i] / p->rho[i];
                    set->ids[total] = p->id[i];
                    set->weights[total] = w;
                    wsum += w;
                }
                ++total;
            }
            if (pass == 0) {
                if (total == first)
                    return sph_fail(err, SPH_ERR_INPUT,
                                    "%s: observer '%s' has no particle within the cut-off radius "
                                    "%g of its position: place it inside a body",
                                    scene->path, scene->observers[o].name, cutoff);
                set->offset[o + 1] = total;
            } else {
                for (int q = first; q < total; ++q) set->weights[q] /= wsum;
            }
        }
        if (pass == 0) {
            set->ids = malloc((size_t)total * sizeof(int32_t));
            set->weights = malloc((size_t)total * sizeof(double));
            if (!set->ids || !set->weights)
                return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
        }
    }
    return SPH_OK;
}

/* (sigma . n)_a of particle i, sigma = -p I + tau (tau in VTK order) */
static double traction(const double *pressure, const double *tensor6, int i, const double *normal,
                       int a) {
    /* VTK slot of tau_ab: xx yy zz xy yz xz */
    static const int slot[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};
    double t = -pressure[i] * normal[a];
    for (int b = 0; b < 3; ++b) t += tensor6[(size_t)i * 6 + (size_t)slot[a][b]] * normal[b];
    return t;
}

void sph_observers_eval(const sph_observer_set *set, int n, const double *pos, const int32_t *id,
                        const double *pressure, const double *tensor6, int32_t *slot_of_id,
                        double *out) {
    for (int i = 0; i < n; ++i) slot_of_id[id[i]] = i;
    for (int o = 0; o < set->count; ++o) {
        const double *normal = set->normals + o * 3;
        const bool stress = normal[0] != 0.0 || normal[1] != 0.0 || normal[2] != 0.0;
        for (int a = 0; a < set->dim; ++a) {
            double x = 0.0;
            for (int q = set->offset[o]; q < set->offset[o + 1]; ++q) {
                const int i = slot_of_id[set->ids[q]];
                x += set->weights[q] *
                     (stress ? traction(pressure, tensor6, i, normal, a) : pos[(size_t)a * n + i]);
            }
            out[o * set->dim + a] = x;
        }
    }
}

void sph_observers_free(sph_observer_set *set) {
    free(set->offset);
    free(set->normals);
    free(set->ids);
    free(set->weights);
    memset(set, 0, sizeof *set);
}
