#include "progress.h"

#include <unistd.h>

#define TTY_INTERVAL 0.5

void sph_progress_init(sph_progress *p, FILE *out, bool enabled, double log_interval,
                       double wall_now, double sim_time, long acoustic_steps) {
    p->enabled = enabled;
    p->out = out;
    p->tty = enabled && isatty(fileno(out));
    p->interval = p->tty ? TTY_INTERVAL : log_interval;
    p->start_wall = p->last_wall = wall_now;
    p->start_time = sim_time;
    p->start_steps = acoustic_steps;
    p->drawn = 0;
}

static void format_duration(double s, char *buf, size_t len) {
    if (!(s >= 0) || s > 1e8)
        snprintf(buf, len, "?");
    else if (s < 100)
        snprintf(buf, len, "%.0f s", s);
    else if (s < 6000)
        snprintf(buf, len, "%.0f min %02.0f s", (double)(long)(s / 60),
                 s - 60 * (double)(long)(s / 60));
    else
        snprintf(buf, len, "%.1f h", s / 3600);
}

void sph_progress_update(sph_progress *p, double wall_now, double t, double end, long acoustic,
                         long advection, int particles, bool force) {
    if (!p->enabled || (!force && wall_now - p->last_wall < p->interval)) return;
    p->last_wall = wall_now;
    const double elapsed = wall_now - p->start_wall;
    const double rate =
        elapsed > 0 ? (double)particles * (double)(acoustic - p->start_steps) / elapsed : 0;
    const double done = t - p->start_time;
    const double eta = done > 0 ? elapsed * (end - t) / done : -1;
    char eta_text[32];
    format_duration(eta, eta_text, sizeof eta_text);
    char line[256];
    const int len = snprintf(line, sizeof line,
                             "sphsolid: t = %.4g / %.4g s (%3.0f%%)  %ld acoustic / %ld advection "
                             "steps  %.3g M particle-substeps/s  ETA %s",
                             t, end, 100.0 * t / end, acoustic, advection, rate / 1e6, eta_text);
    if (p->tty) {
        /* redraw in place; pad over a longer previous line */
        const int pad = p->drawn > len ? p->drawn - len : 0;
        fprintf(p->out, "\r%s%*s", line, pad, "");
        p->drawn = len;
    } else {
        fprintf(p->out, "%s\n", line);
    }
    fflush(p->out);
}

void sph_progress_finish(sph_progress *p) {
    if (p->tty && p->drawn > 0) {
        fputc('\n', p->out);
        fflush(p->out);
    }
    p->drawn = 0;
}
