#include "opencl_runtime.h"

#include "embedded_sources.h"

#include <stdlib.h>
#include <string.h>

#define MAX_PLATFORMS 16
#define MAX_DEVICES   64

const char *sph_cl_error_name(cl_int code) {
    switch (code) {
    case CL_SUCCESS:
        return "CL_SUCCESS";
    case CL_DEVICE_NOT_FOUND:
        return "CL_DEVICE_NOT_FOUND";
    case CL_DEVICE_NOT_AVAILABLE:
        return "CL_DEVICE_NOT_AVAILABLE";
    case CL_COMPILER_NOT_AVAILABLE:
        return "CL_COMPILER_NOT_AVAILABLE";
    case CL_MEM_OBJECT_ALLOCATION_FAILURE:
        return "CL_MEM_OBJECT_ALLOCATION_FAILURE";
    case CL_OUT_OF_RESOURCES:
        return "CL_OUT_OF_RESOURCES";
    case CL_OUT_OF_HOST_MEMORY:
        return "CL_OUT_OF_HOST_MEMORY";
    case CL_BUILD_PROGRAM_FAILURE:
        return "CL_BUILD_PROGRAM_FAILURE";
    case CL_INVALID_VALUE:
        return "CL_INVALID_VALUE";
    case CL_INVALID_DEVICE:
        return "CL_INVALID_DEVICE";
    case CL_INVALID_BUFFER_SIZE:
        return "CL_INVALID_BUFFER_SIZE";
    case CL_INVALID_BUILD_OPTIONS:
        return "CL_INVALID_BUILD_OPTIONS";
    case CL_INVALID_KERNEL_NAME:
        return "CL_INVALID_KERNEL_NAME";
    case CL_INVALID_ARG_INDEX:
        return "CL_INVALID_ARG_INDEX";
    case CL_INVALID_ARG_VALUE:
        return "CL_INVALID_ARG_VALUE";
    case CL_INVALID_ARG_SIZE:
        return "CL_INVALID_ARG_SIZE";
    case CL_INVALID_KERNEL_ARGS:
        return "CL_INVALID_KERNEL_ARGS";
    case CL_INVALID_WORK_GROUP_SIZE:
        return "CL_INVALID_WORK_GROUP_SIZE";
    case CL_INVALID_WORK_ITEM_SIZE:
        return "CL_INVALID_WORK_ITEM_SIZE";
    case CL_INVALID_GLOBAL_WORK_SIZE:
        return "CL_INVALID_GLOBAL_WORK_SIZE";
    case CL_INVALID_MEM_OBJECT:
        return "CL_INVALID_MEM_OBJECT";
    case CL_INVALID_COMMAND_QUEUE:
        return "CL_INVALID_COMMAND_QUEUE";
    case CL_KERNEL_ARG_INFO_NOT_AVAILABLE:
        return "CL_KERNEL_ARG_INFO_NOT_AVAILABLE";
    case -1001:
        return "CL_PLATFORM_NOT_FOUND_KHR (no OpenCL driver installed)";
    default:
        return "OpenCL error";
    }
}

/* All devices of all platforms, in loader order. */
static int enumerate(cl_platform_id *platform_of, cl_device_id *devices, int max) {
    cl_platform_id platforms[MAX_PLATFORMS];
    cl_uint np = 0;
    if (clGetPlatformIDs(MAX_PLATFORMS, platforms, &np) != CL_SUCCESS) return 0;
    int count = 0;
    for (cl_uint p = 0; p < np && count < max; ++p) {
        cl_uint nd = 0;
        cl_device_id ids[MAX_DEVICES];
        if (clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, MAX_DEVICES, ids, &nd) != CL_SUCCESS)
            continue;
        for (cl_uint d = 0; d < nd && count < max; ++d) {
            platform_of[count] = platforms[p];
            devices[count++] = ids[d];
        }
    }
    return count;
}

int sph_opencl_device_count(void) {
    cl_platform_id plat[MAX_DEVICES];
    cl_device_id dev[MAX_DEVICES];
    return enumerate(plat, dev, MAX_DEVICES);
}

sph_status sph_opencl_device_info_get(int index, sph_opencl_device_info *info, sph_error *err) {
    cl_platform_id plat[MAX_DEVICES];
    cl_device_id dev[MAX_DEVICES];
    const int count = enumerate(plat, dev, MAX_DEVICES);
    if (count == 0)
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "no OpenCL device found (is an OpenCL driver such as pocl-opencl-icd or "
                        "the GPU vendor's ICD installed?)");
    if (index < 0 || index >= count)
        return sph_fail(err, SPH_ERR_INPUT,
                        "--device %d: there are %d OpenCL devices (0..%d); see `sphsolid devices`",
                        index, count, count - 1);
    memset(info, 0, sizeof *info);
    info->platform = plat[index];
    info->device = dev[index];
    clGetDeviceInfo(dev[index], CL_DEVICE_TYPE, sizeof info->type, &info->type, NULL);
    clGetDeviceInfo(dev[index], CL_DEVICE_NAME, sizeof info->name, info->name, NULL);
    clGetDeviceInfo(dev[index], CL_DEVICE_VERSION, sizeof info->version, info->version, NULL);
    clGetDeviceInfo(dev[index], CL_DRIVER_VERSION, sizeof info->driver, info->driver, NULL);
    clGetPlatformInfo(plat[index], CL_PLATFORM_NAME, sizeof info->platform_name,
                      info->platform_name, NULL);
    clGetDeviceInfo(dev[index], CL_DEVICE_GLOBAL_MEM_SIZE, sizeof info->global_mem,
                    &info->global_mem, NULL);
    clGetDeviceInfo(dev[index], CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof info->max_alloc,
                    &info->max_alloc, NULL);
    clGetDeviceInfo(dev[index], CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof info->max_work_group,
                    &info->max_work_group, NULL);
    clGetDeviceInfo(dev[index], CL_DEVICE_MAX_COMPUTE_UNITS, sizeof info->compute_units,
                    &info->compute_units, NULL);
    cl_device_fp_config fp64 = 0;
    clGetDeviceInfo(dev[index], CL_DEVICE_DOUBLE_FP_CONFIG, sizeof fp64, &fp64, NULL);
    info->has_fp64 = fp64 != 0;
    return SPH_OK;
}

static const char *type_name(cl_device_type t) {
    if (t & CL_DEVICE_TYPE_GPU) return "GPU";
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    if (t & CL_DEVICE_TYPE_CPU) return "CPU";
    return "other";
}

int sph_opencl_find_gpu(char *reason, size_t len) {
    const int count = sph_opencl_device_count();
    if (count == 0) {
        snprintf(reason, len, "no OpenCL platform found: using the native CPU backend");
        return -1;
    }
    for (int k = 0; k < count; ++k) {
        sph_opencl_device_info info;
        sph_error err;
        if (sph_opencl_device_info_get(k, &info, &err)) continue;
        if (info.type & (CL_DEVICE_TYPE_GPU | CL_DEVICE_TYPE_ACCELERATOR)) {
            snprintf(reason, len, "OpenCL device %d (%s, %s) is the first GPU found", k, info.name,
                     info.platform_name);
            return k;
        }
    }
    snprintf(reason, len,
             "%d OpenCL device(s) but no GPU: using the native CPU backend (a CPU OpenCL device "
             "such as pocl is for testing the kernels: --backend opencl)",
             count);
    return -1;
}

void sph_opencl_print_devices(FILE *out) {
    const int count = sph_opencl_device_count();
    fprintf(out, "native CPU backend: --backend cpu (always available)\n");
    if (count == 0) {
        fprintf(out, "no OpenCL devices (no ICD or driver installed)\n");
        return;
    }
    for (int k = 0; k < count; ++k) {
        sph_opencl_device_info info;
        sph_error err;
        if (sph_opencl_device_info_get(k, &info, &err)) continue;
        fprintf(out,
                "OpenCL device %d: %s [%s] platform \"%s\", %s, driver %s, %u compute units, "
                "%.1f GiB, double precision: %s\n",
                k, info.name, type_name(info.type), info.platform_name, info.version, info.driver,
                info.compute_units, (double)info.global_mem / (1024.0 * 1024.0 * 1024.0),
                info.has_fp64 ? "yes" : "no");
    }
}

/* ---- program assembly ---------------------------------------------------- */

typedef struct {
    char *text;
    size_t len, cap;
    const char *included[64];
    int nincluded;
} source_buffer;

static int append(source_buffer *b, const char *s, size_t n) {
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 1 << 16;
        while (b->len + n + 1 > cap) cap *= 2;
        char *t = realloc(b->text, cap);
        if (!t) return -1;
        b->text = t;
        b->cap = cap;
    }
    memcpy(b->text + b->len, s, n);
    b->len += n;
    b->text[b->len] = '\0';
    return 0;
}

static const sph_embedded_file *embedded_file(const char *name) {
    for (const sph_embedded_file *f = sph_embedded_files; f->name; ++f)
        if (strcmp(f->name, name) == 0) return f;
    return NULL;
}

/* If `line` is `#include "name"` (any spacing), copy the name into `name`. */
static int include_target(const char *line, size_t n, char *name, size_t cap) {
    size_t k = 0;
    while (k < n && (line[k] == ' ' || line[k] == '\t')) ++k;
    if (k >= n || line[k] != '#') return 0;
    ++k;
    while (k < n && (line[k] == ' ' || line[k] == '\t')) ++k;
    if (n - k < 7 || strncmp(line + k, "include", 7) != 0) return 0;
    k += 7;
    while (k < n && (line[k] == ' ' || line[k] == '\t')) ++k;
    if (k >= n || line[k] != '"') return 0;
    const size_t start = ++k;
    while (k < n && line[k] != '"') ++k;
    if (k >= n || k - start + 1 > cap) return 0;
    memcpy(name, line + start, k - start);
    name[k - start] = '\0';
    return 1;
}

/* Append an embedded file, replacing each `#include "x"` of another embedded
 * file by that file's text (each file once: they all have include guards). */
static int append_file(source_buffer *b, const sph_embedded_file *file) {
    for (int k = 0; k < b->nincluded; ++k)
        if (b->included[k] == file->name) return 0;
    if (b->nincluded >= 64) return -1;
    b->included[b->nincluded++] = file->name;
    const char *p = file->text;
    while (*p) {
        const char *eol = strchr(p, '\n');
        const size_t n = eol ? (size_t)(eol - p) + 1 : strlen(p);
        char name[128];
        const sph_embedded_file *inc =
            include_target(p, n, name, sizeof name) ? embedded_file(name) : NULL;
        if (inc ? append_file(b, inc) != 0 : append(b, p, n) != 0) return -1;
        p += n;
    }
    return append(b, "\n", 1);
}

char *sph_opencl_program_source(const char *const *files, int nfiles) {
    source_buffer b = {0};
    for (int k = 0; k < nfiles; ++k)
        if (!embedded_file(files[k]) || append_file(&b, embedded_file(files[k])) != 0) {
            free(b.text);
            return NULL;
        }
    return b.text;
}

sph_status sph_opencl_build_program(cl_context ctx, cl_device_id dev, const char *const *files,
                                    int nfiles, const char *options, cl_program *out,
                                    sph_error *err) {
    char *source = sph_opencl_program_source(files, nfiles);
    if (!source)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot assemble the embedded OpenCL sources");
    cl_int rc;
    const char *src = source;
    cl_program prog = clCreateProgramWithSource(ctx, 1, &src, NULL, &rc);
    free(source);
    if (rc != CL_SUCCESS)
        return sph_fail(err, SPH_ERR_RUNTIME, "clCreateProgramWithSource failed: %s",
                        sph_cl_error_name(rc));
    char full_options[1024];
    snprintf(full_options, sizeof full_options, "%s -cl-kernel-arg-info", options);
    rc = clBuildProgram(prog, 1, &dev, full_options, NULL, NULL);
    if (rc != CL_SUCCESS) {
        char log[1536] = "";
        clGetProgramBuildInfo(prog, dev, CL_PROGRAM_BUILD_LOG, sizeof log - 1, log, NULL);
        clReleaseProgram(prog);
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "OpenCL program build failed (%s) with options %s: %s",
                        sph_cl_error_name(rc), full_options, log);
    }
    *out = prog;
    return SPH_OK;
}

/* ---- kernels with named arguments --------------------------------------- */

sph_status sph_cl_kernel_create(cl_program program, const char *name, const sph_cl_arg *resources,
                                int nresources, sph_cl_kernel *k, sph_error *err) {
    memset(k, 0, sizeof *k);
    snprintf(k->name, sizeof k->name, "%s", name);
    cl_int rc;
    k->kernel = clCreateKernel(program, name, &rc);
    if (rc != CL_SUCCESS)
        return sph_fail(err, SPH_ERR_RUNTIME, "clCreateKernel(%s) failed: %s", name,
                        sph_cl_error_name(rc));
    rc = clGetKernelInfo(k->kernel, CL_KERNEL_NUM_ARGS, sizeof k->nargs, &k->nargs, NULL);
    if (rc != CL_SUCCESS || k->nargs > SPH_CL_MAX_ARGS)
        return sph_fail(err, SPH_ERR_RUNTIME, "kernel %s: cannot query its arguments", name);
    for (cl_uint a = 0; a < k->nargs; ++a) {
        rc = clGetKernelArgInfo(k->kernel, a, CL_KERNEL_ARG_NAME, sizeof k->arg_name[a],
                                k->arg_name[a], NULL);
        if (rc != CL_SUCCESS)
            return sph_fail(err, SPH_ERR_RUNTIME, "kernel %s: argument names unavailable (%s)",
                            name, sph_cl_error_name(rc));
        k->resource[a] = -1;
        for (int r = 0; r < nresources; ++r)
            if (strcmp(resources[r].name, k->arg_name[a]) == 0) k->resource[a] = r;
    }
    return SPH_OK;
}

void sph_cl_kernel_release(sph_cl_kernel *k) {
    if (k->kernel) clReleaseKernel(k->kernel);
    k->kernel = NULL;
}

sph_status sph_cl_kernel_bind(sph_cl_kernel *k, const sph_cl_arg *resources,
                              const sph_cl_arg *overrides, int noverrides, sph_error *err) {
    for (cl_uint a = 0; a < k->nargs; ++a) {
        const sph_cl_arg *arg = NULL;
        for (int o = 0; o < noverrides; ++o)
            if (strcmp(overrides[o].name, k->arg_name[a]) == 0) arg = &overrides[o];
        if (!arg && k->resource[a] >= 0) arg = &resources[k->resource[a]];
        if (!arg)
            return sph_fail(err, SPH_ERR_RUNTIME, "kernel %s: no value for argument '%s'", k->name,
                            k->arg_name[a]);
        const cl_int rc = clSetKernelArg(k->kernel, a, arg->size, arg->value);
        if (rc != CL_SUCCESS)
            return sph_fail(err, SPH_ERR_RUNTIME, "kernel %s: setting argument '%s' failed: %s",
                            k->name, k->arg_name[a], sph_cl_error_name(rc));
    }
    return SPH_OK;
}
