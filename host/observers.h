/* observers.h — material-point observers.
 *
 * An observer follows the particles within the cut-off of its position at
 * t = 0 and reports their Shepard-weighted mean position
 * sum W_j V_j x_j / sum W_j V_j with the weights frozen at t = 0 (the
 * reference code's tip probe for the plate, whose observer keeps its initial
 * neighbours: reference notes §6.1).
 */
#ifndef SPH_OBSERVERS_H
#define SPH_OBSERVERS_H

#include "particles.h"
#include "scene.h"
#include "sph_constants.h"

typedef struct {
    int count, dim;
    int *offset;     /* [count + 1] into ids/weights */
    int32_t *ids;    /* particle ids */
    double *weights; /* W V, normalised per observer */
} sph_observer_set;

sph_status sph_observers_init(const sph_scene *scene, const sph_particles *p,
                              const sph_params_f64 *prm, sph_observer_set *set, sph_error *err);
/* Observer positions [count * dim] from backend-ordered positions and ids;
 * `slot_of_id` is scratch of n entries. */
void sph_observers_eval(const sph_observer_set *set, int n, const double *pos, const int32_t *id,
                        int32_t *slot_of_id, double *out);
void sph_observers_free(sph_observer_set *set);

#endif
