/* run.h — one simulation from scene file to results.
 *
 * sph_simulation_open loads and validates the scene, generates the particles,
 * resolves the feature set and creates the backend; sph_simulation_run runs
 * the time loop and, when an output directory is given, writes
 * timeseries.csv and summary.json into it.  The CLI and the tests use the
 * same path.
 */
#ifndef SPH_RUN_H
#define SPH_RUN_H

#include "analysis.h"
#include "backend.h"
#include "observers.h"
#include "particles.h"
#include "scene.h"
#include "solver.h"

#include <stdbool.h>

typedef struct {
    const char *scene_path;
    const char *const *overrides; /* "key=value" */
    int noverrides;
    sph_backend_request backend;
    sph_precision precision;
    const char *out_dir;      /* NULL: no files */
    const char *restart_dir;  /* continue the run whose checkpoint is in this directory */
    double checkpoint_every;  /* simulated seconds between checkpoints; 0: none */
    double checkpoint_wall;   /* wall seconds between checkpoints; 0: none */
    double progress_interval; /* log-line interval when stderr is not a terminal (s) */
    bool quiet;               /* no messages on stderr */
    long max_acoustic_steps;  /* > 0: stop early (tests) */
} sph_run_options;

typedef struct {
    sph_run_options options;
    sph_scene scene;
    sph_particles particles;
    sph_features features;
    double prm[PRM_COUNT];
    sph_backend *backend;
    sph_observer_set observers;
    sph_timeseries series;
    sph_run_stats stats;
    sph_metrics metrics;
    double setup_seconds;
    bool scene_loaded;
    double restart_time; /* NAN unless restarted */
    int snapshot_count;
} sph_simulation;

/* With options.restart_dir the scene is the one stored in that run's
 * checkpoint (options.scene_path must be NULL); overrides may change only
 * time.end and output.* there. */
sph_status sph_simulation_open(sph_simulation *sim, const sph_run_options *opt, sph_error *err);
sph_status sph_simulation_run(sph_simulation *sim, sph_error *err);
void sph_simulation_close(sph_simulation *sim);

#endif
