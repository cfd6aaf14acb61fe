#include "output.h"

#include "hdf5_file.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* A failed run leaves nothing that looks like a complete result: the time
 * series, the snapshots and their index get (or keep) the `.partial` suffix;
 * they stay for inspection.  The checkpoint stays as it is: it is a restart
 * point, not a result (a restart renames the snapshots it keeps back,
 * checkpoint.c). */
static void demote_results(const char *dir) {
    char from[1400], to[1500];
    const char *files[] = {"timeseries.csv", "snapshots.hdf.series"};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; ++k) {
        snprintf(from, sizeof from, "%s/%s", dir, files[k]);
        snprintf(to, sizeof to, "%s.partial", from);
        if (access(from, F_OK) == 0) rename(from, to);
    }
    char sub[1100];
    snprintf(sub, sizeof sub, "%s/snapshots", dir);
    DIR *d = opendir(sub);
    if (!d) return;
    for (struct dirent *e = readdir(d); e; e = readdir(d)) {
        int index = -1, used = 0;
        if (sscanf(e->d_name, "snapshot_%d.hdf%n", &index, &used) != 1 || e->d_name[used] != '\0')
            continue;
        snprintf(from, sizeof from, "%s/%s", sub, e->d_name);
        snprintf(to, sizeof to, "%s.partial", from);
        rename(from, to);
    }
    closedir(d);
}

/* A stream's pending output reached the disk; with SPHSOLID_TEST_DISK_FULL
 * matching `path`, it did not (ENOSPC). */
static bool stream_ok(FILE *f, const char *path) {
    if (sph_test_disk_full(path)) {
        errno = ENOSPC;
        return false;
    }
    return !ferror(f) && fflush(f) == 0;
}

sph_status sph_output_make_dirs(const char *dir, sph_error *err) {
    char path[1024];
    if (snprintf(path, sizeof path, "%s", dir) >= (int)sizeof path)
        return sph_fail(err, SPH_ERR_INPUT, "--out %s: path too long", dir);
    for (char *p = path + 1; *p; ++p) {
        if (*p != '/') continue;
        *p = '\0';
        if (mkdir(path, 0777) != 0 && errno != EEXIST)
            return sph_fail(err, SPH_ERR_RUNTIME, "cannot create output directory %s: %s", path,
                            strerror(errno));
        *p = '/';
    }
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot create output directory %s: %s", path,
                        strerror(errno));
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))
        return sph_fail(err, SPH_ERR_RUNTIME, "output path %s is not a directory", path);
    return SPH_OK;
}

static const char *axis_name(int a) {
    return a == 0 ? "x" : (a == 1 ? "y" : "z");
}

/* Most columns of timeseries.csv: the fixed ones and 3 per observer. */
#define MAX_COLUMNS (20 + 3 * SPH_SCENE_MAX_OBSERVERS)

/* The header's column names.  They are written as they are, unquoted:
 * `sphsolid compare` and tools/plot_run.py split lines at commas, so no
 * column name may hold a comma, a quote or a line break, and none may repeat
 * another.  The scene's name rule (sph_name_check) keeps observer names so;
 * a scene built otherwise (a test, the fuzz harness) is refused here the
 * same way rather than writing a file its readers reject. */
static sph_status csv_columns(const sph_scene *scene, char names[][SPH_NAME_LEN + 24], int *count,
                              sph_error *err) {
    int n = 0;
    /* fluids (the eulerian formulations): the internal energy where solids
     * have the strain energy, the total mass, and no monitor columns (fixed
     * particles neither cluster nor zigzag) */
    const bool fluid = SPH_FORMULATION_IS_EULERIAN(scene->formulation);
    const char *fixed[] = {"time", "kinetic_energy", fluid ? "internal_energy" : "strain_energy",
                           "total_energy"};
    for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; ++k)
        snprintf(names[n++], SPH_NAME_LEN + 24, "%s", fixed[k]);
    if (fluid) snprintf(names[n++], SPH_NAME_LEN + 24, "mass");
    for (int a = 0; a < scene->dim; ++a)
        snprintf(names[n++], SPH_NAME_LEN + 24, "momentum_%s", axis_name(a));
    if (scene->dim == 2) {
        snprintf(names[n++], SPH_NAME_LEN + 24, "angular_momentum");
    } else if (scene->dim == 3) { /* a line has no angular momentum */
        for (int a = 0; a < 3; ++a)
            snprintf(names[n++], SPH_NAME_LEN + 24, "angular_momentum_%s", axis_name(a));
    }
    if (!fluid) {
        snprintf(names[n++], SPH_NAME_LEN + 24, "min_distance_ratio");
        snprintf(names[n++], SPH_NAME_LEN + 24, "zigzag_indicator");
    }
    /* fluids with forces: the coefficients (004 §4.3) and the force on the
     * walls, pressure and viscous parts */
    if (fluid && scene->has_forces) {
        snprintf(names[n++], SPH_NAME_LEN + 24, "drag_coefficient");
        snprintf(names[n++], SPH_NAME_LEN + 24, "lift_coefficient");
        for (int a = 0; a < scene->dim; ++a)
            snprintf(names[n++], SPH_NAME_LEN + 24, "pressure_force_%s", axis_name(a));
        for (int a = 0; a < scene->dim; ++a)
            snprintf(names[n++], SPH_NAME_LEN + 24, "viscous_force_%s", axis_name(a));
    }
    if (scene->nobservers < 0 || scene->nobservers > SPH_SCENE_MAX_OBSERVERS)
        return sph_fail(err, SPH_ERR_INPUT, "timeseries.csv: %d observers (at most %d)",
                        scene->nobservers, SPH_SCENE_MAX_OBSERVERS);
    for (int o = 0; o < scene->nobservers; ++o) {
        char why[256];
        if (!sph_name_check(scene->observers[o].name, why, sizeof why))
            return sph_fail(err, SPH_ERR_INPUT, "timeseries.csv: observers[%d].name: %s", o, why);
        /* a position's components, or a traction's (scene.h, sph_observed) */
        const bool traction = scene->observers[o].quantity == SPH_OBSERVE_TRACTION;
        for (int a = 0; a < scene->dim; ++a)
            snprintf(names[n++], SPH_NAME_LEN + 24, "%s_%s%s", scene->observers[o].name,
                     traction ? "traction_" : "", axis_name(a));
    }
    for (int c = 1; c < n; ++c)
        for (int k = 0; k < c; ++k)
            if (strcmp(names[c], names[k]) == 0)
                return sph_fail(err, SPH_ERR_INPUT,
                                "timeseries.csv: column %s would appear twice (an observer's name "
                                "repeats another or a built-in column)",
                                names[c]);
    *count = n;
    return SPH_OK;
}

sph_status sph_output_open(sph_output *out, const char *dir, const sph_scene *scene,
                           const sph_timeseries *resumed, sph_error *err) {
    memset(out, 0, sizeof *out);
    if (scene->dim < 1 || scene->dim > 3)
        return sph_fail(err, SPH_ERR_INPUT, "timeseries.csv: dimension %d", scene->dim);
    char columns[MAX_COLUMNS][SPH_NAME_LEN + 24];
    int ncolumns = 0;
    sph_status st = csv_columns(scene, columns, &ncolumns, err);
    if (st) return st;
    st = sph_output_make_dirs(dir, err);
    if (st) return st;
    snprintf(out->dir, sizeof out->dir, "%s", dir);
    snprintf(out->csv_final, sizeof out->csv_final, "%s/timeseries.csv", dir);
    snprintf(out->csv_partial, sizeof out->csv_partial, "%s/timeseries.csv.partial", dir);
    char old_summary[1100];
    snprintf(old_summary, sizeof old_summary, "%s/summary.json", dir);
    char old_checkpoint[1100];
    snprintf(old_checkpoint, sizeof old_checkpoint, "%s/checkpoint/checkpoint.h5", dir);
    if ((unlink(out->csv_final) != 0 && errno != ENOENT) ||
        (unlink(old_summary) != 0 && errno != ENOENT) ||
        (!resumed && unlink(old_checkpoint) != 0 && errno != ENOENT))
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot remove the previous results in %s: %s", dir,
                        strerror(errno));
    out->csv = fopen(out->csv_partial, "w");
    if (!out->csv)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", out->csv_partial,
                        strerror(errno));
    out->dim = scene->dim;
    out->nobservers = scene->nobservers;
    out->fluid = SPH_FORMULATION_IS_EULERIAN(scene->formulation);
    out->forces = out->fluid && scene->has_forces;
    out->scene = scene;
    for (int c = 0; c < ncolumns; ++c) fprintf(out->csv, "%s%s", c ? "," : "", columns[c]);
    fputc('\n', out->csv);
    if (!stream_ok(out->csv, out->csv_partial))
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", out->csv_partial,
                        strerror(errno));
    const size_t per_row = (size_t)(scene->nobservers * scene->dim);
    for (int k = 0; resumed && k < resumed->count; ++k) {
        sph_status rst = sph_output_row(out, resumed->time[k], &resumed->diag[k],
                                        resumed->observers + (size_t)k * per_row, err);
        if (rst) return rst;
    }
    return SPH_OK;
}

sph_status sph_output_row(sph_output *out, double t, const sph_diagnostics *d,
                          const double *observers, sph_error *err) {
    FILE *f = out->csv;
    if (out->fluid)
        fprintf(f, "%.9g,%.12g,%.12g,%.15g,%.15g", t, d->kinetic, d->strain, d->total_energy,
                d->mass);
    else
        fprintf(f, "%.9g,%.12g,%.12g,%.12g", t, d->kinetic, d->strain, d->kinetic + d->strain);
    for (int a = 0; a < out->dim; ++a) fprintf(f, ",%.12g", d->momentum[a]);
    if (out->dim == 2)
        fprintf(f, ",%.12g", d->angular[2]);
    else if (out->dim == 3)
        fprintf(f, ",%.12g,%.12g,%.12g", d->angular[0], d->angular[1], d->angular[2]);
    if (!out->fluid) fprintf(f, ",%.6g,%.6g", d->min_distance_ratio, d->zigzag);
    if (out->forces) {
        double cd, cl;
        sph_force_coefficients(out->scene, d, &cd, &cl);
        fprintf(f, ",%.12g,%.12g", cd, cl);
        for (int a = 0; a < out->dim; ++a) fprintf(f, ",%.12g", d->wall_pressure_force[a]);
        for (int a = 0; a < out->dim; ++a) fprintf(f, ",%.12g", d->wall_viscous_force[a]);
    }
    for (int k = 0; k < out->nobservers * out->dim; ++k) fprintf(f, ",%.12g", observers[k]);
    fputc('\n', f);
    if (!stream_ok(f, out->csv_partial))
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", out->csv_partial,
                        strerror(errno));
    return SPH_OK;
}

sph_status sph_output_close(sph_output *out, bool success, sph_error *err) {
    if (!out->csv) return SPH_OK;
    const int failed = ferror(out->csv) | fclose(out->csv);
    out->csv = NULL;
    if (!success) {
        demote_results(out->dir);
        return SPH_OK;
    }
    if (failed) {
        const sph_status st = sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s",
                                       out->csv_partial, strerror(errno));
        demote_results(out->dir);
        return st;
    }
    if (rename(out->csv_partial, out->csv_final) != 0) {
        const sph_status st = sph_fail(err, SPH_ERR_RUNTIME, "cannot rename %s to %s: %s",
                                       out->csv_partial, out->csv_final, strerror(errno));
        demote_results(out->dir);
        return st;
    }
    return SPH_OK;
}

sph_status sph_output_write_json(const char *dir, const char *name, json_object *obj,
                                 sph_error *err) {
    char final_path[1100], partial[1200];
    snprintf(final_path, sizeof final_path, "%s/%s", dir, name);
    snprintf(partial, sizeof partial, "%s.partial", final_path);
    /* summary.json is written last: without it the run is not complete */
    const bool summary = strcmp(name, "summary.json") == 0;
    FILE *f = fopen(partial, "w");
    if (!f) {
        const sph_status st =
            sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", partial, strerror(errno));
        if (summary) demote_results(dir);
        return st;
    }
    const char *text = json_object_to_json_string_ext(obj, JSON_C_TO_STRING_PRETTY |
                                                               JSON_C_TO_STRING_NOSLASHESCAPE);
    const bool bad = fputs(text, f) < 0 || fputc('\n', f) == EOF || !stream_ok(f, partial);
    const int write_errno = errno;
    const int closed = fclose(f);
    if (bad || closed != 0) {
        const sph_status st = sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", partial,
                                       strerror(bad ? write_errno : errno));
        unlink(partial);
        if (summary) demote_results(dir);
        return st;
    }
    if (rename(partial, final_path) != 0) {
        const sph_status st =
            sph_fail(err, SPH_ERR_RUNTIME, "cannot rename %s: %s", partial, strerror(errno));
        unlink(partial);
        if (summary) demote_results(dir);
        return st;
    }
    return SPH_OK;
}

/* The length of the well-formed UTF-8 sequence at s[0..n) (n > 0), or 0 with
 * the length of its maximal ill-formed subpart in *bad (Unicode 15, 3.9,
 * Table 3-7: the second byte's range depends on the first). */
static size_t utf8_sequence(const unsigned char *s, size_t n, size_t *bad) {
    const unsigned char c = s[0];
    size_t len;
    unsigned char lo = 0x80, hi = 0xBF; /* the second byte's range */
    if (c < 0x80) return 1;
    if (c >= 0xC2 && c <= 0xDF)
        len = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        len = 3;
        if (c == 0xE0) lo = 0xA0; /* overlong */
        if (c == 0xED) hi = 0x9F; /* surrogates */
    } else if (c >= 0xF0 && c <= 0xF4) {
        len = 4;
        if (c == 0xF0) lo = 0x90; /* overlong */
        if (c == 0xF4) hi = 0x8F; /* beyond U+10FFFF */
    } else {
        *bad = 1; /* a continuation byte, C0, C1 or F5..FF */
        return 0;
    }
    size_t k = 1;
    for (; k < len && k < n; ++k) {
        const unsigned char b = s[k];
        if (k == 1 ? (b < lo || b > hi) : (b < 0x80 || b > 0xBF)) break;
    }
    if (k == len) return len;
    *bad = k;
    return 0;
}

char *sph_utf8_repair(const char *s, size_t len, size_t *out_len) {
    /* U+FFFD takes 3 bytes and replaces at least 1 */
    if (len > (SIZE_MAX - 1) / 3) return NULL;
    char *out = malloc(3 * len + 1);
    if (!out) return NULL;
    const unsigned char *p = (const unsigned char *)s;
    size_t i = 0, o = 0;
    while (i < len) {
        size_t bad = 0;
        const size_t n = utf8_sequence(p + i, len - i, &bad);
        if (n) {
            memcpy(out + o, p + i, n);
            o += n;
            i += n;
        } else {
            memcpy(out + o, "\xEF\xBF\xBD", 3);
            o += 3;
            i += bad;
        }
    }
    out[o] = '\0';
    *out_len = o;
    return out;
}

json_object *sph_json_string_len(const char *s, size_t len) {
    if (!s) return json_object_new_string("");
    size_t n = 0;
    char *text = sph_utf8_repair(s, len, &n);
    if (!text || n > INT_MAX) {
        free(text);
        return NULL;
    }
    /* with its length: a NUL byte stays one (json-c writes \u0000) */
    json_object *o = json_object_new_string_len(text, (int)n);
    free(text);
    return o;
}

json_object *sph_json_string(const char *s) {
    return sph_json_string_len(s, s ? strlen(s) : 0);
}
