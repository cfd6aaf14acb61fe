#include "checkpoint.h"

#include "hdf5_file.h"
#include "snapshot.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* 3: the precision as a name (mixed precision); 4: the monitor's gradient
 * scale (the run's largest velocity gradient so far) in the series; 5: the
 * run's checkpoint settings (attributes checkpoint_every, checkpoint_wall),
 * so that a restart goes on writing checkpoints.  Format 4 differs only by
 * their absence and still restarts. */
#define CHECKPOINT_FORMAT        5
#define CHECKPOINT_FORMAT_OLDEST 4
#define DIAG_VALUES              11 /* kinetic, strain, momentum[3], angular[3], monitor[3] */
/* series_fluid: mass, total energy, wall pressure force[3], wall viscous force[3] */
#define FLUID_VALUES 8

void sph_checkpoint_path(const char *run_dir, char *buf, size_t len) {
    snprintf(buf, len, "%s/checkpoint/checkpoint.h5", run_dir);
}

static void diag_pack(const sph_diagnostics *d, double *out) {
    out[0] = d->kinetic;
    out[1] = d->strain;
    for (int a = 0; a < 3; ++a) {
        out[2 + a] = d->momentum[a];
        out[5 + a] = d->angular[a];
    }
    out[8] = d->min_distance_ratio;
    out[9] = d->zigzag;
    out[10] = d->gradient_scale;
}

static void diag_unpack(const double *in, sph_diagnostics *d) {
    d->kinetic = in[0];
    d->strain = in[1];
    for (int a = 0; a < 3; ++a) {
        d->momentum[a] = in[2 + a];
        d->angular[a] = in[5 + a];
    }
    d->min_distance_ratio = in[8];
    d->zigzag = in[9];
    d->gradient_scale = in[10];
}

static hid_t field_memtype(sph_field_type t) {
    return sph_field_is_real(t) ? H5T_NATIVE_DOUBLE
                                : (t == FIELD_TYPE_INT32 ? H5T_NATIVE_INT32 : H5T_NATIVE_UINT8);
}

static size_t field_host_size(sph_field_type t) {
    return sph_field_is_real(t) ? sizeof(double)
                                : (t == FIELD_TYPE_INT32 ? sizeof(int32_t) : sizeof(uint8_t));
}

static sph_status write_fields(const sph_h5_writer *w, sph_backend *be, sph_error *err) {
    hid_t g;
    sph_status st = sph_h5_group(w, w->file, "fields", &g, err);
    if (st) return st;
    void *scratch = NULL;
    for (int f = 0; !st && f < FIELD_COUNT; ++f) {
        const sph_field_info *info = &be->fields[f];
        if (!info->present || sph_field_is_derived((sph_field)f)) continue;
        const size_t count = (size_t)be->n * (size_t)info->components;
        void *buf = realloc(scratch, count * sizeof(double));
        if (!buf) {
            st = sph_fail(err, SPH_ERR_RUNTIME, "out of host memory for a checkpoint");
            break;
        }
        scratch = buf;
        st = be->ops->download(be, (sph_field)f, scratch, err);
        if (st) break;
        /* reals are stored in the field's precision: the restore is exact */
        const hid_t filetype =
            sph_field_is_real(info->type)
                ? (sph_field_element_size(info->type, &be->features) == sizeof(double)
                       ? H5T_IEEE_F64LE
                       : H5T_IEEE_F32LE)
                : (info->type == FIELD_TYPE_INT32 ? H5T_STD_I32LE : H5T_STD_U8LE);
        const hsize_t dims[1] = {(hsize_t)count};
        st = sph_h5_write(w, g, info->name, field_memtype(info->type), filetype, 1, dims, scratch,
                          err);
    }
    free(scratch);
    H5Gclose(g);
    return st;
}

static sph_status write_series(const sph_h5_writer *w, const sph_timeseries *ts, sph_error *err) {
    const hsize_t count = (hsize_t)ts->count;
    const size_t per_row = (size_t)(ts->nobservers * ts->dim);
    double *diag = malloc((size_t)count * DIAG_VALUES * sizeof(double) + 1);
    if (!diag) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory for a checkpoint");
    for (hsize_t k = 0; k < count; ++k) diag_pack(&ts->diag[k], diag + k * DIAG_VALUES);
    const hsize_t d1[1] = {count}, d2[2] = {count, DIAG_VALUES},
                  d3[2] = {count, (hsize_t)(per_row > 0 ? per_row : 1)};
    sph_status st = sph_h5_write(w, w->file, "series_time", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1,
                                 d1, ts->time, err);
    if (!st)
        st = sph_h5_write(w, w->file, "series_diagnostics", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 2,
                          d2, diag, err);
    if (!st && per_row > 0)
        st = sph_h5_write(w, w->file, "series_observers", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 2, d3,
                          ts->observers, err);
    /* fluids: the total mass and energy of each row (zeros for solids; a
     * checkpoint without the dataset restores zeros) */
    if (!st) {
        for (hsize_t k = 0; k < count; ++k) {
            double *row = diag + FLUID_VALUES * k;
            row[0] = ts->diag[k].mass;
            row[1] = ts->diag[k].total_energy;
            for (int a = 0; a < 3; ++a) {
                row[2 + a] = ts->diag[k].wall_pressure_force[a];
                row[5 + a] = ts->diag[k].wall_viscous_force[a];
            }
        }
        const hsize_t d4[2] = {count, FLUID_VALUES};
        st = sph_h5_write(w, w->file, "series_fluid", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 2, d4,
                          diag, err);
    }
    free(diag);
    return st;
}

sph_status sph_checkpoint_write(const char *run_dir, sph_backend *be,
                                const sph_checkpoint_header *h, const sph_timeseries *ts,
                                const char *scene_text, sph_error *err) {
    char dir[1100], path[1200];
    snprintf(dir, sizeof dir, "%s/checkpoint", run_dir);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot create %s: %s", dir, strerror(errno));
    sph_checkpoint_path(run_dir, path, sizeof path);
    sph_h5_writer w;
    sph_status st = sph_h5_create(&w, path, err);
    if (st) return st;
    const hid_t root = w.file;
    const int64_t ints[] = {CHECKPOINT_FORMAT,  be->n,        h->output_index, h->acoustic_steps,
                            h->advection_steps, h->nsnapshots};
    const char *names[] = {"format",         "particles",       "output_index",
                           "acoustic_steps", "advection_steps", "snapshot_count"};
    for (size_t k = 0; !st && k < sizeof ints / sizeof ints[0]; ++k)
        st = sph_h5_attr_int64s(&w, root, names[k], &ints[k], 1, err);
    if (!st) st = sph_h5_attr_double(&w, root, "time", h->time, err);
    if (!st) st = sph_h5_attr_double(&w, root, "max_speed2", h->max_speed2, err);
    if (!st) st = sph_h5_attr_double(&w, root, "checkpoint_every", h->checkpoint_every, err);
    if (!st) st = sph_h5_attr_double(&w, root, "checkpoint_wall", h->checkpoint_wall, err);
    if (!st) st = sph_h5_attr_string(&w, root, "backend", be->kind_name, err);
    if (!st) st = sph_h5_attr_string(&w, root, "precision", sph_precision_name(&be->features), err);
    if (!st) st = sph_h5_attr_string(&w, root, "sphsolid_version", SPHSOLID_VERSION, err);
    if (!st) {
        /* the scene as a dataset: attributes are limited to 64 KiB */
        const hsize_t len[1] = {strlen(scene_text) + 1};
        st = sph_h5_write(&w, root, "scene_text", H5T_NATIVE_CHAR, H5T_NATIVE_CHAR, 1, len,
                          scene_text, err);
    }
    double carried[SPH_CARRIED_LEN];
    memcpy(carried, h->carried, sizeof carried);
    const hsize_t clen[1] = {SPH_CARRIED_LEN}, slen[1] = {(hsize_t)h->nsnapshots};
    if (!st)
        st = sph_h5_write(&w, root, "carried", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, clen, carried,
                          err);
    if (!st && h->nsnapshots > 0)
        st = sph_h5_write(&w, root, "snapshot_times", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, slen,
                          h->snapshot_times, err);
    if (!st) st = write_series(&w, ts, err);
    if (!st) st = write_fields(&w, be, err);
    if (st) {
        sph_h5_abandon(&w);
        return st;
    }
    return sph_h5_commit(&w, true, err);
}

sph_status sph_checkpoint_read_scene(const char *run_dir, char **scene_text, sph_error *err) {
    char path[1200];
    sph_checkpoint_path(run_dir, path, sizeof path);
    *scene_text = NULL;
    hid_t file;
    sph_status st = sph_h5_open_read(path, &file, err);
    if (st) return st;
    size_t len = 0;
    st = sph_h5_size(file, path, "scene_text", &len, err);
    char *text = st ? NULL : calloc(len + 1, 1);
    if (!st && !text) st = sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    if (!st) st = sph_h5_read(file, path, "scene_text", H5T_NATIVE_CHAR, text, len, err);
    H5Fclose(file);
    if (st) {
        free(text);
        return st;
    }
    *scene_text = text;
    return SPH_OK;
}

static sph_status read_int(hid_t f, const char *path, const char *name, long *out, sph_error *err) {
    int64_t v = 0;
    sph_status st = sph_h5_read_attr_int64(f, path, name, &v, err);
    *out = (long)v;
    return st;
}

/* The format, refused clearly when this sphsolid cannot read it. */
static sph_status read_format(hid_t f, const char *path, long *format, sph_error *err) {
    sph_status st = read_int(f, path, "format", format, err);
    if (!st && (*format < CHECKPOINT_FORMAT_OLDEST || *format > CHECKPOINT_FORMAT))
        st = sph_fail(err, SPH_ERR_INPUT,
                      "%s: checkpoint format %ld, this sphsolid reads formats %d to %d", path,
                      *format, CHECKPOINT_FORMAT_OLDEST, CHECKPOINT_FORMAT);
    return st;
}

/* The checkpoint settings; format 4 has none (0: no checkpoints). */
static sph_status read_settings(hid_t f, const char *path, long format, double *every, double *wall,
                                sph_error *err) {
    *every = *wall = 0.0;
    if (format < 5) return SPH_OK;
    sph_status st = sph_h5_read_attr_double(f, path, "checkpoint_every", every, err);
    if (!st) st = sph_h5_read_attr_double(f, path, "checkpoint_wall", wall, err);
    if (!st && (!(*every >= 0.0) || !(*wall >= 0.0) || !isfinite(*every) || !isfinite(*wall)))
        st = sph_fail(err, SPH_ERR_INPUT, "%s: checkpoint settings %g, %g: not valid intervals",
                      path, *every, *wall);
    return st;
}

sph_status sph_checkpoint_read_info(const char *run_dir, sph_checkpoint_info *info,
                                    sph_error *err) {
    memset(info, 0, sizeof *info);
    char path[1200];
    sph_checkpoint_path(run_dir, path, sizeof path);
    hid_t f;
    sph_status st = sph_h5_open_read(path, &f, err);
    if (st) return st;
    st = read_format(f, path, &info->format, err);
    if (!st) st = sph_h5_read_attr_double(f, path, "time", &info->time, err);
    if (!st)
        st = read_settings(f, path, info->format, &info->checkpoint_every, &info->checkpoint_wall,
                           err);
    H5Fclose(f);
    return st;
}

/* The snapshots a checkpoint lists were complete when it was taken; a run
 * that failed later marked them .partial (output.c): a restart continues
 * that run, so they are results again. */
static void restore_snapshots(const char *run_dir, long count) {
    for (long k = 0; k < count && k <= INT32_MAX; ++k) {
        char name[64], path[1200], partial[1300];
        sph_snapshot_name((int)k, name, sizeof name);
        snprintf(path, sizeof path, "%s/%s", run_dir, name);
        snprintf(partial, sizeof partial, "%s.partial", path);
        if (access(path, F_OK) != 0 && access(partial, F_OK) == 0) rename(partial, path);
    }
}

/* A value no run writes: the checkpoint was damaged or edited. */
__attribute__((format(printf, 3, 4))) static sph_status damaged(sph_error *err, const char *path,
                                                                const char *fmt, ...) {
    char what[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return sph_fail(err, SPH_ERR_INPUT,
                    "%s: %s: no run writes such a checkpoint (damaged or edited); restart from "
                    "an intact one or run the scene again",
                    path, what);
}

/* The counters, before anything is allocated or renamed by them.  Every
 * output samples the series and advances output_index (host/run/solver.c),
 * so the series has at least output_index rows (more after a restart that
 * extended a run whose end was not an output time: the end's row, then the
 * grid again, resume_output_index in solver.c); the next output time,
 * output_index * output_interval, is after the time reached; a snapshot is
 * written at outputs only. */
static sph_status check_header(const char *path, const sph_checkpoint_header *h, long nsnap,
                               double output_interval, sph_error *err) {
    if (!(isfinite(h->time) && h->time >= 0.0))
        return damaged(err, path, "attribute 'time' is %g", h->time);
    if (!(isfinite(h->max_speed2) && h->max_speed2 >= 0.0))
        return damaged(err, path, "attribute 'max_speed2' is %g", h->max_speed2);
    if (h->advection_steps < 0 || h->acoustic_steps < h->advection_steps)
        return damaged(err, path,
                       "attributes 'acoustic_steps' %ld and 'advection_steps' %ld (0 <= "
                       "advection_steps <= acoustic_steps)",
                       h->acoustic_steps, h->advection_steps);
    if (h->output_index < 1 || h->output_index > INT32_MAX ||
        !((double)h->output_index * output_interval >= h->time * (1.0 - 1e-12)))
        return damaged(err, path,
                       "attribute 'output_index' %ld at t = %.9g s with time.output_interval = "
                       "%g s (the next output time comes after t)",
                       h->output_index, h->time, output_interval);
    if (nsnap < 0 || nsnap > h->output_index)
        return damaged(err, path,
                       "attribute 'snapshot_count' %ld (from 0 to 'output_index', %ld: snapshots "
                       "are written at outputs)",
                       nsnap, h->output_index);
    return SPH_OK;
}

/* Non-decreasing finite times from 0 to t; `name` for the message. */
static sph_status check_times(const char *path, const char *name, const double *v, size_t count,
                              double t, sph_error *err) {
    for (size_t k = 0; k < count; ++k)
        if (!(isfinite(v[k]) && v[k] >= 0.0 && v[k] <= t && (k == 0 || v[k] >= v[k - 1])))
            return damaged(err, path,
                           "dataset '%s'[%zu] is %.9g (times from 0 to t = %.9g s, in order)", name,
                           k, v[k], t);
    return SPH_OK;
}

static sph_status check_finite(const char *path, const char *name, const double *v, size_t count,
                               sph_error *err) {
    for (size_t k = 0; k < count; ++k)
        if (!isfinite(v[k])) return damaged(err, path, "dataset '%s'[%zu] is %g", name, k, v[k]);
    return SPH_OK;
}

/* The fields against the scene: finite reals, positive mass, volume and
 * density, the ids a permutation of the scene's particles (the backends
 * index the initial set by them), and each particle's body, material,
 * constraint and kind those of the particle of its id. */
static sph_status check_fields(const char *path, const sph_backend *be, const sph_checkpoint *ck,
                               const sph_particles *initial, sph_error *err) {
    const int n = be->n;
    for (int k = 0; k < FIELD_COUNT; ++k) {
        const sph_field_info *info = &be->fields[k];
        if (!ck->field[k] || !sph_field_is_real(info->type)) continue;
        const double *v = ck->field[k];
        const size_t count = (size_t)n * (size_t)info->components;
        const bool positive = k == FIELD_MASS || k == FIELD_VOL || k == FIELD_RHO;
        for (size_t i = 0; i < count; ++i)
            if (!isfinite(v[i]) || (positive && !(v[i] > 0.0)))
                return damaged(err, path, "fields/%s[%zu] is %g%s", info->name, i, v[i],
                               positive ? " (positive in every run)" : "");
    }
    const int32_t *id = ck->field[FIELD_ID];
    if (!id || initial->n != n) return damaged(err, path, "no 'fields/id' of %d particles", n);
    unsigned char *seen = calloc((size_t)n, 1);
    if (!seen) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    sph_status st = SPH_OK;
    for (int s = 0; !st && s < n; ++s) {
        const int32_t i = id[s];
        if (i < 0 || i >= n || seen[i]) {
            st = damaged(err, path,
                         "fields/id[%d] is %d (the ids are the scene's particles 0 to %d, each "
                         "once)",
                         s, (int)i, n - 1);
            break;
        }
        seen[i] = 1;
        static const struct {
            sph_field field;
            const char *what;
        } tags[] = {{FIELD_BODY, "body"},
                    {FIELD_MATERIAL, "material"},
                    {FIELD_FIXED, "constraint"},
                    {FIELD_KIND, "kind"}};
        for (size_t t = 0; t < sizeof tags / sizeof tags[0]; ++t) {
            const uint8_t *have = ck->field[tags[t].field];
            const uint8_t *want = tags[t].field == FIELD_BODY       ? initial->body
                                  : tags[t].field == FIELD_MATERIAL ? initial->material
                                  : tags[t].field == FIELD_FIXED    ? initial->fixed
                                                                    : initial->kind;
            if (!have || !want || have[s] == want[i]) continue;
            st = damaged(err, path,
                         "fields/%s[%d] is %d, but the scene gives particle %d (fields/id) %s %d",
                         be->fields[tags[t].field].name, s, (int)have[s], (int)i, tags[t].what,
                         (int)want[i]);
            break;
        }
    }
    free(seen);
    const int32_t *contacts = ck->field[FIELD_CONTACT_COUNT];
    for (int s = 0; !st && contacts && s < n; ++s)
        if (contacts[s] < 0 || contacts[s] > n)
            st = damaged(err, path, "fields/contact_count[%d] is %d", s, (int)contacts[s]);
    return st;
}

sph_status sph_checkpoint_read(const char *run_dir, const sph_backend *be,
                               const sph_checkpoint_scene *scene, sph_checkpoint *ck,
                               sph_timeseries *ts, sph_error *err) {
    memset(ck, 0, sizeof *ck);
    char path[1200];
    sph_checkpoint_path(run_dir, path, sizeof path);
    hid_t f;
    sph_status st = sph_h5_open_read(path, &f, err);
    if (st) return st;
    long format = 0, n = 0, nsnap = 0;
    char *backend = NULL, *precision = NULL;
    st = read_format(f, path, &format, err);
    if (!st)
        st = read_settings(f, path, format, &ck->h.checkpoint_every, &ck->h.checkpoint_wall, err);
    if (!st) st = read_int(f, path, "particles", &n, err);
    if (!st && n != be->n)
        st = sph_fail(err, SPH_ERR_INPUT,
                      "%s: the checkpoint has %ld particles, the scene makes %d", path, n, be->n);
    if (!st) st = read_int(f, path, "output_index", &ck->h.output_index, err);
    if (!st) st = read_int(f, path, "acoustic_steps", &ck->h.acoustic_steps, err);
    if (!st) st = read_int(f, path, "advection_steps", &ck->h.advection_steps, err);
    if (!st) st = read_int(f, path, "snapshot_count", &nsnap, err);
    if (!st) st = sph_h5_read_attr_double(f, path, "time", &ck->h.time, err);
    if (!st) st = sph_h5_read_attr_double(f, path, "max_speed2", &ck->h.max_speed2, err);
    if (!st) st = sph_h5_read_attr_string(f, path, "backend", &backend, err);
    if (!st) st = sph_h5_read_attr_string(f, path, "precision", &precision, err);
    if (!st) {
        snprintf(ck->backend, sizeof ck->backend, "%s", backend);
        snprintf(ck->precision, sizeof ck->precision, "%s", precision);
        ck->n = (int)n;
        st =
            sph_h5_read(f, path, "carried", H5T_NATIVE_DOUBLE, ck->h.carried, SPH_CARRIED_LEN, err);
    }
    free(backend);
    free(precision);
    if (!st) st = check_header(path, &ck->h, nsnap, scene->output_interval, err);
    if (!st) st = check_finite(path, "carried", ck->h.carried, SPH_CARRIED_LEN, err);
    /* the series' length bounds output_index, and so the snapshot count,
     * by what the file holds before anything is allocated by them */
    size_t rows = 0;
    if (!st) st = sph_h5_size(f, path, "series_time", &rows, err);
    if (!st && rows < (size_t)ck->h.output_index)
        st = damaged(err, path,
                     "dataset 'series_time' has %zu rows, attribute 'output_index' %ld (a row "
                     "per output)",
                     rows, ck->h.output_index);
    if (!st && nsnap > 0) {
        ck->h.nsnapshots = (int)nsnap;
        ck->h.snapshot_times = malloc((size_t)nsnap * sizeof(double));
        st = ck->h.snapshot_times ? sph_h5_read(f, path, "snapshot_times", H5T_NATIVE_DOUBLE,
                                                ck->h.snapshot_times, (size_t)nsnap, err)
                                  : sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
        if (!st)
            st = check_times(path, "snapshot_times", ck->h.snapshot_times, (size_t)nsnap,
                             ck->h.time, err);
    }
    /* the series */
    const size_t per_row = (size_t)(ts->nobservers * ts->dim);
    double *time = NULL, *diag = NULL, *obs = NULL;
    if (!st) {
        time = malloc(rows * sizeof(double) + 1);
        diag = malloc(rows * DIAG_VALUES * sizeof(double) + 1);
        obs = calloc(rows * per_row + 1, sizeof(double));
        if (!time || !diag || !obs) st = sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    if (!st) st = sph_h5_read(f, path, "series_time", H5T_NATIVE_DOUBLE, time, rows, err);
    if (!st)
        st = sph_h5_read(f, path, "series_diagnostics", H5T_NATIVE_DOUBLE, diag, rows * DIAG_VALUES,
                         err);
    if (!st && per_row > 0)
        st = sph_h5_read(f, path, "series_observers", H5T_NATIVE_DOUBLE, obs, rows * per_row, err);
    double *fluid = NULL;
    if (!st && H5Lexists(f, "series_fluid", H5P_DEFAULT) > 0) {
        fluid = malloc(rows * FLUID_VALUES * sizeof(double) + 1);
        st = fluid ? sph_h5_read(f, path, "series_fluid", H5T_NATIVE_DOUBLE, fluid,
                                 rows * FLUID_VALUES, err)
                   : sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    if (!st) st = check_times(path, "series_time", time, rows, ck->h.time, err);
    if (!st) st = check_finite(path, "series_diagnostics", diag, rows * DIAG_VALUES, err);
    if (!st) st = check_finite(path, "series_observers", obs, rows * per_row, err);
    if (!st && fluid) st = check_finite(path, "series_fluid", fluid, rows * FLUID_VALUES, err);
    for (size_t k = 0; !st && k < rows; ++k) {
        sph_diagnostics d = {0};
        diag_unpack(diag + k * DIAG_VALUES, &d);
        if (fluid) {
            const double *row = fluid + FLUID_VALUES * k;
            d.mass = row[0];
            d.total_energy = row[1];
            for (int a = 0; a < 3; ++a) {
                d.wall_pressure_force[a] = row[2 + a];
                d.wall_viscous_force[a] = row[5 + a];
            }
        }
        st = sph_timeseries_append(ts, time[k], &d, obs + k * per_row, err);
    }
    free(fluid);
    free(time);
    free(diag);
    free(obs);
    /* the fields */
    const hid_t g = st ? -1 : H5Gopen2(f, "fields", H5P_DEFAULT);
    if (!st && g < 0) st = sph_fail(err, SPH_ERR_INPUT, "%s: no group 'fields'", path);
    for (int k = 0; !st && k < FIELD_COUNT; ++k) {
        const sph_field_info *info = &be->fields[k];
        if (!info->present || sph_field_is_derived((sph_field)k)) continue;
        const size_t count = (size_t)be->n * (size_t)info->components;
        ck->field[k] = malloc(count * field_host_size(info->type));
        if (!ck->field[k]) {
            st = sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
            break;
        }
        st = sph_h5_read(g, path, info->name, field_memtype(info->type), ck->field[k], count, err);
    }
    if (g >= 0) H5Gclose(g);
    H5Fclose(f);
    if (!st) st = check_fields(path, be, ck, scene->initial, err);
    if (st)
        sph_checkpoint_free(ck);
    else
        restore_snapshots(run_dir, nsnap);
    return st;
}

sph_status sph_checkpoint_restore(const sph_checkpoint *ck, sph_backend *be, sph_error *err) {
    sph_status st = SPH_OK;
    for (int k = 0; !st && k < FIELD_COUNT; ++k)
        if (be->fields[k].present && !sph_field_is_derived((sph_field)k))
            st = be->ops->upload_field(be, (sph_field)k, ck->field[k], err);
    if (!st) st = be->ops->upload_carried(be, ck->h.carried, err);
    return st;
}

void sph_checkpoint_free(sph_checkpoint *ck) {
    for (int k = 0; k < FIELD_COUNT; ++k) free(ck->field[k]);
    free(ck->h.snapshot_times);
    memset(ck, 0, sizeof *ck);
}
