/* test_support.h — shared pieces of the backend-parameterised tests: the
 * backend named on the command line, programmatic particle sets, and paths
 * of the shipped cases. */
#ifndef SPH_TEST_SUPPORT_H
#define SPH_TEST_SUPPORT_H

#include "backend.h"
#include "run.h"
#include "sph_constants.h"
#include "test_util.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* whether the backend allocated a buffer of this name (summary.json's memory records) */
static inline bool test_has_buffer(const sph_backend *be, const char *name) {
    for (int k = 0; k < be->nbuffers; ++k)
        if (strcmp(be->buffers[k].name, name) == 0) return true;
    return false;
}

/* Under the sanitizers (SPHSOLID_SANITIZED, tests/CMakeLists.txt) the longest
 * physics runs are cut short: the same code paths run for fewer steps, ten
 * times slower per step, and the bounds that need the whole run are left to
 * the release build, which runs every test in full.  Each test says which. */
static inline bool test_sanitized(void) {
    const char *s = getenv("SPHSOLID_SANITIZED");
    return s && *s && strcmp(s, "0") != 0;
}

/* The override "time.end=<end>" written into buf (for test_run_case); returns buf. */
static inline const char *test_end_override(char *buf, size_t size, double end) {
    snprintf(buf, size, "time.end=%.17g", end);
    return buf;
}

/* argv[1]: "cpu" or "opencl" (OpenCL takes the first device: pocl in CI). */
static inline sph_backend_kind test_backend_kind(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "opencl") == 0) return SPH_BACKEND_OPENCL;
    return SPH_BACKEND_CPU;
}

static inline const char *test_source_dir(void) {
    const char *dir = getenv("SPHSOLID_SOURCE_DIR");
    return dir ? dir : ".";
}

/* A case's scene: "NAME" is cases/NAME/scene.cfg, "NAME/FILE.cfg" that file
 * of the case (e.g. "shu_osher_1d/line.cfg"). */
static inline void test_case_path(const char *case_name, char *buf, size_t len) {
    const size_t k = strlen(case_name);
    if (k > 4 && strcmp(case_name + k - 4, ".cfg") == 0)
        snprintf(buf, len, "%s/cases/%s", test_source_dir(), case_name);
    else
        snprintf(buf, len, "%s/cases/%s/scene.cfg", test_source_dir(), case_name);
}

/* A file of the repository, e.g. "cases/spinning_plate_2d/scene.cfg". */
static inline void test_repo_path(const char *rel, char *buf, size_t len) {
    snprintf(buf, len, "%s/%s", test_source_dir(), rel);
}

/* Scene texts written to a private temporary directory. */
typedef struct {
    char dir[256];
    int count;
} test_scene_dir;

static inline int test_scene_dir_open(test_scene_dir *d, const char *name) {
    d->count = 0;
    snprintf(d->dir, sizeof d->dir, "/tmp/%s.XXXXXX", name);
    if (mkdtemp(d->dir)) return 0;
    perror("mkdtemp");
    return -1;
}

/* Write `text` to a fresh scene file of the directory; its path into `path`. */
static inline void test_scene_write(test_scene_dir *d, const char *text, char *path, size_t size) {
    snprintf(path, size, "%s/scene%d.cfg", d->dir, d->count++);
    FILE *f = fopen(path, "w");
    if (!f) {
        perror(path);
        exit(2);
    }
    fputs(text, f);
    fclose(f);
}

static inline void test_scene_dir_close(test_scene_dir *d) {
    for (int i = 0; i < d->count; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/scene%d.cfg", d->dir, i);
        unlink(path);
    }
    rmdir(d->dir);
}

/* A particle set of `n` particles, all of one body, unit density and mass
 * rho0 dp^d; positions filled by the caller. */
static inline int test_particles_alloc(sph_particles *p, int n, int dim, double rho0, double dp) {
    memset(p, 0, sizeof *p);
    p->n = n;
    p->dim = dim;
    p->pos = calloc((size_t)n * dim, sizeof(double));
    p->vel = calloc((size_t)n * dim, sizeof(double));
    p->mass = calloc((size_t)n, sizeof(double));
    p->rho = calloc((size_t)n, sizeof(double));
    p->id = calloc((size_t)n, sizeof(int32_t));
    p->body = calloc((size_t)n, sizeof(uint8_t));
    if (!p->pos || !p->vel || !p->mass || !p->rho || !p->id || !p->body) return -1;
    for (int i = 0; i < n; ++i) {
        p->mass[i] = rho0 * (dim == 2 ? dp * dp : dp * dp * dp);
        p->rho[i] = rho0;
        p->id[i] = i;
    }
    p->body_count[0] = n;
    return 0;
}

/* qsort order of ints */
static inline int test_cmp_int(const void *a, const void *b) {
    const int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* A reproducible uniform random number in [0, 1) (LCG; *s is the state). */
static inline double test_urand(unsigned *s) {
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / 16777216.0;
}

/* A random cloud for the neighbour tests: `n` particles uniform in a box of
 * side `extent`, the first `cluster` of them packed in a cube of side dp/2
 * at its centre (to exceed the initial neighbour capacity); velocities
 * uniform in [-0.5, 0.5). */
static inline int test_random_cloud(sph_particles *p, int n, int dim, double dp, double extent,
                                    int cluster, unsigned seed) {
    if (test_particles_alloc(p, n, dim, 1000.0, dp)) return -1;
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < dim; ++a) {
            p->pos[(size_t)a * n + i] = i < cluster ? 0.5 * extent + 0.5 * dp * test_urand(&seed)
                                                    : extent * test_urand(&seed);
            p->vel[(size_t)a * n + i] = test_urand(&seed) - 0.5;
        }
    return 0;
}

/* Elastic feature set and parameter block for hand-made particle sets. */
static inline void test_feature_set(sph_features *f, int dim, bool double_precision,
                                    sph_rotation rotation) {
    memset(f, 0, sizeof *f);
    f->dim = dim;
    f->double_precision = double_precision;
    f->formulation = rotation == SPH_ROTATION_NONE ? SPH_FORMULATION_ENOG : SPH_FORMULATION_ENOG_A;
    f->rotation = rotation;
    f->kernel = SPH_KERNEL_WENDLAND_C2;
    f->stepping = SPH_STEPPING_DUAL;
    f->nbodies = 1;
}

static inline void test_params(sph_params_f64 *prm, int dim, double dp, double n_body) {
    memset(prm, 0, sizeof *prm);
    const double rho0 = 1000.0, e = 2e6, nu = 0.3975;
    prm->h = 1.3 * dp;
    prm->cutoff = 2.6 * dp;
    prm->materials[0].rho0 = rho0;
    prm->materials[0].c0 = sqrt(e / (3.0 * (1.0 - 2.0 * nu) * rho0));
    prm->materials[0].shear_modulus = e / (2.0 * (1.0 + nu));
    prm->materials[0].bulk_modulus = rho0 * prm->materials[0].c0 * prm->materials[0].c0;
    prm->xi_e = 0.7 * dim + 2.1;
    prm->nbodies = 1;
    prm->dp = dp;
    prm->body_count[0] = (int)n_body;
}

static inline sph_status test_backend(sph_backend_kind kind, const sph_features *f,
                                      const sph_params_f64 *prm, int n, sph_backend **be,
                                      sph_error *err) {
    const sph_backend_request req = {.kind = kind, .device_index = -1, .quiet = true};
    return sph_backend_create(&req, f, prm, n, be, err);
}

/* Run a shipped case with overrides on a backend; returns the status. */
/* ... with the OpenCL pair geometry chosen (device/sph_pair_geometry.h) */
static inline sph_status test_run_case_geometry(const char *case_name, const char *const *overrides,
                                                int noverrides, sph_backend_kind kind,
                                                sph_precision precision, sph_pair_geometry geometry,
                                                long max_steps, sph_simulation *sim,
                                                sph_error *err) {
    char path[1024];
    test_case_path(case_name, path, sizeof path);
    const sph_run_options opt = {
        .scene_path = path,
        .overrides = overrides,
        .noverrides = noverrides,
        .backend = {.kind = kind, .device_index = -1, .quiet = true, .pair_geometry = geometry},
        .precision = precision,
        .out_dir = NULL,
        .quiet = true,
        .max_acoustic_steps = max_steps,
    };
    sph_status st = sph_simulation_open(sim, &opt, err);
    if (!st) st = sph_simulation_run(sim, err);
    return st;
}

static inline sph_status test_run_case(const char *case_name, const char *const *overrides,
                                       int noverrides, sph_backend_kind kind,
                                       sph_precision precision, long max_steps, sph_simulation *sim,
                                       sph_error *err) {
    return test_run_case_geometry(case_name, overrides, noverrides, kind, precision,
                                  SPH_PAIR_GEOMETRY_AUTO, max_steps, sim, err);
}

#endif
