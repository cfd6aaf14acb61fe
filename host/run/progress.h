/* progress.h — what a long run tells the user while it runs.
 *
 * On a terminal: one line, redrawn in place about twice a second, with the
 * simulated time and its percentage, acoustic and advection steps,
 * particle-substeps per second and the estimated time to the end.  When
 * stderr is not a terminal (batch jobs, CI logs): the same as a plain log
 * line every `log_interval` seconds.  Disabled by --quiet.
 */
#ifndef SPH_PROGRESS_H
#define SPH_PROGRESS_H

#include <stdbool.h>
#include <stdio.h>

typedef struct {
    bool enabled, tty;
    double interval;   /* seconds between updates */
    double start_wall; /* wall clock at the start of this run (or restart) */
    double start_time; /* simulated time then */
    long start_steps;  /* acoustic steps then */
    double last_wall;
    int drawn; /* characters of the live line on screen */
    FILE *out;
} sph_progress;

void sph_progress_init(sph_progress *p, FILE *out, bool enabled, double log_interval,
                       double wall_now, double sim_time, long acoustic_steps);
/* Report if an update is due (or `force`). */
void sph_progress_update(sph_progress *p, double wall_now, double t, double end, long acoustic,
                         long advection, int particles, bool force);
/* End the live line so later messages start on a fresh line. */
void sph_progress_finish(sph_progress *p);

#endif
