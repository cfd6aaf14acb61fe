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

/* One sphsolid process at a time in an output directory: an flock(2) on
 * DIR/.sphsolid.lock, held for the run's lifetime (the kernel drops it when
 * the process exits or dies, so a crashed run leaves no stale lock; the file
 * stays, holding the pid of the last holder while it holds it).
 * docs/output-format.md, "The output directory lock". */
typedef enum {
    SPH_DIR_LOCK_RUN,     /* exclusive; DIR is created first (a run's --out) */
    SPH_DIR_LOCK_SOURCE,  /* shared, where DIR exists (a restart's source read by
                             a run writing elsewhere) */
    SPH_DIR_LOCK_IF_USED, /* exclusive, only where a run has used DIR (relax --out) */
} sph_dir_lock_mode;

typedef struct {
    int fd;
    bool held;
    bool exclusive;
} sph_dir_lock;

/* Take the lock or fail (SPH_ERR_RUNTIME) with one sentence "LABEL DIR is in
 * use by another sphsolid process (pid N): ..."; a filesystem without locks
 * (or, for SOURCE and IF_USED, no lock file to take) leaves it not held. */
sph_status sph_dir_lock_take(sph_dir_lock *lock, const char *dir, sph_dir_lock_mode mode,
                             const char *label, sph_error *err);
void sph_dir_lock_release(sph_dir_lock *lock);

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
    bool no_work_limit;       /* run even when the predicted work is absurd (work_estimate.h) */
} sph_run_options;

typedef struct {
    sph_run_options options;
    sph_scene scene;
    sph_particles particles;
    sph_features features;
    sph_params_f64 prm;
    sph_backend *backend;
    sph_observer_set observers;
    sph_timeseries series;
    sph_run_stats stats;
    sph_metrics metrics;
    sph_fluid_metrics fluid_metrics; /* fluid scenes (the eulerian formulations) */
    sph_wave_metrics wave_metrics;   /* scenes with analysis.wave */
    double setup_seconds;
    bool scene_loaded;
    double restart_time; /* NAN unless restarted */
    int snapshot_count;
    sph_dir_lock out_lock;    /* options.out_dir, from open to close */
    sph_dir_lock source_lock; /* a restart's directory when it is not out_dir */
} sph_simulation;

/* With options.restart_dir the scene is the one stored in that run's
 * checkpoint (options.scene_path must be NULL); overrides may change only
 * time.end and output.* there, and not to an end before the checkpoint.  A
 * restart takes the checkpoint settings the checkpoint records unless
 * options.checkpoint_every / checkpoint_wall (> 0) override them.
 * options.out_dir is locked (sph_dir_lock) before anything in it changes and
 * until sph_simulation_close. */
sph_status sph_simulation_open(sph_simulation *sim, const sph_run_options *opt, sph_error *err);
sph_status sph_simulation_run(sph_simulation *sim, sph_error *err);
void sph_simulation_close(sph_simulation *sim);

#endif
