#include "analysis.h"

#include <stdlib.h>
#include <string.h>

sph_status sph_timeseries_init(sph_timeseries *ts, int dim, int nobservers, sph_error *err) {
    memset(ts, 0, sizeof *ts);
    ts->dim = dim;
    ts->nobservers = nobservers;
    ts->capacity = 256;
    ts->time = malloc((size_t)ts->capacity * sizeof(double));
    ts->diag = malloc((size_t)ts->capacity * sizeof(sph_diagnostics));
    ts->observers = malloc((size_t)ts->capacity * (size_t)(nobservers * dim + 1) * sizeof(double));
    if (!ts->time || !ts->diag || !ts->observers)
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    return SPH_OK;
}

sph_status sph_timeseries_append(sph_timeseries *ts, double t, const sph_diagnostics *d,
                                 const double *observers, sph_error *err) {
    const size_t per_row = (size_t)(ts->nobservers * ts->dim);
    if (ts->count == ts->capacity) {
        const int cap = ts->capacity * 2;
        double *time = realloc(ts->time, (size_t)cap * sizeof(double));
        if (time) ts->time = time;
        sph_diagnostics *diag = realloc(ts->diag, (size_t)cap * sizeof(sph_diagnostics));
        if (diag) ts->diag = diag;
        double *obs = realloc(ts->observers, (size_t)cap * (per_row + 1) * sizeof(double));
        if (obs) ts->observers = obs;
        if (!time || !diag || !obs) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
        ts->capacity = cap;
    }
    ts->time[ts->count] = t;
    ts->diag[ts->count] = *d;
    if (per_row)
        memcpy(ts->observers + (size_t)ts->count * per_row, observers, per_row * sizeof(double));
    ts->count++;
    return SPH_OK;
}

void sph_timeseries_free(sph_timeseries *ts) {
    free(ts->time);
    free(ts->diag);
    free(ts->observers);
    memset(ts, 0, sizeof *ts);
}

double sph_first_period(const double *t, const double *y, int count) {
    /* skip the start, where y = 0 exactly: begin after the first sample that
     * left the rest position */
    int start = 1;
    while (start < count && y[start] == 0.0) ++start;
    int crossings = 0;
    for (int k = start; k + 1 < count; ++k) {
        if ((y[k] > 0.0) == (y[k + 1] > 0.0)) continue;
        if (++crossings == 2) return t[k] + (t[k + 1] - t[k]) * y[k] / (y[k] - y[k + 1]);
    }
    return NAN;
}

static double norm3(const double *v) {
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

void sph_metrics_compute(const sph_timeseries *ts, int period_observer, int period_axis,
                         double initial_momentum_scale, double angular_momentum_scale,
                         sph_metrics *m) {
    m->first_period = NAN;
    m->max_angular_momentum_error = NAN;
    m->max_linear_momentum_drift = NAN;
    m->initial_kinetic_energy = ts->count ? ts->diag[0].kinetic : NAN;
    m->final_total_energy_ratio = NAN;
    m->max_observer_displacement = NAN;
    if (ts->count == 0) return;
    const sph_diagnostics *d0 = &ts->diag[0];
    const double l0 = norm3(d0->angular);
    double max_l = 0.0, max_p = 0.0;
    for (int k = 0; k < ts->count; ++k) {
        double dl[3], dp[3];
        for (int a = 0; a < 3; ++a) {
            dl[a] = ts->diag[k].angular[a] - d0->angular[a];
            dp[a] = ts->diag[k].momentum[a] - d0->momentum[a];
        }
        max_l = fmax(max_l, norm3(dl));
        max_p = fmax(max_p, norm3(dp));
    }
    /* a bar hitting a wall starts with |L(0)| ~ 1e-20 from round-off: an
     * error relative to it would read 1e9 % */
    if (l0 > 1e-9 * angular_momentum_scale && l0 > 0.0) m->max_angular_momentum_error = max_l / l0;
    if (initial_momentum_scale > 0.0) m->max_linear_momentum_drift = max_p / initial_momentum_scale;
    const double e0 = d0->kinetic + d0->strain;
    const sph_diagnostics *de = &ts->diag[ts->count - 1];
    if (e0 > 0.0) m->final_total_energy_ratio = (de->kinetic + de->strain) / e0;

    if (period_observer >= 0 && period_observer < ts->nobservers) {
        const int stride = ts->nobservers * ts->dim;
        const int col = period_observer * ts->dim + period_axis;
        double *y = malloc((size_t)ts->count * sizeof(double));
        if (!y) return;
        double max_disp = 0.0;
        for (int k = 0; k < ts->count; ++k) {
            y[k] = ts->observers[(size_t)k * stride + col] - ts->observers[col];
            max_disp = fmax(max_disp, fabs(y[k]));
        }
        m->first_period = sph_first_period(ts->time, y, ts->count);
        m->max_observer_displacement = max_disp;
        free(y);
    }
}
