/* opencl_runtime.h — OpenCL plumbing shared by the device backend and the CLI.
 *
 * Devices are numbered across all platforms in the order the ICD loader
 * reports them (the numbers `sphsolid devices` prints and `--device N`
 * takes).  Programs are assembled from the sources embedded in the binary,
 * with `#include "..."` of embedded files resolved here, and built with the
 * scene's feature options.  Kernel arguments are bound by parameter name
 * (clGetKernelArgInfo), so a kernel whose signature grows with a feature needs
 * no host change beyond providing the named resource.
 */
#ifndef SPH_OPENCL_RUNTIME_H
#define SPH_OPENCL_RUNTIME_H

#include "sph_error.h"

#include <CL/cl.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef struct {
    cl_platform_id platform;
    cl_device_id device;
    cl_device_type type;
    char name[256];
    char platform_name[256];
    char version[128];
    char driver[128];
    bool has_fp64;
    cl_ulong global_mem;
    cl_ulong max_alloc;
    size_t max_work_group;
    cl_uint compute_units;
} sph_opencl_device_info;

/* Number of OpenCL devices on all platforms (0 when there is no ICD). */
int sph_opencl_device_count(void);
sph_status sph_opencl_device_info_get(int index, sph_opencl_device_info *info, sph_error *err);
/* Index of the first GPU (or accelerator), or -1; `reason` says which and why. */
int sph_opencl_find_gpu(char *reason, size_t len);
/* `sphsolid devices`: one line per device plus the native backend. */
void sph_opencl_print_devices(FILE *out);

/* Program from embedded files, in order; includes resolved. */
sph_status sph_opencl_build_program(cl_context ctx, cl_device_id dev, const char *const *files,
                                    int nfiles, const char *options, cl_program *out,
                                    sph_error *err);
/* The assembled source text (tests, debugging); caller frees. */
char *sph_opencl_program_source(const char *const *files, int nfiles);

const char *sph_cl_error_name(cl_int code);

/* A named argument value: `value` points to a cl_mem handle or a scalar. */
typedef struct {
    const char *name;
    size_t size;
    const void *value;
} sph_cl_arg;

#define SPH_CL_MAX_ARGS 40
typedef struct {
    cl_kernel kernel;
    char name[64];
    cl_uint nargs;
    int resource[SPH_CL_MAX_ARGS]; /* index into the resource table; -1: per call */
    char arg_name[SPH_CL_MAX_ARGS][48];
} sph_cl_kernel;

sph_status sph_cl_kernel_create(cl_program program, const char *name, const sph_cl_arg *resources,
                                int nresources, sph_cl_kernel *k, sph_error *err);
void sph_cl_kernel_release(sph_cl_kernel *k);
/* Set every argument from the resource table or, first, from `overrides`. */
sph_status sph_cl_kernel_bind(sph_cl_kernel *k, const sph_cl_arg *resources,
                              const sph_cl_arg *overrides, int noverrides, sph_error *err);

#endif
