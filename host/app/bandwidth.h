/* bandwidth.h — the device's attainable memory bandwidth (`sphsolid bandwidth`).
 *
 * A streaming copy dst[i] = src[i] over two buffers of a few hundred MiB:
 * on an OpenCL device a one-line kernel timed with profiling events, on the
 * native backend an OpenMP loop over the threads the solver uses, timed with
 * omp_get_wtime.  The best of several runs (after one warm-up run that also
 * faults the pages in) is reported as GB/s = 2 x buffer bytes / seconds
 * (read + write counted, the STREAM convention; a write-allocate cache moves
 * a third stream that is not counted).  tools/bench.py divides the bytes each
 * solver phase must move by its time and compares with this figure.
 */
#ifndef SPH_BANDWIDTH_H
#define SPH_BANDWIDTH_H

#include "sph_error.h"

#include <stdbool.h>
#include <stddef.h>

typedef struct {
    bool opencl;      /* false: the native backend (OpenMP) */
    int device_index; /* OpenCL device; -1: the first GPU, else device 0 */
    double megabytes; /* MiB per buffer (two buffers); <= 0: 256 */
    int repeats;      /* timed runs; <= 0: 10 */
} sph_bandwidth_request;

typedef struct {
    char backend[16];    /* "cpu" or "opencl" */
    char device[512];    /* device name (OpenCL: name, platform) */
    char version[128];   /* OpenCL version ("" native) */
    char driver[128];    /* driver version ("" native) */
    int device_index;    /* OpenCL device number, -1 native */
    int threads;         /* OpenMP threads (native), compute units (OpenCL) */
    size_t buffer_bytes; /* bytes per buffer actually used */
    int repeats;
    double best_seconds, median_seconds;
    double best_gbs, median_gbs; /* 1e9 bytes per second, read + write */
} sph_bandwidth_result;

sph_status sph_bandwidth_measure(const sph_bandwidth_request *req, sph_bandwidth_result *out,
                                 sph_error *err);

/* `sphsolid bandwidth [--backend cpu|opencl] [--device N] [--size-mb M]
 * [--repeat K] [--json]`: returns the exit status (0, 1 runtime, 2 input). */
int sph_bandwidth_main(int argc, char **argv);

#endif
