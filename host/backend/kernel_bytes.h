/* kernel_bytes.h — the bytes a profiled phase moves, from the kernels' own
 * buffer declarations (the comment "buffers of NAME: reads ...;
 * writes ...; updates ..." directly above each kernel in device/) and this run's
 * buffer sizes (docs/benchmarks.md, "Bandwidth").
 *
 * Each declared buffer counts once per call over its whole extent: a
 * particle field n x components x its element size in this precision
 * (host/model/fields.c), a non-field buffer by the shape the declaration
 * gives it ("int*n", "real*d*pairs", ...), read-only and write-only buffers
 * once, read-and-written ("updates") twice; neighbour gathers are assumed to
 * hit cache.  A buffer this run does not have (a feature that drops the
 * argument, a field the scene lacks) counts zero. */
#ifndef SPH_KERNEL_BYTES_H
#define SPH_KERNEL_BYTES_H

#include "backend.h"
#include "sph_error.h"

#include <stddef.h>

/* The sizes the declarations' shapes refer to besides n and d. */
typedef struct {
    double pair_slots; /* "pairs": the neighbour slots the pair loops traverse,
                          the sum of the neighbour counts of the last rebuild */
    double grid_cells; /* "cells": the cells of the last rebuild's grid */
    double padded_n;   /* "npad": the sort's padded length (OpenCL), else n */
    long substeps;     /* the substeps profiled (the native fused substep phase) */
} sph_bytes_sizes;

/* Measure the sizes at the end of a run: downloads the neighbour counts. */
sph_status sph_bytes_sizes_measure(sph_backend *be, sph_bytes_sizes *out, sph_error *err);

/* Bytes one call of the profiled phase `rec` moves, or -1 where the phase is
 * no declared kernel (host reads) or its sizes are chosen per launch by the
 * host (the permutation's slots).  `kernels` receives the kernels counted,
 * "a + b + ..." (empty when -1). */
double sph_phase_bytes(const sph_backend *be, const sph_profile_record *rec,
                       const sph_bytes_sizes *sizes, char *kernels, size_t cap);

#endif
