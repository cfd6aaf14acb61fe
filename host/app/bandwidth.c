#include "bandwidth.h"

#include "opencl_runtime.h"

#include <errno.h>
#include <json-c/json.h>
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_MIB     256.0
#define DEFAULT_REPEATS 10
#define MAX_REPEATS     1000
/* Buffers are a whole number of these (16-byte elements in groups of 1024). */
#define GRANULE ((size_t)16 * 1024)

static const char *copy_source =
    "__kernel void copy(__global const uint4 *restrict src, __global uint4 *restrict dst) {\n"
    "    const size_t i = get_global_id(0);\n"
    "    dst[i] = src[i];\n"
    "}\n";

static int compare_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Best and median of the timed runs, and the rates they give. */
static void summarise(double *seconds, int repeats, size_t bytes, sph_bandwidth_result *out) {
    qsort(seconds, (size_t)repeats, sizeof(double), compare_double);
    out->repeats = repeats;
    out->buffer_bytes = bytes;
    out->best_seconds = seconds[0];
    out->median_seconds = repeats % 2 ? seconds[repeats / 2]
                                      : 0.5 * (seconds[repeats / 2 - 1] + seconds[repeats / 2]);
    out->best_gbs = 2.0 * (double)bytes / out->best_seconds / 1e9;
    out->median_gbs = 2.0 * (double)bytes / out->median_seconds / 1e9;
}

static size_t buffer_bytes(double megabytes, size_t limit) {
    size_t bytes = (size_t)(megabytes * 1048576.0);
    if (bytes > limit) bytes = limit;
    return bytes / GRANULE * GRANULE;
}

/* ---- native: an OpenMP streaming copy ------------------------------------ */

static sph_status measure_native(const sph_bandwidth_request *req, sph_bandwidth_result *out,
                                 double *seconds, sph_error *err) {
    const size_t bytes = buffer_bytes(req->megabytes, (size_t)1 << 40);
    if (bytes == 0) return sph_fail(err, SPH_ERR_INPUT, "--size-mb %g: too small", req->megabytes);
    const size_t count = bytes / sizeof(double);
    double *src = aligned_alloc(64, bytes), *dst = aligned_alloc(64, bytes);
    if (!src || !dst) {
        free(src);
        free(dst);
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "out of host memory: the copy needs two buffers of %.1f MiB",
                        (double)bytes / 1048576.0);
    }
    /* first touch by the thread that later copies the same range */
    const long long n = (long long)count;
#pragma omp parallel for schedule(static)
    for (long long i = 0; i < n; ++i) {
        src[i] = (double)i;
        dst[i] = 0.0;
    }
    for (int r = -1; r < req->repeats; ++r) { /* r = -1: warm-up, not timed */
        const double t0 = omp_get_wtime();
#pragma omp parallel for schedule(static)
        for (long long i = 0; i < n; ++i) dst[i] = src[i];
        const double t = omp_get_wtime() - t0;
        if (r >= 0) seconds[r] = t;
    }
    const bool copied = dst[0] == 0.0 && dst[count / 2] == (double)(count / 2) &&
                        dst[count - 1] == (double)(count - 1);
    free(src);
    free(dst);
    if (!copied) return sph_fail(err, SPH_ERR_RUNTIME, "the native copy did not copy the buffer");
    snprintf(out->backend, sizeof out->backend, "cpu");
    snprintf(out->device, sizeof out->device, "native CPU backend, %d OpenMP thread%s",
             omp_get_max_threads(), omp_get_max_threads() == 1 ? "" : "s");
    out->threads = omp_get_max_threads();
    out->device_index = -1;
    summarise(seconds, req->repeats, bytes, out);
    return SPH_OK;
}

/* ---- OpenCL: a copy kernel timed with profiling events ------------------- */

static sph_status cl_fail(sph_error *err, const char *what, cl_int rc) {
    return sph_fail(err, SPH_ERR_RUNTIME, "%s failed: %s (%d)", what, sph_cl_error_name(rc), rc);
}

static sph_status measure_opencl(const sph_bandwidth_request *req, sph_bandwidth_result *out,
                                 double *seconds, sph_error *err) {
    int index = req->device_index;
    if (index < 0) {
        char reason[256];
        index = sph_opencl_find_gpu(reason, sizeof reason);
        if (index < 0) index = 0;
    }
    sph_opencl_device_info dev;
    sph_status st = sph_opencl_device_info_get(index, &dev, err);
    if (st) return st;
    /* two buffers within a third of the device's memory, each within its largest allocation */
    size_t limit = (size_t)(dev.global_mem / 6);
    if ((size_t)dev.max_alloc < limit) limit = (size_t)dev.max_alloc;
    const size_t bytes = buffer_bytes(req->megabytes, limit);
    if (bytes == 0)
        return sph_fail(err, SPH_ERR_INPUT, "--size-mb %g: too small for OpenCL device %d",
                        req->megabytes, index);

    cl_context ctx = NULL;
    cl_command_queue queue = NULL;
    cl_program program = NULL;
    cl_kernel kernel = NULL;
    cl_mem src = NULL, dst = NULL;
    cl_int rc;
    ctx = clCreateContext(NULL, 1, &dev.device, NULL, NULL, &rc);
    if (rc != CL_SUCCESS) {
        st = cl_fail(err, "clCreateContext", rc);
        goto done;
    }
    queue = clCreateCommandQueue(ctx, dev.device, CL_QUEUE_PROFILING_ENABLE, &rc);
    if (rc != CL_SUCCESS) {
        st = cl_fail(err, "clCreateCommandQueue", rc);
        goto done;
    }
    program = clCreateProgramWithSource(ctx, 1, &copy_source, NULL, &rc);
    if (rc == CL_SUCCESS) rc = clBuildProgram(program, 1, &dev.device, "", NULL, NULL);
    if (rc != CL_SUCCESS) {
        st = cl_fail(err, "building the copy kernel", rc);
        goto done;
    }
    kernel = clCreateKernel(program, "copy", &rc);
    if (rc != CL_SUCCESS) {
        st = cl_fail(err, "clCreateKernel", rc);
        goto done;
    }
    src = clCreateBuffer(ctx, CL_MEM_READ_ONLY, bytes, NULL, &rc);
    if (rc == CL_SUCCESS) dst = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, bytes, NULL, &rc);
    if (rc != CL_SUCCESS) {
        st = sph_fail(err, SPH_ERR_RUNTIME,
                      "OpenCL device %d (%s): two buffers of %.1f MiB could not be allocated (%s)",
                      index, dev.name, (double)bytes / 1048576.0, sph_cl_error_name(rc));
        goto done;
    }
    const cl_uint pattern = 0x5a5a1234u, zero = 0;
    rc = clEnqueueFillBuffer(queue, src, &pattern, sizeof pattern, 0, bytes, 0, NULL, NULL);
    if (rc == CL_SUCCESS)
        rc = clEnqueueFillBuffer(queue, dst, &zero, sizeof zero, 0, bytes, 0, NULL, NULL);
    if (rc == CL_SUCCESS) rc = clSetKernelArg(kernel, 0, sizeof src, &src);
    if (rc == CL_SUCCESS) rc = clSetKernelArg(kernel, 1, sizeof dst, &dst);
    if (rc != CL_SUCCESS) {
        st = cl_fail(err, "preparing the copy", rc);
        goto done;
    }
    const size_t global = bytes / 16;
    for (int r = -1; r < req->repeats; ++r) { /* r = -1: warm-up, not timed */
        cl_event ev = NULL;
        cl_ulong start = 0, end = 0;
        rc = clEnqueueNDRangeKernel(queue, kernel, 1, NULL, &global, NULL, 0, NULL, &ev);
        if (rc == CL_SUCCESS) rc = clWaitForEvents(1, &ev);
        if (rc == CL_SUCCESS)
            rc =
                clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_START, sizeof start, &start, NULL);
        if (rc == CL_SUCCESS)
            rc = clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_END, sizeof end, &end, NULL);
        if (ev) clReleaseEvent(ev);
        if (rc != CL_SUCCESS) {
            st = cl_fail(err, "running the copy kernel", rc);
            goto done;
        }
        if (end <= start) {
            st = sph_fail(err, SPH_ERR_RUNTIME,
                          "OpenCL device %d (%s) reported no time for the copy kernel", index,
                          dev.name);
            goto done;
        }
        if (r >= 0) seconds[r] = 1e-9 * (double)(end - start);
    }
    cl_uint check[4] = {0, 0, 0, 0};
    rc = clEnqueueReadBuffer(queue, dst, CL_TRUE, bytes - sizeof check, sizeof check, check, 0,
                             NULL, NULL);
    if (rc != CL_SUCCESS) {
        st = cl_fail(err, "reading the copy back", rc);
        goto done;
    }
    if (check[0] != pattern || check[3] != pattern) {
        st = sph_fail(err, SPH_ERR_RUNTIME, "OpenCL device %d (%s): the copy kernel did not copy",
                      index, dev.name);
        goto done;
    }
    snprintf(out->backend, sizeof out->backend, "opencl");
    sph_format(out->device, sizeof out->device, "%s (%s)", dev.name, dev.platform_name);
    snprintf(out->version, sizeof out->version, "%s", dev.version);
    snprintf(out->driver, sizeof out->driver, "%s", dev.driver);
    out->device_index = index;
    out->threads = (int)dev.compute_units;
    summarise(seconds, req->repeats, bytes, out);
done:
    if (src) clReleaseMemObject(src);
    if (dst) clReleaseMemObject(dst);
    if (kernel) clReleaseKernel(kernel);
    if (program) clReleaseProgram(program);
    if (queue) clReleaseCommandQueue(queue);
    if (ctx) clReleaseContext(ctx);
    return st;
}

sph_status sph_bandwidth_measure(const sph_bandwidth_request *req_in, sph_bandwidth_result *out,
                                 sph_error *err) {
    sph_bandwidth_request req = *req_in;
    if (!(req.megabytes > 0)) req.megabytes = DEFAULT_MIB;
    if (req.repeats <= 0) req.repeats = DEFAULT_REPEATS;
    if (req.repeats > MAX_REPEATS) req.repeats = MAX_REPEATS;
    memset(out, 0, sizeof *out);
    double *seconds = malloc((size_t)req.repeats * sizeof(double));
    if (!seconds) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    const sph_status st = req.opencl ? measure_opencl(&req, out, seconds, err)
                                     : measure_native(&req, out, seconds, err);
    free(seconds);
    return st;
}

/* ---- the command --------------------------------------------------------- */

static const char bandwidth_usage[] =
    "usage: sphsolid bandwidth [--backend cpu|opencl] [--device N] [--size-mb M] [--repeat K]\n"
    "                          [--json]\n"
    "\n"
    "Attainable memory bandwidth of a device: a streaming copy dst[i] = src[i] over two\n"
    "buffers of M MiB (default 256; OpenCL: at most a sixth of the device's memory each),\n"
    "best of K timed runs (default 10) after one warm-up.  GB/s counts read + write\n"
    "(2 x M MiB per run, the STREAM convention).  OpenCL: a copy kernel timed with\n"
    "profiling events; cpu: an OpenMP loop on the native backend's threads.\n"
    "--backend defaults to an OpenCL GPU when one is present, else cpu (as `sphsolid run`).\n"
    "--json    one JSON object on stdout instead of the text line\n";

static int usage_error(const char *fmt, const char *arg) {
    fprintf(stderr, "sphsolid bandwidth: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(run `sphsolid bandwidth --help` for usage)\n");
    return SPH_ERR_INPUT;
}

static void print_json(const sph_bandwidth_result *r) {
    json_object *o = json_object_new_object();
    json_object_object_add(o, "backend", json_object_new_string(r->backend));
    json_object_object_add(o, "device", json_object_new_string(r->device));
    json_object_object_add(o, "device_index", json_object_new_int(r->device_index));
    json_object_object_add(o, "opencl_version", json_object_new_string(r->version));
    json_object_object_add(o, "driver_version", json_object_new_string(r->driver));
    json_object_object_add(o, r->device_index < 0 ? "threads" : "compute_units",
                           json_object_new_int(r->threads));
    json_object_object_add(o, "buffer_bytes", json_object_new_int64((int64_t)r->buffer_bytes));
    json_object_object_add(o, "repeats", json_object_new_int(r->repeats));
    json_object_object_add(o, "best_seconds", json_object_new_double(r->best_seconds));
    json_object_object_add(o, "median_seconds", json_object_new_double(r->median_seconds));
    json_object_object_add(o, "best_gbs", json_object_new_double(r->best_gbs));
    json_object_object_add(o, "median_gbs", json_object_new_double(r->median_gbs));
    json_object_object_add(o, "counted", json_object_new_string("read + write (STREAM copy)"));
    printf("%s\n", json_object_to_json_string_ext(o, JSON_C_TO_STRING_PRETTY));
    json_object_put(o);
}

int sph_bandwidth_main(int argc, char **argv) {
    sph_bandwidth_request req = {.opencl = false, .device_index = -1};
    bool backend_given = false, json = false;
    for (int k = 0; k < argc; ++k) {
        const char *a = argv[k];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(bandwidth_usage, stdout);
            return 0;
        }
        if (strcmp(a, "--json") == 0) {
            json = true;
            continue;
        }
        if (strcmp(a, "--backend") != 0 && strcmp(a, "--device") != 0 &&
            strcmp(a, "--size-mb") != 0 && strcmp(a, "--repeat") != 0)
            return usage_error(a[0] == '-' ? "unknown option %s" : "unexpected argument %s", a);
        if (k + 1 >= argc) return usage_error("%s needs a value", a);
        const char *value = argv[++k];
        char *end;
        errno = 0;
        if (strcmp(a, "--backend") == 0) {
            if (strcmp(value, "cpu") == 0)
                req.opencl = false;
            else if (strcmp(value, "opencl") == 0)
                req.opencl = true;
            else
                return usage_error("--backend %s: expected opencl or cpu", value);
            backend_given = true;
        } else if (strcmp(a, "--device") == 0) {
            const long d = strtol(value, &end, 10);
            if (errno || end == value || *end || d < 0 || d > 1000)
                return usage_error("--device %s: expected a device number (see `sphsolid devices`)",
                                   value);
            req.device_index = (int)d;
        } else if (strcmp(a, "--size-mb") == 0) {
            const double m = strtod(value, &end);
            if (errno || end == value || *end || !(m >= 1.0) || !(m <= 1048576.0))
                return usage_error("--size-mb %s: expected MiB per buffer, 1 to 1048576", value);
            req.megabytes = m;
        } else {
            const long r = strtol(value, &end, 10);
            if (errno || end == value || *end || r < 1 || r > MAX_REPEATS)
                return usage_error("--repeat %s: expected a number of runs, 1 to 1000", value);
            req.repeats = (int)r;
        }
    }
    if (req.device_index >= 0) {
        if (backend_given && !req.opencl)
            return usage_error(
                "%s", "--device selects an OpenCL device; it does not go with --backend cpu");
        req.opencl = true;
    } else if (!backend_given) {
        char reason[256];
        req.opencl = sph_opencl_find_gpu(reason, sizeof reason) >= 0;
    }
    sph_bandwidth_result r;
    sph_error err = {0};
    const sph_status st = sph_bandwidth_measure(&req, &r, &err);
    if (st) {
        fprintf(stderr, "sphsolid bandwidth: %s\n", err.msg);
        return (int)st;
    }
    if (json) {
        print_json(&r);
    } else {
        printf("%s%s%s%s%s: copy of 2 x %.1f MiB, best of %d: %.2f GB/s (median %.2f GB/s; read + "
               "write counted)\n",
               r.device, r.version[0] ? ", " : "", r.version, r.driver[0] ? ", driver " : "",
               r.driver, (double)r.buffer_bytes / 1048576.0, r.repeats, r.best_gbs, r.median_gbs);
    }
    return 0;
}
