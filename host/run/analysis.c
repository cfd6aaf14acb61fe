#include "analysis.h"

#include <stdio.h>
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

void sph_initial_sums_compute(const sph_particles *p, sph_initial_sums *s) {
    memset(s, 0, sizeof *s);
    const size_t n = (size_t)p->n;
    for (size_t i = 0; i < n; ++i) {
        double x[3] = {0.0, 0.0, 0.0}, v[3] = {0.0, 0.0, 0.0};
        for (int d = 0; d < p->dim && d < 3; ++d) {
            x[d] = p->pos[(size_t)d * n + i];
            v[d] = p->vel[(size_t)d * n + i];
        }
        const double m = p->mass[i];
        const double speed = norm3(v), r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        s->total_mass += m;
        s->momentum_sum += m * speed;
        s->angular[0] += m * (x[1] * v[2] - x[2] * v[1]);
        s->angular[1] += m * (x[2] * v[0] - x[0] * v[2]);
        s->angular[2] += m * (x[0] * v[1] - x[1] * v[0]);
        s->angular_sum += m * sqrt(r2) * speed;
        s->polar_inertia += m * r2;
    }
}

/* Append "; text" (or "text" to an empty buffer); truncated text ends in "...". */
static void add_reason(char *why, size_t size, const char *text) {
    const size_t used = strlen(why);
    if (used + 1 >= size) return;
    const int n = snprintf(why + used, size - used, "%s%s", used ? "; " : "", text);
    if (n >= 0 && (size_t)n >= size - used && size >= 4) memcpy(why + size - 4, "...", 4);
}

static const char *constraint_type_name(sph_constraint_type type) {
    switch (type) {
    case SPH_CONSTRAINT_FIXED:
        return "fixed";
    case SPH_CONSTRAINT_FIXED_AXES:
        return "fixed_axes";
    case SPH_CONSTRAINT_VELOCITY:
        return "velocity";
    }
    return "?";
}

bool sph_angular_momentum_conserved(const sph_scene *scene, char *why, size_t size) {
    if (size) why[0] = '\0';
    bool conserved = true;
    char text[3 * SPH_NAME_LEN + 64];
    /* a constrained particle is held or driven by a force from outside the
     * bodies: its reaction torque changes L (the clamped plate's |L - L0| /
     * |L0| swings through 200 % with each oscillation) */
    for (int b = 0; b < scene->nbodies; ++b) {
        const sph_body *body = &scene->bodies[b];
        for (int c = 0; c < body->nconstraints; ++c) {
            const sph_constraint *con = &body->constraints[c];
            const char *region = con->region >= 0 && con->region < scene->nshapes
                                     ? scene->shapes[con->region].name
                                     : "";
            snprintf(text, sizeof text, "constraint '%s' on region '%s' of body '%s'",
                     constraint_type_name(con->type), region[0] ? region : "(inline)", body->name);
            add_reason(why, size, text);
            conserved = false;
        }
    }
    /* a wall pushes along its normal at the contact points: a torque about
     * the origin unless the line of action passes through it */
    for (int w = 0; w < scene->nwalls; ++w) {
        snprintf(text, sizeof text, "wall '%s'", scene->walls[w].name);
        add_reason(why, size, text);
        conserved = false;
    }
    /* fluids: a wall body takes force and torque from the fluid, the far
     * field lets momentum in and out, and about a point of a periodic
     * domain the angular momentum is not conserved (a particle leaving at one
     * side enters at the other with the same velocity, its arm changed) */
    for (int b = 0; b < scene->nbodies; ++b)
        if (scene->bodies[b].role == SPH_BODY_WALL) {
            snprintf(text, sizeof text, "wall body '%s'", scene->bodies[b].name);
            add_reason(why, size, text);
            conserved = false;
        }
    if (scene->has_far_field) {
        add_reason(why, size, "far field");
        conserved = false;
    }
    if (scene->periodic_mask) {
        add_reason(why, size, "periodic boundary");
        conserved = false;
    }
    /* uniform gravity exerts the torque x_c cross M g about the origin */
    const double *g = scene->gravity;
    if (g[0] != 0.0 || g[1] != 0.0 || (scene->dim == 3 && g[2] != 0.0)) {
        add_reason(why, size, "gravity");
        conserved = false;
    }
    return conserved;
}

void sph_metrics_compute(const sph_timeseries *ts, int period_observer, int period_axis,
                         const sph_initial_sums *initial, const char *not_conserved,
                         sph_metrics *m) {
    m->first_period = NAN;
    m->max_angular_momentum_error = NAN;
    snprintf(m->angular_momentum_not_conserved, sizeof m->angular_momentum_not_conserved, "%s",
             not_conserved ? not_conserved : "");
    m->initial_angular_momentum = norm3(initial->angular);
    m->max_linear_momentum_drift = NAN;
    m->initial_kinetic_energy = ts->count ? ts->diag[0].kinetic : NAN;
    m->final_total_energy_ratio = NAN;
    m->max_observer_displacement = NAN;
    m->total_mass = initial->total_mass;
    m->momentum_scale = m->angular_momentum_scale = m->energy_scale = NAN;
    if (ts->count == 0) return;
    const sph_diagnostics *d0 = &ts->diag[0];
    const double l0 = norm3(d0->angular);
    double max_l = 0.0, max_p = 0.0, max_kinetic = 0.0, max_energy = 0.0;
    for (int k = 0; k < ts->count; ++k) {
        double dl[3], dp[3];
        for (int a = 0; a < 3; ++a) {
            dl[a] = ts->diag[k].angular[a] - d0->angular[a];
            dp[a] = ts->diag[k].momentum[a] - d0->momentum[a];
        }
        max_l = fmax(max_l, norm3(dl));
        max_p = fmax(max_p, norm3(dp));
        max_kinetic = fmax(max_kinetic, ts->diag[k].kinetic);
        max_energy = fmax(max_energy, ts->diag[k].kinetic + ts->diag[k].strain);
    }
    m->momentum_scale = sqrt(2.0 * initial->total_mass * max_kinetic);
    m->angular_momentum_scale = sqrt(2.0 * initial->polar_inertia * max_kinetic);
    m->energy_scale = max_energy;
    /* "no spin" from the host's double L(0) against the same sum of
     * magnitudes, never from the device's L(0), which carries the run
     * precision's round-off (1e-8 of the scale in single); the error itself
     * is measured from the device's L(0), whose round-off it shares */
    const bool spins = m->initial_angular_momentum > 1e-9 * initial->angular_sum &&
                       m->initial_angular_momentum > 0.0;
    if (!m->angular_momentum_not_conserved[0] && spins && l0 > 0.0)
        m->max_angular_momentum_error = max_l / l0;
    /* the same outside forces (constraints, walls, gravity) change the linear
     * momentum: its drift is reported only where it is conserved (a periodic
     * domain conserves it: "periodic boundary" alone does not count) */
    const bool only_periodic = strcmp(m->angular_momentum_not_conserved, "periodic boundary") == 0;
    if ((!m->angular_momentum_not_conserved[0] || only_periodic) && initial->momentum_sum > 0.0)
        m->max_linear_momentum_drift = max_p / initial->momentum_sum;
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

/* Mean spacing of the upward zero crossings of y(t) - mean over the
 * samples, by linear interpolation; NAN with fewer than two crossings. */
static double crossing_period(const double *t, const double *y, int count) {
    if (count < 3) return NAN;
    double mean = 0.0;
    for (int k = 0; k < count; ++k) mean += y[k];
    mean /= count;
    double first = NAN, last = NAN;
    int crossings = 0;
    for (int k = 1; k < count; ++k) {
        const double a = y[k - 1] - mean, b = y[k] - mean;
        if (a < 0.0 && b >= 0.0) {
            const double tc = t[k - 1] + (t[k] - t[k - 1]) * (-a) / (b - a);
            if (crossings == 0) first = tc;
            last = tc;
            ++crossings;
        }
    }
    return crossings >= 2 ? (last - first) / (crossings - 1) : NAN;
}

/* The normal traction of observer o at sample k. */
static double normal_traction(const sph_timeseries *ts, const sph_scene *scene, int o, int k) {
    const double *t =
        ts->observers + (size_t)k * (size_t)(ts->nobservers * ts->dim) + (size_t)(o * ts->dim);
    double s = 0.0;
    for (int a = 0; a < ts->dim; ++a) s += t[a] * scene->observers[o].normal[a];
    return s;
}

/* The first pulse of observer o's normal traction from sample `from` on
 * (sph_wave_metrics): its amplitude, and in *end the sample after it. */
static double pulse_amplitude(const sph_timeseries *ts, const sph_scene *scene, int o, int from,
                              int *end) {
    *end = ts->count;
    double peak = 0.0;
    for (int k = from; k < ts->count; ++k)
        peak = fmax(peak, fabs(normal_traction(ts, scene, o, k)));
    if (!(peak > 0.0)) return NAN;
    int start = from;
    while (start < ts->count && fabs(normal_traction(ts, scene, o, start)) < 0.5 * peak) ++start;
    if (start == ts->count) return NAN;
    const double sign = normal_traction(ts, scene, o, start) > 0.0 ? 1.0 : -1.0;
    int stop = start;
    while (stop < ts->count && sign * normal_traction(ts, scene, o, stop) >= 0.5 * peak) ++stop;
    /* the next pulse is sought once this one has died down to a tenth */
    *end = stop;
    while (*end < ts->count && sign * normal_traction(ts, scene, o, *end) >= 0.1 * peak) ++*end;
    const int len = stop - start, lo = start + len / 4, hi = stop - len / 4;
    double sum = 0.0;
    for (int k = lo; k < hi; ++k) sum += normal_traction(ts, scene, o, k);
    return hi > lo ? sum / (double)(hi - lo) : NAN;
}

/* Z = sqrt(rho0 M) of the material at x (sph_wave_metrics), NaN outside
 * every body. */
static double impedance_at(const sph_scene *scene, const double x[3]) {
    for (int b = 0; b < scene->nbodies; ++b) {
        if (!sph_shape_contains(scene, scene->bodies[b].shape, x)) continue;
        const sph_material *m = &scene->materials[sph_body_material_at(scene, b, x)];
        const double modulus =
            m->bulk_modulus + 2.0 * m->shear_modulus * (1.0 - 1.0 / (double)scene->dim);
        return sqrt(m->density * modulus);
    }
    return NAN;
}

double sph_first_pulse(const sph_timeseries *ts, const sph_scene *scene, int o) {
    if (o < 0 || o >= ts->nobservers || scene->observers[o].quantity != SPH_OBSERVE_TRACTION)
        return NAN;
    int end;
    return pulse_amplitude(ts, scene, o, 0, &end);
}

void sph_wave_metrics_compute(const sph_timeseries *ts, const sph_scene *scene,
                              sph_wave_metrics *m) {
    m->incident = m->reflected = m->transmitted = NAN;
    m->transmitted_ratio = m->reflected_ratio = NAN;
    m->transmitted_ratio_theory = m->reflected_ratio_theory = NAN;
    m->impedance_incident = m->impedance_transmitted = NAN;
    const int in = scene->wave_incident, out = scene->wave_transmitted;
    if (in < 0 || out < 0 || in == out || in >= ts->nobservers || out >= ts->nobservers) return;
    const double z1 = impedance_at(scene, scene->observers[in].position),
                 z2 = impedance_at(scene, scene->observers[out].position);
    m->impedance_incident = z1;
    m->impedance_transmitted = z2;
    m->transmitted_ratio_theory = 2.0 * z2 / (z1 + z2);
    m->reflected_ratio_theory = (z2 - z1) / (z2 + z1);
    if (ts->count == 0) return;
    int end, unused;
    m->incident = pulse_amplitude(ts, scene, in, 0, &end);
    m->reflected = pulse_amplitude(ts, scene, in, end, &unused);
    m->transmitted = pulse_amplitude(ts, scene, out, 0, &unused);
    m->transmitted_ratio = m->transmitted / m->incident;
    m->reflected_ratio = m->reflected / m->incident;
}

void sph_fluid_metrics_compute(const sph_timeseries *ts, const sph_scene *scene,
                               sph_fluid_metrics *m) {
    m->max_mass_drift = m->max_total_energy_drift = NAN;
    m->mean_drag_coefficient = m->lift_amplitude = m->strouhal_number = NAN;
    m->force_window_start = NAN;
    if (ts->count == 0 || !SPH_FORMULATION_IS_EULERIAN(scene->formulation)) return;
    const sph_diagnostics *d0 = &ts->diag[0];
    double max_dm = 0.0, max_de = 0.0;
    for (int k = 0; k < ts->count; ++k) {
        max_dm = fmax(max_dm, fabs(ts->diag[k].mass - d0->mass));
        max_de = fmax(max_de, fabs(ts->diag[k].total_energy - d0->total_energy));
    }
    if (d0->mass > 0.0) m->max_mass_drift = max_dm / d0->mass;
    if (scene->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE && d0->total_energy > 0.0)
        m->max_total_energy_drift = max_de / d0->total_energy;
    if (!scene->has_forces) return;
    /* the trailing window: forces.window, or the second half of the run */
    const double t_end = ts->time[ts->count - 1];
    const double window = scene->force_window > 0.0 ? scene->force_window : 0.5 * t_end;
    const double start = fmax(0.0, t_end - window);
    m->force_window_start = start;
    int first = 0;
    while (first < ts->count && ts->time[first] < start) ++first;
    const int count = ts->count - first;
    if (count < 1) return;
    double *t = malloc((size_t)count * sizeof(double)),
           *cl = malloc((size_t)count * sizeof(double));
    if (!t || !cl) {
        free(t);
        free(cl);
        return;
    }
    double sum_cd = 0.0, lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < count; ++k) {
        double cd, c_l;
        sph_force_coefficients(scene, &ts->diag[first + k], &cd, &c_l);
        t[k] = ts->time[first + k];
        cl[k] = c_l;
        sum_cd += cd;
        lo = fmin(lo, c_l);
        hi = fmax(hi, c_l);
    }
    m->mean_drag_coefficient = sum_cd / count;
    m->lift_amplitude = 0.5 * (hi - lo);
    const double period = crossing_period(t, cl, count);
    /* St = f L / U (004 §4.3) */
    if (isfinite(period) && period > 0.0)
        m->strouhal_number =
            scene->force_reference_length / (period * scene->force_reference_speed);
    free(t);
    free(cl);
}

void sph_force_coefficients(const sph_scene *scene, const sph_diagnostics *d, double *drag,
                            double *lift) {
    /* C = 2 F / (rho U^2 L) per unit depth in 2D (004 §4.3): drag along the
     * free stream (x), lift across it (y) */
    const double q = 0.5 * scene->force_reference_density * scene->force_reference_speed *
                     scene->force_reference_speed * scene->force_reference_length;
    const double fx = d->wall_pressure_force[0] + d->wall_viscous_force[0];
    const double fy = d->wall_pressure_force[1] + d->wall_viscous_force[1];
    *drag = q > 0.0 ? fx / q : NAN;
    *lift = q > 0.0 ? fy / q : NAN;
}
