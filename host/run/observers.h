/* observers.h — material-point observers.
 *
 * An observer follows the particles within the cut-off of its position at
 * t = 0 and reports their Shepard-weighted mean position
 * sum W_j V_j x_j / sum W_j V_j with the weights frozen at t = 0 (the
 * reference code's tip probe for the plate, whose observer keeps its initial
 * neighbours: reference notes §6.1).  A traction observer (quantity =
 * "traction") reports the same weighted mean of sigma . n over those
 * particles, sigma = -p I + tau.
 */
#ifndef SPH_OBSERVERS_H
#define SPH_OBSERVERS_H

#include "particles.h"
#include "scene.h"
#include "sph_constants.h"

#include <stdbool.h>

typedef struct {
    int count, dim;
    bool traction;   /* some observer reports a traction: eval needs the stress */
    double *normals; /* [count * 3]: each observer's normal (0 for a position) */
    int *offset;     /* [count + 1] into ids/weights */
    int32_t *ids;    /* particle ids */
    double *weights; /* W V, normalised per observer */
} sph_observer_set;

sph_status sph_observers_init(const sph_scene *scene, const sph_particles *p,
                              const sph_params_f64 *prm, sph_observer_set *set, sph_error *err);
/* Observer values [count * dim] from backend-ordered positions and ids,
 * and, where set->traction, the pressure [n] and the shear stress [n][6] in
 * VTK order (xx, yy, zz, xy, yz, xz; the cpu kernels' stress_output);
 * `slot_of_id` is scratch of n entries. */
void sph_observers_eval(const sph_observer_set *set, int n, const double *pos, const int32_t *id,
                        const double *pressure, const double *tensor6, int32_t *slot_of_id,
                        double *out);
void sph_observers_free(sph_observer_set *set);

#endif
