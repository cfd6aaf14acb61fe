/* work_estimate.h — what a run will cost, predicted before it starts.
 *
 * From the scene, the particles and the output directory alone: the
 * acoustic substeps (time.end over CFL_ac h / (c0 + max |v|), and at least
 * one per output time), the particle-substeps, the outputs and snapshots
 * and the bytes they will write against the free space of the output
 * directory's filesystem.  A run whose prediction is absurd (a material
 * faster than sound in any solid, more substeps, particle-substeps or
 * outputs than the limits below, more bytes than the disk holds) is refused
 * as bad input before anything is written, in the scene-error format
 * ("FILE:LINE: KEY: what is wrong", or "--set KEY=VALUE: KEY: ..." for an
 * override) naming the key behind it; --no-work-limit runs it anyway with
 * the same text as a warning.  docs/scene-format.md, "Predicted work".
 */
#ifndef SPH_WORK_ESTIMATE_H
#define SPH_WORK_ESTIMATE_H

#include "particles.h"
#include "scene.h"
#include "sph_error.h"

#include <stdbool.h>

/* The limits, each far beyond the largest shipped case or benchmark
 * (docs/benchmarks.md) and far below what the absurd inputs of issue 34
 * predict (1e+150 substeps and more):
 *
 * - a bulk sound speed above 1e5 m/s: no solid carries sound faster than
 *   about 36 km/s (the bound from fundamental constants; diamond: 18 km/s),
 *   and the scenes are in SI units.  The shipped materials stay below
 *   6 km/s; Poisson's ratio 0.49999999999 on the 2D plate's rubber gives
 *   5.8e6 m/s (a 30-minute run of a 0.2-second case);
 * - 1e9 acoustic substeps: the longest benchmark (2D plate H/dp = 30 to
 *   t = 1 s) takes 1.7e5; at the per-substep floor of small cases (about
 *   90 us, docs/benchmarks.md) 1e9 are more than a day;
 * - 1e14 particle-substeps: the largest benchmark (3D plate H/dp = 9 to
 *   t = 0.1 s, 1.18 M particles) takes 6e10; at the fastest rate measured
 *   (8.2e8 particle-substeps/s, H100, single precision) 1e14 are 34 hours;
 * - 1e8 output times: every output is a row of the time series, kept in
 *   memory for the analysis (about 100 bytes each, 10 GB at the limit) and
 *   written to timeseries.csv; the shipped cases have at most a few
 *   thousand. */
#define SPH_WORK_MAX_SOUND_SPEED       1e5
#define SPH_WORK_MAX_SUBSTEPS          1e9
#define SPH_WORK_MAX_PARTICLE_SUBSTEPS 1e14
#define SPH_WORK_MAX_OUTPUTS           1e8

typedef struct {
    double start_time;            /* simulated time the run starts from (a restart's checkpoint) */
    const char *out_dir;          /* NULL: no files */
    const char *const *overrides; /* the run's "key=value" overrides, to name them */
    int noverrides;
    double checkpoint_every; /* simulated seconds between checkpoints; 0: none */
    bool double_precision;   /* snapshots in double (else single) */
    bool no_limit;           /* --no-work-limit: warn instead of refusing */
    bool quiet;              /* no warnings or notes */
} sph_work_request;

typedef struct {
    double sound_speed; /* the largest c0 of the bodies' materials, m/s */
    int material;       /* its index in scene->materials */
    double max_speed;   /* the largest initial particle speed, m/s */
    double h;           /* smoothing length, m */
    double dt_acoustic; /* CFL_ac h / (c0 + max |v|) at the start, s */
    /* CFL_ad h / max(max |v|, U_ref) at the start (INFINITY at rest); the
     * acceleration criterion can only shorten it */
    double dt_advection;
    double outputs;           /* output times after start_time */
    double substeps;          /* at least this many acoustic substeps */
    double particle_substeps; /* particles x substeps */
    double snapshots;         /* snapshot files written */
    double snapshot_bytes;    /* about, each */
    double bytes;             /* snapshots, time series and index, in all */
    double free_bytes;        /* on the output directory's filesystem; NAN: unknown */
} sph_work_estimate;

/* Predict the run; prm holds sph_params_fill's constants. */
void sph_work_estimate_compute(const sph_scene *scene, const sph_particles *particles,
                               const sph_params_f64 *prm, const sph_work_request *request,
                               sph_work_estimate *out);

/* Predict and judge: SPH_ERR_INPUT with the first limit exceeded (unless
 * request->no_limit), warnings and notes on stderr unless request->quiet. */
sph_status sph_work_check(const sph_scene *scene, const sph_particles *particles,
                          const sph_params_f64 *prm, const sph_work_request *request,
                          sph_work_estimate *out, sph_error *err);

#endif
