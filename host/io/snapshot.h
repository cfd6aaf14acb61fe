/* snapshot.h — particle snapshots as VTKHDF files with a ParaView .series
 * index (layout and rationale: docs/output-format.md).
 *
 * The device stall is only the field download: the host then hands the
 * copies to a writer thread that derives pressure and von Mises stress,
 * reorders rows by particle id, compresses and writes the file, and rewrites
 * the series index, while the time loop goes on.  At most one write is in
 * flight; the next snapshot, a checkpoint or the end of the run waits for it
 * (HDF5 is only ever called from one thread at a time).
 */
#ifndef SPH_SNAPSHOT_H
#define SPH_SNAPSHOT_H

#include "backend.h"
#include "particles.h"
#include "scene.h"

#include <pthread.h>
#include <stdbool.h>

/* What every snapshot records about its run (strings owned by the caller). */
typedef struct {
    const sph_scene *scene;
    const sph_particles *initial; /* displacement reference, by particle id */
    const sph_params_f64 *prm;
    const char *commit, *backend, *device, *build_options, *precision;
    const char *parameters_json; /* summary.json's "resolved" object */
} sph_snapshot_context;

typedef struct {
    char dir[1024]; /* the run directory */
    sph_snapshot_context ctx;
    int n, dim;
    bool double_precision;
    int count, capacity; /* snapshots written (or in flight) */
    double *times;
    /* the job handed to the writer thread */
    bool busy;
    pthread_t thread;
    sph_status job_status;
    sph_error job_err;
    int job_index;
    double job_time;
    long job_acoustic, job_advection;
    double *pos, *vel, *rho, *tau, *alpha; /* backend order, field layout */
    /* fluids (the eulerian formulations): pressure [n], vorticity [3n] */
    double *pressure, *vorticity;
    bool fluid;
    int32_t *id;
    uint8_t *body;
    uint8_t *material;   /* row of the run's material table (0 with one material) */
    double *row_scratch; /* [n * 6] */
} sph_snapshots;

/* Prepare the snapshot directory.  `keep` snapshots of an interrupted run
 * (restart) stay; later ones and any older series are removed. */
sph_status sph_snapshots_open(sph_snapshots *s, const char *run_dir,
                              const sph_snapshot_context *ctx, int n, bool double_precision,
                              int keep, const double *kept_times, sph_error *err);
/* Download the state and start writing snapshot number s->count at time t. */
sph_status sph_snapshots_write(sph_snapshots *s, sph_backend *be, double t, long acoustic_steps,
                               long advection_steps, sph_error *err);
/* Wait for the write in flight; returns its status. */
sph_status sph_snapshots_wait(sph_snapshots *s, sph_error *err);
/* Wait, then release everything. */
void sph_snapshots_close(sph_snapshots *s);

/* "snapshots/snapshot_NNNNNN.hdf" */
void sph_snapshot_name(int index, char *buf, size_t len);

#endif
