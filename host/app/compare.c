#include "compare.h"

#include <errno.h>
#include <hdf5.h>
#include <json-c/json.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

/* Unmatched snapshots listed one by one before "... and N more". */
#define MAX_LISTED_SNAPSHOTS 10

/* Times (rows, snapshots) agree to this fraction of the larger end time. */
#define TIME_RTOL 1e-9

typedef struct {
    char path[PATH_MAX];
    bool partial; /* timeseries.csv.partial: a torn last line is dropped */
    int ncols;
    char **names;
    int nrows;
    double *v; /* nrows x ncols, row-major */
} csv_table;

typedef struct {
    char *name; /* relative to the run directory */
    double time;
} series_file;

typedef struct {
    char path[PATH_MAX];
    int n;
    series_file *files;
} series_index;

/* What summary.json says about a run. */
typedef struct {
    /* summary.json present with status "completed" or "unstable" */
    bool complete;
    char why[384];                     /* why not, when not complete */
    char note[384];                    /* "unstable": where the monitor stopped it, else "" */
    double scale[SPH_COMPARE_NSCALES]; /* "scales" (NaN when absent) */
} run_summary;

typedef struct {
    const char *dir;
    char label; /* 'A' or 'B' */
    bool has_csv, has_series;
    csv_table csv;
    series_index series;
    run_summary summary;
} run_files;

typedef struct {
    char path[PATH_MAX];
    hid_t file, vtk, pointdata; /* pointdata: H5I_INVALID_HID when there is none */
} snapshot_file;

typedef struct {
    double *v; /* n x ncomp */
    long n;
    int ncomp;
} field_data;

/* --fields bookkeeping: which requested names were compared at least once. */
typedef struct {
    const sph_compare_options *opt;
    bool *found;
} field_filter;

void sph_compare_options_default(sph_compare_options *opt) {
    memset(opt, 0, sizeof *opt);
    opt->rtol = 1e-9;
    opt->atol = 0.0;
}

/* summary.json "scales" keys (named so in the report) and the
 * timeseries.csv columns each one scales, by SPH_COMPARE_SCALE_*. */
static const char *const scale_keys[SPH_COMPARE_NSCALES] = {"momentum", "angular_momentum",
                                                            "energy"};
static const char *const scale_columns[SPH_COMPARE_NSCALES] = {
    "momentum_*", "angular_momentum*", "kinetic_energy, strain_energy, total_energy"};

/* The physical scale of a time-series column: the quantities that are zero
 * in theory in many runs (the linear momentum of a spinning plate, the
 * angular momentum of a translating bar, the strain energy of a rigid
 * motion) are compared against the size they would have if they were not,
 * not against their own round-off.  -1: none (relative to its values). */
static int column_scale(const char *name) {
    if (strncmp(name, "momentum_", 9) == 0) return SPH_COMPARE_SCALE_MOMENTUM;
    if (strcmp(name, "angular_momentum") == 0 || strncmp(name, "angular_momentum_", 17) == 0)
        return SPH_COMPARE_SCALE_ANGULAR_MOMENTUM;
    if (strcmp(name, "kinetic_energy") == 0 || strcmp(name, "strain_energy") == 0 ||
        strcmp(name, "total_energy") == 0)
        return SPH_COMPARE_SCALE_ENERGY;
    return -1;
}

/* ---- result bookkeeping ------------------------------------------------ */

static sph_status add_note(sph_compare_result *res, bool failure, sph_error *err, const char *fmt,
                           ...) __attribute__((format(printf, 4, 5)));

static sph_status add_note(sph_compare_result *res, bool failure, sph_error *err, const char *fmt,
                           ...) {
    sph_compare_note note = {.failure = failure};
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(note.text, sizeof note.text, fmt, ap);
    va_end(ap);
    if (failure) res->failed = true;
    /* the same field can be missing from every snapshot: say it once */
    for (int k = 0; k < res->nnotes; ++k)
        if (strcmp(res->notes[k].text, note.text) == 0) return SPH_OK;
    if (res->nnotes == res->notes_cap) {
        const int cap = res->notes_cap ? 2 * res->notes_cap : 16;
        sph_compare_note *grown = realloc(res->notes, (size_t)cap * sizeof *grown);
        if (!grown) return sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory");
        res->notes = grown;
        res->notes_cap = cap;
    }
    res->notes[res->nnotes++] = note;
    return SPH_OK;
}

static sph_compare_item *get_item(sph_compare_result *res, const char *name, sph_compare_kind kind,
                                  sph_error *err) {
    for (int k = 0; k < res->nitems; ++k)
        if (res->items[k].kind == kind && strcmp(res->items[k].name, name) == 0)
            return &res->items[k];
    if (res->nitems == res->items_cap) {
        const int cap = res->items_cap ? 2 * res->items_cap : 16;
        sph_compare_item *grown = realloc(res->items, (size_t)cap * sizeof *grown);
        if (!grown) {
            sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory");
            return NULL;
        }
        res->items = grown;
        res->items_cap = cap;
    }
    sph_compare_item *it = &res->items[res->nitems++];
    memset(it, 0, sizeof *it);
    sph_format(it->name, sizeof it->name, "%s", name);
    it->kind = kind;
    it->physical_scale = -1;
    return it;
}

/* Fold one comparison (a row range or a snapshot) into the item. */
static void item_update(sph_compare_result *res, sph_compare_item *it, sph_compare_where w,
                        const sph_compare_options *opt) {
    w.rel = w.abs == 0.0 ? 0.0 : (w.scale > 0.0 ? w.abs / w.scale : INFINITY);
    if (it->ncompared == 0 || w.abs > it->max.abs) it->max = w;
    it->ncompared++;
    const double tol = opt->atol + opt->rtol * w.scale;
    if (w.abs > tol) {
        const double excess = tol > 0.0 ? w.abs / tol : INFINITY;
        if (!it->failed || excess > it->worst_excess) {
            it->worst = w;
            it->worst_excess = excess;
        }
        it->failed = true;
        res->failed = true;
    }
}

/* |a - b| where NaN in one run only is an infinite difference and equal
 * non-finite values (NaN in both, the same infinity) are no difference. */
static double difference(double a, double b) {
    if (isnan(a) || isnan(b)) return isnan(a) && isnan(b) ? 0.0 : INFINITY;
    if (a == b) return 0.0;
    return fabs(a - b);
}

static bool time_match(double a, double b, double tol) {
    return fabs(a - b) <= tol;
}

/* ---- timeseries.csv ---------------------------------------------------- */

static void csv_free(csv_table *t) {
    for (int c = 0; c < t->ncols; ++c) free(t->names[c]);
    free(t->names);
    free(t->v);
    t->names = NULL;
    t->v = NULL;
    t->ncols = t->nrows = 0;
}

static char *trim(char *s) {
    while (*s == ' ' || *s == '\t') ++s;
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r' || s[n - 1] == '\n'))
        s[--n] = '\0';
    return s;
}

static sph_status csv_header(csv_table *t, char *line, sph_error *err) {
    int n = 1;
    for (const char *p = line; *p; ++p) n += *p == ',';
    t->names = calloc((size_t)n, sizeof *t->names);
    if (!t->names) return sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory");
    char *rest = line;
    for (int c = 0; c < n; ++c) {
        char *comma = strchr(rest, ',');
        if (comma) *comma = '\0';
        const char *name = trim(rest);
        if (!*name)
            return sph_fail(err, SPH_ERR_RUNTIME, "%s: line 1: column %d has no name", t->path,
                            c + 1);
        t->names[c] = strdup(name);
        if (!t->names[c]) return sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory");
        t->ncols = c + 1;
        rest = comma ? comma + 1 : rest + strlen(rest);
    }
    return SPH_OK;
}

static sph_status csv_row(csv_table *t, const char *line, int lineno, int *cap, sph_error *err) {
    if (t->nrows == *cap) {
        const int grown_cap = *cap ? 2 * *cap : 64;
        double *grown = realloc(t->v, (size_t)grown_cap * (size_t)t->ncols * sizeof *grown);
        if (!grown) return sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory");
        t->v = grown;
        *cap = grown_cap;
    }
    double *row = t->v + (size_t)t->nrows * (size_t)t->ncols;
    const char *p = line;
    for (int c = 0; c < t->ncols; ++c) {
        char *end;
        row[c] = strtod(p, &end);
        if (end == p)
            return sph_fail(err, SPH_ERR_RUNTIME, "%s: line %d: column %s is not a number", t->path,
                            lineno, t->names[c]);
        p = end;
        while (*p == ' ' || *p == '\t') ++p;
        const char expected = c + 1 < t->ncols ? ',' : '\0';
        if (*p != expected)
            return sph_fail(err, SPH_ERR_RUNTIME,
                            "%s: line %d: expected %d numbers (one per column)", t->path, lineno,
                            t->ncols);
        if (*p) ++p;
    }
    t->nrows++;
    return SPH_OK;
}

static sph_status csv_read(csv_table *t, sph_error *err) {
    FILE *f = fopen(t->path, "r");
    if (!f) return sph_fail(err, SPH_ERR_RUNTIME, "cannot read %s: %s", t->path, strerror(errno));
    char *line = NULL;
    size_t line_cap = 0;
    int lineno = 0, row_cap = 0;
    sph_status st = SPH_OK;
    ssize_t got;
    while (!st && (got = getline(&line, &line_cap, f)) >= 0) {
        ++lineno;
        /* a killed run's timeseries.csv.partial may end in a row cut short,
         * which may still parse (a number cut in its digits): every row is
         * written with its newline, so a last line without one is dropped */
        if (t->partial && t->names && got > 0 && line[got - 1] != '\n') break;
        char *text = trim(line);
        if (!*text) continue;
        st = t->names ? csv_row(t, text, lineno, &row_cap, err) : csv_header(t, text, err);
    }
    if (!st && ferror(f))
        st = sph_fail(err, SPH_ERR_RUNTIME, "cannot read %s: %s", t->path, strerror(errno));
    free(line);
    fclose(f);
    if (!st && !t->names)
        st = sph_fail(err, SPH_ERR_RUNTIME, "%s: empty file (no header)", t->path);
    return st;
}

static int csv_column(const csv_table *t, const char *name) {
    for (int c = 0; c < t->ncols; ++c)
        if (strcmp(t->names[c], name) == 0) return c;
    return -1;
}

/* ---- snapshots.hdf.series ------------------------------------------- */

static void series_free(series_index *s) {
    for (int k = 0; k < s->n; ++k) free(s->files[k].name);
    free(s->files);
    s->files = NULL;
    s->n = 0;
}

static sph_status series_read(series_index *s, sph_error *err) {
    json_object *root = json_object_from_file(s->path);
    if (!root) {
        char why[512];
        const char *last = json_util_get_last_err();
        sph_format(why, sizeof why, "%s", last ? last : "invalid JSON");
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot read %s: %s", s->path, trim(why));
    }
    sph_status st = SPH_OK;
    json_object *files;
    if (!json_object_object_get_ex(root, "files", &files) ||
        !json_object_is_type(files, json_type_array)) {
        st = sph_fail(err, SPH_ERR_RUNTIME, "%s: no \"files\" array", s->path);
        goto done;
    }
    const size_t n = json_object_array_length(files);
    s->files = calloc(n ? n : 1, sizeof *s->files);
    if (!s->files) {
        st = sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory");
        goto done;
    }
    for (size_t k = 0; k < n; ++k) {
        json_object *entry = json_object_array_get_idx(files, k), *name, *time;
        if (!json_object_is_type(entry, json_type_object) ||
            !json_object_object_get_ex(entry, "name", &name) ||
            !json_object_is_type(name, json_type_string) ||
            !json_object_object_get_ex(entry, "time", &time) ||
            !(json_object_is_type(time, json_type_double) ||
              json_object_is_type(time, json_type_int))) {
            st = sph_fail(err, SPH_ERR_RUNTIME,
                          "%s: files[%zu] needs a string \"name\" and a number \"time\"", s->path,
                          k);
            goto done;
        }
        s->files[k].name = strdup(json_object_get_string(name));
        if (!s->files[k].name) {
            st = sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory");
            goto done;
        }
        s->files[k].time = json_object_get_double(time);
        s->n = (int)k + 1;
    }
done:
    json_object_put(root);
    return st;
}

/* ---- run directories --------------------------------------------------- */

static sph_status join_path(char *buf, size_t len, const char *dir, const char *name,
                            sph_error *err) {
    const int n =
        name[0] == '/' ? snprintf(buf, len, "%s", name) : snprintf(buf, len, "%s/%s", dir, name);
    if (n < 0 || (size_t)n >= len)
        return sph_fail(err, SPH_ERR_INPUT, "path too long: %s/%s", dir, name);
    return SPH_OK;
}

static bool is_file(const char *path) {
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* summary.json: whether the run finished, and its physical scales.  The
 * file is written last, through a temporary name, so its presence is what
 * marks a finished run; a run killed (or still running) has none.  A run
 * the instability monitor stopped ("unstable") finished too, with results
 * up to the stop: comparing two such runs (does the blow-up reproduce?) is
 * a comparison of complete results, and one that stopped earlier than the
 * other has fewer rows, a failure of its own; it is noted, not failed. */
static void summary_read(run_summary *sm, const char *dir, bool partial_csv) {
    for (int k = 0; k < SPH_COMPARE_NSCALES; ++k) sm->scale[k] = NAN;
    sm->complete = false;
    char path[PATH_MAX + 16];
    sph_format(path, sizeof path, "%s/summary.json", dir);
    if (!is_file(path)) {
        sph_format(sm->why, sizeof sm->why,
                   "no summary.json%s: the run was killed or is still running",
                   partial_csv ? " and only timeseries.csv.partial" : "");
        return;
    }
    json_object *root = json_object_from_file(path);
    if (!root || !json_object_is_type(root, json_type_object)) {
        sph_format(sm->why, sizeof sm->why, "%s is not a JSON object", path);
        json_object_put(root);
        return;
    }
    json_object *status = NULL, *scales = NULL;
    const char *text = json_object_object_get_ex(root, "status", &status) &&
                               json_object_is_type(status, json_type_string)
                           ? json_object_get_string(status)
                           : NULL;
    if (!text) {
        sph_format(sm->why, sizeof sm->why, "summary.json has no \"status\"");
    } else if (strcmp(text, "completed") != 0 && strcmp(text, "unstable") != 0) {
        sph_format(sm->why, sizeof sm->why, "summary.json status \"%s\"", text);
    } else if (partial_csv) {
        sph_format(sm->why, sizeof sm->why, "only timeseries.csv.partial");
    } else {
        sm->complete = true;
    }
    json_object *ins = NULL, *time = NULL;
    if (text && strcmp(text, "unstable") == 0) {
        double stop = NAN;
        if (json_object_object_get_ex(root, "instability", &ins) &&
            json_object_object_get_ex(ins, "time", &time))
            stop = json_object_get_double(time);
        sph_format(sm->note, sizeof sm->note,
                   "summary.json status \"unstable\": stopped by the instability monitor at "
                   "t = %.9g s",
                   stop);
    }
    if (json_object_object_get_ex(root, "scales", &scales) &&
        json_object_is_type(scales, json_type_object)) {
        for (int k = 0; k < SPH_COMPARE_NSCALES; ++k) {
            json_object *v = NULL;
            if (!json_object_object_get_ex(scales, scale_keys[k], &v) ||
                !(json_object_is_type(v, json_type_double) ||
                  json_object_is_type(v, json_type_int)))
                continue;
            const double x = json_object_get_double(v);
            if (isfinite(x) && x > 0.0) sm->scale[k] = x;
        }
    }
    json_object_put(root);
}

static sph_status run_open(run_files *r, const char *dir, char label, sph_error *err) {
    r->dir = dir;
    r->label = label;
    struct stat st;
    if (stat(dir, &st) != 0)
        return sph_fail(err, SPH_ERR_INPUT, "run directory %s: %s", dir, strerror(errno));
    if (!S_ISDIR(st.st_mode))
        return sph_fail(err, SPH_ERR_INPUT, "%s is not a run directory (not a directory)", dir);
    sph_status s = join_path(r->csv.path, sizeof r->csv.path, dir, "timeseries.csv", err);
    if (!s) s = join_path(r->series.path, sizeof r->series.path, dir, "snapshots.hdf.series", err);
    if (s) return s;
    r->has_csv = is_file(r->csv.path);
    r->has_series = is_file(r->series.path);
    if (!r->has_csv) {
        /* a killed run's time series: compared as far as it goes, and the
         * run reported incomplete (summary_read) */
        char partial[PATH_MAX + 16];
        sph_format(partial, sizeof partial, "%s.partial", r->csv.path);
        if (is_file(partial) && strlen(partial) < sizeof r->csv.path) {
            sph_format(r->csv.path, sizeof r->csv.path, "%s", partial);
            r->csv.partial = r->has_csv = true;
        }
    }
    if (!r->has_csv && !r->has_series)
        return sph_fail(err, SPH_ERR_INPUT,
                        "%s is not a run directory: it has neither timeseries.csv nor "
                        "snapshots.hdf.series",
                        dir);
    summary_read(&r->summary, dir, r->csv.partial);
    if (r->has_csv && (s = csv_read(&r->csv, err))) return s;
    if (r->has_series && (s = series_read(&r->series, err))) return s;
    return SPH_OK;
}

static void run_free(run_files *r) {
    csv_free(&r->csv);
    series_free(&r->series);
}

/* The largest |time| at the end of either run: the scale of TIME_RTOL. */
static double end_time(const run_files *a, const run_files *b) {
    double t = 0.0;
    const run_files *runs[2] = {a, b};
    for (int k = 0; k < 2; ++k) {
        const run_files *r = runs[k];
        if (r->has_csv && r->csv.nrows > 0) {
            const int tc = csv_column(&r->csv, "time");
            if (tc >= 0) {
                const double v =
                    fabs(r->csv.v[(size_t)(r->csv.nrows - 1) * (size_t)r->csv.ncols + (size_t)tc]);
                if (isfinite(v)) t = fmax(t, v);
            }
        }
        for (int s = 0; s < r->series.n; ++s)
            if (isfinite(r->series.files[s].time)) t = fmax(t, fabs(r->series.files[s].time));
    }
    return t;
}

/* ---- time series ------------------------------------------------------- */

static sph_status compare_timeseries(const run_files *a, const run_files *b,
                                     const sph_compare_options *opt, sph_compare_result *res,
                                     sph_error *err) {
    const csv_table *ta = &a->csv, *tb = &b->csv;
    const int time_a = csv_column(ta, "time"), time_b = csv_column(tb, "time");
    if (time_a < 0) return sph_fail(err, SPH_ERR_RUNTIME, "%s: no \"time\" column", ta->path);
    if (time_b < 0) return sph_fail(err, SPH_ERR_RUNTIME, "%s: no \"time\" column", tb->path);
    res->has_timeseries = true;
    const int nrows = ta->nrows < tb->nrows ? ta->nrows : tb->nrows;
    sph_status st = SPH_OK;
    if (ta->nrows != tb->nrows)
        st = add_note(res, !opt->common_prefix, err,
                      "timeseries.csv: run A has %d rows, run B has %d (the first %d compared)",
                      ta->nrows, tb->nrows, nrows);
    for (int r = 0; !st && r < nrows; ++r) {
        const double t1 = ta->v[(size_t)r * (size_t)ta->ncols + (size_t)time_a];
        const double t2 = tb->v[(size_t)r * (size_t)tb->ncols + (size_t)time_b];
        if (!time_match(t1, t2, res->time_tol)) {
            st = add_note(res, true, err,
                          "timeseries.csv: times differ from line %d on: t = %.17g s in run A, "
                          "%.17g s in run B",
                          r + 2, t1, t2);
            break;
        }
    }
    if (st) return st;
    res->nrows = nrows;
    for (int c = 0; c < ta->ncols; ++c) {
        if (c == time_a) continue;
        const int cb = csv_column(tb, ta->names[c]);
        if (cb < 0) {
            st = add_note(res, false, err, "timeseries.csv column %s is only in run A",
                          ta->names[c]);
            if (st) return st;
            continue;
        }
        if (nrows == 0) continue;
        sph_compare_where w = {.time = ta->v[(size_t)time_a]};
        for (int r = 0; r < nrows; ++r) {
            const double x = ta->v[(size_t)r * (size_t)ta->ncols + (size_t)c];
            const double y = tb->v[(size_t)r * (size_t)tb->ncols + (size_t)cb];
            if (isfinite(x)) w.scale = fmax(w.scale, fabs(x));
            if (isfinite(y)) w.scale = fmax(w.scale, fabs(y));
            const double d = difference(x, y);
            if (d > w.abs) {
                w.abs = d;
                w.time = ta->v[(size_t)r * (size_t)ta->ncols + (size_t)time_a];
            }
        }
        const int kind = column_scale(ta->names[c]);
        /* marked as physical only where it is larger than the values by
         * more than their printed digits (kinetic energy: its own maximum) */
        const bool physical = kind >= 0 && res->scales[kind] > w.scale * (1.0 + 1e-6);
        if (physical) w.scale = res->scales[kind];
        sph_compare_item *it = get_item(res, ta->names[c], SPH_COMPARE_COLUMN, err);
        if (!it) return SPH_ERR_RUNTIME;
        if (physical) it->physical_scale = kind;
        item_update(res, it, w, opt);
    }
    for (int c = 0; c < tb->ncols; ++c) {
        if (c == time_b || csv_column(ta, tb->names[c]) >= 0) continue;
        st = add_note(res, false, err, "timeseries.csv column %s is only in run B", tb->names[c]);
        if (st) return st;
    }
    return SPH_OK;
}

/* ---- snapshots --------------------------------------------------------- */

static void snapshot_close(snapshot_file *s) {
    if (s->pointdata >= 0) H5Gclose(s->pointdata);
    if (s->vtk >= 0) H5Gclose(s->vtk);
    if (s->file >= 0) H5Fclose(s->file);
    s->pointdata = s->vtk = s->file = H5I_INVALID_HID;
}

static sph_status snapshot_open(snapshot_file *s, const run_files *r, const series_file *entry,
                                sph_error *err) {
    s->file = s->vtk = s->pointdata = H5I_INVALID_HID;
    sph_status st = join_path(s->path, sizeof s->path, r->dir, entry->name, err);
    if (st) return st;
    if (!is_file(s->path))
        return sph_fail(err, SPH_ERR_RUNTIME, "%s (listed in %s) does not exist", s->path,
                        r->series.path);
    s->file = H5Fopen(s->path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (s->file < 0) return sph_fail(err, SPH_ERR_RUNTIME, "cannot read %s as HDF5", s->path);
    s->vtk = H5Gopen2(s->file, "VTKHDF", H5P_DEFAULT);
    if (s->vtk < 0)
        return sph_fail(err, SPH_ERR_RUNTIME, "%s: no /VTKHDF group (not a VTKHDF snapshot)",
                        s->path);
    if (H5Lexists(s->vtk, "PointData", H5P_DEFAULT) > 0) {
        s->pointdata = H5Gopen2(s->vtk, "PointData", H5P_DEFAULT);
        if (s->pointdata < 0)
            return sph_fail(err, SPH_ERR_RUNTIME, "%s: cannot open /VTKHDF/PointData", s->path);
    }
    return SPH_OK;
}

/* Read a numeric dataset of shape [N] or [N, C] into doubles.  *why is set
 * (and nothing read) when it is not such a dataset. */
static sph_status read_field(hid_t loc, const char *name, const snapshot_file *s, field_data *out,
                             const char **why, sph_error *err) {
    memset(out, 0, sizeof *out);
    *why = NULL;
    hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
    if (d < 0) {
        *why = "not a dataset";
        return SPH_OK;
    }
    sph_status st = SPH_OK;
    hid_t type = H5Dget_type(d), space = H5Dget_space(d);
    if (type < 0 || space < 0) {
        st = sph_fail(err, SPH_ERR_RUNTIME, "%s: cannot read dataset %s", s->path, name);
        goto done;
    }
    const H5T_class_t cls = H5Tget_class(type);
    if (cls != H5T_INTEGER && cls != H5T_FLOAT) {
        *why = "not numeric";
        goto done;
    }
    hsize_t dims[H5S_MAX_RANK];
    const int rank = H5Sget_simple_extent_dims(space, dims, NULL);
    if (rank < 1 || rank > 2) {
        *why = "not of shape [N] or [N, C]";
        goto done;
    }
    const hsize_t ncomp = rank == 2 ? dims[1] : 1;
    if (dims[0] > (hsize_t)LONG_MAX || ncomp > (hsize_t)INT_MAX ||
        (ncomp > 0 && dims[0] > (hsize_t)(SIZE_MAX / sizeof(double)) / ncomp)) {
        st = sph_fail(err, SPH_ERR_RUNTIME, "%s: dataset %s is too large", s->path, name);
        goto done;
    }
    out->n = (long)dims[0];
    out->ncomp = (int)ncomp;
    const size_t count = (size_t)dims[0] * (size_t)ncomp;
    out->v = malloc(count ? count * sizeof *out->v : 1);
    if (!out->v) {
        st = sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory reading %s from %s", name,
                      s->path);
        goto done;
    }
    if (count && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out->v) < 0)
        st = sph_fail(err, SPH_ERR_RUNTIME, "%s: cannot read dataset %s", s->path, name);
done:
    if (space >= 0) H5Sclose(space);
    if (type >= 0) H5Tclose(type);
    H5Dclose(d);
    if (st) {
        free(out->v);
        out->v = NULL;
    }
    return st;
}

static bool field_selected(const field_filter *ff, const char *name) {
    if (!ff->opt->fields) return true;
    for (int k = 0; k < ff->opt->nfields; ++k)
        if (strcmp(ff->opt->fields[k], name) == 0) return true;
    return false;
}

static void field_mark_found(field_filter *ff, const char *name) {
    if (!ff->opt->fields) return;
    for (int k = 0; k < ff->opt->nfields; ++k)
        if (strcmp(ff->opt->fields[k], name) == 0) ff->found[k] = true;
}

/* One field of one matched snapshot pair; `ids` (or NULL) maps rows to
 * particle ids. */
static sph_status compare_field(const char *name, const field_data *fa, const field_data *fb,
                                const double *ids, double time, const char *snap_name,
                                const sph_compare_options *opt, field_filter *ff,
                                sph_compare_result *res, sph_error *err) {
    if (fa->ncomp != fb->ncomp)
        return add_note(res, true, err,
                        "%s at t = %.9g s: %s has %d components in run A, %d in run B", snap_name,
                        time, name, fa->ncomp, fb->ncomp);
    if (fa->n != fb->n)
        return add_note(res, true, err, "%s at t = %.9g s: %s has %ld rows in run A, %ld in run B",
                        snap_name, time, name, fa->n, fb->n);
    sph_compare_where w = {.time = time};
    size_t worst = 0;
    const size_t count = (size_t)fa->n * (size_t)fa->ncomp;
    for (size_t k = 0; k < count; ++k) {
        const double x = fa->v[k], y = fb->v[k];
        if (isfinite(x)) w.scale = fmax(w.scale, fabs(x));
        if (isfinite(y)) w.scale = fmax(w.scale, fabs(y));
        const double d = difference(x, y);
        if (d > w.abs) {
            w.abs = d;
            worst = k;
        }
    }
    const size_t ncomp = fa->ncomp > 0 ? (size_t)fa->ncomp : 1;
    const long row = (long)(worst / ncomp);
    w.component = (int)(worst % ncomp);
    w.particle = row;
    /* report the particle's id, which is the row unless the file says otherwise */
    if (ids && isfinite(ids[row]) && fabs(ids[row]) < 1e18) w.particle = (long)ids[row];
    sph_compare_item *it = get_item(res, name, SPH_COMPARE_FIELD, err);
    if (!it) return SPH_ERR_RUNTIME;
    item_update(res, it, w, opt);
    field_mark_found(ff, name);
    return SPH_OK;
}

/* Fields in `s` absent from `other` (names of the PointData group). */
static sph_status note_fields_only_in(const snapshot_file *s, const snapshot_file *other,
                                      char label, const field_filter *ff, sph_compare_result *res,
                                      sph_error *err) {
    if (s->pointdata < 0) return SPH_OK;
    H5G_info_t info;
    if (H5Gget_info(s->pointdata, &info) < 0)
        return sph_fail(err, SPH_ERR_RUNTIME, "%s: cannot list /VTKHDF/PointData", s->path);
    for (hsize_t k = 0; k < info.nlinks; ++k) {
        char name[256];
        if (H5Lget_name_by_idx(s->pointdata, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name,
                               H5P_DEFAULT) < 0)
            return sph_fail(err, SPH_ERR_RUNTIME, "%s: cannot list /VTKHDF/PointData", s->path);
        if (!field_selected(ff, name)) continue;
        if (other->pointdata >= 0 && H5Lexists(other->pointdata, name, H5P_DEFAULT) > 0) continue;
        sph_status st =
            add_note(res, false, err, "point-data field %s is only in run %c", name, label);
        if (st) return st;
    }
    return SPH_OK;
}

static sph_status compare_snapshot_pair(const run_files *a, const run_files *b,
                                        const series_file *ea, const series_file *eb,
                                        const sph_compare_options *opt, field_filter *ff,
                                        sph_compare_result *res, sph_error *err) {
    snapshot_file sa, sb;
    field_data pa = {0}, pb = {0}, ids = {0}, fa = {0}, fb = {0};
    sph_status st = snapshot_open(&sa, a, ea, err);
    if (!st)
        st = snapshot_open(&sb, b, eb, err);
    else
        sb.file = sb.vtk = sb.pointdata = H5I_INVALID_HID;
    const char *why = NULL;
    if (!st) st = read_field(sa.vtk, "Points", &sa, &pa, &why, err);
    if (!st && why) st = sph_fail(err, SPH_ERR_RUNTIME, "%s: /VTKHDF/Points is %s", sa.path, why);
    if (!st) st = read_field(sb.vtk, "Points", &sb, &pb, &why, err);
    if (!st && why) st = sph_fail(err, SPH_ERR_RUNTIME, "%s: /VTKHDF/Points is %s", sb.path, why);
    if (st) goto done;
    if (pa.n != pb.n) {
        st = add_note(res, true, err, "%s at t = %.9g s: %ld particles in run A, %ld in run B",
                      ea->name, ea->time, pa.n, pb.n);
        goto done;
    }
    res->nsnapshots++;
    if (sa.pointdata >= 0 && H5Lexists(sa.pointdata, "particle_id", H5P_DEFAULT) > 0) {
        st = read_field(sa.pointdata, "particle_id", &sa, &ids, &why, err);
        if (st) goto done;
        if (why || ids.n != pa.n || ids.ncomp != 1) {
            free(ids.v);
            ids.v = NULL;
        }
    }
    if (field_selected(ff, "Points")) {
        st = compare_field("Points", &pa, &pb, ids.v, ea->time, ea->name, opt, ff, res, err);
        if (st) goto done;
    }
    if (sa.pointdata >= 0 && sb.pointdata >= 0) {
        H5G_info_t info;
        if (H5Gget_info(sa.pointdata, &info) < 0) {
            st = sph_fail(err, SPH_ERR_RUNTIME, "%s: cannot list /VTKHDF/PointData", sa.path);
            goto done;
        }
        for (hsize_t k = 0; k < info.nlinks; ++k) {
            char name[256];
            if (H5Lget_name_by_idx(sa.pointdata, ".", H5_INDEX_NAME, H5_ITER_INC, k, name,
                                   sizeof name, H5P_DEFAULT) < 0) {
                st = sph_fail(err, SPH_ERR_RUNTIME, "%s: cannot list /VTKHDF/PointData", sa.path);
                goto done;
            }
            if (!field_selected(ff, name) || H5Lexists(sb.pointdata, name, H5P_DEFAULT) <= 0)
                continue;
            const char *why_a = NULL, *why_b = NULL;
            st = read_field(sa.pointdata, name, &sa, &fa, &why_a, err);
            if (!st) st = read_field(sb.pointdata, name, &sb, &fb, &why_b, err);
            if (!st && (why_a || why_b))
                st = add_note(res, false, err, "point-data %s not compared: %s in run %c", name,
                              why_a ? why_a : why_b, why_a ? 'A' : 'B');
            else if (!st && (fa.n != pa.n || fb.n != pb.n))
                st = add_note(res, true, err,
                              "%s at t = %.9g s: %s has %ld rows in run A, %ld in run B, for %ld "
                              "particles",
                              ea->name, ea->time, name, fa.n, fb.n, pa.n);
            else if (!st)
                st = compare_field(name, &fa, &fb, ids.v, ea->time, ea->name, opt, ff, res, err);
            free(fa.v);
            free(fb.v);
            fa.v = fb.v = NULL;
            if (st) goto done;
        }
    }
    st = note_fields_only_in(&sa, &sb, 'A', ff, res, err);
    if (!st) st = note_fields_only_in(&sb, &sa, 'B', ff, res, err);
done:
    free(pa.v);
    free(pb.v);
    free(ids.v);
    free(fa.v);
    free(fb.v);
    snapshot_close(&sa);
    snapshot_close(&sb);
    return st;
}

static sph_status note_unmatched(const series_index *s, const bool *matched, char label,
                                 sph_compare_result *res, sph_error *err) {
    int listed = 0, more = 0;
    for (int k = 0; k < s->n; ++k) {
        if (matched[k]) continue;
        if (listed == MAX_LISTED_SNAPSHOTS) {
            ++more;
            continue;
        }
        ++listed;
        sph_status st = add_note(res, false, err, "snapshot at t = %.9g s (%s) is only in run %c",
                                 s->files[k].time, s->files[k].name, label);
        if (st) return st;
    }
    if (more)
        return add_note(res, false, err, "... and %d more snapshots only in run %c", more, label);
    return SPH_OK;
}

static sph_status compare_snapshots(const run_files *a, const run_files *b,
                                    const sph_compare_options *opt, field_filter *ff,
                                    sph_compare_result *res, sph_error *err) {
    res->has_snapshots = true;
    bool *matched_a = calloc((size_t)a->series.n + 1, sizeof *matched_a);
    bool *matched_b = calloc((size_t)b->series.n + 1, sizeof *matched_b);
    sph_status st = SPH_OK;
    if (!matched_a || !matched_b) {
        st = sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory");
        goto done;
    }
    for (int i = 0; !st && i < a->series.n; ++i) {
        const double t = a->series.files[i].time;
        int best = -1;
        for (int j = 0; j < b->series.n; ++j) {
            const double u = b->series.files[j].time;
            if (matched_b[j] || !time_match(t, u, res->time_tol)) continue;
            if (best < 0 || fabs(u - t) < fabs(b->series.files[best].time - t)) best = j;
        }
        if (best < 0) continue;
        matched_a[i] = matched_b[best] = true;
        st = compare_snapshot_pair(a, b, &a->series.files[i], &b->series.files[best], opt, ff, res,
                                   err);
    }
    if (!st) st = note_unmatched(&a->series, matched_a, 'A', res, err);
    if (!st) st = note_unmatched(&b->series, matched_b, 'B', res, err);
done:
    free(matched_a);
    free(matched_b);
    return st;
}

/* ---- the comparison ---------------------------------------------------- */

static sph_status compare_loaded(const run_files *a, const run_files *b,
                                 const sph_compare_options *opt, field_filter *ff,
                                 sph_compare_result *res, sph_error *err) {
    res->time_tol = TIME_RTOL * end_time(a, b);
    for (int k = 0; k < SPH_COMPARE_NSCALES; ++k) {
        /* the larger of the two runs' statements (fmax ignores a NaN): the
         * same scene gives the same scale to round-off */
        res->scales[k] = fmax(a->summary.scale[k], b->summary.scale[k]);
    }
    sph_status st = SPH_OK;
    const run_files *runs[2] = {a, b};
    for (int k = 0; k < 2 && !st; ++k) {
        const run_files *r = runs[k];
        if (r->summary.note[0])
            st = add_note(res, false, err, "run %c (%s): %s", r->label, r->dir, r->summary.note);
        if (st || r->summary.complete) continue;
        char text[sizeof res->incomplete];
        sph_format(text, sizeof text, "run %c (%s) is incomplete: %s", r->label, r->dir,
                   r->summary.why);
        if (!opt->common_prefix && !res->incomplete[0])
            sph_format(res->incomplete, sizeof res->incomplete, "%s", text);
        if (opt->common_prefix)
            st =
                add_note(res, false, err, "%s; the common prefix compared (--common-prefix)", text);
        else
            st = add_note(res, true, err, "%s; --common-prefix compares the part both runs have",
                          text);
    }
    if (st) return st;
    if (a->has_csv && b->has_csv)
        st = compare_timeseries(a, b, opt, res, err);
    else if (a->has_csv || b->has_csv)
        st = add_note(res, false, err, "timeseries.csv is only in run %c (not compared)",
                      a->has_csv ? 'A' : 'B');
    if (st) return st;
    if (a->has_series && b->has_series)
        st = compare_snapshots(a, b, opt, ff, res, err);
    else if (a->has_series || b->has_series)
        st = add_note(res, false, err, "snapshots are only in run %c (not compared)",
                      a->has_series ? 'A' : 'B');
    if (st) return st;
    for (int k = 0; opt->fields && k < opt->nfields; ++k)
        if (!ff->found[k])
            return sph_fail(err, SPH_ERR_INPUT,
                            "--fields %s: no snapshot of both %s and %s has this point-data field",
                            opt->fields[k], a->dir, b->dir);
    if (res->nitems == 0 && !res->failed)
        return sph_fail(err, SPH_ERR_INPUT,
                        "%s and %s share nothing to compare (timeseries.csv: %s/%s, snapshots: "
                        "%s/%s, %d matched by time)",
                        a->dir, b->dir, a->has_csv ? "yes" : "no", b->has_csv ? "yes" : "no",
                        a->has_series ? "yes" : "no", b->has_series ? "yes" : "no",
                        res->nsnapshots);
    return SPH_OK;
}

sph_status sph_compare_runs(const char *dir_a, const char *dir_b, const sph_compare_options *opt,
                            sph_compare_result *res, sph_error *err) {
    memset(res, 0, sizeof *res);
    if (!(opt->rtol >= 0.0) || !isfinite(opt->rtol))
        return sph_fail(err, SPH_ERR_INPUT, "--rtol %g: must be a finite number >= 0", opt->rtol);
    if (!(opt->atol >= 0.0) || !isfinite(opt->atol))
        return sph_fail(err, SPH_ERR_INPUT, "--atol %g: must be a finite number >= 0", opt->atol);
    run_files *runs = calloc(2, sizeof *runs);
    field_filter ff = {.opt = opt};
    if (opt->fields) ff.found = calloc((size_t)opt->nfields + 1, sizeof *ff.found);
    if (!runs || (opt->fields && !ff.found)) {
        free(runs);
        free(ff.found);
        return sph_fail(err, SPH_ERR_RUNTIME, "compare: out of memory");
    }
    /* errors are reported through sph_status naming the file, not by HDF5's
     * own stack dump; the caller's setting is restored */
    H5E_auto2_t old_func = NULL;
    void *old_data = NULL;
    H5Eget_auto2(H5E_DEFAULT, &old_func, &old_data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    sph_status st = run_open(&runs[0], dir_a, 'A', err);
    if (!st) st = run_open(&runs[1], dir_b, 'B', err);
    if (!st) st = compare_loaded(&runs[0], &runs[1], opt, &ff, res, err);
    H5Eset_auto2(H5E_DEFAULT, old_func, old_data);
    run_free(&runs[0]);
    run_free(&runs[1]);
    free(runs);
    free(ff.found);
    return st;
}

void sph_compare_result_free(sph_compare_result *res) {
    free(res->items);
    free(res->notes);
    memset(res, 0, sizeof *res);
}

/* ---- the report -------------------------------------------------------- */

static void format_where(char *buf, size_t len, const sph_compare_item *it,
                         const sph_compare_where *w) {
    if (w->abs == 0.0)
        sph_format(buf, len, "-");
    else if (it->kind == SPH_COMPARE_COLUMN)
        sph_format(buf, len, "t = %.9g s", w->time);
    else
        sph_format(buf, len, "particle %ld, component %d, t = %.9g s", w->particle, w->component,
                   w->time);
}

static void print_items(FILE *f, const sph_compare_result *res, sph_compare_kind kind) {
    fprintf(f, "  %-28s %14s %10s %10s  %-6s %s\n", kind == SPH_COMPARE_COLUMN ? "column" : "field",
            "max |a-b|", "rel", "scale", "status", "where");
    for (int k = 0; k < res->nitems; ++k) {
        const sph_compare_item *it = &res->items[k];
        if (it->kind != kind) continue;
        char where[256];
        format_where(where, sizeof where, it, &it->max);
        /* '*': the physical scale of summary.json, listed below the table */
        fprintf(f, "  %-28s %14.6e %10.3e %10.3e%c %-6s %s", it->name, it->max.abs, it->max.rel,
                it->max.scale, it->physical_scale >= 0 ? '*' : ' ', it->failed ? "FAIL" : "ok",
                where);
        if (it->failed && (it->worst.abs != it->max.abs || it->worst.time != it->max.time)) {
            format_where(where, sizeof where, it, &it->worst);
            fprintf(f, "; beyond tolerance at %s: %.6e (rel %.3e)", where, it->worst.abs,
                    it->worst.rel);
        }
        fputc('\n', f);
    }
}

/* Which scale the time-series columns were measured against. */
static void print_scales(FILE *f, const sph_compare_result *res) {
    bool any = false;
    for (int k = 0; k < SPH_COMPARE_NSCALES; ++k) any = any || isfinite(res->scales[k]);
    if (!any) {
        fprintf(f, "  scale: the largest |value| of each column (neither run's summary.json "
                   "states \"scales\")\n");
        return;
    }
    fprintf(f, "  scale: the largest |value| of each column or, where larger (*), the\n"
               "  physical scale of summary.json \"scales\" (the larger of the two runs):\n");
    for (int k = 0; k < SPH_COMPARE_NSCALES; ++k) {
        if (isfinite(res->scales[k]))
            fprintf(f, "    %-17s %.6e  for %s\n", scale_keys[k], res->scales[k], scale_columns[k]);
        else
            fprintf(f, "    %-17s (not stated)  %s relative to their values\n", scale_keys[k],
                    scale_columns[k]);
    }
}

/* The failing item furthest beyond its tolerance, or NULL. */
static const sph_compare_item *worst_item(const sph_compare_result *res) {
    const sph_compare_item *worst = NULL;
    for (int k = 0; k < res->nitems; ++k) {
        const sph_compare_item *it = &res->items[k];
        if (!it->failed) continue;
        if (!worst || it->worst_excess > worst->worst_excess ||
            (it->worst_excess == worst->worst_excess && it->worst.rel > worst->worst.rel))
            worst = it;
    }
    return worst;
}

void sph_compare_print(FILE *f, const char *dir_a, const char *dir_b,
                       const sph_compare_options *opt, const sph_compare_result *res) {
    fprintf(f, "compare: A = %s\n         B = %s\n", dir_a, dir_b);
    fprintf(f, "tolerance: max |a-b| <= atol + rtol * scale, rtol=%g, atol=%g\n", opt->rtol,
            opt->atol);
    if (res->has_timeseries) {
        fprintf(f, "time series (timeseries.csv): %d rows compared\n", res->nrows);
        print_items(f, res, SPH_COMPARE_COLUMN);
        print_scales(f, res);
    }
    if (res->has_snapshots) {
        fprintf(f, "snapshots: %d pairs compared (times matched within %.3g s)\n", res->nsnapshots,
                res->time_tol);
        print_items(f, res, SPH_COMPARE_FIELD);
    }
    int nfail = 0;
    for (int k = 0; k < res->nitems; ++k) nfail += res->items[k].failed;
    const sph_compare_note *first_failure = NULL;
    for (int k = 0; k < res->nnotes; ++k) {
        const sph_compare_note *n = &res->notes[k];
        fprintf(f, "%s %s\n", n->failure ? "FAIL:" : "note:", n->text);
        if (n->failure) {
            ++nfail;
            if (!first_failure) first_failure = n;
        }
    }
    if (!res->failed) {
        fprintf(f, "compare: PASS (%d fields within rtol=%g, atol=%g)\n", res->nitems, opt->rtol,
                opt->atol);
        return;
    }
    const sph_compare_item *it = worst_item(res);
    if (res->incomplete[0]) /* the cause of any other difference: say it first */
        fprintf(f, "compare: FAIL: %s", res->incomplete);
    else if (it && it->kind == SPH_COMPARE_FIELD)
        fprintf(f,
                "compare: FAIL: %s differs by %.6e (rel %.3e) at particle %ld, component %d, "
                "t = %.9g s",
                it->name, it->worst.abs, it->worst.rel, it->worst.particle, it->worst.component,
                it->worst.time);
    else if (it)
        fprintf(f, "compare: FAIL: %s differs by %.6e (rel %.3e) at t = %.9g s", it->name,
                it->worst.abs, it->worst.rel, it->worst.time);
    else
        fprintf(f, "compare: FAIL: %s", first_failure ? first_failure->text : "differences");
    if (nfail > 1)
        fprintf(f, " (+%d more failure%s listed above)", nfail - 1, nfail > 2 ? "s" : "");
    fputc('\n', f);
}

/* ---- command line ------------------------------------------------------ */

static const char compare_usage[] =
    "usage: sphsolid compare RUN_A RUN_B [--rtol X] [--atol X] [--fields a,b,c]\n"
    "                        [--common-prefix]\n"
    "\n"
    "Compare two run directories: timeseries.csv row by row, and the snapshots\n"
    "matched by time (/VTKHDF/Points and the point-data fields present in both).\n"
    "A field fails when max |a-b| > atol + rtol * scale, scale = max |value|, and\n"
    "for the momentum, angular momentum and energy columns at least the physical\n"
    "scale of the runs' summary.json \"scales\" (quantities zero in theory).\n"
    "An incomplete run (killed or still running: no summary.json) fails.\n"
    "--rtol    relative tolerance (default 1e-9)\n"
    "--atol    absolute tolerance (default 0)\n"
    "--fields  compare only these point-data fields (Points included by name)\n"
    "--common-prefix  compare the part both runs have: an incomplete run (its\n"
    "          timeseries.csv.partial) and different row counts are no failure\n"
    "exit status: 0 within tolerance, 3 differences beyond it or an incomplete run,\n"
    "             2 bad input, 1 runtime failure\n";

static int usage_error(const char *fmt, const char *arg) {
    fprintf(stderr, "sphsolid compare: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n%s", compare_usage);
    return SPH_ERR_INPUT;
}

static bool parse_tolerance(const char *text, double *out) {
    char *end;
    errno = 0;
    const double v = strtod(text, &end);
    if (end == text || *end != '\0' || errno == ERANGE || !isfinite(v) || v < 0.0) return false;
    *out = v;
    return true;
}

/* Split "a,b,c" in place into `names` (at most as many as commas + 1). */
static int split_fields(char *list, const char **names) {
    int n = 0;
    char *rest = list;
    for (;;) {
        char *comma = strchr(rest, ',');
        if (comma) *comma = '\0';
        names[n++] = rest;
        if (!*rest) return -1;
        if (!comma) return n;
        rest = comma + 1;
    }
}

static int compare_and_report(const char *dir_a, const char *dir_b,
                              const sph_compare_options *opt) {
    sph_compare_result res;
    sph_error err = {0};
    const sph_status st = sph_compare_runs(dir_a, dir_b, opt, &res, &err);
    int rc;
    if (st) {
        fprintf(stderr, "sphsolid compare: %s\n", err.msg);
        rc = (int)st;
    } else {
        sph_compare_print(stdout, dir_a, dir_b, opt, &res);
        rc = res.failed ? SPH_COMPARE_DIFFERS : 0;
    }
    sph_compare_result_free(&res);
    return rc;
}

int sph_compare_main(int argc, char **argv) {
    sph_compare_options opt;
    sph_compare_options_default(&opt);
    const char *dirs[2] = {NULL, NULL};
    int ndirs = 0, rc = 0;
    char *fields_text = NULL;
    const char **fields = NULL;
    bool options_done = false;
    for (int k = 0; k < argc; ++k) {
        const char *a = argv[k];
        if (!options_done && a[0] == '-' && a[1] != '\0') {
            if (strcmp(a, "--") == 0) {
                options_done = true;
                continue;
            }
            if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
                fputs(compare_usage, stdout);
                goto done;
            }
            if (strcmp(a, "--common-prefix") == 0) {
                opt.common_prefix = true;
                continue;
            }
            const bool takes_value =
                strcmp(a, "--rtol") == 0 || strcmp(a, "--atol") == 0 || strcmp(a, "--fields") == 0;
            if (!takes_value) {
                rc = usage_error("unknown option %s", a);
                goto done;
            }
            if (k + 1 >= argc) {
                rc = usage_error("%s needs a value", a);
                goto done;
            }
            const char *value = argv[++k];
            if (strcmp(a, "--fields") == 0) {
                free(fields_text);
                free(fields);
                fields_text = strdup(value);
                size_t n = 1;
                for (const char *p = value; *p; ++p) n += *p == ',';
                fields = calloc(n, sizeof *fields);
                if (!fields_text || !fields) {
                    fprintf(stderr, "sphsolid compare: out of memory\n");
                    rc = SPH_ERR_RUNTIME;
                    goto done;
                }
                opt.nfields = split_fields(fields_text, fields);
                if (opt.nfields < 0) {
                    rc = usage_error("--fields %s: empty field name", value);
                    goto done;
                }
                opt.fields = fields;
            } else if (!parse_tolerance(value, strcmp(a, "--rtol") == 0 ? &opt.rtol : &opt.atol)) {
                fprintf(stderr, "sphsolid compare: %s %s: expected a finite number >= 0\n%s", a,
                        value, compare_usage);
                rc = SPH_ERR_INPUT;
                goto done;
            }
        } else if (ndirs < 2) {
            dirs[ndirs++] = a;
        } else {
            rc = usage_error("unexpected argument %s (compare takes two run directories)", a);
            goto done;
        }
    }
    if (ndirs < 2)
        rc = usage_error("%s", "compare needs two run directories");
    else
        rc = compare_and_report(dirs[0], dirs[1], &opt);
done:
    free(fields_text);
    free(fields);
    return rc;
}
