#include "snapshot.h"

#include "physics.h"
#include "hdf5_file.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define SERIES_NAME "snapshots.hdf.series"
#define VTK_VERTEX  1

void sph_snapshot_name(int index, char *buf, size_t len) {
    snprintf(buf, len, "snapshots/snapshot_%06d.hdf", index);
}

/* Remove snapshot files numbered `keep` and up, and stray partial files. */
static sph_status clear_snapshots(const char *dir, int keep, sph_error *err) {
    char sub[1100];
    snprintf(sub, sizeof sub, "%s/snapshots", dir);
    DIR *d = opendir(sub);
    if (!d) return SPH_OK;
    sph_status st = SPH_OK;
    for (struct dirent *e = readdir(d); e && !st; e = readdir(d)) {
        int index = -1, used = 0;
        if (sscanf(e->d_name, "snapshot_%d.hdf%n", &index, &used) != 1) continue;
        const bool partial = strcmp(e->d_name + used, ".partial") == 0;
        if (e->d_name[used] != '\0' && !partial) continue;
        if (index < keep && !partial) continue;
        char path[1400];
        snprintf(path, sizeof path, "%s/%s", sub, e->d_name);
        if (unlink(path) != 0 && errno != ENOENT)
            st = sph_fail(err, SPH_ERR_RUNTIME, "cannot remove the old snapshot %s: %s", path,
                          strerror(errno));
    }
    closedir(d);
    return st;
}

static sph_status write_series(const sph_snapshots *s, int count, sph_error *err) {
    char path[1100], partial[1200];
    snprintf(path, sizeof path, "%s/%s", s->dir, SERIES_NAME);
    snprintf(partial, sizeof partial, "%s.partial", path);
    FILE *f = fopen(partial, "w");
    if (!f) return sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", partial, strerror(errno));
    fprintf(f, "{\n  \"file-series-version\": \"1.0\",\n  \"files\": [\n");
    for (int k = 0; k < count; ++k) {
        char name[64];
        sph_snapshot_name(k, name, sizeof name);
        fprintf(f, "    { \"name\": \"%s\", \"time\": %.17g }%s\n", name, s->times[k],
                k + 1 < count ? "," : "");
    }
    fprintf(f, "  ]\n}\n");
    const bool bad = ferror(f) || fflush(f) != 0 || sph_test_disk_full(partial);
    if (sph_test_disk_full(partial)) errno = ENOSPC;
    const int write_errno = errno;
    if (fclose(f) != 0 || bad) {
        const sph_status st = sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", partial,
                                       strerror(bad ? write_errno : errno));
        unlink(partial);
        return st;
    }
    if (rename(partial, path) != 0)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot rename %s: %s", partial, strerror(errno));
    return SPH_OK;
}

sph_status sph_snapshots_open(sph_snapshots *s, const char *run_dir,
                              const sph_snapshot_context *ctx, int n, bool double_precision,
                              int keep, const double *kept_times, sph_error *err) {
    memset(s, 0, sizeof *s);
    snprintf(s->dir, sizeof s->dir, "%s", run_dir);
    s->ctx = *ctx;
    s->n = n;
    s->dim = ctx->scene->dim;
    s->double_precision = double_precision;
    char sub[1100];
    snprintf(sub, sizeof sub, "%s/snapshots", run_dir);
    if (mkdir(sub, 0777) != 0 && errno != EEXIST)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot create %s: %s", sub, strerror(errno));
    sph_status st = clear_snapshots(run_dir, keep, err);
    if (st) return st;
    s->capacity = keep + 64;
    s->times = malloc((size_t)s->capacity * sizeof(double));
    const size_t nn = (size_t)n;
    s->pos = malloc(nn * 3 * sizeof(double));
    s->vel = malloc(nn * 3 * sizeof(double));
    s->rho = malloc(nn * sizeof(double));
    s->tau = malloc(nn * 6 * sizeof(double));
    s->alpha = malloc(nn * sizeof(double));
    s->id = malloc(nn * sizeof(int32_t));
    s->body = calloc(nn, 1);
    s->material = calloc(nn, 1);
    s->row_scratch = malloc(nn * 6 * sizeof(double));
    s->fluid = SPH_FORMULATION_IS_EULERIAN(ctx->scene->formulation);
    if (s->fluid) {
        s->pressure = malloc(nn * sizeof(double));
        s->vorticity = malloc(nn * 3 * sizeof(double));
    }
    if (!s->times || !s->pos || !s->vel || !s->rho || !s->tau || !s->alpha || !s->id || !s->body ||
        !s->material || !s->row_scratch || (s->fluid && (!s->pressure || !s->vorticity)))
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory for snapshots");
    for (int k = 0; k < keep; ++k) s->times[k] = kept_times[k];
    s->count = keep;
    if (keep > 0) return write_series(s, keep, err);
    char series[1100];
    snprintf(series, sizeof series, "%s/%s", run_dir, SERIES_NAME);
    if (unlink(series) != 0 && errno != ENOENT)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot remove %s: %s", series, strerror(errno));
    return SPH_OK;
}

/* Rows in particle-id order: out[id[k] * comps + c] = in[c * n + k] (field
 * layout in), padded with zeros to `comps` components. */
static void by_id(const sph_snapshots *s, const double *in, int in_comps, int comps, double *out) {
    const int n = s->n;
    for (int k = 0; k < n; ++k) {
        const size_t row = (size_t)s->id[k] * (size_t)comps;
        for (int c = 0; c < comps; ++c)
            out[row + (size_t)c] = c < in_comps ? in[(size_t)c * (size_t)n + (size_t)k] : 0.0;
    }
}

/* Positions (points, displacement) are stored as the run holds them: float
 * in single precision, double in double and mixed (a history field). */
static hid_t position_type(const sph_snapshots *s) {
    return strcmp(s->ctx.precision, "single") == 0 ? H5T_IEEE_F32LE : H5T_IEEE_F64LE;
}

static sph_status write_ids(const sph_snapshots *s, const sph_h5_writer *w, hid_t pd,
                            sph_error *err);

/* Fluids, after velocity and density: pressure (the EOS state the run
 * holds), vorticity (the z component in 2D, a vector in 3D, of the velocity
 * written beside it: the download forms it, eulerian_vorticity), the Mach number |v| / c with
 * the ideal gas's c = sqrt(gamma p / rho) (compressible), the ids. */
static sph_status write_fluid_point_data(const sph_snapshots *s, const sph_h5_writer *w, hid_t pd,
                                         sph_error *err) {
    const sph_scene *sc = s->ctx.scene;
    const int n = s->n, dim = s->dim;
    double *rows = s->row_scratch;
    const hsize_t vec_dims[2] = {(hsize_t)n, 3}, scalar_dims[1] = {(hsize_t)n};
    sph_status st = SPH_OK;
    if (sc->output_field[SPH_OUT_PRESSURE]) {
        by_id(s, s->pressure, 1, 1, rows);
        st = sph_h5_write(w, pd, "pressure", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, scalar_dims,
                          rows, err);
    }
    if (!st && sc->output_field[SPH_OUT_VORTICITY]) {
        if (dim == 2) {
            by_id(s, s->vorticity, 1, 1, rows);
            st = sph_h5_write(w, pd, "vorticity", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, scalar_dims,
                              rows, err);
        } else {
            by_id(s, s->vorticity, 3, 3, rows);
            st = sph_h5_write(w, pd, "vorticity", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 2, vec_dims,
                              rows, err);
        }
    }
    if (!st && sc->output_field[SPH_OUT_MACH_NUMBER]) {
        const sph_physics *k = sph_physics_for(dim, true);
        for (int i = 0; i < n; ++i) {
            double v2 = 0.0;
            for (int a = 0; a < dim; ++a) {
                const double v = s->vel[(size_t)a * (size_t)n + (size_t)i];
                v2 += v * v;
            }
            const double c =
                k->ideal_gas_sound_speed(s->pressure[i], s->rho[i], s->ctx.prm->materials[0].gamma);
            /* a wall particle of the ideal gas: at rest, p = 0, c = 0 */
            rows[s->id[i]] = v2 > 0.0 ? sqrt(v2) / c : 0.0;
        }
        st = sph_h5_write(w, pd, "mach_number", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, scalar_dims,
                          rows, err);
    }
    return st ? st : write_ids(s, w, pd, err);
}

static sph_status write_point_data(const sph_snapshots *s, const sph_h5_writer *w, hid_t pd,
                                   sph_error *err) {
    const sph_scene *sc = s->ctx.scene;
    const int n = s->n, dim = s->dim;
    const hid_t real_type = s->double_precision ? H5T_IEEE_F64LE : H5T_IEEE_F32LE;
    double *rows = s->row_scratch;
    const hsize_t vec_dims[2] = {(hsize_t)n, 3}, scalar_dims[1] = {(hsize_t)n},
                  tensor_dims[2] = {(hsize_t)n, 6};
    sph_status st = SPH_OK;
    if (sc->output_field[SPH_OUT_VELOCITY]) {
        by_id(s, s->vel, dim, 3, rows);
        st = sph_h5_write(w, pd, "velocity", H5T_NATIVE_DOUBLE, real_type, 2, vec_dims, rows, err);
    }
    if (!st && sc->output_field[SPH_OUT_DISPLACEMENT]) {
        by_id(s, s->pos, dim, 3, rows);
        const sph_particles *p0 = s->ctx.initial; /* initial set: index = id */
        /* x(0) as the run stored it: a single-precision run starts from
         * positions rounded to float, so its displacement at t = 0 is 0
         * (mixed precision keeps positions in double) */
        const bool float_positions = position_type(s) == H5T_IEEE_F32LE;
        for (int i = 0; i < n; ++i)
            for (int a = 0; a < dim; ++a) {
                const double x0 = p0->pos[(size_t)a * (size_t)n + (size_t)i];
                rows[(size_t)i * 3 + (size_t)a] -= float_positions ? (double)(float)x0 : x0;
            }
        st = sph_h5_write(w, pd, "displacement", H5T_NATIVE_DOUBLE, position_type(s), 2, vec_dims,
                          rows, err);
    }
    if (!st && sc->output_field[SPH_OUT_DENSITY]) {
        by_id(s, s->rho, 1, 1, rows);
        st =
            sph_h5_write(w, pd, "density", H5T_NATIVE_DOUBLE, real_type, 1, scalar_dims, rows, err);
    }
    if (s->fluid) return st ? st : write_fluid_point_data(s, w, pd, err);
    const bool want_p = sc->output_field[SPH_OUT_PRESSURE],
               want_vm = sc->output_field[SPH_OUT_VON_MISES],
               want_tau = sc->output_field[SPH_OUT_SHEAR_STRESS];
    if (!st && (want_p || want_vm || want_tau)) {
        /* derived by the physics source itself (device/sph_elasticity.h) */
        const sph_physics *k = sph_physics_for(dim, true);
        double *p = malloc((size_t)n * sizeof(double) * 2);
        double *t6 = want_tau ? malloc((size_t)n * 6 * sizeof(double)) : NULL;
        if (!p || (want_tau && !t6)) {
            free(p);
            free(t6);
            return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory for a snapshot");
        }
        double *vm = p + n;
        k->stress_output(s->ctx.prm, n, s->rho, s->tau, s->material, p, vm, t6);
        if (want_p) {
            by_id(s, p, 1, 1, rows);
            st = sph_h5_write(w, pd, "pressure", H5T_NATIVE_DOUBLE, real_type, 1, scalar_dims, rows,
                              err);
        }
        if (!st && want_vm) {
            by_id(s, vm, 1, 1, rows);
            st = sph_h5_write(w, pd, "von_mises", H5T_NATIVE_DOUBLE, real_type, 1, scalar_dims,
                              rows, err);
        }
        if (!st && want_tau) {
            /* t6 is [n][6] in backend order: reorder rows by id */
            for (int i = 0; i < n; ++i)
                memcpy(rows + (size_t)s->id[i] * 6, t6 + (size_t)i * 6, 6 * sizeof(double));
            st = sph_h5_write(w, pd, "shear_stress", H5T_NATIVE_DOUBLE, real_type, 2, tensor_dims,
                              rows, err);
        }
        free(p);
        free(t6);
    }
    if (!st && sc->output_field[SPH_OUT_PLASTIC_STRAIN]) {
        /* the J2 hardening variable: equivalent plastic strain (003 eq. 11) */
        by_id(s, s->alpha, 1, 1, rows);
        st = sph_h5_write(w, pd, "plastic_strain", H5T_NATIVE_DOUBLE, real_type, 1, scalar_dims,
                          rows, err);
    }
    return st ? st : write_ids(s, w, pd, err);
}

static sph_status write_ids(const sph_snapshots *s, const sph_h5_writer *w, hid_t pd,
                            sph_error *err) {
    const sph_scene *sc = s->ctx.scene;
    const int n = s->n;
    double *rows = s->row_scratch;
    const hsize_t scalar_dims[1] = {(hsize_t)n};
    sph_status st = SPH_OK;
    if (sc->output_field[SPH_OUT_BODY_ID] || sc->output_field[SPH_OUT_PARTICLE_ID] ||
        sc->output_field[SPH_OUT_MATERIAL_ID]) {
        int32_t *ints = (int32_t *)rows; /* n int32 fit in the n*6 doubles */
        if (sc->output_field[SPH_OUT_BODY_ID]) {
            for (int i = 0; i < n; ++i) ints[s->id[i]] = s->body[i];
            st = sph_h5_write(w, pd, "body_id", H5T_NATIVE_INT32, H5T_STD_I32LE, 1, scalar_dims,
                              ints, err);
        }
        if (!st && sc->output_field[SPH_OUT_MATERIAL_ID]) {
            /* the material's index in the scene's materials list */
            int row_of[SPH_MAX_MATERIALS], scene_index[SPH_MAX_MATERIALS] = {0};
            sph_scene_material_rows(sc, row_of);
            for (int m = 0; m < SPH_MAX_MATERIALS; ++m)
                if (row_of[m] >= 0) scene_index[row_of[m]] = m;
            for (int i = 0; i < n; ++i) ints[s->id[i]] = scene_index[s->material[i]];
            st = sph_h5_write(w, pd, "material_id", H5T_NATIVE_INT32, H5T_STD_I32LE, 1, scalar_dims,
                              ints, err);
        }
        if (!st && sc->output_field[SPH_OUT_PARTICLE_ID]) {
            for (int i = 0; i < n; ++i) ints[i] = i;
            st = sph_h5_write(w, pd, "particle_id", H5T_NATIVE_INT32, H5T_STD_I32LE, 1, scalar_dims,
                              ints, err);
        }
    }
    return st;
}

static sph_status write_provenance(const sph_snapshots *s, const sph_h5_writer *w, sph_error *err) {
    const sph_snapshot_context *c = &s->ctx;
    const sph_scene *sc = c->scene;
    hid_t g;
    sph_status st = sph_h5_group(w, w->file, "sphsolid", &g, err);
    if (st) return st;
    const int64_t index = s->job_index, ac = s->job_acoustic, ad = s->job_advection;
    const struct {
        const char *name, *value;
    } strings[] = {
        {"sphsolid_version", SPHSOLID_VERSION},
        {"commit", c->commit},
        {"formulation", sph_formulation_name(sc->formulation)},
        {"rotation", sph_rotation_name(sc->rotation)},
        {"kernel", sph_kernel_name(sc->kernel)},
        {"precision", c->precision},
        {"backend", c->backend},
        {"device", c->device},
        {"build_options", c->build_options},
        {"scene_path", sc->path},
        {"scene_text", sc->resolved_text ? sc->resolved_text : ""},
        {"parameters", c->parameters_json},
    };
    st = sph_h5_attr_double(w, g, "time", s->job_time, err);
    if (!st) st = sph_h5_attr_int64s(w, g, "snapshot_index", &index, 1, err);
    if (!st) st = sph_h5_attr_int64s(w, g, "acoustic_steps", &ac, 1, err);
    if (!st) st = sph_h5_attr_int64s(w, g, "advection_steps", &ad, 1, err);
    for (size_t k = 0; !st && k < sizeof strings / sizeof strings[0]; ++k)
        st = sph_h5_attr_string(w, g, strings[k].name, strings[k].value, err);
    H5Gclose(g);
    return st;
}

static sph_status write_file(sph_snapshots *s, sph_error *err) {
    char name[64], path[1200];
    sph_snapshot_name(s->job_index, name, sizeof name);
    snprintf(path, sizeof path, "%s/%s", s->dir, name);
    sph_h5_writer w;
    sph_status st = sph_h5_create(&w, path, err);
    if (st) return st;
    const int n = s->n;
    const hsize_t one[1] = {1};
    const int64_t count = n, version[2] = {1, 0};
    hid_t vtk = -1, pd = -1;
    st = sph_h5_group(&w, w.file, "VTKHDF", &vtk, err);
    if (!st) st = sph_h5_attr_int64s(&w, vtk, "Version", version, 2, err);
    if (!st) st = sph_h5_attr_string(&w, vtk, "Type", "UnstructuredGrid", err);
    const char *counts[] = {"NumberOfPoints", "NumberOfCells", "NumberOfConnectivityIds"};
    for (int k = 0; !st && k < 3; ++k)
        st = sph_h5_write(&w, vtk, counts[k], H5T_NATIVE_INT64, H5T_STD_I64LE, 1, one, &count, err);
    double *rows = s->row_scratch;
    if (!st) {
        by_id(s, s->pos, s->dim, 3, rows);
        const hsize_t dims[2] = {(hsize_t)n, 3};
        st = sph_h5_write(&w, vtk, "Points", H5T_NATIVE_DOUBLE, position_type(s), 2, dims, rows,
                          err);
    }
    /* one vertex cell per particle */
    int64_t *ids = (int64_t *)rows; /* n + 1 int64 fit in the n*6 doubles */
    for (int64_t k = 0; k <= n; ++k) ids[k] = k;
    const hsize_t ndims[1] = {(hsize_t)n}, odims[1] = {(hsize_t)n + 1};
    if (!st)
        st = sph_h5_write(&w, vtk, "Connectivity", H5T_NATIVE_INT64, H5T_STD_I64LE, 1, ndims, ids,
                          err);
    if (!st)
        st = sph_h5_write(&w, vtk, "Offsets", H5T_NATIVE_INT64, H5T_STD_I64LE, 1, odims, ids, err);
    if (!st) {
        uint8_t *types = (uint8_t *)rows;
        memset(types, VTK_VERTEX, (size_t)n);
        st = sph_h5_write(&w, vtk, "Types", H5T_NATIVE_UINT8, H5T_STD_U8LE, 1, ndims, types, err);
    }
    if (!st) st = sph_h5_group(&w, vtk, "PointData", &pd, err);
    if (!st) st = write_point_data(s, &w, pd, err);
    if (pd >= 0) H5Gclose(pd);
    if (vtk >= 0) H5Gclose(vtk);
    if (!st) st = write_provenance(s, &w, err);
    if (st) {
        sph_h5_abandon(&w);
        return st;
    }
    st = sph_h5_commit(&w, false, err);
    if (!st) st = write_series(s, s->job_index + 1, err);
    return st;
}

static void *writer_main(void *arg) {
    sph_snapshots *s = arg;
    s->job_status = write_file(s, &s->job_err);
    return NULL;
}

sph_status sph_snapshots_wait(sph_snapshots *s, sph_error *err) {
    if (!s->busy) return SPH_OK;
    pthread_join(s->thread, NULL);
    s->busy = false;
    if (s->job_status && err) *err = s->job_err;
    return s->job_status;
}

sph_status sph_snapshots_write(sph_snapshots *s, sph_backend *be, double t, long acoustic_steps,
                               long advection_steps, sph_error *err) {
    sph_status st = sph_snapshots_wait(s, err);
    if (st) return st;
    if (s->count == s->capacity) {
        const int cap = 2 * s->capacity;
        double *times = realloc(s->times, (size_t)cap * sizeof(double));
        if (!times) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory for snapshots");
        s->times = times;
        s->capacity = cap;
    }
    const sph_scene *sc = s->ctx.scene;
    const bool want_stress = sc->output_field[SPH_OUT_PRESSURE] ||
                             sc->output_field[SPH_OUT_VON_MISES] ||
                             sc->output_field[SPH_OUT_SHEAR_STRESS];
    st = be->ops->download(be, FIELD_POS, s->pos, err);
    if (!st) st = be->ops->download(be, FIELD_ID, s->id, err);
    if (!st && sc->output_field[SPH_OUT_VELOCITY])
        st = be->ops->download(be, FIELD_VEL, s->vel, err);
    if (!st && (want_stress || sc->output_field[SPH_OUT_DENSITY]))
        st = be->ops->download(be, FIELD_RHO, s->rho, err);
    if (s->fluid) {
        if (!st && (sc->output_field[SPH_OUT_PRESSURE] || sc->output_field[SPH_OUT_MACH_NUMBER]))
            st = be->ops->download(be, FIELD_PRESSURE, s->pressure, err);
        if (!st && sc->output_field[SPH_OUT_MACH_NUMBER] && !sc->output_field[SPH_OUT_VELOCITY])
            st = be->ops->download(be, FIELD_VEL, s->vel, err);
        if (!st && sc->output_field[SPH_OUT_MACH_NUMBER] && !sc->output_field[SPH_OUT_DENSITY])
            st = be->ops->download(be, FIELD_RHO, s->rho, err);
        if (!st && sc->output_field[SPH_OUT_VORTICITY])
            st = be->ops->download(be, FIELD_VORTICITY, s->vorticity, err);
    } else if (!st && want_stress) {
        st = be->ops->download(be, FIELD_TAU, s->tau, err);
    }
    if (!st && sc->output_field[SPH_OUT_PLASTIC_STRAIN])
        st = be->ops->download(be, FIELD_PLASTIC_STRAIN, s->alpha, err);
    if (!st && (want_stress || sc->output_field[SPH_OUT_MATERIAL_ID])) {
        if (be->fields[FIELD_MATERIAL].present)
            st = be->ops->download(be, FIELD_MATERIAL, s->material, err);
        else
            memset(s->material, 0, (size_t)s->n);
    }
    if (!st && sc->output_field[SPH_OUT_BODY_ID]) {
        if (be->fields[FIELD_BODY].present)
            st = be->ops->download(be, FIELD_BODY, s->body, err);
        else
            memset(s->body, 0, (size_t)s->n);
    }
    if (st) return st;
    s->job_index = s->count;
    s->job_time = t;
    s->job_acoustic = acoustic_steps;
    s->job_advection = advection_steps;
    s->times[s->count++] = t;
    if (pthread_create(&s->thread, NULL, writer_main, s) != 0) {
        /* no thread: write on this one */
        st = write_file(s, err);
        return st;
    }
    s->busy = true;
    return SPH_OK;
}

void sph_snapshots_close(sph_snapshots *s) {
    sph_snapshots_wait(s, NULL);
    free(s->times);
    free(s->pos);
    free(s->vel);
    free(s->rho);
    free(s->tau);
    free(s->alpha);
    free(s->id);
    free(s->body);
    free(s->material);
    free(s->row_scratch);
    free(s->pressure);
    free(s->vorticity);
    memset(s, 0, sizeof *s);
}
