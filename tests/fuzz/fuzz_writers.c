/* fuzz_writers.c — libFuzzer harness over the writers of a run directory
 * (the input convention is in fuzz_writers.h): names and free text of
 * arbitrary bytes through the real timeseries.csv writer and the real
 * summary.json string path, read back by the project's own readers.
 *
 * Besides "no crash, no leak, no undefined behaviour", every input must keep
 * these invariants, checked here so that the fuzzer reports a violation as
 * a crash:
 *   - timeseries.csv: the writer refuses (SPH_ERR_INPUT) exactly the
 *     observer names the scene's rule refuses (sph_name_check, the validator
 *     the scene loader uses) and names whose columns would repeat a column;
 *     what it writes, `sphsolid compare` (sph_compare_runs) reads back with
 *     every column, under its name, and every row;
 *   - summary.json: the file is valid UTF-8 (checked by a decoder of this
 *     file's own, independent of output.c's) and json-c parses it (with
 *     JSON_TOKENER_VALIDATE_UTF8); each string reads back as written when it
 *     was valid UTF-8, and otherwise keeps every well-formed character in
 *     order, with one to as many U+FFFD as there were ill-formed bytes.
 *
 * Build: cmake -DCMAKE_C_COMPILER=clang -DSPHSOLID_FUZZ=ON (README, Tests). */
#include "fuzz_writers.h"

#include "compare.h"
#include "output.h"
#include "scene.h"

#include <dirent.h>
#include <json-c/json.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_FIELDS  (2 + SPH_SCENE_MAX_OBSERVERS)
#define MAX_COLUMNS (12 + 3 * SPH_SCENE_MAX_OBSERVERS)
#define COLUMN_LEN  (SPH_NAME_LEN + 24)

__attribute__((format(printf, 2, 3))) static void violate(fuzz_writers_result *res, const char *fmt,
                                                          ...) {
    if (res->violation[0]) return; /* keep the first */
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(res->violation, sizeof res->violation, fmt, ap);
    va_end(ap);
}

/* ---- UTF-8, decoded by value (not by output.c's byte ranges) ----------- */

/* The length of the well-formed character at s (n bytes left), 0 when the
 * byte there starts none: an overlong form, a surrogate or a value beyond
 * U+10FFFF are ill-formed. */
static size_t utf8_char(const unsigned char *s, size_t n) {
    const unsigned c = s[0];
    size_t len;
    uint32_t v, min;
    if (c < 0x80) return 1;
    if ((c & 0xE0) == 0xC0) {
        len = 2, v = c & 0x1F, min = 0x80;
    } else if ((c & 0xF0) == 0xE0) {
        len = 3, v = c & 0x0F, min = 0x800;
    } else if ((c & 0xF8) == 0xF0) {
        len = 4, v = c & 0x07, min = 0x10000;
    } else {
        return 0;
    }
    if (n < len) return 0;
    for (size_t k = 1; k < len; k++) {
        if ((s[k] & 0xC0) != 0x80) return 0;
        v = v << 6 | (s[k] & 0x3F);
    }
    if (v < min || v > 0x10FFFF || (v >= 0xD800 && v <= 0xDFFF)) return 0;
    return len;
}

/* Scan s: its well-formed characters other than U+FFFD go to `kept` (room
 * for n bytes), the U+FFFD are counted in *fffd and the bytes that start no
 * character in *bad; returns the length of `kept`. */
static size_t utf8_scan(const char *s, size_t n, char *kept, size_t *fffd, size_t *bad) {
    const unsigned char *p = (const unsigned char *)s;
    size_t i = 0, k = 0;
    *fffd = *bad = 0;
    while (i < n) {
        const size_t len = utf8_char(p + i, n - i);
        if (len == 0) {
            ++*bad;
            ++i;
        } else if (len == 3 && memcmp(p + i, "\xEF\xBF\xBD", 3) == 0) {
            ++*fffd;
            i += 3;
        } else {
            memcpy(kept + k, p + i, len);
            k += len;
            i += len;
        }
    }
    return k;
}

/* `got` is what summary.json holds for the string `given`. */
static void check_repaired(fuzz_writers_result *res, const char *what, const char *given,
                           size_t given_len, const char *got, size_t got_len) {
    res->json_strings++;
    char *kept_given = malloc(given_len + 1), *kept_got = malloc(got_len + 1);
    if (!kept_given || !kept_got) abort();
    size_t fffd_given, bad_given, fffd_got, bad_got;
    const size_t n_given = utf8_scan(given, given_len, kept_given, &fffd_given, &bad_given);
    const size_t n_got = utf8_scan(got, got_len, kept_got, &fffd_got, &bad_got);
    if (bad_got)
        violate(res, "%s: %zu bytes of the JSON string are not UTF-8", what, bad_got);
    else if (bad_given == 0 && (got_len != given_len || memcmp(got, given, got_len) != 0))
        violate(res, "%s: valid UTF-8 (%zu bytes) reads back changed (%zu bytes)", what, given_len,
                got_len);
    else if (n_got != n_given || memcmp(kept_got, kept_given, n_got) != 0)
        violate(res, "%s: the well-formed characters changed", what);
    else if (bad_given && (fffd_got < fffd_given + 1 || fffd_got > fffd_given + bad_given))
        violate(res, "%s: %zu ill-formed bytes gave %zu U+FFFD", what, bad_given,
                fffd_got - fffd_given);
    free(kept_given);
    free(kept_got);
}

/* ---- files --------------------------------------------------------------- */

static char *read_all(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, len = 0;
    char *buf = malloc(cap + 1);
    for (size_t got; buf && (got = fread(buf + len, 1, cap - len, f)) > 0;) {
        len += got;
        if (len == cap) {
            char *grown = realloc(buf, (cap *= 2) + 1);
            if (!grown) free(buf);
            buf = grown;
        }
    }
    fclose(f);
    if (!buf) abort();
    buf[len] = '\0';
    *size = len;
    return buf;
}

static void remove_dir(const char *dir) {
    DIR *d = opendir(dir);
    if (d) {
        for (struct dirent *e = readdir(d); e; e = readdir(d)) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
            char path[1400];
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            unlink(path);
        }
        closedir(d);
    }
    rmdir(dir);
}

/* ---- timeseries.csv ------------------------------------------------------ */

/* The header's columns as docs/output-format.md lists them, written out
 * here rather than taken from output.c; true when one repeats another. */
static bool expected_columns(const sph_scene *sc, char cols[][COLUMN_LEN], int *n) {
    static const char *const axes[] = {"x", "y", "z"};
    int k = 0;
    const char *fixed[] = {"time", "kinetic_energy", "strain_energy", "total_energy"};
    for (int i = 0; i < 4; i++) snprintf(cols[k++], COLUMN_LEN, "%s", fixed[i]);
    for (int a = 0; a < sc->dim; a++) snprintf(cols[k++], COLUMN_LEN, "momentum_%s", axes[a]);
    if (sc->dim == 2)
        snprintf(cols[k++], COLUMN_LEN, "angular_momentum");
    else
        for (int a = 0; a < 3; a++) snprintf(cols[k++], COLUMN_LEN, "angular_momentum_%s", axes[a]);
    snprintf(cols[k++], COLUMN_LEN, "min_distance_ratio");
    snprintf(cols[k++], COLUMN_LEN, "zigzag_indicator");
    for (int o = 0; o < sc->nobservers; o++)
        for (int a = 0; a < sc->dim; a++)
            snprintf(cols[k++], COLUMN_LEN, "%s_%s", sc->observers[o].name, axes[a]);
    *n = k;
    for (int i = 1; i < k; i++)
        for (int j = 0; j < i; j++)
            if (strcmp(cols[i], cols[j]) == 0) return true;
    return false;
}

/* Any double, NaN and infinities included, from a little generator seeded
 * by the input (the values only need to round-trip through the file). */
static double next_value(uint64_t *state) {
    *state = *state * 6364136223846793005u + 1442695040888963407u;
    double x;
    const uint64_t bits = *state ^ (*state >> 29);
    memcpy(&x, &bits, sizeof x);
    return x;
}

static void check_csv(fuzz_writers_result *res, const char *dir, const sph_scene *sc, int nrows,
                      uint64_t seed) {
    char cols[MAX_COLUMNS][COLUMN_LEN];
    int ncols = 0;
    const bool repeated = expected_columns(sc, cols, &ncols);
    res->names_valid = true;
    for (int o = 0; o < sc->nobservers; o++) {
        char why[256];
        if (!sph_name_check(sc->observers[o].name, why, sizeof why)) res->names_valid = false;
    }
    sph_output out;
    sph_error err = {0};
    sph_status st = sph_output_open(&out, dir, sc, NULL, &err);
    const bool expect_ok = res->names_valid && !repeated;
    if ((st == SPH_OK) != expect_ok || (st && st != SPH_ERR_INPUT)) {
        violate(res, "timeseries.csv: the writer %s (status %d: %s) names %s the rule%s",
                st ? "refused" : "accepted", (int)st, err.msg,
                res->names_valid ? "that keep" : "that break",
                repeated ? ", a repeated column" : "");
        if (!st) sph_output_close(&out, false, &err);
        return;
    }
    if (st) return;
    res->csv_written = true;
    const int per_row = sc->nobservers * sc->dim;
    double observers[3 * SPH_SCENE_MAX_OBSERVERS];
    for (int r = 0; !st && r < nrows; r++) {
        sph_diagnostics d;
        memset(&d, 0, sizeof d);
        d.kinetic = next_value(&seed);
        d.strain = next_value(&seed);
        for (int a = 0; a < 3; a++) {
            d.momentum[a] = next_value(&seed);
            d.angular[a] = next_value(&seed);
        }
        d.min_distance_ratio = next_value(&seed);
        d.zigzag = next_value(&seed);
        for (int k = 0; k < per_row; k++) observers[k] = next_value(&seed);
        /* times increase: compare matches rows by time */
        st = sph_output_row(&out, 0.25 * r, &d, observers, &err);
    }
    if (!st) st = sph_output_close(&out, true, &err);
    if (st) {
        violate(res, "timeseries.csv: writing failed: %s", err.msg);
        return;
    }

    sph_compare_options opt;
    sph_compare_options_default(&opt);
    sph_compare_result cmp;
    st = sph_compare_runs(dir, dir, &opt, &cmp, &err);
    if (st) {
        violate(res, "sphsolid compare rejects what the writer wrote: %s", err.msg);
    } else if (cmp.nrows != nrows) {
        violate(res, "sphsolid compare reads %d rows of %d", cmp.nrows, nrows);
    } else if (nrows > 0) {
        /* every column but time is an item, under its name */
        for (int c = 1; c < ncols; c++) {
            bool found = false;
            for (int i = 0; i < cmp.nitems && !found; i++)
                found = cmp.items[i].kind == SPH_COMPARE_COLUMN &&
                        strcmp(cmp.items[i].name, cols[c]) == 0;
            if (!found) violate(res, "sphsolid compare has no column %s", cols[c]);
        }
        int ncolumn_items = 0;
        for (int i = 0; i < cmp.nitems; i++)
            ncolumn_items += cmp.items[i].kind == SPH_COMPARE_COLUMN;
        if (ncolumn_items != ncols - 1)
            violate(res, "sphsolid compare reads %d columns besides time, the writer wrote %d",
                    ncolumn_items, ncols - 1);
    }
    sph_compare_result_free(&cmp);
}

/* ---- summary.json -------------------------------------------------------- */

static json_object *member(json_object *o, const char *key) {
    json_object *v = NULL;
    return o && json_object_object_get_ex(o, key, &v) ? v : NULL;
}

static void check_json_string(fuzz_writers_result *res, const char *what, json_object *v,
                              const char *given, size_t given_len) {
    if (!v || !json_object_is_type(v, json_type_string)) {
        violate(res, "summary.json: %s is missing or not a string", what);
        return;
    }
    check_repaired(res, what, given, given_len, json_object_get_string(v),
                   (size_t)json_object_get_string_len(v));
}

static void check_json(fuzz_writers_result *res, const char *dir, const char *const *fields,
                       const size_t *lens, int nfields, const uint8_t *data, size_t size) {
    /* the shape of summary.json's "scene": strings made by sph_json_string
     * as run.c makes them, written by sph_output_write_json */
    json_object *root = json_object_new_object();
    json_object *scene = json_object_new_object();
    json_object_object_add(root, "status", sph_json_string("completed"));
    json_object_object_add(scene, "title", sph_json_string(fields[0]));
    json_object_object_add(scene, "path", sph_json_string(fields[1]));
    json_object *list = json_object_new_array();
    for (int k = 0; k < nfields; k++) json_object_array_add(list, sph_json_string(fields[k]));
    json_object_object_add(scene, "overrides", list);
    json_object_object_add(scene, "resolved_text", sph_json_string_len((const char *)data, size));
    json_object_object_add(root, "scene", scene);
    sph_error err = {0};
    const sph_status st = sph_output_write_json(dir, "summary.json", root, &err);
    json_object_put(root);
    if (st) {
        violate(res, "summary.json: writing failed: %s", err.msg);
        return;
    }

    char path[1200];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    size_t len = 0;
    char *text = read_all(path, &len);
    if (!text) {
        violate(res, "summary.json: cannot read it back");
        return;
    }
    for (size_t i = 0; i < len;) {
        const size_t n = utf8_char((const unsigned char *)text + i, len - i);
        if (!n) {
            violate(res, "summary.json: byte %zu (0x%02X) is not UTF-8", i,
                    (unsigned)(unsigned char)text[i]);
            break;
        }
        i += n;
    }
    json_tokener *tok = json_tokener_new();
    if (!tok) abort();
    json_tokener_set_flags(tok, JSON_TOKENER_STRICT | JSON_TOKENER_VALIDATE_UTF8);
    json_object *parsed = json_tokener_parse_ex(tok, text, (int)len);
    const enum json_tokener_error jerr = json_tokener_get_error(tok);
    size_t end = json_tokener_get_parse_end(tok);
    json_tokener_free(tok);
    while (end < len && (text[end] == '\n' || text[end] == ' ')) end++;
    if (!parsed || jerr != json_tokener_success || end != len) {
        violate(res, "summary.json does not parse: %s (at byte %zu of %zu)",
                json_tokener_error_desc(jerr), end, len);
    } else {
        json_object *sc = member(parsed, "scene");
        check_json_string(res, "scene.title", member(sc, "title"), fields[0], lens[0]);
        check_json_string(res, "scene.path", member(sc, "path"), fields[1], lens[1]);
        json_object *ovr = member(sc, "overrides");
        if (!ovr || !json_object_is_type(ovr, json_type_array) ||
            (int)json_object_array_length(ovr) != nfields)
            violate(res, "summary.json: scene.overrides is not an array of %d", nfields);
        for (int k = 0; ovr && k < nfields && k < (int)json_object_array_length(ovr); k++)
            check_json_string(res, "scene.overrides[k]", json_object_array_get_idx(ovr, (size_t)k),
                              fields[k], lens[k]);
        check_json_string(res, "scene.resolved_text (all the input)", member(sc, "resolved_text"),
                          (const char *)data, size);
    }
    json_object_put(parsed);
    free(text);
}

/* ---- the entry point ----------------------------------------------------- */

void fuzz_writers_run(const uint8_t *data, size_t size, fuzz_writers_result *res) {
    memset(res, 0, sizeof *res);
    const int dim = size > 0 && (data[0] & 1) ? 3 : 2;
    const int nrows = size > 0 ? (data[0] >> 1) & 3 : 0;
    /* the fields, each a NUL-terminated copy; missing ones are "" */
    char *fields[MAX_FIELDS];
    size_t lens[MAX_FIELDS];
    int nfields = 0;
    size_t pos = size > 0 ? 1 : 0;
    while (nfields < MAX_FIELDS && (pos < size || nfields < 2)) {
        const uint8_t *nul = pos < size ? memchr(data + pos, 0, size - pos) : NULL;
        const size_t len = pos < size ? (nul ? (size_t)(nul - data) : size) - pos : 0;
        fields[nfields] = malloc(len + 1);
        if (!fields[nfields]) abort();
        if (len) memcpy(fields[nfields], data + pos, len);
        fields[nfields][len] = '\0';
        lens[nfields++] = len;
        pos += len + 1;
    }

    sph_scene *sc = calloc(1, sizeof *sc);
    if (!sc) abort();
    sc->dim = dim;
    sc->nobservers = nfields - 2;
    res->nobservers = sc->nobservers;
    for (int o = 0; o < sc->nobservers; o++)
        snprintf(sc->observers[o].name, sizeof sc->observers[o].name, "%s", fields[2 + o]);
    uint64_t seed = 1469598103934665603u; /* FNV-1a of the input */
    for (size_t i = 0; i < size; i++) seed = (seed ^ data[i]) * 1099511628211u;

    const char *tmp = getenv("TMPDIR");
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/fuzz_writers.XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(dir)) {
        violate(res, "cannot create a directory under %s", tmp && *tmp ? tmp : "/tmp");
    } else {
        check_csv(res, dir, sc, nrows, seed);
        check_json(res, dir, (const char *const *)fields, lens, nfields, data, size);
        remove_dir(dir);
    }
    free(sc);
    for (int k = 0; k < nfields; k++) free(fields[k]);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fuzz_writers_result res;
    fuzz_writers_run(data, size, &res);
    if (res.violation[0]) {
        fprintf(stderr, "fuzz_writers: invariant violated: %s\n", res.violation);
        abort();
    }
    return 0;
}
