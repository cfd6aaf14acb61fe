#include "solver.h"

#include "physics.h"
#include "instability.h"
#include "progress.h"
#include "sph_constants.h"
#include "wall_clock.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double *pos;
    int32_t *id, *slot;
    double *obs;
    /* traction observers: the state the stress comes from, and the stress */
    double *rho, *tau, *pressure, *tensor6;
    uint8_t *material;
} sample_scratch;

static void sample_scratch_free(sample_scratch *s) {
    free(s->obs);
    free(s->pos);
    free(s->id);
    free(s->slot);
    free(s->rho);
    free(s->tau);
    free(s->pressure);
    free(s->tensor6);
    free(s->material);
}

/* What the monitor reduction says besides the time-series columns. */
typedef struct {
    bool nonfinite;            /* a NaN/Inf in the energies or a position/velocity */
    double lower[3], upper[3]; /* bounding box of the particles */
} monitor_state;

/* Diagnostics, monitor and observers at the current time: one row of the
 * series (none when the state is no longer finite: the caller trips). */
static sph_status sample(const sph_solver_args *a, sample_scratch *s, double t, sph_timeseries *ts,
                         monitor_state *ms, sph_error *err) {
    sph_backend *be = a->backend;
    const int dim = a->scene->dim;
    sph_diagnostics d;
    sph_status st = be->ops->diagnostics(be, &d, err);
    if (st) return st;
    double mon[SPH_MONITOR_NCOMP_MAX];
    st = be->ops->monitor(be, mon, err);
    if (st) return st;
    for (int k = 0; k < 3; ++k) {
        ms->upper[k] = k < dim ? mon[SPH_MONITOR_MAX_X + k] : 0.0;
        ms->lower[k] = k < dim ? -mon[SPH_MONITOR_MAX_X + dim + k] : 0.0;
    }
    ms->nonfinite = !isfinite(d.kinetic) || !isfinite(d.strain) || mon[SPH_MONITOR_NONFINITE] > 0;
    if (ms->nonfinite) return SPH_OK;
    d.min_distance_ratio = -mon[SPH_MONITOR_NEG_MIN_DIST];
    /* The mismatch over the largest velocity gradient of the run so far, not
     * over the current one: at the turning points of a vibration every |L_i|
     * passes through zero while the particle-scale content left by the half
     * cycle before does not, and the plate with SPH-GNOG-A at H/dp = 15 read
     * 0.35 at t = 0.21 s (its tip at rest), 0.04-0.07 between the turning
     * points (docs/scene-format.md, "monitor") */
    d.gradient_scale = mon[SPH_MONITOR_GRADV];
    if (ts->count > 0)
        d.gradient_scale = fmax(d.gradient_scale, ts->diag[ts->count - 1].gradient_scale);
    d.zigzag = d.gradient_scale > 0 ? mon[SPH_MONITOR_MISMATCH] / d.gradient_scale : 0.0;
    if (a->observers->count > 0) {
        st = be->ops->download(be, FIELD_POS, s->pos, err);
        if (!st) st = be->ops->download(be, FIELD_ID, s->id, err);
        if (!st && a->observers->traction) {
            /* sigma = -p I + tau by the physics source (device/sph_elasticity.h) */
            st = be->ops->download(be, FIELD_RHO, s->rho, err);
            if (!st) st = be->ops->download(be, FIELD_TAU, s->tau, err);
            if (!st && be->fields[FIELD_MATERIAL].present)
                st = be->ops->download(be, FIELD_MATERIAL, s->material, err);
            if (!st)
                sph_physics_for(dim, true)->stress_output(
                    a->prm, be->n, s->rho, s->tau,
                    be->fields[FIELD_MATERIAL].present ? s->material : NULL, s->pressure, NULL,
                    s->tensor6);
        }
        if (st) return st;
        sph_observers_eval(a->observers, be->n, s->pos, s->id, s->pressure, s->tensor6, s->slot,
                           s->obs);
    }
    st = sph_timeseries_append(ts, t, &d, s->obs, err);
    if (!st && a->output) st = sph_output_row(a->output, t, &d, s->obs, err);
    return st;
}

/* Record a trip of the monitor at time t: find the particle behind it, and
 * either stop the run (SPH_UNSTABLE; non-finite values always stop) or warn
 * once and go on.  Only the first trip of a run is recorded. */
static sph_status trip(const sph_solver_args *a, sph_trip_kind kind, double t, const char *what,
                       double value, double threshold, const double domain[2][3],
                       sph_run_stats *stats, sph_error *err) {
    const sph_scene *sc = a->scene;
    sph_trip_location where;
    sph_status st =
        sph_instability_locate(a->backend, a->prm, kind, domain[0], domain[1], &where, err);
    if (st) return st;
    const bool stop = kind == SPH_TRIP_NONFINITE || sc->monitor_action == SPH_MONITOR_STOP;
    stats->instability_time = t;
    stats->instability_value = value;
    stats->instability_threshold = threshold;
    stats->instability_particle = where.particle;
    stats->instability_body = where.body;
    memcpy(stats->instability_position, where.position, sizeof where.position);
    stats->instability_stopped = stop;
    snprintf(stats->instability_field, sizeof stats->instability_field, "%s", where.field);
    snprintf(stats->instability_quantity, sizeof stats->instability_quantity, "%s", what);

    char quantity[160], place[256] = "";
    if (kind == SPH_TRIP_NONFINITE && where.nonpositive)
        sph_format(quantity, sizeof quantity,
                   "a %s that is not positive (a smaller time.cfl_acoustic may carry a strong "
                   "discontinuity)",
                   where.field);
    else if (kind == SPH_TRIP_NONFINITE)
        sph_format(quantity, sizeof quantity, "%s%s%s",
                   where.field[0] ? "non-finite values (NaN or Inf) in '"
                                  : "the energies overflowed (every field is finite), fastest",
                   where.field, where.field[0] ? "'" : "");
    else {
        /* as many digits as it takes for the two to differ in print (a
         * speed ratio of 10.0000001 read "10 > 10") */
        int digits = 3;
        char v[40], th[40];
        do {
            sph_format(v, sizeof v, "%.*g", digits, value);
            sph_format(th, sizeof th, "%.*g", digits < 6 ? 6 : digits, threshold);
        } while (strcmp(v, th) == 0 && ++digits <= 17);
        sph_format(quantity, sizeof quantity, "%s %s %s %s", what, v, value > threshold ? ">" : "<",
                   th);
    }
    if (where.particle >= 0) {
        const double *x = where.position;
        if (sc->dim == 1)
            sph_format(place, sizeof place, " at particle %ld of body '%s' (x = %.6g)",
                       where.particle, sc->bodies[where.body].name, x[0]);
        else if (sc->dim == 2)
            sph_format(place, sizeof place, " at particle %ld of body '%s' (x = %.6g, %.6g)",
                       where.particle, sc->bodies[where.body].name, x[0], x[1]);
        else
            sph_format(place, sizeof place, " at particle %ld of body '%s' (x = %.6g, %.6g, %.6g)",
                       where.particle, sc->bodies[where.body].name, x[0], x[1], x[2]);
    }
    if (stop)
        return sph_fail(err, SPH_UNSTABLE,
                        "instability at t = %.6g s: %s%s; the run stopped there (%s), results "
                        "up to it are kept",
                        t, quantity, place,
                        kind == SPH_TRIP_NONFINITE
                            ? (where.nonpositive
                                   ? "a fluid state that cannot go on always stops a run"
                                   : "a non-finite state always stops a run")
                            : "monitor.action = \"stop\"");
    if (!a->quiet)
        fprintf(stderr, "sphsolid: warning: instability at t = %.6g s: %s%s\n", t, quantity, place);
    return SPH_OK;
}

/* The instability monitor at an output time (device/monitor.cl,
 * docs/scene-format.md "monitor"): non-finite state, zigzag indicator,
 * clustering, energy growth, particles outside the domain; the first trip
 * is recorded. */
static sph_status check_stability(const sph_solver_args *a, const sph_timeseries *ts,
                                  const monitor_state *ms, double t, const double domain[2][3],
                                  sph_run_stats *stats, sph_error *err) {
    const sph_scene *sc = a->scene;
    if (ms->nonfinite)
        return trip(a, SPH_TRIP_NONFINITE, t, "non-finite state", NAN, NAN, domain, stats, err);
    if (sc->monitor_action == SPH_MONITOR_OFF || ts->count == 0 || !isnan(stats->instability_time))
        return SPH_OK;
    const sph_diagnostics *d = &ts->diag[ts->count - 1];
    /* fixed fluid particles neither cluster nor zigzag (and their periodic
     * images are not in the monitor's pair distances) */
    const bool fluid = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    if (!fluid && d->zigzag > sc->monitor_zigzag)
        return trip(a, SPH_TRIP_ZIGZAG, t, "zigzag indicator", d->zigzag, sc->monitor_zigzag,
                    domain, stats, err);
    if (!fluid && d->min_distance_ratio < sc->monitor_min_distance)
        return trip(a, SPH_TRIP_CLUSTERING, t, "minimum pair distance / dp", d->min_distance_ratio,
                    sc->monitor_min_distance, domain, stats, err);
    /* without external work (a constraint that prescribes a velocity) the
     * total energy of a stable run can only fall; gravity's work is not in
     * the energy, so the check is left to scenes without it */
    const double e0 = ts->diag[0].kinetic + ts->diag[0].strain, e = d->kinetic + d->strain;
    bool gravity = false;
    for (int k = 0; k < sc->dim; ++k) gravity |= sc->gravity[k] != 0.0;
    /* a fluid's fixed-state buffers and far field let energy flow in */
    const bool inflow = fluid && (sph_constraint_count(sc) > 0 || sc->has_far_field);
    if (e0 > 0 && !gravity && !inflow && !sph_scene_has_driven_constraint(sc) &&
        e > (1.0 + sc->monitor_energy_growth) * e0)
        return trip(a, SPH_TRIP_ENERGY, t, "total energy / initial", e / e0,
                    1.0 + sc->monitor_energy_growth, domain, stats, err);
    double outside = -INFINITY;
    for (int k = 0; k < sc->dim; ++k)
        outside = fmax(outside, fmax(ms->upper[k] - domain[1][k], domain[0][k] - ms->lower[k]));
    if (outside > 0)
        return trip(a, SPH_TRIP_DOMAIN, t, "distance outside the monitored domain [m]", outside,
                    0.0, domain, stats, err);
    return SPH_OK;
}

/* The monitored domain: given in the scene, or the initial bounding box of
 * the particles grown on every side by monitor.domain_margin times its
 * largest extent. */
static void monitor_domain(const sph_scene *sc, const sph_particles *p, double domain[2][3]) {
    for (int k = 0; k < 3; ++k) {
        domain[0][k] = k < sc->dim ? INFINITY : 0.0;
        domain[1][k] = k < sc->dim ? -INFINITY : 0.0;
    }
    if (sc->monitor_has_domain) {
        for (int k = 0; k < sc->dim; ++k) {
            domain[0][k] = sc->monitor_domain_lower[k];
            domain[1][k] = sc->monitor_domain_upper[k];
        }
        return;
    }
    for (int i = 0; i < p->n; ++i)
        for (int k = 0; k < sc->dim; ++k) {
            const double x = p->pos[(size_t)k * p->n + i];
            domain[0][k] = fmin(domain[0][k], x);
            domain[1][k] = fmax(domain[1][k], x);
        }
    double extent = 0.0;
    for (int k = 0; k < sc->dim; ++k) extent = fmax(extent, domain[1][k] - domain[0][k]);
    for (int k = 0; k < sc->dim; ++k) {
        domain[0][k] -= sc->monitor_domain_margin * extent;
        domain[1][k] += sc->monitor_domain_margin * extent;
    }
}

/* Half the interval the next rebuild's frozen pair geometry serves (the
 * positions it is taken at, x + s v, device/neighbour_build.cl): the coming
 * advection step, cfl_ad h / max(max |v|, U_ref), or with single-criterion
 * stepping the coming acoustic step, either cut at the next output time.
 * The acceleration criterion, which the rebuild's own reduction feeds, is
 * left out: the shift depends only on state a checkpoint holds, so a
 * restart rebuilds the same geometry.  TLSPH's reference configuration, and
 * time.frozen_geometry = "start" (the public reference code's choice): 0. */
static double geometry_shift(const sph_scene *sc, double h, double c0, double u_ref,
                             double max_speed2, double t, double next_output) {
    if (sc->formulation == SPH_FORMULATION_TLSPH || SPH_FORMULATION_IS_EULERIAN(sc->formulation) ||
        sc->geometry_at_start)
        return 0.0;
    const double speed = sqrt(max_speed2);
    double interval;
    if (sc->stepping == SPH_STEPPING_DUAL) {
        const double u = fmax(speed, u_ref);
        interval = u > 0.0 ? sc->cfl_advection * h / u : INFINITY;
    } else {
        interval = sc->cfl_acoustic * h / (c0 + speed);
    }
    interval = fmin(interval, next_output - t);
    return isfinite(interval) && interval > 0.0 ? 0.5 * interval : 0.0;
}

/* The first checkpoint time after t on the grid k * every, without a loop
 * (adding `every` until passing t loses the addition to rounding once every
 * is below the resolution of t, and takes t / every turns before that): an
 * interval shorter than the steps gives a checkpoint after every advection
 * step.  Checkpoints never shorten a step, so the results do not depend on
 * it. */
static double next_checkpoint_after(double t, double every) {
    if (!(every > 0.0)) return INFINITY;
    const double next = (floor(t / every) + 1.0) * every;
    return next > t && isfinite(next) ? next : nextafter(t, INFINITY);
}

/* Substeps per backend call inside a long advection step, so that the
 * progress line comes within its interval whatever the steps: about a tenth
 * of the interval at the rate of the last call, a multiple of the OpenCL
 * device clock's batch of 64 from 64 up (those batches stay whole), at least
 * one.  An advection step shorter than that is one call, as before. */
#define SUBSTEP_CHUNK_FIRST 64
#define SUBSTEP_CHUNK_MAX   (1L << 24)
static long substep_chunk(double seconds_each, double interval) {
    if (!(seconds_each > 0.0)) return SUBSTEP_CHUNK_MAX;
    const double n = 0.1 * interval / seconds_each;
    if (n >= (double)SUBSTEP_CHUNK_MAX) return SUBSTEP_CHUNK_MAX;
    if (n < 64.0) return n < 1.0 ? 1 : (long)n;
    return (long)n / 64 * 64;
}

/* The output a restart writes next.  A run that ended between two output
 * times wrote its end as an output and moved past the grid time after it
 * (end 0.55 s with outputs every 0.1 s: the next index is 7, at 0.7 s); a
 * restart to a later end gives that grid time its output (0.6 s), so the
 * extended run keeps the grid and has one row more, at the old end
 * (checkpoint.c allows a series longer than output_index).  A checkpoint
 * taken between outputs has its next grid time after it: unchanged. */
static long resume_output_index(const sph_checkpoint *ck, double output_interval) {
    const long k = ck->h.output_index;
    return k > 1 && (double)(k - 1) * output_interval > ck->h.time ? k - 1 : k;
}

/* Write a checkpoint of the state at this advection-step boundary. */
static sph_status checkpoint(const sph_solver_args *a, double t, double max_speed2,
                             long output_index, const sph_run_stats *stats,
                             const sph_timeseries *ts, sph_error *err) {
    sph_checkpoint_header h = {0};
    h.time = t;
    h.max_speed2 = max_speed2;
    h.output_index = output_index;
    h.acoustic_steps = stats->acoustic_steps;
    h.advection_steps = stats->advection_steps;
    h.checkpoint_every = a->checkpoint_every; /* a restart continues them */
    h.checkpoint_wall = a->checkpoint_wall;
    sph_status st = SPH_OK;
    if (a->snapshots) {
        /* HDF5 is called from one thread at a time */
        st = sph_snapshots_wait(a->snapshots, err);
        h.nsnapshots = a->snapshots->count;
        h.snapshot_times = a->snapshots->times;
    }
    if (!st) st = a->backend->ops->download_carried(a->backend, h.carried, err);
    if (!st)
        st = sph_checkpoint_write(a->run_dir, a->backend, &h, ts, a->scene->resolved_text, err);
    return st;
}

sph_status sph_solve(const sph_solver_args *a, sph_timeseries *ts, sph_run_stats *stats,
                     sph_error *err) {
    const sph_scene *sc = a->scene;
    sph_backend *be = a->backend;
    memset(stats, 0, sizeof *stats);
    stats->instability_time = NAN;
    stats->instability_particle = -1;
    double domain[2][3];
    monitor_domain(sc, a->initial, domain);
    monitor_state ms;
    const int n = be->n;
    sample_scratch s = {0};
    s.obs = calloc((size_t)(sc->nobservers * sc->dim + 1), sizeof(double));
    if (a->observers->count > 0) {
        s.pos = malloc((size_t)n * (size_t)sc->dim * sizeof(double));
        s.id = malloc((size_t)n * sizeof(int32_t));
        s.slot = malloc((size_t)n * sizeof(int32_t));
    }
    const bool traction = a->observers->traction;
    if (traction) {
        const size_t nn = (size_t)n, nsym = (size_t)(sc->dim * (sc->dim + 1) / 2);
        s.rho = malloc(nn * sizeof(double));
        s.tau = malloc(nn * nsym * sizeof(double));
        s.pressure = malloc(nn * sizeof(double));
        s.tensor6 = malloc(nn * 6 * sizeof(double));
        s.material = malloc(nn);
    }
    if (!s.obs || (a->observers->count > 0 && (!s.pos || !s.id || !s.slot)) ||
        (traction && (!s.rho || !s.tau || !s.pressure || !s.tensor6 || !s.material))) {
        sample_scratch_free(&s);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }

    /* the fastest sound speed of the materials in use (rows past them are 0) */
    const double h = a->prm->h;
    double c0 = 0.0;
    for (int m = 0; m < SPH_MAX_MATERIALS; ++m)
        if (a->prm->materials[m].c0 > c0) c0 = a->prm->materials[m].c0;
    const bool dual = sc->stepping == SPH_STEPPING_DUAL;
    /* TLSPH (tl_step.cl) works on the reference configuration: the rebuild at
     * t = 0 gives the reference neighbours, pair geometry and B0, and there is
     * no later rebuild, hence no advection step: every acoustic step (the
     * acoustic CFL criterion only) is an outer step of its own. */
    /* The fluid formulations (eulerian_step.cl) keep their particles fixed:
     * one rebuild too, and no advection step. */
    const bool fluid = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    const bool total_lagrangian = sc->formulation == SPH_FORMULATION_TLSPH || fluid;
    /* The step clock's speed (device/sph_step_clock.h): dt = CFL h / (C0 +
     * max speed).  The compressible fluid's reduction gives the signal speed
     * max (c + |v|) itself, each particle's sound speed its own: C0 = 0. */
    const bool own_sound_speed = sc->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE;
    const double c_clock = own_sound_speed ? 0.0 : c0;
    /* the largest initial speed: U_ref unless the scene gives one, and the
     * speed that sets the first rebuild's geometry shift */
    double v0max2 = 0.0;
    for (int i = 0; i < a->initial->n; ++i) {
        double v2 = 0.0;
        for (int d = 0; d < sc->dim; ++d) {
            const double v = a->initial->vel[(size_t)d * a->initial->n + i];
            v2 += v * v;
        }
        v0max2 = fmax(v0max2, v2);
    }
    const double u_ref = sc->has_reference_speed ? sc->reference_speed : sqrt(v0max2);
    stats->reference_speed = u_ref;
    double speed_limit = sc->monitor_speed_limit * (c0 + u_ref);

    const double t0 = sph_wall_seconds();
    sph_rebuild_info info;
    double t = 0.0, max_speed2 = 0.0;
    long output_index = 0;
    sph_status st = be->ops->upload(be, a->initial, err);
    if (a->resume) {
        /* the stored state replaces the initial one; the rebuild then starts
         * from the same particle order the interrupted run had */
        const sph_checkpoint *ck = a->resume;
        output_index = resume_output_index(ck, sc->output_interval);
        if (total_lagrangian) {
            /* the reference configuration first, from the initial particles
             * in the original run's deterministic order; the stored fields
             * are in that same slot order (no rebuild since) */
            if (!st) st = be->ops->rebuild(be, &info, err);
            if (!st) st = sph_checkpoint_restore(ck, be, err);
        } else {
            if (!st) st = sph_checkpoint_restore(ck, be, err);
            const double next = fmin((double)output_index * sc->output_interval, sc->end_time);
            be->geometry_shift =
                geometry_shift(sc, h, c0, u_ref, ck->h.max_speed2, ck->h.time, next);
            if (!st) st = be->ops->rebuild(be, &info, err);
        }
        t = ck->h.time;
        max_speed2 = ck->h.max_speed2;
        stats->acoustic_steps = ck->h.acoustic_steps;
        stats->advection_steps = ck->h.advection_steps;
    } else {
        be->geometry_shift =
            geometry_shift(sc, h, c0, u_ref, v0max2, 0.0, fmin(sc->output_interval, sc->end_time));
        if (!st) st = be->ops->rebuild(be, &info, err);
        max_speed2 = info.max_speed2;
        /* fluids: particles.c has checked every initial density and
         * pressure; a speed that still overflows (c + |v| beyond the
         * doubles) could not size a step (solids go on to the monitor,
         * which reports the overflow) */
        if (!st && fluid && !isfinite(max_speed2))
            st = sph_fail(err, SPH_ERR_INPUT,
                          "%s: the initial state has a non-finite speed or a density or "
                          "pressure that is not positive",
                          sc->path);
        if (!st) st = sample(a, &s, 0.0, ts, &ms, err);
        if (!st && a->snapshots) st = sph_snapshots_write(a->snapshots, be, 0.0, 0, 0, err);
        if (!st) st = check_stability(a, ts, &ms, 0.0, domain, stats, err);
        output_index = 1;
    }
    /* the compressible fluid's limit: monitor.speed_limit times the initial
     * largest signal speed (the first rebuild's, before any restored state) */
    if (own_sound_speed) speed_limit = sc->monitor_speed_limit * sqrt(info.max_speed2);
    const long start_steps = stats->acoustic_steps;
    sph_progress progress;
    sph_progress_init(&progress, stderr, !a->quiet, a->progress_interval, t0, t,
                      stats->acoustic_steps);
    double next_output = fmin((double)output_index * sc->output_interval, sc->end_time);
    const bool checkpoints = a->run_dir && (a->checkpoint_every > 0 || a->checkpoint_wall > 0);
    double next_checkpoint = next_checkpoint_after(t, a->checkpoint_every);
    /* without progress lines an advection step's substeps are one call */
    long chunk = progress.enabled ? SUBSTEP_CHUNK_FIRST : LONG_MAX;
    /* TLSPH and the fluids have no rebuild to end an advection step: their
     * substeps run on to the next output or checkpoint time in one call, the
     * backend advancing the clock (no host wait per substep), and each counts
     * as an advection step of its own, as before.  With wall-time
     * checkpoints, which are checked between outer steps, one substep per
     * outer step as before. */
    const bool long_steps = total_lagrangian && !(a->checkpoint_wall > 0);
    double last_checkpoint_wall = t0;
    bool stop = false;
    while (!st && !stop && t < sc->end_time) {
        /* one advection step */
        double t_adv_end = INFINITY;
        if (long_steps) {
            t_adv_end = next_checkpoint; /* INFINITY without checkpoints */
        } else if (dual) {
            const double accel_term = sc->acceleration_criterion ? info.max_accel_term : 0.0;
            const double speed = fmax(fmax(sqrt(info.max_speed2), sqrt(accel_term)), u_ref);
            if (speed > 0.0) t_adv_end = t + sc->cfl_advection * h / speed;
        }
        /* its substeps, under the step clock (device/sph_step_clock.h),
         * which the backend may advance on the device */
        double clock[SPH_CLOCK_LEN] = {0};
        clock[CLOCK_T] = t;
        clock[CLOCK_MAX_SPEED2] = max_speed2;
        clock[CLOCK_T_ADV_END] = t_adv_end;
        clock[CLOCK_NEXT_OUTPUT] = next_output;
        clock[CLOCK_CFL_H] = sc->cfl_acoustic * h;
        clock[CLOCK_C0] = c_clock;
        clock[CLOCK_ONE_SUBSTEP] = long_steps ? 0.0 : !dual || total_lagrangian;
        step_clock_plan(clock);
        bool at_output = false;
        long substeps = 0; /* of this outer step */
        for (;;) {
            clock[CLOCK_SPEED_LIMIT] =
                sc->monitor_action != SPH_MONITOR_OFF && isnan(stats->instability_time)
                    ? speed_limit
                    : INFINITY;
            clock[CLOCK_COUNT] = 0.0;
            long limit = a->max_acoustic_steps > 0
                             ? a->max_acoustic_steps - (stats->acoustic_steps - start_steps)
                             : LONG_MAX;
            if (limit > chunk) limit = chunk;
            const double call_wall = progress.enabled ? sph_wall_seconds() : 0.0;
            st = sph_backend_advance(be, clock, limit, err);
            if (st) break;
            t = clock[CLOCK_T];
            max_speed2 = clock[CLOCK_MAX_SPEED2];
            at_output = clock[CLOCK_ON_OUTPUT] != 0.0;
            stats->acoustic_steps += (long)clock[CLOCK_COUNT];
            substeps += (long)clock[CLOCK_COUNT];
            /* checked at every substep, from its own reduction: a blow-up
             * shrinks the acoustic step with the growing speed, so it might
             * never reach the next output time and the monitor there */
            const int halted = (int)clock[CLOCK_HALTED];
            if (halted == CLOCK_NONFINITE)
                st = trip(a, SPH_TRIP_NONFINITE, t, "non-finite state", NAN, NAN, domain, stats,
                          err);
            else if (halted == CLOCK_TOO_FAST)
                st = own_sound_speed
                         ? trip(a, SPH_TRIP_SPEED, t, "maximum (c + |v|) / initial maximum",
                                sqrt(max_speed2) * sc->monitor_speed_limit / speed_limit,
                                sc->monitor_speed_limit, domain, stats, err)
                         : trip(a, SPH_TRIP_SPEED, t, "maximum speed / (c0 + initial speed)",
                                sqrt(max_speed2) / (c0 + u_ref), sc->monitor_speed_limit, domain,
                                stats, err);
            if (st) {
                /* stop here, with a snapshot of the state that went wrong */
                if (st == SPH_UNSTABLE && a->snapshots && sc->snapshot_every > 0) {
                    sph_error serr;
                    const sph_status sst = sph_snapshots_write(
                        a->snapshots, be, t, stats->acoustic_steps,
                        stats->advection_steps + (long_steps ? substeps : 1), &serr);
                    if (sst) {
                        st = sst;
                        *err = serr;
                    }
                }
                break;
            }
            if (a->max_acoustic_steps > 0 &&
                stats->acoustic_steps - start_steps >= a->max_acoustic_steps) {
                stop = true;
                break;
            }
            if (clock[CLOCK_STEP_ENDED] != 0.0) break;
            if (clock[CLOCK_HALTED] == CLOCK_RUNNING) {
                /* the chunk ran out inside the step: a progress line if one
                 * is due, and the rest of the step as the clock planned it */
                const double now = sph_wall_seconds();
                chunk = substep_chunk((now - call_wall) / clock[CLOCK_COUNT], progress.interval);
                sph_progress_update(&progress, now, t, sc->end_time, stats->acoustic_steps,
                                    stats->advection_steps, n, false);
                continue;
            }
            /* a speed warning that let the run go on: the rest of the step */
            clock[CLOCK_HALTED] = CLOCK_RUNNING;
            step_clock_plan(clock);
        }
        if (st) break;
        stats->advection_steps += long_steps ? substeps : 1;
        if (at_output) {
            st = sample(a, &s, t, ts, &ms, err);
            if (!st) st = check_stability(a, ts, &ms, t, domain, stats, err);
            const bool unstable = st == SPH_UNSTABLE;
            const bool last = t >= sc->end_time;
            /* a run stopped by the monitor ends with a snapshot of the state */
            if ((!st || unstable) && a->snapshots && sc->snapshot_every > 0 &&
                (output_index % sc->snapshot_every == 0 || last || unstable)) {
                sph_error serr;
                const sph_status sst = sph_snapshots_write(
                    a->snapshots, be, t, stats->acoustic_steps, stats->advection_steps, &serr);
                if (sst) {
                    st = sst;
                    *err = serr;
                }
            }
            ++output_index;
            next_output = fmin((double)output_index * sc->output_interval, sc->end_time);
        }
        const double wall = sph_wall_seconds();
        if (!st && checkpoints &&
            (t >= next_checkpoint || t >= sc->end_time ||
             (a->checkpoint_wall > 0 && wall - last_checkpoint_wall >= a->checkpoint_wall))) {
            st = checkpoint(a, t, max_speed2, output_index, stats, ts, err);
            last_checkpoint_wall = sph_wall_seconds();
            next_checkpoint = next_checkpoint_after(t, a->checkpoint_every);
        }
        if (!st && !stop && t < sc->end_time && !total_lagrangian) {
            be->geometry_shift = geometry_shift(sc, h, c0, u_ref, max_speed2, t, next_output);
            st = be->ops->rebuild(be, &info, err);
        }
        sph_progress_update(&progress, wall, t, sc->end_time, stats->acoustic_steps,
                            stats->advection_steps, n, false);
    }
    if (!st && !stop)
        sph_progress_update(&progress, sph_wall_seconds(), t, sc->end_time, stats->acoustic_steps,
                            stats->advection_steps, n, true);
    sph_progress_finish(&progress);
    if (a->snapshots) {
        sph_error werr;
        const sph_status wst = sph_snapshots_wait(a->snapshots, &werr);
        if (!st && wst) {
            *err = werr;
            st = wst;
        }
    }
    stats->wall_seconds = sph_wall_seconds() - t0;
    stats->end_time = t;
    if (stats->wall_seconds > 0)
        stats->particle_substeps_per_second =
            (double)n * (double)(stats->acoustic_steps - start_steps) / stats->wall_seconds;
    sample_scratch_free(&s);
    return st;
}
