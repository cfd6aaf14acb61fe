/* fuzz_checkpoint.c — libFuzzer harness over the checkpoint reader (the
 * input convention is in fuzz_checkpoint.h): a valid checkpoint, edited
 * through HDF5 as the input says (values, lengths, types, missing parts),
 * read as `sphsolid run --restart` reads it.
 *
 * Besides "no crash, no leak, no undefined behaviour, no hang", every input
 * must end in one of two ways, checked here so that the fuzzer reports a
 * violation as a crash:
 *   - refused with SPH_ERR_INPUT and a message naming the checkpoint file;
 *   - accepted, with what checkpoint.h promises a restart: a finite time
 *     >= 0, the same in the info and the state; the scene's particle count;
 *     a series row per output (at least output_index rows) and at most
 *     output_index snapshots, their times in order up to the time; every real value
 *     finite, mass, volume and density positive; the ids a permutation of
 *     the scene's particles and each particle's body and kind those the
 *     scene gives the particle of its id.
 * The invariants are restated here, not called from checkpoint.c.
 *
 * The checkpoint is written once per process by sph_checkpoint_write from a
 * stand-in backend whose fields are the scene's particles in reversed order
 * (so that slot and id differ), and copied back before each input.
 *
 * Build: cmake -DCMAKE_C_COMPILER=clang -DSPHSOLID_FUZZ=ON (docs/tests.md, "Fuzzing"). */
#include "fuzz_checkpoint.h"

#include "checkpoint.h"
#include "fields.h"
#include "particles.h"
#include "scene.h"

#include <float.h>
#include <hdf5.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A 3 x 2 box of fluid at dp = 0.25 around a wall disc of radius 0.5 (its
 * particles at dp/2), far field on every side: the fields of walls and a far
 * field (kind, body, normal, wall_force), about 130 particles. */
static const char SCENE[] =
    "title = \"fuzz_checkpoint\";\n"
    "dimension = 2;\n"
    "resolution = { dp = 0.25; };\n"
    "method = { formulation = \"eulerian-wc\"; kernel = \"laguerre-gauss\"; };\n"
    "time = { end = 1.0; output_interval = 0.1; };\n"
    "materials = { fluid = { density = 1.0; sound_speed = 10.0; viscosity = 0.02; }; };\n"
    "shapes = {\n"
    "  box = { type = \"box\"; lower = [0.0, 0.0]; upper = [3.0, 2.0]; };\n"
    "  disc = { type = \"disc\"; centre = [1.0, 1.0]; radius = 0.5; };\n"
    "  flow = { type = \"difference\"; parts = [\"box\", \"disc\"]; };\n"
    "};\n"
    "boundary = { lower = [0.0, 0.0]; upper = [3.0, 2.0];\n"
    "             far_field = { density = 1.0; velocity = [1.0, 0.0]; }; };\n"
    "bodies = ( { name = \"fluid\"; material = \"fluid\"; shape = \"flow\"; },\n"
    "           { name = \"cylinder\"; role = \"wall\"; shape = \"disc\"; spacing = 0.5; } );\n"
    "forces = { reference_density = 1.0; reference_speed = 1.0; reference_length = 1.0; };\n";

/* The pristine checkpoint: 0.5 s into the scene, six outputs (0 to 0.5 s),
 * two snapshots. */
#define PRISTINE_TIME    0.5
#define PRISTINE_OUTPUTS 6

/* The stand-in backend: sph_checkpoint_write downloads the fields from it. */
typedef struct {
    sph_backend be; /* first: the ops get &be */
    const sph_particles *p;
} standin_backend;

typedef struct {
    bool ready;
    char dir[512], path[1200];
    uint8_t *bytes; /* the pristine file */
    size_t nbytes;
    sph_scene scene;
    sph_particles particles;
    standin_backend standin;
} fixture;

/* The process's fixture: libFuzzer calls the entry point with inputs only,
 * so the checkpoint written once is kept here (this harness's own state;
 * nothing of the library is global). */
static fixture the_fixture;

__attribute__((format(printf, 2, 3))) static void violate(fuzz_checkpoint_result *res,
                                                          const char *fmt, ...) {
    if (res->violation[0]) return; /* keep the first */
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(res->violation, sizeof res->violation, fmt, ap);
    va_end(ap);
}

/* ---- the stand-in backend ---------------------------------------------- */

static int id_of_slot(int n, int s) {
    return n - 1 - s;
}

static sph_status standin_download(sph_backend *be, sph_field field, void *host, sph_error *err) {
    (void)err;
    const sph_particles *p = ((standin_backend *)be)->p;
    const int n = be->n;
    const sph_field_info *info = &be->fields[field];
    for (int s = 0; s < n; ++s) {
        const int i = id_of_slot(n, s);
        if (sph_field_is_real(info->type)) {
            double *out = host;
            for (int a = 0; a < info->components; ++a) {
                double v = 0.0;
                if (field == FIELD_POS) v = p->pos[(size_t)a * n + i];
                if (field == FIELD_VEL) v = p->vel[(size_t)a * n + i];
                if (field == FIELD_NORMAL && p->normal) v = p->normal[(size_t)a * n + i];
                if (field == FIELD_MASS) v = p->mass[i];
                if (field == FIELD_RHO) v = p->rho[i];
                if (field == FIELD_VOL) v = p->mass[i] / p->rho[i];
                out[(size_t)a * n + s] = v;
            }
        } else if (info->type == FIELD_TYPE_INT32) {
            ((int32_t *)host)[s] = field == FIELD_ID ? i : 0;
        } else {
            const uint8_t *from = field == FIELD_BODY       ? p->body
                                  : field == FIELD_MATERIAL ? p->material
                                  : field == FIELD_FIXED    ? p->fixed
                                  : field == FIELD_KIND     ? p->kind
                                                            : NULL;
            ((uint8_t *)host)[s] = from ? from[i] : 0;
        }
    }
    return SPH_OK;
}

static const sph_backend_ops standin_ops = {.download = standin_download};

/* ---- the fixture -------------------------------------------------------- */

static void remove_fixture(void) {
    fixture *fx = &the_fixture;
    if (!fx->ready) return;
    char sub[1024];
    unlink(fx->path);
    snprintf(sub, sizeof sub, "%.900s/checkpoint", fx->dir);
    rmdir(sub);
    rmdir(fx->dir);
    free(fx->bytes);
    sph_particles_free(&fx->particles);
    sph_scene_free(&fx->scene);
    fx->ready = false;
}

static bool make_fixture(fixture *fx) {
    sph_error err = {0};
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    const char *tmp = getenv("TMPDIR");
    snprintf(fx->dir, sizeof fx->dir, "%s/fuzz_checkpoint.XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(fx->dir)) return false;
    sph_checkpoint_path(fx->dir, fx->path, sizeof fx->path);
    if (sph_scene_load_text(&fx->scene, "fuzz_checkpoint.cfg", SCENE, NULL, 0, &err) ||
        sph_particles_generate(&fx->scene, &fx->particles, &err)) {
        fprintf(stderr, "fuzz_checkpoint: the fixture's scene: %s\n", err.msg);
        return false;
    }
    sph_backend *be = &fx->standin.be;
    fx->standin.p = &fx->particles;
    be->ops = &standin_ops;
    be->kind_name = "cpu";
    be->n = fx->particles.n;
    sph_features_from_scene(&fx->scene, &fx->particles, SPH_PRECISION_DOUBLE, &be->features);
    sph_fields_layout(&be->features, be->fields);

    sph_timeseries ts;
    if (sph_timeseries_init(&ts, fx->scene.dim, fx->scene.nobservers, &err)) return false;
    sph_status st = SPH_OK;
    for (int k = 0; !st && k < PRISTINE_OUTPUTS; ++k) {
        sph_diagnostics d = {0};
        d.kinetic = 0.1 * k;
        d.mass = 6.0;
        d.min_distance_ratio = 0.9;
        st = sph_timeseries_append(&ts, 0.1 * k, &d, NULL, &err);
    }
    double snapshot_times[2] = {0.0, PRISTINE_TIME};
    sph_checkpoint_header h = {.time = PRISTINE_TIME,
                               .max_speed2 = 1.0,
                               .output_index = PRISTINE_OUTPUTS,
                               .acoustic_steps = 100,
                               .advection_steps = 100,
                               .nsnapshots = 2,
                               .snapshot_times = snapshot_times};
    h.carried[0] = 1.0;
    if (!st) st = sph_checkpoint_write(fx->dir, be, &h, &ts, fx->scene.resolved_text, &err);
    sph_timeseries_free(&ts);
    if (st) {
        fprintf(stderr, "fuzz_checkpoint: writing the fixture: %s\n", err.msg);
        return false;
    }
    FILE *f = fopen(fx->path, "rb");
    if (!f) return false;
    fseek(f, 0, SEEK_END);
    const long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    fx->bytes = len > 0 ? malloc((size_t)len) : NULL;
    fx->nbytes = fx->bytes ? fread(fx->bytes, 1, (size_t)len, f) : 0;
    fclose(f);
    if (fx->nbytes != (size_t)len) return false;
    fx->ready = true;
    atexit(remove_fixture);
    return true;
}

/* ---- the edits ------------------------------------------------------------ */

static const char *const TARGET_NAMES[FUZZ_TARGET_FIRST_FIELD] = {
    [FUZZ_TARGET_FORMAT] = "format",
    [FUZZ_TARGET_PARTICLES] = "particles",
    [FUZZ_TARGET_OUTPUT_INDEX] = "output_index",
    [FUZZ_TARGET_ACOUSTIC_STEPS] = "acoustic_steps",
    [FUZZ_TARGET_ADVECTION_STEPS] = "advection_steps",
    [FUZZ_TARGET_SNAPSHOT_COUNT] = "snapshot_count",
    [FUZZ_TARGET_TIME] = "time",
    [FUZZ_TARGET_MAX_SPEED2] = "max_speed2",
    [FUZZ_TARGET_CHECKPOINT_EVERY] = "checkpoint_every",
    [FUZZ_TARGET_CHECKPOINT_WALL] = "checkpoint_wall",
    [FUZZ_TARGET_BACKEND] = "backend",
    [FUZZ_TARGET_PRECISION] = "precision",
    [FUZZ_TARGET_CARRIED] = "carried",
    [FUZZ_TARGET_SNAPSHOT_TIMES] = "snapshot_times",
    [FUZZ_TARGET_SERIES_TIME] = "series_time",
    [FUZZ_TARGET_SERIES_DIAGNOSTICS] = "series_diagnostics",
    [FUZZ_TARGET_SERIES_FLUID] = "series_fluid"};

typedef struct {
    int op, mode, index;
    int8_t small;
    uint8_t raw[8];
} edit;

static double special_double(int8_t k) {
    const double v[] = {NAN,     INFINITY, -INFINITY,         -0.0,
                        DBL_MAX, 4.9e-324, (double)INT64_MAX, -(double)INT64_MAX};
    return v[(uint8_t)k % 8];
}

static int64_t special_int(int8_t k, int n) {
    const int64_t v[] = {0, -1, INT64_MAX, INT64_MIN, INT32_MAX, (int64_t)INT32_MAX + 1, 1, n};
    return v[(uint8_t)k % 8];
}

/* The value an edit gives, from the value there now. */
static double value_double(const edit *e, double now) {
    double raw;
    memcpy(&raw, e->raw, sizeof raw);
    switch (e->mode) {
    case FUZZ_VALUE_RAW:
        return raw;
    case FUZZ_VALUE_SCALE:
        return now * (1.0 + e->small / 16.0);
    case FUZZ_VALUE_SMALL:
        return e->small;
    default:
        return special_double(e->small);
    }
}

static int64_t value_int(const edit *e, int64_t now, int n) {
    int64_t raw;
    memcpy(&raw, e->raw, sizeof raw);
    switch (e->mode) {
    case FUZZ_VALUE_RAW:
        return raw;
    case FUZZ_VALUE_SCALE: {
        const double v = (double)now * (1.0 + e->small / 16.0);
        return v > -9.2e18 && v < 9.2e18 ? (int64_t)v : 0;
    }
    case FUZZ_VALUE_SMALL:
        return e->small;
    default:
        return special_int(e->small, n);
    }
}

static bool is_integer_type(hid_t type) {
    return H5Tget_class(type) == H5T_INTEGER;
}

static void write_string_attribute(hid_t loc, const char *name, const edit *e) {
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, 8);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(loc, name, t, space, H5P_DEFAULT, H5P_DEFAULT);
    if (a >= 0) {
        H5Awrite(a, t, e->raw);
        H5Aclose(a);
    }
    H5Sclose(space);
    H5Tclose(t);
}

static void edit_attribute(hid_t file, const char *name, const edit *e, int n) {
    hid_t type = -1;
    const hid_t old = H5Aopen(file, name, H5P_DEFAULT);
    bool integer = false, string = false;
    double now_d = 0.0;
    int64_t now_i = 0;
    if (old >= 0) {
        type = H5Aget_type(old);
        integer = type >= 0 && is_integer_type(type);
        string = type >= 0 && H5Tget_class(type) == H5T_STRING;
        /* the value there when it is one (an earlier edit may have made an
         * array of it) */
        const hid_t space = H5Aget_space(old);
        const bool one = space >= 0 && H5Sget_simple_extent_npoints(space) == 1;
        if (space >= 0) H5Sclose(space);
        if (one && integer)
            H5Aread(old, H5T_NATIVE_INT64, &now_i);
        else if (one && !string)
            H5Aread(old, H5T_NATIVE_DOUBLE, &now_d);
        if (type >= 0) H5Tclose(type);
        H5Aclose(old);
    }
    H5Adelete(file, name);
    if (e->op == FUZZ_EDIT_DELETE) return;
    if (e->op == FUZZ_EDIT_STRING || string) {
        write_string_attribute(file, name, e);
        return;
    }
    /* op 1: an array of `index % 4` values (a scalar when 0) */
    const hsize_t count = e->op == FUZZ_EDIT_RESIZE ? (hsize_t)(e->index % 4) : 0;
    const hid_t space = count ? H5Screate_simple(1, &count, NULL) : H5Screate(H5S_SCALAR);
    const hid_t ftype = integer ? H5T_STD_I64LE : H5T_IEEE_F64LE;
    const hid_t a = H5Acreate2(file, name, ftype, space, H5P_DEFAULT, H5P_DEFAULT);
    if (a >= 0) {
        int64_t iv[4];
        double dv[4];
        for (int k = 0; k < 4; ++k) {
            iv[k] = value_int(e, now_i, n);
            dv[k] = value_double(e, now_d);
        }
        H5Awrite(a, integer ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE, integer ? (void *)iv : dv);
        H5Aclose(a);
    }
    H5Sclose(space);
}

static void edit_dataset(hid_t file, const char *name, const edit *e, int n) {
    const hid_t ds = H5Dopen2(file, name, H5P_DEFAULT);
    hid_t ftype = -1;
    hssize_t len = 0;
    if (ds >= 0) {
        ftype = H5Dget_type(ds);
        const hid_t space = H5Dget_space(ds);
        len = space >= 0 ? H5Sget_simple_extent_npoints(space) : 0;
        if (space >= 0) H5Sclose(space);
    }
    const bool integer = ftype >= 0 && is_integer_type(ftype);
    if (e->op == FUZZ_EDIT_SET && ds >= 0 && len > 0) {
        /* one value (of any rank, counted in storage order), converted to
         * the file's type by HDF5: the whole dataset read and written back */
        const size_t at = (size_t)e->index % (size_t)len;
        if (integer) {
            int64_t *v = malloc((size_t)len * sizeof *v);
            if (v && H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0) {
                v[at] = value_int(e, v[at], n);
                H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
            }
            free(v);
        } else {
            double *v = malloc((size_t)len * sizeof *v);
            if (v && H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0) {
                v[at] = value_double(e, v[at]);
                H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
            }
            free(v);
        }
    }
    if (ds >= 0) H5Dclose(ds);
    if (e->op == FUZZ_EDIT_SET) {
        if (ftype >= 0) H5Tclose(ftype);
        return;
    }
    H5Ldelete(file, name, H5P_DEFAULT);
    if (e->op == FUZZ_EDIT_RESIZE) {
        /* `index % 1024` values of the old type, each the value given */
        const hsize_t count = (hsize_t)(e->index % 1024);
        const hid_t space = H5Screate_simple(1, &count, NULL);
        const hid_t t = ftype >= 0 ? ftype : H5T_IEEE_F64LE;
        const hid_t nds = H5Dcreate2(file, name, t, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        if (nds >= 0 && count > 0) {
            if (integer) {
                int64_t *v = malloc(count * sizeof *v);
                for (hsize_t k = 0; v && k < count; ++k) v[k] = value_int(e, 0, n);
                if (v) H5Dwrite(nds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
                free(v);
            } else {
                double *v = malloc(count * sizeof *v);
                for (hsize_t k = 0; v && k < count; ++k) v[k] = value_double(e, 1.0);
                if (v) H5Dwrite(nds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
                free(v);
            }
        }
        if (nds >= 0) H5Dclose(nds);
        H5Sclose(space);
    } else if (e->op == FUZZ_EDIT_STRING) {
        /* a string in place of the numbers */
        const hsize_t count = 1;
        const hid_t t = H5Tcopy(H5T_C_S1);
        H5Tset_size(t, 8);
        const hid_t space = H5Screate_simple(1, &count, NULL);
        const hid_t nds = H5Dcreate2(file, name, t, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        if (nds >= 0) {
            H5Dwrite(nds, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, e->raw);
            H5Dclose(nds);
        }
        H5Sclose(space);
        H5Tclose(t);
    }
    if (ftype >= 0) H5Tclose(ftype);
}

/* The targets: the attributes, the datasets, then each stored field. */
static int target_count(const fixture *fx, const char **fields, int max_fields) {
    int nf = 0;
    for (int k = 0; k < FIELD_COUNT && nf < max_fields; ++k)
        if (fx->standin.be.fields[k].present && !sph_field_is_derived((sph_field)k))
            fields[nf++] = fx->standin.be.fields[k].name;
    return FUZZ_TARGET_FIRST_FIELD + nf;
}

static int apply_edits(const fixture *fx, const uint8_t *data, size_t size) {
    const char *fields[FIELD_COUNT];
    const int ntargets = target_count(fx, fields, FIELD_COUNT);
    const hid_t file = H5Fopen(fx->path, H5F_ACC_RDWR, H5P_DEFAULT);
    if (file < 0) return -1;
    int applied = 0;
    for (size_t at = 0;
         at + FUZZ_CHECKPOINT_EDIT_BYTES <= size && applied < FUZZ_CHECKPOINT_MAX_EDITS;
         at += FUZZ_CHECKPOINT_EDIT_BYTES, ++applied) {
        const uint8_t *b = data + at;
        const edit e = {.op = b[1] & 3,
                        .mode = (b[1] >> 2) & 3,
                        .index = b[2] | (b[3] << 8),
                        .small = (int8_t)b[4],
                        .raw = {b[4], b[5], b[6], b[7], b[8], b[9], b[10], b[11]}};
        const int target = b[0] % ntargets;
        const int n = fx->standin.be.n;
        if (target < FUZZ_TARGET_ATTRIBUTES) {
            edit_attribute(file, TARGET_NAMES[target], &e, n);
        } else if (target < FUZZ_TARGET_FIRST_FIELD) {
            edit_dataset(file, TARGET_NAMES[target], &e, n);
        } else {
            char name[128];
            snprintf(name, sizeof name, "fields/%s", fields[target - FUZZ_TARGET_FIRST_FIELD]);
            edit_dataset(file, name, &e, n);
        }
    }
    H5Fclose(file);
    return applied;
}

/* ---- the invariants ------------------------------------------------------- */

static void check_accepted(const fixture *fx, const sph_checkpoint_info *info,
                           const sph_checkpoint *ck, const sph_timeseries *ts,
                           fuzz_checkpoint_result *res) {
    const sph_backend *be = &fx->standin.be;
    const sph_particles *p = &fx->particles;
    const int n = be->n;
    const double t = ck->h.time;
    if (!(isfinite(t) && t >= 0.0) || info->time != t)
        violate(res, "accepted the time %g (info %g)", t, info->time);
    if (ck->n != n) violate(res, "accepted %d particles for the scene's %d", ck->n, n);
    if (ts->count < ck->h.output_index)
        violate(res, "accepted %d series rows with output_index %ld", ts->count,
                ck->h.output_index);
    if (ck->h.nsnapshots < 0 || ck->h.nsnapshots > ck->h.output_index)
        violate(res, "accepted %d snapshots with output_index %ld", ck->h.nsnapshots,
                ck->h.output_index);
    for (int k = 0; k < ck->h.nsnapshots; ++k) {
        const double s = ck->h.snapshot_times[k];
        if (!(s >= 0.0 && s <= t && (k == 0 || s >= ck->h.snapshot_times[k - 1])))
            violate(res, "accepted snapshot time %d = %g (t = %g)", k, s, t);
    }
    for (int k = 0; k < ts->count; ++k)
        if (!(ts->time[k] >= 0.0 && ts->time[k] <= t))
            violate(res, "accepted series time %d = %g (t = %g)", k, ts->time[k], t);
    if (!(isfinite(ck->h.max_speed2) && ck->h.max_speed2 >= 0.0))
        violate(res, "accepted max_speed2 %g", ck->h.max_speed2);
    for (int k = 0; k < FIELD_COUNT; ++k) {
        const sph_field_info *f = &be->fields[k];
        if (!f->present || sph_field_is_derived((sph_field)k)) continue;
        if (!ck->field[k]) {
            violate(res, "accepted without the field %s", f->name);
            continue;
        }
        if (!sph_field_is_real(f->type)) continue;
        const double *v = ck->field[k];
        const bool positive = k == FIELD_MASS || k == FIELD_VOL || k == FIELD_RHO;
        for (size_t i = 0; i < (size_t)n * (size_t)f->components; ++i)
            if (!isfinite(v[i]) || (positive && !(v[i] > 0.0)))
                violate(res, "accepted %s[%zu] = %g", f->name, i, v[i]);
    }
    const int32_t *id = ck->field[FIELD_ID];
    const uint8_t *kind = ck->field[FIELD_KIND], *body = ck->field[FIELD_BODY];
    if (!id) return;
    int *count = calloc((size_t)n, sizeof *count);
    for (int s = 0; count && s < n; ++s) {
        if (id[s] < 0 || id[s] >= n || count[id[s]]++) {
            violate(res, "accepted id[%d] = %d", s, (int)id[s]);
            break;
        }
        if (kind && p->kind && kind[s] != p->kind[id[s]])
            violate(res, "accepted kind[%d] = %d for particle %d of kind %d", s, kind[s],
                    (int)id[s], p->kind[id[s]]);
        if (body && body[s] != p->body[id[s]])
            violate(res, "accepted body[%d] = %d for particle %d of body %d", s, body[s],
                    (int)id[s], p->body[id[s]]);
    }
    free(count);
}

void fuzz_checkpoint_run(const uint8_t *data, size_t size, fuzz_checkpoint_result *res) {
    memset(res, 0, sizeof *res);
    fixture *fx = &the_fixture;
    if (!fx->ready && !make_fixture(fx)) {
        violate(res, "the fixture could not be made");
        return;
    }
    FILE *f = fopen(fx->path, "wb");
    const bool copied = f && fwrite(fx->bytes, 1, fx->nbytes, f) == fx->nbytes;
    if (f && fclose(f) != 0) violate(res, "cannot write %s", fx->path);
    if (!copied) {
        violate(res, "cannot write %s", fx->path);
        return;
    }
    res->edits = apply_edits(fx, data, size);
    if (res->edits < 0) {
        violate(res, "the edits could not open %s", fx->path);
        return;
    }

    sph_error err = {0};
    sph_checkpoint_info info;
    sph_status st = sph_checkpoint_read_info(fx->dir, &info, &err);
    sph_checkpoint ck;
    memset(&ck, 0, sizeof ck);
    sph_timeseries ts;
    if (sph_timeseries_init(&ts, fx->scene.dim, fx->scene.nobservers, &err)) {
        violate(res, "out of memory for the series");
        return;
    }
    if (!st) {
        const sph_checkpoint_scene scene = {&fx->particles, fx->scene.output_interval};
        st = sph_checkpoint_read(fx->dir, &fx->standin.be, &scene, &ck, &ts, &err);
    }
    res->accepted = st == SPH_OK;
    if (st) {
        snprintf(res->message, sizeof res->message, "%.1000s", err.msg);
        if (st != SPH_ERR_INPUT) violate(res, "refused with status %d: %s", (int)st, err.msg);
        if (!strstr(err.msg, fx->path))
            violate(res, "the refusal does not name %s: %s", fx->path, err.msg);
    } else {
        check_accepted(fx, &info, &ck, &ts, res);
        sph_checkpoint_free(&ck);
    }
    sph_timeseries_free(&ts);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fuzz_checkpoint_result res;
    fuzz_checkpoint_run(data, size, &res);
    if (res.violation[0]) {
        fprintf(stderr, "fuzz_checkpoint: invariant violated: %s\n", res.violation);
        abort();
    }
    return 0;
}
