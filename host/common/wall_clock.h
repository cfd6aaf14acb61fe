/* wall_clock.h — the host's monotonic wall clock, for run times, progress
 * and the profile's host phases. */
#ifndef SPH_WALL_CLOCK_H
#define SPH_WALL_CLOCK_H

#include <time.h>

/* Seconds since an arbitrary fixed point (CLOCK_MONOTONIC). */
static inline double sph_wall_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif
