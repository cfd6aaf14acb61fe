/* checkpoint.h — the complete state of a run at an advection-step boundary.
 *
 * A checkpoint holds every present per-particle field in the backend's
 * current order (the order the next configuration rebuild starts from), the
 * state carried between substeps (max |v|^2 and the R-bar sums), the time
 * loop's counters, the recorded time series and snapshot times, and the
 * resolved scene text.  Restoring it and rebuilding reproduces the
 * uninterrupted run bit for bit on the same backend and precision: the
 * rebuild's sort is deterministic given the same order, and checkpoints are
 * taken at boundaries the run passes anyway (they never shorten a step).
 *
 * The file is DIR/checkpoint/checkpoint.h5, written through a temporary name,
 * synced and renamed (hdf5_file.h): a run killed while writing keeps the
 * previous checkpoint.
 *
 * It also records the run's checkpoint settings (--checkpoint-every,
 * --checkpoint-wall; format 5): a restart goes on writing checkpoints as the
 * run did unless a flag says otherwise.  Format 4 (before those settings)
 * still restarts, with no checkpoints unless a flag asks for them.
 */
#ifndef SPH_CHECKPOINT_H
#define SPH_CHECKPOINT_H

#include "analysis.h"
#include "backend.h"

#include <stdbool.h>

typedef struct {
    double time;
    double max_speed2; /* from the last substep: sizes the next one */
    long output_index; /* index of the next output time */
    long acoustic_steps, advection_steps;
    int nsnapshots; /* snapshots written so far */
    double *snapshot_times;
    double carried[SPH_CARRIED_LEN];
    double checkpoint_every; /* the run's settings (0: none); a restart continues them */
    double checkpoint_wall;
} sph_checkpoint_header;

/* What a restart checks before it builds anything. */
typedef struct {
    long format;
    double time;
    double checkpoint_every, checkpoint_wall; /* 0: none (or a format-4 checkpoint) */
} sph_checkpoint_info;

typedef struct {
    sph_checkpoint_header h;
    int n;
    char precision[8]; /* "double", "single" or "mixed" */
    char backend[32];
    void *field[FIELD_COUNT]; /* host copies (reals as double) */
} sph_checkpoint;

/* "DIR/checkpoint/checkpoint.h5" */
void sph_checkpoint_path(const char *run_dir, char *buf, size_t len);

sph_status sph_checkpoint_write(const char *run_dir, sph_backend *be,
                                const sph_checkpoint_header *h, const sph_timeseries *ts,
                                const char *scene_text, sph_error *err);

/* The resolved scene stored in a run's checkpoint (malloc'ed). */
sph_status sph_checkpoint_read_scene(const char *run_dir, char **scene_text, sph_error *err);
/* Its format, time and checkpoint settings (a format this sphsolid cannot
 * read is an input error naming both formats). */
sph_status sph_checkpoint_read_info(const char *run_dir, sph_checkpoint_info *info, sph_error *err);

/* The scene a checkpoint must belong to: its particles as the scene places
 * them, and its output interval. */
typedef struct {
    const sph_particles *initial;
    double output_interval;
} sph_checkpoint_scene;

/* The state, for a backend of the same scene (`be` gives the field layout);
 * the series is appended to `ts`.  Everything read is checked before it is
 * used, so that a damaged or edited checkpoint is an input error naming the
 * file and the value (never a crash, a hang or a run from a state no run
 * could reach): the counters against each other and against the time and
 * the output interval, the series and snapshot times, every real value
 * finite, mass, volume and density positive, the ids a permutation of the
 * scene's particles, and each particle's body, material, constraint and
 * kind those the scene gives the particle of its id. */
sph_status sph_checkpoint_read(const char *run_dir, const sph_backend *be,
                               const sph_checkpoint_scene *scene, sph_checkpoint *ck,
                               sph_timeseries *ts, sph_error *err);
/* Put the fields and the carried state into the backend. */
sph_status sph_checkpoint_restore(const sph_checkpoint *ck, sph_backend *be, sph_error *err);
void sph_checkpoint_free(sph_checkpoint *ck);

#endif
