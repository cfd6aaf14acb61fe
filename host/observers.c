#include "observers.h"

#include "backend_cpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sph_status sph_observers_init(const sph_scene *scene, const sph_particles *p,
                              const sph_params_f64 *prm, sph_observer_set *set, sph_error *err) {
    memset(set, 0, sizeof *set);
    set->count = scene->nobservers;
    set->dim = scene->dim;
    set->offset = calloc((size_t)set->count + 1, sizeof(int));
    if (!set->offset) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    if (set->count == 0) return SPH_OK;
    const cpu_kernels *k = cpu_kernels_for(scene->dim, true);
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

void sph_observers_eval(const sph_observer_set *set, int n, const double *pos, const int32_t *id,
                        int32_t *slot_of_id, double *out) {
    for (int i = 0; i < n; ++i) slot_of_id[id[i]] = i;
    for (int o = 0; o < set->count; ++o)
        for (int a = 0; a < set->dim; ++a) {
            double x = 0.0;
            for (int q = set->offset[o]; q < set->offset[o + 1]; ++q)
                x += set->weights[q] * pos[(size_t)a * n + slot_of_id[set->ids[q]]];
            out[o * set->dim + a] = x;
        }
}

void sph_observers_free(sph_observer_set *set) {
    free(set->offset);
    free(set->ids);
    free(set->weights);
    memset(set, 0, sizeof *set);
}
