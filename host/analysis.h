/* analysis.h — the recorded time series and the case metrics derived from it.
 *
 * first_period: the first oscillation period of an observer coordinate
 *   (003 Table 1, 000 Table 1): the motion starts at the rest position with
 *   its largest speed, so one full period ends at the second zero crossing of
 *   the displacement; crossings are located by linear interpolation between
 *   samples.
 * max_angular_momentum_error: max over the samples of |L(t) - L(0)| / |L(0)|
 *   (003 Fig. 13).
 */
#ifndef SPH_ANALYSIS_H
#define SPH_ANALYSIS_H

#include "backend.h"

#include <math.h>

typedef struct {
    int dim, nobservers;
    int count, capacity;
    double *time;
    sph_diagnostics *diag;
    double *observers; /* [count][nobservers * dim] */
} sph_timeseries;

sph_status sph_timeseries_init(sph_timeseries *ts, int dim, int nobservers, sph_error *err);
sph_status sph_timeseries_append(sph_timeseries *ts, double t, const sph_diagnostics *d,
                                 const double *observers, sph_error *err);
void sph_timeseries_free(sph_timeseries *ts);

typedef struct {
    double first_period;               /* NAN when not requested or not found */
    double max_angular_momentum_error; /* NAN when L(0) = 0 */
    double max_linear_momentum_drift;  /* max |P(t) - P(0)| / sum m |v(0)| */
    double initial_kinetic_energy;
    double final_total_energy_ratio;  /* E(end) / E(0) */
    double max_observer_displacement; /* of the period observer along its axis */
} sph_metrics;

/* Period from samples y(t) (displacement from the start value). */
double sph_first_period(const double *t, const double *y, int count);

/* initial_momentum_scale: sum m |v|; angular_momentum_scale: sum m |x - x_c| |v|.
 * The angular-momentum error is relative to |L(0)|, and undefined (NaN) where
 * |L(0)| is round-off against the angular scale (a body without spin). */
void sph_metrics_compute(const sph_timeseries *ts, int period_observer, int period_axis,
                         double initial_momentum_scale, double angular_momentum_scale,
                         sph_metrics *m);

#endif
