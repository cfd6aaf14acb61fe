/* solver.h — the time loop: dual-criteria (or single-criterion) stepping.
 *
 * Dual-criteria time stepping (000 §5, eqs. 25-26; 003 eqs. 22-23): the
 * particle configuration (neighbours, frozen pair geometry, B, volumes) is
 * rebuilt once per advection step
 *     dt_ad = CFL_ad h / max(|v|_max, sqrt(4 h |a|_max), U_ref),
 * inside which acoustic substeps of
 *     dt_ac = CFL_ac h / (c0 + |v|_max)
 * advance the state by position Verlet (000 eqs. 27-29).  As in the
 * reference code, the acceleration term uses the pressure and dissipation
 * accelerations only and U_ref floors the advection speed (default: the
 * largest initial speed).  Single-criterion stepping rebuilds after every
 * acoustic step (the papers' comparison and the reference's spinning plate).
 * Output times are hit exactly: the substep before an output time is
 * shortened to land on it.
 */
#ifndef SPH_SOLVER_H
#define SPH_SOLVER_H

#include "analysis.h"
#include "backend.h"
#include "checkpoint.h"
#include "observers.h"
#include "output.h"
#include "scene.h"
#include "snapshot.h"

#include <stdbool.h>

typedef struct {
    double wall_seconds; /* time loop, output included */
    long acoustic_steps, advection_steps;
    double particle_substeps_per_second;
    double end_time; /* simulated time reached */
    double reference_speed;
    /* the first trip of the instability monitor (instability_time NAN: none):
     * what, where (particle id, -1 if unknown; body index; position) and
     * whether the run stopped there (exit status 4) */
    double instability_time, instability_value, instability_threshold;
    char instability_quantity[48];
    char instability_field[32]; /* non-finite values: the first field holding one */
    long instability_particle;
    int instability_body;
    double instability_position[3];
    bool instability_stopped;
} sph_run_stats;

typedef struct {
    const sph_scene *scene;
    sph_backend *backend;
    const sph_particles *initial;
    const sph_params_f64 *prm;
    const sph_observer_set *observers;
    sph_output *output;           /* NULL: no files */
    sph_snapshots *snapshots;     /* NULL: none */
    const char *run_dir;          /* checkpoints go to run_dir/checkpoint */
    double checkpoint_every;      /* simulated seconds between checkpoints; 0: none */
    double checkpoint_wall;       /* wall seconds between checkpoints; 0: none */
    const sph_checkpoint *resume; /* continue from this state (restart) */
    bool quiet;                   /* no progress lines */
    double progress_interval;     /* seconds between log lines when stderr is not a terminal */
    long max_acoustic_steps;      /* > 0: stop after this many (tests) */
} sph_solver_args;

sph_status sph_solve(const sph_solver_args *args, sph_timeseries *ts, sph_run_stats *stats,
                     sph_error *err);

#endif
