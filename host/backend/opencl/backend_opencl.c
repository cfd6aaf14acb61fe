/* backend_opencl.c — the OpenCL device backend.
 *
 * The program is built for the scene's feature set (feature_set.c), so buffers
 * and kernel arguments of unused features do not exist.  Every phase of the
 * scheme runs on the device: the configuration rebuild (reduction, cell keys,
 * bitonic sort, permutation of all fields, cell ranges, neighbour lists with
 * the frozen pair geometry and B), the acoustic substeps and the reductions.
 * Inside the acoustic loop only reduced scalars come back to the host (the
 * maximum speed that sets the next step size); particle data crosses only
 * when the host asks for it (output).
 */
#include "backend.h"
#include "grid.h"
#include "opencl_runtime.h"
#include "wall_clock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SUBSTEP_SUMS_LEN SPH_CARRIED_LEN
#define RESULT_LEN       16

/* Indices of the named resources kernels are bound to. */
enum {
    RES_FIELD0 = 0, /* FIELD_COUNT field buffers */
    RES_NBR_COUNT = FIELD_COUNT,
    RES_NBR_J,
    RES_PAIR_E,
    RES_PAIR_DWV,
    RES_PAIR_INV_R,
    RES_PAIR_W,
    RES_PAIR_POS,
    RES_KEYS,
    RES_KEYS_SORTED,
    RES_CELL_START,
    RES_CELL_END,
    RES_PRM,
    RES_GRID_GEOM,
    RES_PARTIALS,
    RES_SUBSTEP_SUMS,
    RES_OVERFLOW,
    RES_STEP_CLOCK,
    RES_BLOCKS_DONE,
    RES_NGROUPS,
    RES_N,
    RES_NPAD,
    RES_CAP,
    RES_GX,
    RES_GY,
    RES_GZ,
    RES_COUNT
};

typedef struct {
    sph_cl_kernel cell_keys, permute_real, permute_hreal, permute_int, permute_u8, cell_ranges,
        build, pressure, velocity_terms, rebuild_reduce, substep_reduce, diagnostics_reduce,
        finalize;
    sph_cl_kernel sort_local, merge_local, sort_global; /* GPUs: bitonic sort */
    sph_cl_kernel counting_sort;                        /* CPU devices */
    sph_cl_kernel substep_finalize;                     /* device step clock only */
    sph_cl_kernel substep_reduce_finish;                /* device step clock on CPU devices */
    sph_cl_kernel shear_force;                          /* stress-divergence formulations only */
    sph_cl_kernel monitor_reduce;
    sph_cl_kernel contact;                                    /* scenes with several bodies only */
    sph_cl_kernel tl_deformation, tl_acceleration, tl_update; /* TLSPH only */
    sph_cl_kernel shifted_positions;                          /* recomputed pair geometry only */
    /* fluids only (eulerian_step.cl): once after the rebuild, then per step */
    sph_cl_kernel eulerian_prepare, eulerian_correct_pairs;
    sph_cl_kernel eulerian_momentum_rate, eulerian_mass_energy_rate, eulerian_update;
    sph_cl_kernel eulerian_rates, eulerian_rk_update; /* time.integrator "ssp-rk2", "ssp-rk3" */
    sph_cl_kernel eulerian_far_field;                 /* far field only */
    sph_cl_kernel eulerian_vorticity;                 /* 2D and 3D: for the snapshots */
    /* the substep loop (substep_loop.cl), from its own program */
    sph_cl_kernel substep_loop;
} kernel_set;

typedef struct {
    sph_backend *be; /* owner, for the profile records */
    sph_opencl_device_info dev;
    cl_context ctx;
    cl_command_queue queue;
    cl_program program;
    cl_program loop_program; /* the substep loop's, when a launch runs several substeps */
    kernel_set k;
    cl_mem field[FIELD_COUNT], spare[FIELD_COUNT];
    cl_mem pair_w;   /* TLSPH only */
    cl_mem pair_pos; /* recomputed pair geometry only: shifted positions (sph_pair_geometry.h) */
    cl_mem nbr_count, nbr_j, pair_e, pair_dwv, pair_inv_r, keys, cell_start, cell_end, prm,
        grid_geom, partials, substep_sums, overflow, result;
    cl_mem step_clock;  /* device step clock only (device/sph_step_clock.h) */
    cl_mem keys_sorted; /* counting sort only */
    cl_mem blocks_done; /* substep_reduce_finish only: blocks reduced so far */
    cl_int n, npad, cap, gx, gy, gz, ngroups;
    double cutoff;     /* 2h as the device holds it (prm->cutoff in its precision) */
    int substep_ncomp; /* components of the substep reduction (reduction.cl) */
    size_t real_size;
    size_t wg;      /* reductions (SPH_WG) */
    size_t item_wg; /* per-particle kernels */
    size_t sort_wg;
    size_t reduce_items; /* work-items of the first reduction stage */
    bool reduce_blocks;  /* SPH_REDUCE_BLOCKS (reduction.cl) */
    bool counting_sort;  /* SPH_COUNTING_SORT (neighbour_build.cl) */
    bool row_major;
    bool pair_recompute; /* device/sph_pair_geometry.h */
    bool device_clock;   /* the substeps advance the step clock themselves */
    size_t loop_wg;      /* the substep loop's work-group (SPH_LOOP_WG); 0 without it */
    long cells_allocated;
    int periodic_mask; /* fluids: periodic axes of the cell grid (host/model/grid.h) */
    double period[3];
    sph_cl_arg res[RES_COUNT];
} ocl_impl;

static sph_status cl_check(cl_int rc, const char *what, sph_error *err) {
    if (rc == CL_SUCCESS) return SPH_OK;
    return sph_fail(err, SPH_ERR_RUNTIME, "%s failed: %s (%d)", what, sph_cl_error_name(rc), rc);
}

static size_t round_up(size_t x, size_t m) {
    return (x + m - 1) / m * m;
}

static sph_status make_buffer(sph_backend *be, ocl_impl *o, const char *name, size_t bytes,
                              cl_mem *out, sph_error *err) {
    cl_int rc;
    if (bytes == 0) bytes = 16;
    if (bytes > o->dev.max_alloc)
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "buffer '%s' needs %.1f MiB but the device allows at most %.1f MiB per "
                        "allocation",
                        name, (double)bytes / 1048576.0, (double)o->dev.max_alloc / 1048576.0);
    *out = clCreateBuffer(o->ctx, CL_MEM_READ_WRITE, bytes, NULL, &rc);
    if (rc != CL_SUCCESS)
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "device out of memory: buffer '%s' (%.1f MiB) could not be allocated "
                        "(%s); total so far %.1f MiB of %.1f MiB",
                        name, (double)bytes / 1048576.0, sph_cl_error_name(rc),
                        (double)sph_backend_total_bytes(be) / 1048576.0,
                        (double)o->dev.global_mem / 1048576.0);
    sph_backend_record_buffer(be, name, bytes);
    return SPH_OK;
}

static size_t field_bytes(const sph_backend *be, sph_field f);

/* Before anything is allocated: every buffer the run starts with (neighbour
 * lists at their initial capacity; the cell ranges, sized at the first
 * rebuild, estimated at one cell per particle) must fit in the device's
 * global memory, and each in its largest allocation. */
static sph_status check_device_memory(const sph_backend *be, const ocl_impl *o, int device_index,
                                      int cap, sph_error *err) {
    const double n = (double)be->n, real = (double)o->real_size, slots = n * (double)cap;
    const bool tlsph = be->features.formulation == SPH_FORMULATION_TLSPH;
    const double stored = o->pair_recompute ? 0.0 : 1.0;
    const double hreal = (double)sph_field_element_size(FIELD_TYPE_HREAL, &be->features);
    const struct {
        const char *name;
        double bytes;
        int copies;
    } fixed[] = {
        {"nbr_j", slots * sizeof(cl_int), 1},
        {"pair_e", stored * slots * be->features.dim * real, 1},
        {"pair_dwv", stored * slots * real, 1},
        {"pair_inv_r", stored * slots * real, 1},
        {"pair_pos", (1.0 - stored) * n * be->features.dim * hreal, 1},
        {"pair_w", tlsph ? slots * real : 0.0, 1},
        {"nbr_count", n * sizeof(cl_int), 1},
        {"keys", (double)o->npad * sizeof(cl_ulong), o->counting_sort ? 2 : 1},
        {"partials", (double)o->ngroups * sph_partial_ncomp(&be->features) * real, 1},
        {"cell_start", n * sizeof(cl_int), 2}, /* and cell_end */
    };
    double total = 0.0, largest = 0.0;
    const char *largest_name = "";
    for (int f = 0; f < FIELD_COUNT; ++f) {
        if (!be->fields[f].present) continue;
        const double bytes = (double)field_bytes(be, (sph_field)f);
        total += 2.0 * bytes; /* the field and its reorder copy */
        if (bytes > largest) {
            largest = bytes;
            largest_name = be->fields[f].name;
        }
    }
    for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; ++k) {
        total += fixed[k].copies * fixed[k].bytes;
        if (fixed[k].bytes > largest) {
            largest = fixed[k].bytes;
            largest_name = fixed[k].name;
        }
    }
    char need_s[32], have_s[32], largest_s[32], alloc_s[32];
    sph_format_bytes(total, need_s, sizeof need_s);
    sph_format_bytes((double)o->dev.global_mem, have_s, sizeof have_s);
    sph_format_bytes(largest, largest_s, sizeof largest_s);
    sph_format_bytes((double)o->dev.max_alloc, alloc_s, sizeof alloc_s);
    if (total > (double)o->dev.global_mem)
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "OpenCL device %d (%s) has %s of global memory, but %d particles need %s "
                        "of buffers (neighbour lists for %d neighbours each); lower the "
                        "resolution or use --backend cpu",
                        device_index, o->dev.name, have_s, be->n, need_s, cap);
    if (largest > (double)o->dev.max_alloc)
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "OpenCL device %d (%s) allocates at most %s per buffer, but buffer '%s' "
                        "for %d particles needs %s (%s of buffers in all, %s of global memory); "
                        "lower the resolution or use --backend cpu",
                        device_index, o->dev.name, alloc_s, largest_name, be->n, largest_s, need_s,
                        have_s);
    return SPH_OK;
}

static void release(cl_mem *m) {
    if (*m) clReleaseMemObject(*m);
    *m = NULL;
}

static size_t field_bytes(const sph_backend *be, sph_field f) {
    const sph_field_info *info = &be->fields[f];
    return (size_t)be->n * (size_t)info->components *
           sph_field_element_size(info->type, &be->features);
}

/* The resource table points at the live handles and scalars, so swapped
 * buffers and regrown arrays are picked up at the next bind. */
static void fill_resources(sph_backend *be, ocl_impl *o) {
    for (int f = 0; f < FIELD_COUNT; ++f)
        o->res[RES_FIELD0 + f] = (sph_cl_arg){be->fields[f].name, sizeof(cl_mem), &o->field[f]};
    o->res[RES_NBR_COUNT] = (sph_cl_arg){"nbr_count", sizeof(cl_mem), &o->nbr_count};
    o->res[RES_NBR_J] = (sph_cl_arg){"nbr_j", sizeof(cl_mem), &o->nbr_j};
    o->res[RES_PAIR_E] = (sph_cl_arg){"pair_e", sizeof(cl_mem), &o->pair_e};
    o->res[RES_PAIR_DWV] = (sph_cl_arg){"pair_dwv", sizeof(cl_mem), &o->pair_dwv};
    o->res[RES_PAIR_INV_R] = (sph_cl_arg){"pair_inv_r", sizeof(cl_mem), &o->pair_inv_r};
    o->res[RES_PAIR_W] = (sph_cl_arg){"pair_w", sizeof(cl_mem), &o->pair_w};
    o->res[RES_PAIR_POS] = (sph_cl_arg){"pair_pos", sizeof(cl_mem), &o->pair_pos};
    o->res[RES_KEYS] = (sph_cl_arg){"keys", sizeof(cl_mem), &o->keys};
    o->res[RES_KEYS_SORTED] = (sph_cl_arg){"keys_sorted", sizeof(cl_mem), &o->keys_sorted};
    o->res[RES_CELL_START] = (sph_cl_arg){"cell_start", sizeof(cl_mem), &o->cell_start};
    o->res[RES_CELL_END] = (sph_cl_arg){"cell_end", sizeof(cl_mem), &o->cell_end};
    o->res[RES_PRM] = (sph_cl_arg){"prm", sizeof(cl_mem), &o->prm};
    o->res[RES_GRID_GEOM] = (sph_cl_arg){"grid_geom", sizeof(cl_mem), &o->grid_geom};
    o->res[RES_PARTIALS] = (sph_cl_arg){"partials", sizeof(cl_mem), &o->partials};
    o->res[RES_SUBSTEP_SUMS] = (sph_cl_arg){"substep_sums", sizeof(cl_mem), &o->substep_sums};
    o->res[RES_OVERFLOW] = (sph_cl_arg){"overflow", sizeof(cl_mem), &o->overflow};
    o->res[RES_STEP_CLOCK] = (sph_cl_arg){"step_clock", sizeof(cl_mem), &o->step_clock};
    o->res[RES_BLOCKS_DONE] = (sph_cl_arg){"blocks_done", sizeof(cl_mem), &o->blocks_done};
    o->res[RES_NGROUPS] = (sph_cl_arg){"ngroups", sizeof(cl_int), &o->ngroups};
    o->res[RES_N] = (sph_cl_arg){"n", sizeof(cl_int), &o->n};
    o->res[RES_NPAD] = (sph_cl_arg){"npad", sizeof(cl_int), &o->npad};
    o->res[RES_CAP] = (sph_cl_arg){"cap", sizeof(cl_int), &o->cap};
    o->res[RES_GX] = (sph_cl_arg){"gx", sizeof(cl_int), &o->gx};
    o->res[RES_GY] = (sph_cl_arg){"gy", sizeof(cl_int), &o->gy};
    o->res[RES_GZ] = (sph_cl_arg){"gz", sizeof(cl_int), &o->gz};
}

/* Bind and enqueue a 1-D launch of `global` items in groups of `local`. */
static sph_status launch(ocl_impl *o, sph_cl_kernel *k, size_t global, size_t local,
                         const sph_cl_arg *overrides, int noverrides, sph_error *err) {
    sph_status st = sph_cl_kernel_bind(k, o->res, overrides, noverrides, err);
    if (st) return st;
    global = round_up(global, local);
    cl_event done = NULL;
    cl_int rc = clEnqueueNDRangeKernel(o->queue, k->kernel, 1, NULL, &global, &local, 0, NULL,
                                       o->be->profiling ? &done : NULL);
    if (rc != CL_SUCCESS)
        return sph_fail(err, SPH_ERR_RUNTIME, "launching kernel %s failed: %s", k->name,
                        sph_cl_error_name(rc));
    if (done) {
        /* profiling: device time of this launch (serialises the queue) */
        cl_ulong start = 0, end = 0;
        rc = clWaitForEvents(1, &done);
        if (rc == CL_SUCCESS)
            rc = clGetEventProfilingInfo(done, CL_PROFILING_COMMAND_START, sizeof start, &start,
                                         NULL);
        if (rc == CL_SUCCESS)
            rc = clGetEventProfilingInfo(done, CL_PROFILING_COMMAND_END, sizeof end, &end, NULL);
        clReleaseEvent(done);
        if (rc != CL_SUCCESS) return cl_check(rc, "reading kernel profiling data", err);
        sph_backend_profile_add(o->be, k->name, 1e-9 * (double)(end - start));
    }
    return SPH_OK;
}

/* A real-valued scalar argument in the program's precision. */
typedef struct {
    double d;
    float f;
} real_scalar;
static sph_cl_arg real_arg(const ocl_impl *o, const char *name, real_scalar *s, double value) {
    s->d = value;
    s->f = (float)value;
    return o->real_size == sizeof(double) ? (sph_cl_arg){name, sizeof(double), &s->d}
                                          : (sph_cl_arg){name, sizeof(float), &s->f};
}

/* Reads of reduced values (a few reals, every substep) use a stack buffer;
 * field downloads allocate. */
#define SMALL_READ 32
static sph_status read_values(ocl_impl *o, cl_mem buf, size_t esize, size_t offset, size_t count,
                              double *out, sph_error *err) {
    const size_t bytes = count * esize;
    double small[SMALL_READ];
    void *tmp = count <= SMALL_READ ? (void *)small : malloc(bytes);
    if (!tmp) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    const cl_int rc =
        clEnqueueReadBuffer(o->queue, buf, CL_TRUE, offset * esize, bytes, tmp, 0, NULL, NULL);
    if (rc == CL_SUCCESS)
        for (size_t k = 0; k < count; ++k)
            out[k] = esize == sizeof(double) ? ((double *)tmp)[k] : (double)((float *)tmp)[k];
    if (tmp != (void *)small) free(tmp);
    return cl_check(rc, "reading a device buffer", err);
}
/* a buffer in the arithmetic precision */
static sph_status read_reals(ocl_impl *o, cl_mem buf, size_t offset, size_t count, double *out,
                             sph_error *err) {
    return read_values(o, buf, o->real_size, offset, count, out, err);
}

static sph_status write_values(ocl_impl *o, cl_mem buf, size_t esize, const double *values,
                               size_t count, sph_error *err) {
    const size_t bytes = count * esize;
    void *tmp = malloc(bytes);
    if (!tmp) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    for (size_t k = 0; k < count; ++k) {
        if (esize == sizeof(double))
            ((double *)tmp)[k] = values[k];
        else
            ((float *)tmp)[k] = (float)values[k];
    }
    const cl_int rc = clEnqueueWriteBuffer(o->queue, buf, CL_TRUE, 0, bytes, tmp, 0, NULL, NULL);
    free(tmp);
    return cl_check(rc, "writing a device buffer", err);
}
static sph_status write_reals(ocl_impl *o, cl_mem buf, const double *values, size_t count,
                              sph_error *err) {
    return write_values(o, buf, o->real_size, values, count, err);
}
/* The parameter block in the run precision: the bytes of the device's
 * struct (device/sph_params.h checks that the layouts agree). */
static size_t params_size(const ocl_impl *o) {
    return o->real_size == sizeof(float) ? sizeof(sph_params_f32) : sizeof(sph_params_f64);
}
static sph_status write_params(ocl_impl *o, const sph_params_f64 *prm, sph_error *err) {
    sph_params_f32 single;
    const void *bytes = prm;
    if (o->real_size == sizeof(float)) {
        sph_params_to_f32(prm, &single);
        bytes = &single;
    }
    const cl_int rc =
        clEnqueueWriteBuffer(o->queue, o->prm, CL_TRUE, 0, params_size(o), bytes, 0, NULL, NULL);
    return cl_check(rc, "writing the parameter block", err);
}
/* a whole floating-point field, in its own precision */
static sph_status write_field(sph_backend *be, ocl_impl *o, sph_field f, const double *values,
                              sph_error *err) {
    return write_values(o, o->field[f], sph_field_element_size(be->fields[f].type, &be->features),
                        values, (size_t)be->n * (size_t)be->fields[f].components, err);
}

/* Two-stage reduction into `result` (device) of `ncomp` components. */
static sph_status finalize(ocl_impl *o, int nmax, int ncomp, cl_mem result, sph_error *err) {
    cl_int nmax_i = nmax, ncomp_i = ncomp;
    const sph_cl_arg args[] = {{"ngroups", sizeof(cl_int), &o->ngroups},
                               {"nmax", sizeof(cl_int), &nmax_i},
                               {"ncomp", sizeof(cl_int), &ncomp_i},
                               {"result", sizeof(cl_mem), &result}};
    return launch(o, &o->k.finalize, o->wg, o->wg, args, 4, err);
}

static sph_status alloc_pairs(sph_backend *be, ocl_impl *o, int cap, sph_error *err) {
    release(&o->nbr_j);
    release(&o->pair_e);
    release(&o->pair_dwv);
    release(&o->pair_inv_r);
    release(&o->pair_w);
    o->cap = cap;
    const size_t slots = (size_t)be->n * (size_t)cap;
    sph_status st = make_buffer(be, o, "nbr_j", slots * sizeof(cl_int), &o->nbr_j, err);
    if (o->pair_recompute) return st; /* the geometry comes from pair_pos */
    if (!st)
        st = make_buffer(be, o, "pair_e", slots * (size_t)be->features.dim * o->real_size,
                         &o->pair_e, err);
    if (!st) st = make_buffer(be, o, "pair_dwv", slots * o->real_size, &o->pair_dwv, err);
    if (!st) st = make_buffer(be, o, "pair_inv_r", slots * o->real_size, &o->pair_inv_r, err);
    if (!st && be->features.formulation == SPH_FORMULATION_TLSPH)
        st = make_buffer(be, o, "pair_w", slots * o->real_size, &o->pair_w, err);
    return st;
}

static sph_status ocl_upload(sph_backend *be, const sph_particles *p, sph_error *err) {
    ocl_impl *o = be->impl;
    const int n = be->n, d = be->features.dim;
    if (p->n != n || p->dim != d)
        return sph_fail(err, SPH_ERR_RUNTIME, "particle set does not match the backend");
    const unsigned char zero = 0;
    for (int f = 0; f < FIELD_COUNT; ++f) {
        if (!o->field[f]) continue;
        sph_status st = cl_check(clEnqueueFillBuffer(o->queue, o->field[f], &zero, 1, 0,
                                                     field_bytes(be, (sph_field)f), 0, NULL, NULL),
                                 "clearing a field", err);
        if (st) return st;
    }
    double *vol = malloc((size_t)n * sizeof(double));
    if (!vol) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    for (int i = 0; i < n; ++i) vol[i] = p->mass[i] / p->rho[i];
    sph_status st = write_field(be, o, FIELD_POS, p->pos, err);
    if (!st) st = write_field(be, o, FIELD_VEL, p->vel, err);
    if (!st) st = write_field(be, o, FIELD_MASS, p->mass, err);
    if (!st) st = write_field(be, o, FIELD_RHO, p->rho, err);
    if (!st) st = write_field(be, o, FIELD_VOL, vol, err);
    /* the compressible initial pressure (eulerian_prepare derives the rest) */
    if (!st && o->field[FIELD_PRESSURE] && p->pressure)
        st = write_field(be, o, FIELD_PRESSURE, p->pressure, err);
    /* walls and the far field: normals (the kinds with the u8 fields below) */
    if (!st && o->field[FIELD_NORMAL] && p->normal)
        st = write_field(be, o, FIELD_NORMAL, p->normal, err);
    free(vol);
    if (st) return st;
    cl_int rc = clEnqueueWriteBuffer(o->queue, o->field[FIELD_ID], CL_TRUE, 0,
                                     (size_t)n * sizeof(cl_int), p->id, 0, NULL, NULL);
    if (rc == CL_SUCCESS && o->field[FIELD_BODY])
        rc = clEnqueueWriteBuffer(o->queue, o->field[FIELD_BODY], CL_TRUE, 0, (size_t)n, p->body, 0,
                                  NULL, NULL);
    if (rc == CL_SUCCESS && o->field[FIELD_FIXED])
        rc = clEnqueueWriteBuffer(o->queue, o->field[FIELD_FIXED], CL_TRUE, 0, (size_t)n, p->fixed,
                                  0, NULL, NULL);
    if (rc == CL_SUCCESS && o->field[FIELD_MATERIAL])
        rc = clEnqueueWriteBuffer(o->queue, o->field[FIELD_MATERIAL], CL_TRUE, 0, (size_t)n,
                                  p->material, 0, NULL, NULL);
    if (rc == CL_SUCCESS && o->field[FIELD_KIND])
        rc = clEnqueueWriteBuffer(o->queue, o->field[FIELD_KIND], CL_TRUE, 0, (size_t)n, p->kind, 0,
                                  NULL, NULL);
    if (rc == CL_SUCCESS)
        rc = clEnqueueFillBuffer(o->queue, o->substep_sums, &zero, 1, 0,
                                 SUBSTEP_SUMS_LEN * o->real_size, 0, NULL, NULL);
    if (rc == CL_SUCCESS && o->blocks_done)
        rc = clEnqueueFillBuffer(o->queue, o->blocks_done, &zero, 1, 0, sizeof(cl_int), 0, NULL,
                                 NULL);
    return cl_check(rc, "uploading the particles", err);
}

/* The keys in cell order.  CPU devices: a counting sort on one work-item
 * that also writes the cell ranges (neighbour_build.cl); the sorted keys
 * become `keys`. */
static sph_status sort_keys_counting(ocl_impl *o, sph_error *err) {
    sph_status st = launch(o, &o->k.counting_sort, 1, 1, NULL, 0, err);
    cl_mem t = o->keys;
    o->keys = o->keys_sorted;
    o->keys_sorted = t;
    return st;
}

/* GPUs: a bitonic sort of the padded keys; the cell ranges follow
 * (cell_ranges). */
static sph_status sort_keys_bitonic(ocl_impl *o, sph_error *err) {
    const size_t npad = (size_t)o->npad;
    sph_status st = launch(o, &o->k.sort_local, npad, o->sort_wg, NULL, 0, err);
    for (cl_int k = (cl_int)o->sort_wg * 2; !st && k <= o->npad; k <<= 1) {
        for (cl_int j = k / 2; !st && j >= (cl_int)o->sort_wg; j >>= 1) {
            const sph_cl_arg args[] = {{"j", sizeof(cl_int), &j}, {"k", sizeof(cl_int), &k}};
            st = launch(o, &o->k.sort_global, npad, o->sort_wg, args, 2, err);
        }
        if (!st) {
            const sph_cl_arg args[] = {{"k", sizeof(cl_int), &k}};
            st = launch(o, &o->k.merge_local, npad, o->sort_wg, args, 1, err);
        }
    }
    return st;
}

/* The fields in the sorted order: each field is gathered into its spare
 * copy, PERMUTE_BATCH fields of one element type per launch
 * (neighbour_build.cl), and the two swap. */
#define PERMUTE_BATCH 8 /* the slots of the permute kernels (neighbour_build.cl) */
static sph_cl_kernel *permute_kernel(sph_backend *be, ocl_impl *o, sph_field f) {
    const sph_field_type type = be->fields[f].type;
    /* a history field is real unless the run is mixed (fields.h) */
    if (type == FIELD_TYPE_HREAL && be->features.mixed_precision) return &o->k.permute_hreal;
    return sph_field_is_real(type)    ? &o->k.permute_real
           : type == FIELD_TYPE_INT32 ? &o->k.permute_int
                                      : &o->k.permute_u8;
}

static sph_status permute_fields(sph_backend *be, ocl_impl *o, sph_error *err) {
    static const char *const ncomp_name[PERMUTE_BATCH] = {"ncomp0", "ncomp1", "ncomp2", "ncomp3",
                                                          "ncomp4", "ncomp5", "ncomp6", "ncomp7"};
    static const char *const src_name[PERMUTE_BATCH] = {"src0", "src1", "src2", "src3",
                                                        "src4", "src5", "src6", "src7"};
    static const char *const dst_name[PERMUTE_BATCH] = {"dst0", "dst1", "dst2", "dst3",
                                                        "dst4", "dst5", "dst6", "dst7"};
    sph_cl_kernel *kinds[] = {&o->k.permute_real, &o->k.permute_hreal, &o->k.permute_int,
                              &o->k.permute_u8};
    for (size_t kind = 0; kind < sizeof kinds / sizeof kinds[0]; ++kind) {
        int f = 0;
        while (f < FIELD_COUNT) {
            cl_int ncomp[PERMUTE_BATCH] = {0};
            sph_cl_arg args[3 * PERMUTE_BATCH];
            int used = 0;
            for (; f < FIELD_COUNT && used < PERMUTE_BATCH; ++f) {
                if (!o->field[f] || permute_kernel(be, o, (sph_field)f) != kinds[kind]) continue;
                ncomp[used] = be->fields[f].components;
                args[3 * used + 1] = (sph_cl_arg){src_name[used], sizeof(cl_mem), &o->field[f]};
                args[3 * used + 2] = (sph_cl_arg){dst_name[used], sizeof(cl_mem), &o->spare[f]};
                ++used;
            }
            if (used == 0) break;
            /* empty slots: no components, any buffer */
            for (int s = used; s < PERMUTE_BATCH; ++s) {
                args[3 * s + 1] = (sph_cl_arg){src_name[s], sizeof(cl_mem), &o->nbr_count};
                args[3 * s + 2] = (sph_cl_arg){dst_name[s], sizeof(cl_mem), &o->nbr_count};
            }
            for (int s = 0; s < PERMUTE_BATCH; ++s)
                args[3 * s] = (sph_cl_arg){ncomp_name[s], sizeof(cl_int), &ncomp[s]};
            sph_status st =
                launch(o, kinds[kind], (size_t)be->n, o->item_wg, args, 3 * PERMUTE_BATCH, err);
            if (st) return st;
        }
    }
    for (int f = 0; f < FIELD_COUNT; ++f) {
        if (!o->field[f]) continue;
        cl_mem t = o->field[f];
        o->field[f] = o->spare[f];
        o->spare[f] = t;
    }
    return SPH_OK;
}

/* The rebuild's steps (sph_backend_rebuild). */
static sph_status ocl_rebuild_reduce(sph_backend *be, double *out, sph_error *err) {
    ocl_impl *o = be->impl;
    const int ncomp = 2 * be->features.dim + 2;
    sph_status st = launch(o, &o->k.rebuild_reduce, o->reduce_items, o->wg, NULL, 0, err);
    if (!st) st = finalize(o, ncomp, ncomp, o->result, err);
    if (!st) st = read_reals(o, o->result, 0, (size_t)ncomp, out, err);
    return st;
}

/* the geometry shift as the kernels' argument */
static sph_cl_arg shift_argument(const sph_backend *be, real_scalar *s) {
    return real_arg(be->impl, "geometry_shift", s, be->geometry_shift);
}

static sph_status ocl_rebuild_sort(sph_backend *be, const sph_grid *grid, sph_error *err) {
    ocl_impl *o = be->impl;
    sph_status st = SPH_OK;
    if (grid->ncells > o->cells_allocated) {
        release(&o->cell_start);
        release(&o->cell_end);
        const size_t bytes = (size_t)grid->ncells * sizeof(cl_int);
        st = make_buffer(be, o, "cell_start", bytes, &o->cell_start, err);
        if (!st) st = make_buffer(be, o, "cell_end", bytes, &o->cell_end, err);
        if (st) return st;
        o->cells_allocated = grid->ncells;
    }
    o->gx = grid->dims[0];
    o->gy = grid->dims[1];
    o->gz = grid->dims[2];
    double geom[4] = {grid->origin[0], grid->origin[1], grid->origin[2], 1.0 / grid->cell};
    st = write_reals(o, o->grid_geom, geom, 4, err);
    real_scalar shift_s;
    const sph_cl_arg shift_arg = shift_argument(be, &shift_s);
    if (!st) st = launch(o, &o->k.cell_keys, (size_t)o->npad, o->item_wg, &shift_arg, 1, err);
    if (!st) st = o->counting_sort ? sort_keys_counting(o, err) : sort_keys_bitonic(o, err);
    if (!st) st = permute_fields(be, o, err);
    if (!st && o->pair_recompute)
        st = launch(o, &o->k.shifted_positions, (size_t)be->n, o->item_wg, &shift_arg, 1, err);
    if (st || o->counting_sort) return st;
    /* the bitonic sort leaves the cell ranges to a pass of their own */
    const cl_int zero = 0;
    st = cl_check(clEnqueueFillBuffer(o->queue, o->cell_start, &zero, sizeof zero, 0,
                                      (size_t)grid->ncells * sizeof(cl_int), 0, NULL, NULL),
                  "clearing cell ranges", err);
    if (!st)
        st = cl_check(clEnqueueFillBuffer(o->queue, o->cell_end, &zero, sizeof zero, 0,
                                          (size_t)grid->ncells * sizeof(cl_int), 0, NULL, NULL),
                      "clearing cell ranges", err);
    if (!st) st = launch(o, &o->k.cell_ranges, (size_t)be->n, o->item_wg, NULL, 0, err);
    return st;
}

static sph_status ocl_rebuild_build(sph_backend *be, const sph_grid *grid, int *needed,
                                    sph_error *err) {
    (void)grid; /* the device holds its geometry (grid_geom, gx, gy, gz) */
    ocl_impl *o = be->impl;
    const cl_int zero = 0;
    cl_int count = 0;
    real_scalar shift_s;
    const sph_cl_arg shift_arg = shift_argument(be, &shift_s);
    sph_status st = cl_check(clEnqueueFillBuffer(o->queue, o->overflow, &zero, sizeof zero, 0,
                                                 sizeof(cl_int), 0, NULL, NULL),
                             "clearing the overflow flag", err);
    if (!st) st = launch(o, &o->k.build, (size_t)be->n, o->item_wg, &shift_arg, 1, err);
    if (!st)
        st = cl_check(clEnqueueReadBuffer(o->queue, o->overflow, CL_TRUE, 0, sizeof count, &count,
                                          0, NULL, NULL),
                      "reading the neighbour count", err);
    *needed = count;
    return st;
}

static sph_status ocl_rebuild_grow(sph_backend *be, int cap, sph_error *err) {
    return alloc_pairs(be, be->impl, cap, err);
}

/* fluids, once (the only rebuild): the initial EOS state and the corrected
 * pair gradients (eulerian_step.cl) */
static sph_status ocl_rebuild_finish(sph_backend *be, sph_error *err) {
    ocl_impl *o = be->impl;
    sph_status st = SPH_OK;
    if (o->k.eulerian_prepare.kernel)
        st = launch(o, &o->k.eulerian_prepare, (size_t)be->n, o->item_wg, NULL, 0, err);
    if (!st && o->k.eulerian_correct_pairs.kernel)
        st = launch(o, &o->k.eulerian_correct_pairs, (size_t)be->n, o->item_wg, NULL, 0, err);
    if (!st && o->k.eulerian_far_field.kernel)
        st = launch(o, &o->k.eulerian_far_field, (size_t)be->n, o->item_wg, NULL, 0, err);
    return st;
}

static int ocl_rebuild_capacity(const sph_backend *be) {
    return ((const ocl_impl *)be->impl)->cap;
}

static sph_status ocl_rebuild(sph_backend *be, sph_rebuild_info *info, sph_error *err) {
    ocl_impl *o = be->impl;
    static const sph_rebuild_steps steps = {ocl_rebuild_reduce, ocl_rebuild_sort,
                                            ocl_rebuild_build,  ocl_rebuild_grow,
                                            ocl_rebuild_finish, ocl_rebuild_capacity};
    return sph_backend_rebuild(be, &steps, o->cutoff, o->periodic_mask, o->period, info, err);
}

/* Enqueue one acoustic substep's passes and the first stage of its
 * reduction (max |v|^2, the R-bar sums): TLSPH's deformation, acceleration
 * and update passes (tl_step.cl), or contact (several bodies), pressure,
 * velocity terms and, for the stress-divergence formulations, the shear
 * force (acoustic_step.cl).  dt_arg: the substep size as an argument, or
 * NULL when the kernels read it from the device step clock. */
static sph_status enqueue_substep(ocl_impl *o, const sph_cl_arg *dt_arg, sph_error *err) {
    const size_t items = (size_t)o->n;
    const int ndt = dt_arg ? 1 : 0;
    sph_status st = SPH_OK;
    if (o->k.eulerian_rk_update.kernel) {
        /* SSP-RK: per stage the rates of its state, then its update
         * (eulerian_step.cl; the rates take the stage, the update also the
         * number of stages) */
        cl_int stages = o->be->features.fluid_rk_stages;
        for (cl_int stage = 0; stage < stages && !st; ++stage) {
            sph_cl_arg args[3] = {{"stage", sizeof(cl_int), &stage},
                                  {"stages", sizeof(cl_int), &stages}};
            if (dt_arg) args[2] = *dt_arg;
            st = launch(o, &o->k.eulerian_rates, items, o->item_wg, args, 2 + ndt, err);
            if (!st)
                st = launch(o, &o->k.eulerian_rk_update, items, o->item_wg, args, 2 + ndt, err);
        }
        if (!st && o->k.eulerian_far_field.kernel)
            st = launch(o, &o->k.eulerian_far_field, items, o->item_wg, NULL, 0, err);
    } else if (o->k.eulerian_update.kernel) {
        st = launch(o, &o->k.eulerian_momentum_rate, items, o->item_wg, dt_arg, ndt, err);
        if (!st)
            st = launch(o, &o->k.eulerian_mass_energy_rate, items, o->item_wg, dt_arg, ndt, err);
        if (!st) st = launch(o, &o->k.eulerian_update, items, o->item_wg, dt_arg, ndt, err);
        /* the far field is state, not a step: no dt (a halted device clock
         * leaves the state it would blend unchanged, so it is idempotent) */
        if (!st && o->k.eulerian_far_field.kernel)
            st = launch(o, &o->k.eulerian_far_field, items, o->item_wg, NULL, 0, err);
    } else if (o->k.tl_deformation.kernel) {
        st = launch(o, &o->k.tl_deformation, items, o->item_wg, dt_arg, ndt, err);
        if (!st) st = launch(o, &o->k.tl_acceleration, items, o->item_wg, dt_arg, ndt, err);
        if (!st) st = launch(o, &o->k.tl_update, items, o->item_wg, dt_arg, ndt, err);
    } else {
        if (o->k.contact.kernel) st = launch(o, &o->k.contact, items, o->item_wg, dt_arg, ndt, err);
        if (!st) st = launch(o, &o->k.pressure, items, o->item_wg, dt_arg, ndt, err);
        if (!st) st = launch(o, &o->k.velocity_terms, items, o->item_wg, dt_arg, ndt, err);
        if (!st && o->k.shear_force.kernel)
            st = launch(o, &o->k.shear_force, items, o->item_wg, dt_arg, ndt, err);
    }
    if (st) return st;
    /* CPU devices with the device clock: the reduction's second stage and
     * the clock's advance come in the same launch (reduction.cl) */
    if (!dt_arg && o->k.substep_reduce_finish.kernel) {
        const sph_cl_arg args[] = {{"result", sizeof(cl_mem), &o->substep_sums}};
        return launch(o, &o->k.substep_reduce_finish, o->reduce_items, o->wg, args, 1, err);
    }
    st = launch(o, &o->k.substep_reduce, o->reduce_items, o->wg, dt_arg, ndt, err);
    if (!st && !dt_arg) {
        cl_int ncomp = o->substep_ncomp;
        const sph_cl_arg args[] = {{"ncomp", sizeof(cl_int), &ncomp},
                                   {"result", sizeof(cl_mem), &o->substep_sums}};
        st = launch(o, &o->k.substep_finalize, o->wg, o->wg, args, 2, err);
    }
    return st;
}

static sph_status ocl_advance(sph_backend *be, double *clock, long limit, sph_error *err);

/* One substep of size dt, then max |v|^2 read back: with the host step
 * clock (devices without double precision, or --step-clock host) dt is the
 * kernels' argument; with the device clock it goes in a clock set up for a
 * lone substep (the tests' direct substeps). */
static sph_status ocl_substep(sph_backend *be, double dt, double *max_speed2, sph_error *err) {
    ocl_impl *o = be->impl;
    if (o->device_clock) {
        double clock[SPH_CLOCK_LEN] = {0};
        clock[CLOCK_DT] = dt;
        clock[CLOCK_T_ADV_END] = INFINITY;
        clock[CLOCK_NEXT_OUTPUT] = INFINITY;
        clock[CLOCK_ONE_SUBSTEP] = 1.0;
        clock[CLOCK_SPEED_LIMIT] = INFINITY;
        const sph_status st = ocl_advance(be, clock, 1, err);
        *max_speed2 = clock[CLOCK_MAX_SPEED2];
        return st;
    }
    real_scalar dt_s;
    const sph_cl_arg dt_arg = real_arg(o, "dt", &dt_s, dt);
    sph_status st = enqueue_substep(o, &dt_arg, err);
    if (!st) st = finalize(o, 1, o->substep_ncomp, o->substep_sums, err);
    const double t0 = be->profiling ? sph_wall_seconds() : 0.0;
    if (!st) st = read_reals(o, o->substep_sums, 0, 1, max_speed2, err);
    if (be->profiling) sph_backend_profile_add(be, "max speed read", sph_wall_seconds() - t0);
    return st;
}

/* How many substeps the clock will likely take to the end of its advection
 * step, from the size of the next one (the sound speed dominates it, so it
 * changes little within a step); at least 1, at most `cap`. */
static long substeps_to_end(const double *clock, long cap) {
    if (clock[CLOCK_ONE_SUBSTEP] != 0.0) return 1;
    const double end = fmin(clock[CLOCK_T_ADV_END], clock[CLOCK_NEXT_OUTPUT]);
    const double k = ceil((end - clock[CLOCK_T]) / clock[CLOCK_DT]);
    if (!(k >= 1.0)) return 1;
    return k < (double)cap ? (long)k : cap;
}

/* The device step clock: enqueue the advection step's substeps, each ending
 * in substep_finalize, which plans the next one's size on the device (or
 * halts the clock, after which the rest are no-ops), and read the clock back
 * once per batch instead of max |v|^2 once per substep.  The batch is the
 * predicted number of substeps to the end of the advection step, at most 64
 * (a halt midway, a blow-up or the end of the run, wastes at most the rest
 * of a batch). */
static sph_status ocl_advance(sph_backend *be, double *clock, long limit, sph_error *err) {
    ocl_impl *o = be->impl;
    if (!o->device_clock) return sph_backend_advance_by_substeps(be, clock, limit, err);
    const size_t bytes = SPH_CLOCK_LEN * sizeof(double);
    sph_status st = cl_check(
        clEnqueueWriteBuffer(o->queue, o->step_clock, CL_FALSE, 0, bytes, clock, 0, NULL, NULL),
        "writing the step clock", err);
    while (!st && clock[CLOCK_HALTED] == CLOCK_RUNNING && clock[CLOCK_COUNT] < (double)limit) {
        const long left = limit - (long)clock[CLOCK_COUNT];
        const long cap = o->loop_wg ? be->substeps_per_launch : 64;
        const long batch = substeps_to_end(clock, left < cap ? left : cap);
        if (o->loop_wg) {
            /* one launch of the substep loop, which stops where the clock
             * halts (device/substep_loop.cl) */
            const cl_int count = (cl_int)batch, stages = be->features.fluid_rk_stages;
            const sph_cl_arg args[] = {{"substeps", sizeof count, &count},
                                       {"stages", sizeof stages, &stages}};
            st = launch(o, &o->k.substep_loop, o->loop_wg, o->loop_wg, args, 2, err);
        } else {
            for (long b = 0; b < batch && !st; ++b) st = enqueue_substep(o, NULL, err);
        }
        const double t0 = be->profiling ? sph_wall_seconds() : 0.0;
        if (!st)
            st = cl_check(clEnqueueReadBuffer(o->queue, o->step_clock, CL_TRUE, 0, bytes, clock, 0,
                                              NULL, NULL),
                          "reading the step clock", err);
        /* the host's only wait inside the acoustic loop: its count in the
         * profile is the number of host synchronisations */
        if (be->profiling) sph_backend_profile_add(be, "step clock read", sph_wall_seconds() - t0);
    }
    if (st) clFinish(o->queue); /* the write may still read `clock` */
    return st;
}

static sph_status ocl_diagnostics(sph_backend *be, sph_diagnostics *out, sph_error *err) {
    ocl_impl *o = be->impl;
    const int d = be->features.dim;
    /* fluids add mass and total energy, and with walls the wall forces
     * (reduction.cl, DIAG_NCOMP) */
    const bool fluid = FORM_IS_EULERIAN((int)be->features.formulation);
    const int ncomp = 2 + d + sph_spin_components(d) + (fluid ? 2 : 0) +
                      (fluid && be->features.fluid_walls ? 2 * d : 0);
    double red[16] = {0};
    sph_status st = launch(o, &o->k.diagnostics_reduce, o->reduce_items, o->wg, NULL, 0, err);
    if (!st) st = finalize(o, 0, ncomp, o->result, err);
    if (!st) st = read_reals(o, o->result, 0, (size_t)ncomp, red, err);
    if (st) return st;
    sph_diagnostics_unpack(red, d, out);
    return SPH_OK;
}

static sph_status ocl_monitor(sph_backend *be, double *out, sph_error *err) {
    ocl_impl *o = be->impl;
    sph_status st = launch(o, &o->k.monitor_reduce, o->reduce_items, o->wg, NULL, 0, err);
    const int ncomp = SPH_MONITOR_NCOMP(be->features.dim);
    if (!st) st = finalize(o, ncomp, ncomp, o->result, err);
    if (!st) st = read_reals(o, o->result, 0, (size_t)ncomp, out, err);
    return st;
}

static sph_status ocl_download(sph_backend *be, sph_field f, void *host, sph_error *err) {
    ocl_impl *o = be->impl;
    if (sph_backend_require_field(be, f, err)) return SPH_ERR_RUNTIME;
    /* a field the steps do not keep is formed from the state first */
    if (f == FIELD_VORTICITY && o->k.eulerian_vorticity.kernel) {
        sph_status st =
            launch(o, &o->k.eulerian_vorticity, (size_t)be->n, o->item_wg, NULL, 0, err);
        if (st) return st;
    }
    const sph_field_info *info = &be->fields[f];
    if (sph_field_is_real(info->type))
        return read_values(o, o->field[f], sph_field_element_size(info->type, &be->features), 0,
                           (size_t)be->n * (size_t)info->components, host, err);
    return cl_check(clEnqueueReadBuffer(o->queue, o->field[f], CL_TRUE, 0, field_bytes(be, f), host,
                                        0, NULL, NULL),
                    "reading a field", err);
}

static sph_status ocl_upload_field(sph_backend *be, sph_field f, const void *host, sph_error *err) {
    ocl_impl *o = be->impl;
    if (sph_backend_require_field(be, f, err)) return SPH_ERR_RUNTIME;
    const sph_field_info *info = &be->fields[f];
    if (sph_field_is_real(info->type)) return write_field(be, o, f, host, err);
    return cl_check(clEnqueueWriteBuffer(o->queue, o->field[f], CL_TRUE, 0, field_bytes(be, f),
                                         host, 0, NULL, NULL),
                    "writing a field", err);
}

static sph_status ocl_download_carried(sph_backend *be, double *out, sph_error *err) {
    ocl_impl *o = be->impl;
    return read_reals(o, o->substep_sums, 0, SPH_CARRIED_LEN, out, err);
}

static sph_status ocl_upload_carried(sph_backend *be, const double *in, sph_error *err) {
    ocl_impl *o = be->impl;
    return write_reals(o, o->substep_sums, in, SPH_CARRIED_LEN, err);
}

static sph_status ocl_download_neighbours(sph_backend *be, sph_neighbour_lists *out,
                                          sph_error *err) {
    ocl_impl *o = be->impl;
    const size_t n = (size_t)be->n, cap = (size_t)o->cap;
    out->n = be->n;
    out->cap = o->cap;
    out->count = malloc(n * sizeof(int32_t));
    out->j = malloc(n * cap * sizeof(int32_t));
    int32_t *raw = malloc(n * cap * sizeof(int32_t));
    if (!out->count || !out->j || !raw) {
        free(raw);
        sph_neighbour_lists_free(out);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    cl_int rc = clEnqueueReadBuffer(o->queue, o->nbr_count, CL_TRUE, 0, n * sizeof(int32_t),
                                    out->count, 0, NULL, NULL);
    if (rc == CL_SUCCESS)
        rc = clEnqueueReadBuffer(o->queue, o->nbr_j, CL_TRUE, 0, n * cap * sizeof(int32_t), raw, 0,
                                 NULL, NULL);
    for (size_t i = 0; i < n; ++i)
        for (size_t k = 0; k < cap; ++k)
            out->j[i * cap + k] = o->row_major ? raw[i * cap + k] : raw[k * n + i];
    free(raw);
    return cl_check(rc, "reading the neighbour lists", err);
}

static void ocl_destroy(sph_backend *be) {
    ocl_impl *o = be->impl;
    if (o) {
        if (o->queue) clFinish(o->queue);
        sph_cl_kernel *all = (sph_cl_kernel *)&o->k;
        for (size_t k = 0; k < sizeof o->k / sizeof(sph_cl_kernel); ++k)
            sph_cl_kernel_release(&all[k]);
        for (int f = 0; f < FIELD_COUNT; ++f) {
            release(&o->field[f]);
            release(&o->spare[f]);
        }
        cl_mem *bufs[] = {&o->nbr_count,  &o->nbr_j,        &o->pair_e,     &o->pair_dwv,
                          &o->pair_inv_r, &o->pair_w,       &o->pair_pos,   &o->keys,
                          &o->cell_start, &o->cell_end,     &o->prm,        &o->grid_geom,
                          &o->partials,   &o->substep_sums, &o->overflow,   &o->result,
                          &o->step_clock, &o->keys_sorted,  &o->blocks_done};
        for (size_t k = 0; k < sizeof bufs / sizeof bufs[0]; ++k) release(bufs[k]);
        if (o->program) clReleaseProgram(o->program);
        if (o->loop_program) clReleaseProgram(o->loop_program);
        if (o->queue) clReleaseCommandQueue(o->queue);
        if (o->ctx) clReleaseContext(o->ctx);
        free(o);
    }
    free(be);
}

static const sph_backend_ops ocl_ops = {
    .upload = ocl_upload,
    .rebuild = ocl_rebuild,
    .substep = ocl_substep,
    .advance = ocl_advance,
    .diagnostics = ocl_diagnostics,
    .monitor = ocl_monitor,
    .download = ocl_download,
    .download_neighbours = ocl_download_neighbours,
    .upload_field = ocl_upload_field,
    .download_carried = ocl_download_carried,
    .upload_carried = ocl_upload_carried,
    .destroy = ocl_destroy,
};

/* Record the program's kernels and their arguments (be->program_kernels). */
static void describe_kernels(sph_backend *be, const ocl_impl *o) {
    const sph_cl_kernel *all = (const sph_cl_kernel *)&o->k;
    size_t len = 0;
    const size_t cap = sizeof be->program_kernels;
    be->program_kernels[0] = '\0';
    for (size_t k = 0; k < sizeof o->k / sizeof(sph_cl_kernel) && len < cap; ++k) {
        if (!all[k].kernel) continue;
        len += (size_t)snprintf(be->program_kernels + len, cap - len, "%s%s(", len ? "\n" : "",
                                all[k].name);
        for (cl_uint a = 0; a < all[k].nargs && len < cap; ++a)
            len += (size_t)snprintf(be->program_kernels + len, cap - len, "%s%s", a ? ", " : "",
                                    all[k].arg_name[a]);
        if (len < cap) len += (size_t)snprintf(be->program_kernels + len, cap - len, ")");
    }
}

static sph_status create_kernels(ocl_impl *o, sph_error *err) {
    const sph_features *f = &o->be->features;
    const bool tlsph = f->formulation == SPH_FORMULATION_TLSPH;
    const bool fluid = FORM_IS_EULERIAN((int)f->formulation), solid = !fluid;
    /* the kernels of this run's program: those of features the run lacks
     * are not in it (the -D options of sph_backend_opencl_create) */
    const struct {
        sph_cl_kernel *k;
        const char *name;
        bool needed;
    } table[] = {
        {&o->k.rebuild_reduce, "rebuild_reduce", true},
        {&o->k.cell_keys, "cell_keys", true},
        /* CPU devices sort by counting, GPUs by a bitonic network followed
         * by cell_ranges */
        {&o->k.counting_sort, "counting_sort", o->counting_sort},
        {&o->k.sort_local, "bitonic_local_sort", !o->counting_sort},
        {&o->k.merge_local, "bitonic_local_merge", !o->counting_sort},
        {&o->k.sort_global, "bitonic_global", !o->counting_sort},
        {&o->k.cell_ranges, "cell_ranges", !o->counting_sort},
        {&o->k.permute_real, "permute_real", true},
        /* the double history fields exist only in mixed precision */
        {&o->k.permute_hreal, "permute_hreal", f->mixed_precision},
        {&o->k.permute_int, "permute_int", true},
        {&o->k.permute_u8, "permute_u8", true},
        {&o->k.shifted_positions, "shifted_positions", o->pair_recompute},
        {&o->k.build, "build_neighbours", true},
        /* the TLSPH passes, or the contact pass (several bodies), pressure,
         * velocity terms and the stress-divergence formulations' third pass */
        {&o->k.tl_deformation, "tl_deformation", tlsph},
        {&o->k.tl_acceleration, "tl_acceleration", tlsph},
        {&o->k.tl_update, "tl_update", tlsph},
        {&o->k.contact, "acoustic_contact", !tlsph && f->contact},
        {&o->k.pressure, "acoustic_pressure", solid},
        {&o->k.velocity_terms, "acoustic_velocity_terms", solid},
        /* the fluid formulations' passes (eulerian_step.cl) */
        {&o->k.eulerian_prepare, "eulerian_prepare", fluid},
        {&o->k.eulerian_correct_pairs, "eulerian_correct_pairs", fluid},
        {&o->k.eulerian_momentum_rate, "eulerian_momentum_rate", fluid && !f->fluid_rk},
        {&o->k.eulerian_mass_energy_rate, "eulerian_mass_energy_rate", fluid && !f->fluid_rk},
        {&o->k.eulerian_update, "eulerian_update", fluid && !f->fluid_rk},
        {&o->k.eulerian_rates, "eulerian_rates", fluid && f->fluid_rk},
        {&o->k.eulerian_rk_update, "eulerian_rk_update", fluid && f->fluid_rk},
        {&o->k.eulerian_far_field, "eulerian_far_field", fluid && f->far_field},
        {&o->k.eulerian_vorticity, "eulerian_vorticity", o->be->fields[FIELD_VORTICITY].present},
        {&o->k.shear_force, "acoustic_shear_force",
         !tlsph && FORM_HAS_STRESS_DIV((int)f->formulation)},
        /* the substep reduction: with the device clock, its second stage
         * advances the clock (in the same launch on CPU devices) */
        {&o->k.substep_reduce, "substep_reduce", true},
        {&o->k.substep_finalize, "substep_finalize", o->device_clock && !o->reduce_blocks},
        {&o->k.substep_reduce_finish, "substep_reduce_finish", o->device_clock && o->reduce_blocks},
        {&o->k.diagnostics_reduce, "diagnostics_reduce", true},
        {&o->k.finalize, "reduce_finalize", true},
        {&o->k.monitor_reduce, "monitor_reduce", true},
    };
    for (size_t t = 0; t < sizeof table / sizeof table[0]; ++t) {
        if (!table[t].needed) continue;
        sph_status st =
            sph_cl_kernel_create(o->program, table[t].name, o->res, RES_COUNT, table[t].k, err);
        if (st) return st;
    }
    return SPH_OK;
}

static size_t pow2_floor(size_t x) {
    size_t p = 1;
    while (p * 2 <= x) p *= 2;
    return p;
}

/* The substep loop (device/substep_loop.cl) runs all of a substep's passes
 * in one work-group, which pays where launches cost more than the passes'
 * work.  Auto: on GPUs up to LOOP_GPU_PARTICLES_PER_ITEM particles per
 * work-item of a group of up to 1024 (an estimate from the H200's 63 us per
 * substep of the 1 612-particle plate, which moves 3 MB: no GPU has run the
 * loop yet); on CPU devices, where pocl runs a work-group on one thread, up
 * to LOOP_CPU_MAX_PARTICLES, measured on two idle cores (the 2D plate: 352
 * particles 1.2x faster with the loop, 668 even, 1 612 1.6x slower;
 * docs/benchmarks.md, "The substep loop"). */
#define LOOP_GPU_PARTICLES_PER_ITEM 4
#define LOOP_GPU_MAX_WG             1024
#define LOOP_CPU_MAX_PARTICLES      512
#define LOOP_DEFAULT_SUBSTEPS       64

/* Why this scene cannot run the substep loop, or NULL.  Its work-group is
 * never larger than the particle count, so at least SPH_WG particles: on
 * pocl 3.1 a group with work-items that had no particle gave wrong results
 * with the averaged rotation (heap corruption; the 2D plate, 233 particles
 * in a group of 256), the same program bit-identical to the per-pass
 * launches under -cl-opt-disable or with every work-item given a particle;
 * the cause is not established (docs/backends.md, "The substep loop"). */
static const char *substep_loop_unavailable(const ocl_impl *o) {
    if (!o->device_clock)
        return "it needs the device step clock (double precision on the device, not "
               "--step-clock host)";
    if ((size_t)o->n < o->wg) return "it needs at least as many particles as a reduction group";
    return NULL;
}

/* The loop kernel of the formulation (device/substep_loop.cl). */
static const char *substep_loop_kernel(const sph_features *f) {
    return f->formulation == SPH_FORMULATION_TLSPH ? "tl_substep_loop"
           : FORM_IS_EULERIAN((int)f->formulation) ? "eulerian_substep_loop"
                                                   : "acoustic_substep_loop";
}

static sph_status build_loop_program(sph_backend *be, ocl_impl *o, sph_error *err) {
    char options[sizeof be->build_options + 64];
    snprintf(options, sizeof options, "%s -DSPH_SUBSTEP_LOOP=1 -DSPH_LOOP_WG=%zu",
             be->build_options, o->loop_wg);
    const char *files[] = {"substep_loop.cl"};
    sph_status st =
        sph_opencl_build_program(o->ctx, o->dev.device, files, 1, options, &o->loop_program, err);
    if (!st)
        st = sph_cl_kernel_create(o->loop_program, substep_loop_kernel(&be->features), o->res,
                                  RES_COUNT, &o->k.substep_loop, err);
    return st;
}

static void drop_loop_program(ocl_impl *o) {
    sph_cl_kernel_release(&o->k.substep_loop);
    if (o->loop_program) clReleaseProgram(o->loop_program);
    o->loop_program = NULL;
}

/* Choose the substeps per launch (req->substeps_per_launch, or by the
 * particle count and the device) and build the loop's program when more
 * than one. */
static sph_status create_substep_loop(sph_backend *be, ocl_impl *o, const sph_backend_request *req,
                                      sph_error *err) {
    be->substeps_per_launch = 1;
    const char *unavailable = substep_loop_unavailable(o);
    const bool gpu = !o->row_major;
    /* a power of two from SPH_WG up, at most the particle count (see
     * substep_loop_unavailable) */
    const size_t most = gpu ? LOOP_GPU_MAX_WG : 4 * o->wg;
    size_t wg = o->wg;
    while (wg * 2 <= most && wg * 2 <= o->dev.max_work_group && wg * 2 <= (size_t)o->n) wg *= 2;
    const long auto_max =
        gpu ? (long)(LOOP_GPU_PARTICLES_PER_ITEM * wg) : (long)LOOP_CPU_MAX_PARTICLES;
    long per_launch = req->substeps_per_launch;
    if (per_launch > 1 && unavailable)
        return sph_fail(err, SPH_ERR_INPUT,
                        "--substeps-per-launch %ld: the substep loop is "
                        "not available for this run: %s",
                        per_launch, unavailable);
    if (per_launch == 0) per_launch = !unavailable && o->n <= auto_max ? LOOP_DEFAULT_SUBSTEPS : 1;
    if (per_launch <= 1) return SPH_OK;
    o->loop_wg = wg;
    sph_status st = build_loop_program(be, o, err);
    /* a kernel this large may not run in a group of that size (its
     * registers): the largest power of two it allows, if at least SPH_WG */
    size_t allowed = 0;
    if (!st)
        st = cl_check(clGetKernelWorkGroupInfo(o->k.substep_loop.kernel, o->dev.device,
                                               CL_KERNEL_WORK_GROUP_SIZE, sizeof allowed, &allowed,
                                               NULL),
                      "querying the substep loop's work-group size", err);
    if (!st && allowed < o->loop_wg && pow2_floor(allowed) >= o->wg) {
        drop_loop_program(o);
        o->loop_wg = pow2_floor(allowed);
        st = build_loop_program(be, o, err);
    } else if (!st && allowed < o->loop_wg) {
        /* chosen by the run: the launches per pass; asked for: an error */
        drop_loop_program(o);
        o->loop_wg = 0;
        if (!req->substeps_per_launch) return SPH_OK;
        st = sph_fail(err, SPH_ERR_RUNTIME,
                      "--substeps-per-launch %ld: the substep loop needs work-groups of %zu on "
                      "OpenCL device %s, which allows %zu for it; use --substeps-per-launch 1",
                      per_launch, o->wg, o->dev.name, allowed);
    }
    if (st) return st;
    be->substeps_per_launch = per_launch;
    const size_t used = strlen(be->build_options);
    snprintf(be->build_options + used, sizeof be->build_options - used,
             "; substep loop: -DSPH_SUBSTEP_LOOP=1 -DSPH_LOOP_WG=%zu", o->loop_wg);
    if (!req->quiet)
        fprintf(stderr,
                "sphsolid: substep loop: up to %ld acoustic substeps per launch, one work-group "
                "of %zu (%s)\n",
                per_launch, o->loop_wg,
                req->substeps_per_launch ? "--substeps-per-launch" : "chosen by particle count");
    return SPH_OK;
}

sph_status sph_backend_opencl_create(const sph_backend_request *req, int device_index,
                                     const sph_features *f, const sph_params_f64 *prm, int n,
                                     sph_backend **out, sph_error *err) {
    const bool quiet = req->quiet;
    *out = NULL;
    if (device_index < 0) {
        /* --backend opencl without --device: the first GPU, else device 0 */
        char reason[256];
        device_index = sph_opencl_find_gpu(reason, sizeof reason);
        if (device_index < 0) device_index = 0;
    }
    sph_backend *be = calloc(1, sizeof *be);
    ocl_impl *o = calloc(1, sizeof *o);
    if (!be || !o) {
        free(be);
        free(o);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    be->impl = o;
    o->be = be;
    be->ops = &ocl_ops;
    be->kind_name = "opencl";
    be->profiling = req->profile;
    be->features = *f;
    be->n = n;
    sph_fields_layout(f, be->fields);
    sph_status st = sph_opencl_device_info_get(device_index, &o->dev, err);
    if (st) goto fail;
    if ((f->double_precision || f->mixed_precision) && !o->dev.has_fp64) {
        st = sph_fail(err, SPH_ERR_INPUT,
                      "OpenCL device %d (%s) has no double precision (cl_khr_fp64), which %s "
                      "precision needs; run with --precision single",
                      device_index, o->dev.name, sph_precision_name(f));
        goto fail;
    }
    sph_format(be->device_name, sizeof be->device_name, "%s (%s, %s)", o->dev.name,
               o->dev.platform_name, o->dev.version);
    o->real_size = f->double_precision ? sizeof(double) : sizeof(float);
    o->row_major = (o->dev.type & CL_DEVICE_TYPE_CPU) != 0;
    /* The step clock on the device needs double precision there
     * (device/sph_step_clock.h). */
    if (req->step_clock == SPH_STEP_CLOCK_DEVICE && !o->dev.has_fp64) {
        st = sph_fail(err, SPH_ERR_INPUT,
                      "--step-clock device: OpenCL device %d (%s) has no double precision "
                      "(cl_khr_fp64), which the device step clock needs; use --step-clock host",
                      device_index, o->dev.name);
        goto fail;
    }
    o->device_clock = req->step_clock != SPH_STEP_CLOCK_HOST && o->dev.has_fp64;
    /* The frozen pair geometry recomputed in every pass instead of streamed
     * from per-slot arrays (device/sph_pair_geometry.h), measured on the 3D
     * plate at H/dp = 5 (204 020 particles): on an H100 the two acoustic
     * passes take 0.474 instead of 0.586 ms per substep in double (0.265
     * against 0.420 in mixed), the rebuild 0.50 instead of 4.06 ms, and the
     * run 203 instead of 1070 MiB; on pocl (2-core CPU, H/dp = 3) the
     * recomputing passes are 18 % slower and the stored arrays win by 11 %
     * per advection step (docs/benchmarks.md).  TLSPH keeps its stored
     * reference geometry. */
    /* fluids (fixed particles, no geometry shift): the periodic axes of
     * the cell grid, and the stored pair geometry, which the correction of
     * eq. 18 overwrites (eulerian_step.cl) */
    o->periodic_mask = prm->periodic_mask;
    for (int a = 0; a < 3; ++a) o->period[a] = prm->period[a];
    o->pair_recompute = f->formulation != SPH_FORMULATION_TLSPH &&
                        !FORM_IS_EULERIAN((int)f->formulation) &&
                        (req->pair_geometry == SPH_PAIR_GEOMETRY_RECOMPUTED ||
                         (req->pair_geometry == SPH_PAIR_GEOMETRY_AUTO && !o->row_major));
    /* Work-group sizes per device kind, measured.  GPUs: 256 for the
     * reductions and the per-particle kernels.  CPU devices (pocl 3.1, 2
     * cores): groups of 16 for the reductions (the 2D plate to 0.1 s: 3.6-3.9 s
     * against 4.7-5.3 s with 256) and of 4 for the per-particle kernels,
     * whose neighbour loops of uneven length cost more in pocl's work-group
     * loops the larger the group (the 3D plate's acoustic_velocity_terms took
     * 54 ms per call with groups of 1, 78 with 4, 121 with 256 while pocl left
     * the component loops rolled).  With them unrolled (UNROLL, sph_prelude.h)
     * that call takes 12.6 ms with 1 or 4, the 3D plate runs the same either
     * way, and the 2D plate at H/dp = 10 to t = 1 s takes 11.0-11.7 s with 4
     * against 11.9-12.6 s with 1 (three runs each, back to back): fewer
     * groups, less of pocl's cost per group (docs/benchmarks.md, "pocl"). */
    const size_t reduce_wg = o->row_major ? 16 : 256;
    o->wg = pow2_floor(o->dev.max_work_group < reduce_wg ? o->dev.max_work_group : reduce_wg);
    o->item_wg = o->row_major ? 4 : o->wg;
    o->sort_wg = pow2_floor(o->dev.max_work_group < 1024 ? o->dev.max_work_group : 1024);
    o->n = n;
    o->cutoff = o->real_size == sizeof(float) ? (double)(float)prm->cutoff : prm->cutoff;
    /* CPU devices sort by counting (SPH_COUNTING_SORT), GPUs by a bitonic
     * network over keys padded to a power of two */
    o->counting_sort = o->row_major;
    o->npad = o->counting_sort ? (cl_int)n : (cl_int)o->sort_wg;
    while (o->npad < n) o->npad *= 2;
    o->ngroups = (cl_int)((n + (int)o->wg - 1) / (int)o->wg);
    /* The reductions' first stage on CPU devices: a work-item per block of
     * SPH_WG particles, no barriers (device/reduction.cl); on GPUs a
     * work-item per particle and a tree over each group. */
    o->reduce_blocks = req->reduction == SPH_REDUCTION_AUTO
                           ? o->row_major
                           : req->reduction == SPH_REDUCTION_BLOCKS;
    o->reduce_items = o->reduce_blocks ? (size_t)o->ngroups : (size_t)o->ngroups * o->wg;
    o->substep_ncomp = sph_substep_ncomp(f);

    st = check_device_memory(be, o, device_index,
                             sph_initial_neighbour_capacity(f->dim, prm->cutoff / prm->dp), err);
    if (st) goto fail;

    cl_int rc;
    o->ctx = clCreateContext(NULL, 1, &o->dev.device, NULL, NULL, &rc);
    if ((st = cl_check(rc, "clCreateContext", err))) goto fail;
    o->queue = clCreateCommandQueue(o->ctx, o->dev.device,
                                    be->profiling ? CL_QUEUE_PROFILING_ENABLE : 0, &rc);
    if ((st = cl_check(rc, "clCreateCommandQueue", err))) goto fail;

    sph_features_build_options(f, (int)o->wg, (int)o->sort_wg, o->row_major, o->pair_recompute,
                               be->build_options, sizeof be->build_options);
    const size_t used = strlen(be->build_options);
    snprintf(be->build_options + used, sizeof be->build_options - used,
             " -DSPH_STEP_CLOCK=%d -DSPH_REDUCE_BLOCKS=%d -DSPH_COUNTING_SORT=%d",
             o->device_clock ? 1 : 0, o->reduce_blocks ? 1 : 0, o->counting_sort ? 1 : 0);
    if (!quiet) fprintf(stderr, "sphsolid: OpenCL build options: %s\n", be->build_options);
    /* a fluid program has no solid pass: reduction.cl brings eulerian_step.cl */
    const char *solid_files[] = {"neighbour_build.cl", "acoustic_step.cl", "tl_step.cl",
                                 "reduction.cl", "monitor.cl"};
    const char *fluid_files[] = {"neighbour_build.cl", "reduction.cl", "monitor.cl"};
    const bool fluid = FORM_IS_EULERIAN((int)f->formulation);
    st = sph_opencl_build_program(o->ctx, o->dev.device, fluid ? fluid_files : solid_files,
                                  fluid ? (int)(sizeof fluid_files / sizeof fluid_files[0])
                                        : (int)(sizeof solid_files / sizeof solid_files[0]),
                                  be->build_options, &o->program, err);
    if (st) goto fail;

    for (int k = 0; k < FIELD_COUNT && !st; ++k) {
        if (!be->fields[k].present) continue;
        const size_t bytes = field_bytes(be, (sph_field)k);
        st = make_buffer(be, o, be->fields[k].name, bytes, &o->field[k], err);
        if (!st) {
            char spare_name[64];
            snprintf(spare_name, sizeof spare_name, "%s (reorder copy)", be->fields[k].name);
            st = make_buffer(be, o, spare_name, bytes, &o->spare[k], err);
        }
    }
    if (!st) st = make_buffer(be, o, "nbr_count", (size_t)n * sizeof(cl_int), &o->nbr_count, err);
    if (!st) st = make_buffer(be, o, "keys", (size_t)o->npad * sizeof(cl_ulong), &o->keys, err);
    if (!st && o->counting_sort)
        st = make_buffer(be, o, "keys_sorted", (size_t)n * sizeof(cl_ulong), &o->keys_sorted, err);
    if (!st) st = make_buffer(be, o, "prm", params_size(o), &o->prm, err);
    if (!st) st = make_buffer(be, o, "grid_geom", 4 * o->real_size, &o->grid_geom, err);
    if (!st)
        st = make_buffer(be, o, "partials",
                         (size_t)o->ngroups * (size_t)sph_partial_ncomp(&be->features) *
                             o->real_size,
                         &o->partials, err);
    if (!st)
        st = make_buffer(be, o, "substep_sums", SUBSTEP_SUMS_LEN * o->real_size, &o->substep_sums,
                         err);
    if (!st) st = make_buffer(be, o, "overflow", sizeof(cl_int), &o->overflow, err);
    if (!st && o->device_clock)
        st = make_buffer(be, o, "step_clock", SPH_CLOCK_LEN * sizeof(double), &o->step_clock, err);
    if (!st && o->device_clock && o->reduce_blocks)
        st = make_buffer(be, o, "blocks_done", sizeof(cl_int), &o->blocks_done, err);
    if (!st && o->pair_recompute)
        st = make_buffer(be, o, "pair_pos",
                         (size_t)n * (size_t)f->dim * sph_field_element_size(FIELD_TYPE_HREAL, f),
                         &o->pair_pos, err);
    if (!st) st = make_buffer(be, o, "result", RESULT_LEN * o->real_size, &o->result, err);
    if (!st)
        st = alloc_pairs(be, o, sph_initial_neighbour_capacity(f->dim, prm->cutoff / prm->dp), err);
    if (!st) st = write_params(o, prm, err);
    if (st) goto fail;
    fill_resources(be, o);
    st = create_kernels(o, err);
    if (!st) st = create_substep_loop(be, o, req, err);
    if (!st) describe_kernels(be, o);
    if (st) goto fail;
    *out = be;
    return SPH_OK;
fail:
    ocl_destroy(be);
    return st;
}
