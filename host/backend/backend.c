#include "backend.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "opencl_runtime.h"

sph_status sph_backend_create(const sph_backend_request *req, const sph_features *f,
                              const sph_params_f64 *prm, int n, sph_backend **out, sph_error *err) {
    *out = NULL;
    if (req->kind == SPH_BACKEND_CPU) {
        sph_status st = sph_backend_cpu_create(req, f, prm, n, out, err);
        if (!st) snprintf((*out)->choice_reason, sizeof(*out)->choice_reason, "requested");
        return st;
    }
    if (req->kind == SPH_BACKEND_OPENCL) {
        sph_status st = sph_backend_opencl_create(req, req->device_index, f, prm, n, out, err);
        if (!st) snprintf((*out)->choice_reason, sizeof(*out)->choice_reason, "requested");
        return st;
    }
    /* Automatic: an OpenCL GPU when one is present, else the native backend
     * (a CPU OpenCL device such as pocl is for testing the kernels). */
    char reason[256];
    const int gpu = sph_opencl_find_gpu(reason, sizeof reason);
    if (gpu >= 0) {
        sph_error gpu_err = {0};
        sph_status st = sph_backend_opencl_create(req, gpu, f, prm, n, out, &gpu_err);
        if (!st) {
            snprintf((*out)->choice_reason, sizeof(*out)->choice_reason, "%s", reason);
            return SPH_OK;
        }
        sph_format(reason, sizeof reason, "the OpenCL GPU failed to start (%s)", gpu_err.msg);
    }
    sph_status st = sph_backend_cpu_create(req, f, prm, n, out, err);
    if (!st) snprintf((*out)->choice_reason, sizeof(*out)->choice_reason, "%s", reason);
    return st;
}

void sph_backend_destroy(sph_backend *be) {
    if (be) be->ops->destroy(be);
}

sph_status sph_backend_advance_by_substeps(sph_backend *be, double *clock, long limit,
                                           sph_error *err) {
    while (clock[CLOCK_HALTED] == CLOCK_RUNNING && clock[CLOCK_COUNT] < (double)limit) {
        double max_speed2 = 0.0;
        const sph_status st = be->ops->substep(be, clock[CLOCK_DT], &max_speed2, err);
        if (st) return st;
        step_clock_finish(clock, max_speed2);
    }
    return SPH_OK;
}

sph_status sph_backend_advance(sph_backend *be, double *clock, long limit, sph_error *err) {
    const double before = clock[CLOCK_COUNT];
    const sph_status st = be->ops->advance ? be->ops->advance(be, clock, limit, err)
                                           : sph_backend_advance_by_substeps(be, clock, limit, err);
    be->substeps += (long)(clock[CLOCK_COUNT] - before);
    return st;
}

void sph_backend_profile_add(sph_backend *be, const char *name, double seconds) {
    for (int k = 0; k < be->nprofile; ++k)
        if (strcmp(be->profile[k].name, name) == 0) {
            be->profile[k].calls++;
            be->profile[k].seconds += seconds;
            return;
        }
    if (be->nprofile >= SPH_MAX_PROFILE_RECORDS) return;
    sph_profile_record *r = &be->profile[be->nprofile++];
    snprintf(r->name, sizeof r->name, "%s", name);
    r->calls = 1;
    r->seconds = seconds;
}

void sph_rebuild_info_unpack(const double *reduced, int dim, sph_rebuild_info *info) {
    for (int a = 0; a < 3; ++a) {
        info->lower[a] = a < dim ? -reduced[a] : 0.0;
        info->upper[a] = a < dim ? reduced[dim + a] : 0.0;
    }
    info->max_speed2 = reduced[2 * dim];
    info->max_accel_term = reduced[2 * dim + 1];
}

void sph_diagnostics_unpack(const double *reduced, int dim, sph_diagnostics *out) {
    memset(out, 0, sizeof *out);
    out->kinetic = reduced[0];
    out->strain = reduced[1];
    for (int a = 0; a < dim; ++a) out->momentum[a] = reduced[2 + a];
    if (dim == 2)
        out->angular[2] = reduced[2 + dim];
    else if (dim == 3)
        for (int a = 0; a < 3; ++a) out->angular[a] = reduced[2 + dim + a];
    /* fluids (device/eulerian_step.cl): mass and total energy follow; the
     * callers' arrays hold zeros there for solids */
    const int nspin = sph_spin_components(dim);
    out->mass = reduced[2 + dim + nspin];
    out->total_energy = reduced[3 + dim + nspin];
    /* the wall pairs' shares of the fluid's momentum rate: the walls get
     * the opposite */
    for (int a = 0; a < dim; ++a) {
        out->wall_pressure_force[a] = -reduced[4 + dim + nspin + a];
        out->wall_viscous_force[a] = -reduced[4 + 2 * dim + nspin + a];
    }
}

void sph_backend_record_buffer(sph_backend *be, const char *name, size_t bytes) {
    for (int k = 0; k < be->nbuffers; ++k)
        if (strcmp(be->buffers[k].name, name) == 0) {
            be->buffers[k].bytes = bytes;
            return;
        }
    if (be->nbuffers >= SPH_MAX_BUFFER_RECORDS) return;
    sph_buffer_record *r = &be->buffers[be->nbuffers++];
    snprintf(r->name, sizeof r->name, "%s", name);
    r->bytes = bytes;
}

size_t sph_backend_total_bytes(const sph_backend *be) {
    size_t total = 0;
    for (int k = 0; k < be->nbuffers; ++k) total += be->buffers[k].bytes;
    return total;
}

void sph_neighbour_lists_free(sph_neighbour_lists *l) {
    free(l->count);
    free(l->j);
    l->count = NULL;
    l->j = NULL;
}

int sph_initial_neighbour_capacity(int dim, double cutoff_over_dp) {
    const double pi = 3.14159265358979323846;
    const double lattice = dim == 1   ? 2.0 * cutoff_over_dp
                           : dim == 2 ? pi * cutoff_over_dp * cutoff_over_dp
                                      : 4.0 / 3.0 * pi * pow(cutoff_over_dp, 3.0);
    int cap = (int)ceil(1.5 * lattice);
    return (cap + 3) / 4 * 4;
}

int sph_grown_neighbour_capacity(int needed) {
    return needed + needed / 4 + 2;
}

sph_status sph_backend_rebuild(sph_backend *be, const sph_rebuild_steps *steps, double cutoff,
                               int periodic_mask, const double period[3], sph_rebuild_info *info,
                               sph_error *err) {
    const int d = be->features.dim;
    double red[2 * 3 + 2];
    sph_status st = steps->reduce(be, red, err);
    if (st) return st;
    sph_rebuild_info_unpack(red, d, info);
    sph_grid grid;
    if ((st = sph_grid_from_bounds(d, info->lower, info->upper, cutoff, be->n, &grid, err)))
        return st;
    sph_grid_make_periodic(&grid, periodic_mask, period);
    be->grid_cells = grid.ncells;
    if ((st = steps->sort(be, &grid, err))) return st;
    for (;;) {
        int needed = 0;
        if ((st = steps->build(be, &grid, &needed, err))) return st;
        if (needed == 0) break;
        if ((st = steps->grow(be, sph_grown_neighbour_capacity(needed), err))) return st;
    }
    if (steps->finish && (st = steps->finish(be, err))) return st;
    info->max_neighbours = steps->capacity(be);
    return SPH_OK;
}

sph_status sph_backend_require_field(const sph_backend *be, sph_field f, sph_error *err) {
    if (be->fields[f].present) return SPH_OK;
    return sph_fail(err, SPH_ERR_RUNTIME, "field '%s' is not present in this run",
                    be->fields[f].name);
}
