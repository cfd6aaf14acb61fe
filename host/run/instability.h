/* instability.h — where an instability is: after the instability monitor
 * (device/monitor.cl, reduced on the device at output times) or the substep's
 * max |v|^2 has tripped, find the particle responsible, its body and its
 * position, so the message can name them.  Runs once per run at most, on
 * host copies of the fields, through the physics source's own per-particle
 * measure (sph_physics.monitor_particle, model/physics.h). */
#ifndef SPH_INSTABILITY_H
#define SPH_INSTABILITY_H

#include "backend.h"

#include <stddef.h>

typedef enum {
    SPH_TRIP_NONFINITE,  /* a NaN or Inf in a field */
    SPH_TRIP_ZIGZAG,     /* zigzag (hourglass) indicator above its threshold */
    SPH_TRIP_CLUSTERING, /* a pair closer than the threshold times dp */
    SPH_TRIP_ENERGY,     /* total energy grew beyond the bound */
    SPH_TRIP_SPEED,      /* a particle faster than the runaway-speed bound */
    SPH_TRIP_DOMAIN      /* a particle left the monitored domain */
} sph_trip_kind;

typedef struct {
    long particle;      /* particle id (index in the initial set); -1: none found */
    int body;           /* body index */
    double position[3]; /* current position */
    char field[32];     /* SPH_TRIP_NONFINITE: the first field holding one */
    /* fluids: every field finite, but a density (or a compressible
     * pressure) not positive, in `field` ("density", "pressure") */
    bool nonpositive;
} sph_trip_location;

/* Find the particle behind a trip of `kind`: the first (lowest id) particle
 * with a non-finite value, the particle with the largest velocity mismatch,
 * the one with the closest neighbour, the fastest one (energy growth,
 * runaway speed), or
 * the one farthest outside [lower, upper] (domain). */
sph_status sph_instability_locate(sph_backend *be, const sph_params_f64 *prm, sph_trip_kind kind,
                                  const double lower[3], const double upper[3],
                                  sph_trip_location *out, sph_error *err);

#endif
