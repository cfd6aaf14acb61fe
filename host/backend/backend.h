/* backend.h — the platform split (after OpenMM's Reference/OpenCL platforms).
 *
 * A backend owns the particle state in its memory and runs the phases of the
 * scheme: the configuration rebuild of an advection step, the acoustic
 * substep, and the reductions.  The native CPU backend (C + OpenMP) is the
 * reference every device backend is tested against; both run the physics
 * source of device/.  The host time loop (solver.c) sees only this interface.
 *
 * Particle order inside a backend changes at every rebuild (sorted by cell);
 * FIELD_ID maps a slot back to the particle's initial index.
 */
#ifndef SPH_BACKEND_H
#define SPH_BACKEND_H

#include "feature_set.h"
#include "fields.h"
#include "grid.h"
#include "particles.h"
#include "sph_constants.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sph_step_clock.h"

typedef enum { SPH_BACKEND_AUTO, SPH_BACKEND_CPU, SPH_BACKEND_OPENCL } sph_backend_kind;

/* How the OpenCL acoustic passes get the frozen pair geometry
 * (device/sph_pair_geometry.h): AUTO recomputes it on GPUs and stores it on
 * CPU devices; the native backend always stores it. */
typedef enum {
    SPH_PAIR_GEOMETRY_AUTO,
    SPH_PAIR_GEOMETRY_STORED,
    SPH_PAIR_GEOMETRY_RECOMPUTED
} sph_pair_geometry;

/* Who advances the acoustic step clock (device/sph_step_clock.h).  OpenCL:
 * AUTO and DEVICE the device, where it has double precision, so that an
 * advection step's substeps are enqueued without a host read after each;
 * HOST reads max |v|^2 after every substep (the fallback for devices without
 * cl_khr_fp64).  The native backend: AUTO and DEVICE run an advection step's
 * substeps in one parallel region, its thread 0 advancing the clock
 * (cpu_kernels.advance); HOST one region and one host clock advance per
 * substep.  All give the same steps. */
typedef enum {
    SPH_STEP_CLOCK_AUTO,
    SPH_STEP_CLOCK_DEVICE,
    SPH_STEP_CLOCK_HOST
} sph_step_clock_mode;

typedef enum { SPH_REDUCTION_AUTO, SPH_REDUCTION_BLOCKS, SPH_REDUCTION_TREE } sph_reduction_mode;

typedef struct {
    sph_backend_kind kind;
    int device_index; /* OpenCL device (as listed by `sphsolid devices`); -1: choose */
    bool quiet;       /* no build-option/choice messages on stderr */
    bool profile;     /* time every phase (serialises the device queue) */
    sph_pair_geometry pair_geometry;
    sph_step_clock_mode step_clock;
    /* OpenCL: acoustic substeps per launch.  0: chosen by the particle count
     * and the device; 1: a launch per pass; N > 1: the substep loop
     * (device/substep_loop.cl), at most N substeps per launch.  The native
     * backend runs an advection step's substeps in one parallel region
     * anyway and ignores it. */
    long substeps_per_launch;
    /* OpenCL: the reductions' first stage by blocks of SPH_WG particles
     * (CPU devices) or by a tree over each work-group (GPUs); AUTO by the
     * device, the others force one (tests run the GPUs' way on pocl) */
    sph_reduction_mode reduction;
} sph_backend_request;

/* Result of a configuration rebuild. */
typedef struct {
    double lower[3], upper[3]; /* bounding box of the particles */
    double max_speed2;         /* max |v|^2 */
    double max_accel_term;     /* max 4 h |a_pressure + a_dissipation| */
    int max_neighbours;        /* capacity of the neighbour arrays after the rebuild */
} sph_rebuild_info;

/* Global diagnostics (device reductions). */
typedef struct {
    double kinetic, strain;
    double momentum[3];
    double angular[3]; /* 2D: angular[2] = L_z */
    /* fluids: total mass and total energy (kinetic + internal; `strain` is
     * the internal energy, device/eulerian_step.cl); 0 for solids */
    double mass, total_energy;
    /* fluids with walls: the force of the fluid on the walls, its pressure
     * part and its viscous part (device/eulerian_step.cl) */
    double wall_pressure_force[3], wall_viscous_force[3];
    /* instability monitor (device/monitor.cl), filled by the solver */
    double min_distance_ratio; /* smallest pair distance / dp */
    double gradient_scale;     /* the largest max |L_i| (Frobenius) of the run up to now */
    double zigzag;             /* max velocity mismatch / gradient_scale */
} sph_diagnostics;

/* A host copy of the frozen neighbour lists (tests). */
typedef struct {
    int n, cap;
    int32_t *count; /* [n] */
    int32_t *j;     /* [n * cap], row-major: slot (i, k) at i*cap + k */
} sph_neighbour_lists;

typedef struct {
    char name[64];
    size_t bytes;
} sph_buffer_record;
#define SPH_MAX_BUFFER_RECORDS (2 * FIELD_COUNT + 16)

/* Time spent per phase (kernel, or host-side step) when profiling. */
typedef struct {
    char name[64];
    long calls;
    double seconds;
} sph_profile_record;
#define SPH_MAX_PROFILE_RECORDS 32

/* Length of the carried substep state (see sph_backend_ops). */
#define SPH_CARRIED_LEN (1 + SPH_MAX_BODIES * (9 + SPH_TORQUE_NCOMP(3)))

typedef struct sph_backend sph_backend;
typedef struct {
    sph_status (*upload)(sph_backend *be, const sph_particles *p, sph_error *err);
    sph_status (*rebuild)(sph_backend *be, sph_rebuild_info *info, sph_error *err);
    /* one acoustic substep of size dt; returns max |v|^2 after it */
    sph_status (*substep)(sph_backend *be, double dt, double *max_speed2, sph_error *err);
    /* optional: substeps under the step clock (SPH_CLOCK_LEN doubles,
     * device/sph_step_clock.h) until it halts or clock[CLOCK_COUNT] reaches
     * `limit`; NULL: sph_backend_advance calls substep once per step */
    sph_status (*advance)(sph_backend *be, double *clock, long limit, sph_error *err);
    sph_status (*diagnostics)(sph_backend *be, sph_diagnostics *out, sph_error *err);
    /* instability monitor measures (device/monitor.cl): the
     * SPH_MONITOR_NCOMP(dim) values laid out in sph_constants.h */
    sph_status (*monitor)(sph_backend *be, double *out, sph_error *err);
    /* copy a field to the host: real fields as double [components * n],
     * int32 and u8 fields in their own type */
    sph_status (*download)(sph_backend *be, sph_field field, void *host, sph_error *err);
    sph_status (*download_neighbours)(sph_backend *be, sph_neighbour_lists *out, sph_error *err);
    /* the inverse of download, for restarts: overwrite a present field */
    sph_status (*upload_field)(sph_backend *be, sph_field field, const void *host, sph_error *err);
    /* State carried from one substep to the next besides the fields: the
     * substep reduction (max |v|^2, per-body sums of the Rodrigues matrices
     * that give R-bar, the torque projection's moments), SPH_CARRIED_LEN
     * values.  Checkpoints save it. */
    sph_status (*download_carried)(sph_backend *be, double *out, sph_error *err);
    sph_status (*upload_carried)(sph_backend *be, const double *in, sph_error *err);
    void (*destroy)(sph_backend *be);
} sph_backend_ops;

struct sph_backend {
    const sph_backend_ops *ops;
    const char *kind_name; /* "cpu" or "opencl" */
    char device_name[256]; /* e.g. "AMD EPYC (2 threads)" */
    char build_options[512];
    /* OpenCL: the program's kernels with their arguments, "name(a, b, ...)"
     * separated by newlines: what this run compiled in (summary.json) */
    char program_kernels[8192];
    char choice_reason[256]; /* why this backend/device was chosen */
    /* OpenCL: acoustic substeps per launch at most (1: a launch per pass,
     * more: the substep loop); 0 on the native backend */
    long substeps_per_launch;
    sph_features features;
    sph_field_info fields[FIELD_COUNT];
    int n;
    /* the next rebuild freezes the pair geometry at x + geometry_shift v:
     * half the interval it serves (device/neighbour_build.cl); 0 unless the
     * solver sets it */
    double geometry_shift;
    /* cells of the last rebuild's grid (the profile's byte counts,
     * kernel_bytes.h) */
    long grid_cells;
    /* acoustic substeps this backend has run (sph_backend_advance): a
     * resumed run's profile covers these, not the checkpoint's earlier ones */
    long substeps;
    int nbuffers;
    sph_buffer_record buffers[SPH_MAX_BUFFER_RECORDS];
    bool profiling;
    int nprofile;
    sph_profile_record profile[SPH_MAX_PROFILE_RECORDS];
    void *impl;
};

/* Choose and create a backend for `n` particles of feature set `f`. */
sph_status sph_backend_create(const sph_backend_request *req, const sph_features *f,
                              const sph_params_f64 *prm, int n, sph_backend **out, sph_error *err);
void sph_backend_destroy(sph_backend *be);

/* Acoustic substeps under the step clock `clock` (SPH_CLOCK_LEN doubles,
 * device/sph_step_clock.h) until it halts or clock[CLOCK_COUNT] reaches
 * `limit`: the backend's advance op where it has one, else one substep and
 * one host-side clock advance at a time (sph_backend_advance_by_substeps). */
sph_status sph_backend_advance(sph_backend *be, double *clock, long limit, sph_error *err);
sph_status sph_backend_advance_by_substeps(sph_backend *be, double *clock, long limit,
                                           sph_error *err);

/* Backend constructors (backend_cpu.c, backend_opencl.c); the OpenCL one
 * takes the device index itself (the request's may be -1). */
sph_status sph_backend_cpu_create(const sph_backend_request *req, const sph_features *f,
                                  const sph_params_f64 *prm, int n, sph_backend **out,
                                  sph_error *err);
sph_status sph_backend_opencl_create(const sph_backend_request *req, int device_index,
                                     const sph_features *f, const sph_params_f64 *prm, int n,
                                     sph_backend **out, sph_error *err);

/* Helpers shared by the backends. */
/* Add `seconds` to the profile record of phase `name`. */
void sph_backend_profile_add(sph_backend *be, const char *name, double seconds);

/* Unpack the results of the rebuild and diagnostics reductions (component
 * layouts of device/reduction.cl). */
void sph_rebuild_info_unpack(const double *reduced, int dim, sph_rebuild_info *info);
void sph_diagnostics_unpack(const double *reduced, int dim, sph_diagnostics *out);

/* Record (or update) the bytes of a named buffer for the memory report. */
void sph_backend_record_buffer(sph_backend *be, const char *name, size_t bytes);
size_t sph_backend_total_bytes(const sph_backend *be);
/* SPH_OK if the run allocated field f, else a runtime error naming it. */
sph_status sph_backend_require_field(const sph_backend *be, sph_field f, sph_error *err);
void sph_neighbour_lists_free(sph_neighbour_lists *l);

/* Initial neighbour capacity: the lattice count within the cut-off (given in
 * units of dp) with room for compression; the rebuild grows it on demand. */
int sph_initial_neighbour_capacity(int dim, double cutoff_over_dp);
/* The capacity a rebuild grows to when a particle has `needed` neighbours
 * beyond the current one: a quarter more, so that the next rebuilds of a
 * compressing body rarely build twice (both backends' rule). */
int sph_grown_neighbour_capacity(int needed);

/* A configuration rebuild, the same sequence on every backend
 * (sph_backend_rebuild): the bounds and advection criteria, the cell grid
 * over the bounds (periodic along the scene's periodic axes), the cell sort
 * and permutation, the neighbour lists, built again at a grown capacity
 * while a particle has more neighbours than they hold, then what follows
 * the lists (the fluids' one-time setup).  A backend gives the steps. */
typedef struct {
    /* the bounding box and the advection criteria: 2 dim + 2 values
     * (sph_rebuild_info_unpack) */
    sph_status (*reduce)(sph_backend *be, double *out, sph_error *err);
    /* cell ranges for `grid`, the cell keys at the shifted positions, the
     * sort and the permutation of every field */
    sph_status (*sort)(sph_backend *be, const sph_grid *grid, sph_error *err);
    /* the lists at the current capacity; *needed: 0, or the largest
     * neighbour count when it exceeds the capacity */
    sph_status (*build)(sph_backend *be, const sph_grid *grid, int *needed, sph_error *err);
    /* the lists' arrays at capacity cap */
    sph_status (*grow)(sph_backend *be, int cap, sph_error *err);
    /* after the lists (NULL: nothing) */
    sph_status (*finish)(sph_backend *be, sph_error *err);
    /* the lists' capacity now */
    int (*capacity)(const sph_backend *be);
} sph_rebuild_steps;

/* Run the rebuild sequence with the backend's steps; `cutoff` is the
 * neighbour cut-off, `periodic_mask` and `period` the periodic axes. */
sph_status sph_backend_rebuild(sph_backend *be, const sph_rebuild_steps *steps, double cutoff,
                               int periodic_mask, const double period[3], sph_rebuild_info *info,
                               sph_error *err);

#endif
