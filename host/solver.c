#include "solver.h"

#include "sph_constants.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct {
    double *pos;
    int32_t *id, *slot;
    double *obs;
} sample_scratch;

/* Diagnostics and observers at the current time: one row of the series. */
static sph_status sample(const sph_solver_args *a, sample_scratch *s, double t, sph_timeseries *ts,
                         sph_error *err) {
    sph_backend *be = a->backend;
    sph_diagnostics d;
    sph_status st = be->ops->diagnostics(be, &d, err);
    if (st) return st;
    if (!isfinite(d.kinetic) || !isfinite(d.strain))
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "the energy became non-finite at t = %.6g s: the simulation is unstable",
                        t);
    if (a->observers->count > 0) {
        st = be->ops->download(be, FIELD_POS, s->pos, err);
        if (!st) st = be->ops->download(be, FIELD_ID, s->id, err);
        if (st) return st;
        sph_observers_eval(a->observers, be->n, s->pos, s->id, s->slot, s->obs);
    }
    st = sph_timeseries_append(ts, t, &d, s->obs, err);
    if (!st && a->output) st = sph_output_row(a->output, t, &d, s->obs, err);
    return st;
}

static void progress(const sph_solver_args *a, double t, const sph_run_stats *s, double elapsed) {
    const double end = a->scene->end_time;
    const double rate =
        elapsed > 0 ? (double)a->backend->n * (double)s->acoustic_steps / elapsed : 0;
    const double eta = t > 0 ? elapsed * (end - t) / t : 0;
    fprintf(stderr,
            "sphsolid: t = %.4g / %.4g s (%.0f%%), %ld acoustic / %ld advection steps, %.3g M "
            "particle-substeps/s, ETA %.0f s\n",
            t, end, 100.0 * t / end, s->acoustic_steps, s->advection_steps, rate / 1e6, eta);
}

sph_status sph_solve(const sph_solver_args *a, sph_timeseries *ts, sph_run_stats *stats,
                     sph_error *err) {
    const sph_scene *sc = a->scene;
    sph_backend *be = a->backend;
    memset(stats, 0, sizeof *stats);
    const int n = be->n;
    sample_scratch s = {0};
    s.obs = calloc((size_t)(sc->nobservers * sc->dim + 1), sizeof(double));
    if (a->observers->count > 0) {
        s.pos = malloc((size_t)n * (size_t)sc->dim * sizeof(double));
        s.id = malloc((size_t)n * sizeof(int32_t));
        s.slot = malloc((size_t)n * sizeof(int32_t));
    }
    if (!s.obs || (a->observers->count > 0 && (!s.pos || !s.id || !s.slot))) {
        free(s.obs);
        free(s.pos);
        free(s.id);
        free(s.slot);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }

    const double h = a->prm[PRM_H], c0 = a->prm[PRM_C0];
    const bool dual = sc->stepping == SPH_STEPPING_DUAL;
    double u_ref = 0.0;
    if (sc->has_reference_speed) {
        u_ref = sc->reference_speed;
    } else {
        for (int i = 0; i < a->initial->n; ++i) {
            double v2 = 0.0;
            for (int d = 0; d < sc->dim; ++d) {
                const double v = a->initial->vel[(size_t)d * a->initial->n + i];
                v2 += v * v;
            }
            u_ref = fmax(u_ref, sqrt(v2));
        }
    }
    stats->reference_speed = u_ref;

    const double t0 = now_seconds();
    double last_report = t0;
    sph_rebuild_info info;
    sph_status st = be->ops->upload(be, a->initial, err);
    if (!st) st = be->ops->rebuild(be, &info, err);
    if (!st) st = sample(a, &s, 0.0, ts, err);

    double t = 0.0, max_speed2 = info.max_speed2;
    long output_index = 1;
    double next_output = fmin(sc->output_interval, sc->end_time);
    bool stop = false;
    while (!st && !stop && t < sc->end_time) {
        /* one advection step */
        double t_adv_end = INFINITY;
        if (dual) {
            const double accel_term = sc->acceleration_criterion ? info.max_accel_term : 0.0;
            const double speed = fmax(fmax(sqrt(info.max_speed2), sqrt(accel_term)), u_ref);
            if (speed > 0.0) t_adv_end = t + sc->cfl_advection * h / speed;
        }
        bool at_output = false;
        for (;;) {
            double dt = sc->cfl_acoustic * h / (c0 + sqrt(max_speed2));
            /* land exactly on the output time (and never step past it) */
            if (t + dt >= next_output * (1.0 - 1e-12)) {
                dt = next_output - t;
                at_output = true;
            }
            st = be->ops->substep(be, dt, &max_speed2, err);
            if (st) break;
            t = at_output ? next_output : t + dt;
            stats->acoustic_steps++;
            if (!isfinite(max_speed2)) {
                st = sph_fail(err, SPH_ERR_RUNTIME,
                              "velocities became non-finite at t = %.6g s after %ld acoustic "
                              "steps: the simulation is unstable",
                              t, stats->acoustic_steps);
                break;
            }
            if (a->max_acoustic_steps > 0 && stats->acoustic_steps >= a->max_acoustic_steps) {
                stop = true;
                break;
            }
            if (at_output || !dual || t >= t_adv_end) break;
        }
        if (st) break;
        stats->advection_steps++;
        if (at_output) {
            st = sample(a, &s, t, ts, err);
            ++output_index;
            next_output = fmin((double)output_index * sc->output_interval, sc->end_time);
        }
        if (!st && !stop && t < sc->end_time) st = be->ops->rebuild(be, &info, err);
        if (!a->quiet && now_seconds() - last_report > 5.0) {
            last_report = now_seconds();
            progress(a, t, stats, last_report - t0);
        }
    }
    stats->wall_seconds = now_seconds() - t0;
    stats->end_time = t;
    if (stats->wall_seconds > 0)
        stats->particle_substeps_per_second =
            (double)n * (double)stats->acoustic_steps / stats->wall_seconds;
    free(s.obs);
    free(s.pos);
    free(s.id);
    free(s.slot);
    return st;
}
