/* scene.c — load, override and validate a scene file (docs/scene-format.md).
 *
 * Three stages, all on one libconfig tree:
 *   1. parse the file (libconfig gives every setting its source line);
 *   2. apply the `--set key=value` overrides to the tree, marking every
 *      setting they create through its libconfig hook so that later messages
 *      can name the override instead of a file line;
 *   3. walk the tree against the schema below, filling sph_scene.  Every
 *      group's members are checked against the keys valid there, so a typo is
 *      an error (with the nearest valid name) rather than a silently ignored
 *      setting that leaves a default in force.
 * The first problem found is reported; nothing is printed.
 */
#include "scene.h"

#include "mesh.h"

#include "sph_constants.h"

#include <libconfig.h>

#include <errno.h>
#include <sys/stat.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* ------------------------------------------------------------------------ */
/* loader state and error reporting                                          */
/* ------------------------------------------------------------------------ */

typedef struct {
    const char *file; /* the scene path, as given */
    sph_error *err;
    sph_scene *scene;
    int nnamed_shapes; /* shapes [0, nnamed_shapes) are the named members of `shapes` */
    /* the definition of every shape and its `parts` setting, for messages */
    const config_setting_t *shape_def[SPH_SCENE_MAX_SHAPES];
    const config_setting_t *shape_parts[SPH_SCENE_MAX_SHAPES];
    int nconstraints_total; /* constraints of the bodies parsed so far */
} loader;

/* An inline table of names and its length: KEYS("a", "b") -> (names, 2). */
#define KEYS(...)                                                                                  \
    (const char *const[]){__VA_ARGS__},                                                            \
        (int)(sizeof((const char *const[]){__VA_ARGS__}) / sizeof(const char *))

static const char *type_name(int type) {
    switch (type) {
    case CONFIG_TYPE_GROUP:
        return "a group { ... }";
    case CONFIG_TYPE_INT:
        return "an integer";
    case CONFIG_TYPE_INT64:
        return "a 64-bit integer";
    case CONFIG_TYPE_FLOAT:
        return "a number";
    case CONFIG_TYPE_STRING:
        return "a string";
    case CONFIG_TYPE_BOOL:
        return "a boolean";
    case CONFIG_TYPE_ARRAY:
        return "an array [ ... ]";
    case CONFIG_TYPE_LIST:
        return "a list ( ... )";
    default:
        return "nothing";
    }
}

/* The override ("key=value") that created `s` or one of its ancestors, else
 * NULL: the value then came from the file. */
static const char *override_of(const config_setting_t *s) {
    for (; s; s = s->parent)
        if (s->hook) return (const char *)s->hook;
    return NULL;
}

static bool plain_name(const char *s) {
    if (!*s) return false;
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') ||
              *s == '_' || *s == '-'))
            return false;
    return true;
}

static bool name_letter(unsigned char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

bool sph_name_check(const char *name, char *why, size_t size) {
    const unsigned char *s = (const unsigned char *)name;
    size_t n = 0;
    for (; s[n]; n++) {
        const unsigned char c = s[n];
        if (name_letter(c) || (n > 0 && ((c >= '0' && c <= '9') || c == '_' || c == '-'))) continue;
        /* the offending byte, printable whatever it is: the message stays
         * one line even for a name with a newline or invalid UTF-8 */
        char shown[8];
        if (c > ' ' && c < 0x7f)
            snprintf(shown, sizeof shown, "'%c'", c);
        else
            snprintf(shown, sizeof shown, "\\x%02X", c);
        snprintf(why, size,
                 "%s %s: names are a letter, then letters, digits, '_' or '-' (they become "
                 "timeseries.csv columns and --set keys)",
                 n == 0 ? "a name cannot start with" : "a name cannot contain", shown);
        return false;
    }
    if (n == 0) {
        snprintf(why, size, "must not be empty");
        return false;
    }
    if (n >= SPH_NAME_LEN) {
        snprintf(why, size, "names are limited to %d characters", SPH_NAME_LEN - 1);
        return false;
    }
    return true;
}

bool sph_observer_name_reserved(const char *name) {
    return strcmp(name, "momentum") == 0 || strcmp(name, "angular_momentum") == 0;
}

/* The `name` member of a list element, if it is a string that no other
 * element of the list shares; path components then read `bodies.plate`
 * (which --set also accepts) rather than `bodies.[0]`. */
static const char *unique_element_name(const config_setting_t *list, int idx) {
    const config_setting_t *e = config_setting_get_elem(list, (unsigned)idx);
    const char *name = NULL;
    if (!e || !config_setting_is_group(e) || !config_setting_lookup_string(e, "name", &name) ||
        !plain_name(name))
        return NULL;
    int n = config_setting_length(list);
    for (int i = 0; i < n; i++) {
        const char *other = NULL;
        const config_setting_t *o = config_setting_get_elem(list, (unsigned)i);
        if (i != idx && config_setting_is_group(o) &&
            config_setting_lookup_string(o, "name", &other) && strcmp(other, name) == 0)
            return NULL;
    }
    return name;
}

/* Full key path of a setting: `materials.rubber.poisson_ratio`,
 * `bodies.plate.constraints.[0].region`, `shapes.beam.lower.[1]`. */
static void setting_path(const config_setting_t *s, char *buf, size_t size) {
    buf[0] = '\0';
    if (!s || !s->parent) return;
    setting_path(s->parent, buf, size);
    size_t len = strlen(buf);
    const char *sep = len > 0 ? "." : "";
    const config_setting_t *p = s->parent;
    if (config_setting_is_group(p) && s->name) {
        snprintf(buf + len, size - len, "%s%s", sep, s->name);
    } else {
        int idx = config_setting_index(s);
        const char *name = config_setting_is_list(p) ? unique_element_name(p, idx) : NULL;
        if (name)
            snprintf(buf + len, size - len, "%s%s", sep, name);
        else
            snprintf(buf + len, size - len, "%s[%d]", sep, idx);
    }
}

/* Report a problem with setting `s` (or with its missing member `key`, when
 * key is not NULL):  "<file>:<line>: <path>: <what>", or
 * "--set <key>=<value>: <path>: <what>" for a value from an override. */
__attribute__((format(printf, 4, 5))) static sph_status
fail_at(loader *L, const config_setting_t *s, const char *key, const char *fmt, ...) {
    char what[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);

    char path[768];
    setting_path(s, path, sizeof path);
    if (key) {
        size_t len = strlen(path);
        snprintf(path + len, sizeof path - len, "%s%s", len > 0 ? "." : "", key);
    }
    const char *ov = override_of(s);
    unsigned line = s ? config_setting_source_line(s) : 0;
    if (ov) return sph_fail(L->err, SPH_ERR_INPUT, "--set %s: %s: %s", ov, path, what);
    if (line > 0)
        return sph_fail(L->err, SPH_ERR_INPUT, "%s:%u: %s: %s", L->file, line, path, what);
    /* the root group has no line of its own */
    return sph_fail(L->err, SPH_ERR_INPUT, "%s: %s: %s", L->file, path, what);
}

/* The prefix fail_at would give setting s ("<file>:<line>: <path>" or
 * "--set <override>: <path>"), kept in the scene for messages about a body
 * or an observer after loading (particles.c). */
static void where_of(const loader *L, const config_setting_t *s, char *buf, size_t size) {
    char path[768];
    setting_path(s, path, sizeof path);
    const char *ov = override_of(s);
    const unsigned line = config_setting_source_line(s);
    if (ov)
        sph_format(buf, size, "--set %s: %s", ov, path);
    else if (line > 0)
        sph_format(buf, size, "%s:%u: %s", L->file, line, path);
    else
        sph_format(buf, size, "%s: %s", L->file, path);
}

/* Optimal-string-alignment edit distance (adjacent transpositions count
 * one), for "did you mean" suggestions. */
static int edit_distance(const char *a, const char *b) {
    size_t la = strlen(a), lb = strlen(b);
    if (la > 63 || lb > 63) return 99;
    int d[64][64];
    for (size_t i = 0; i <= la; i++) d[i][0] = (int)i;
    for (size_t j = 0; j <= lb; j++) d[0][j] = (int)j;
    for (size_t i = 1; i <= la; i++) {
        for (size_t j = 1; j <= lb; j++) {
            int cost = a[i - 1] == b[j - 1] ? 0 : 1;
            int v = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < v) v = d[i][j - 1] + 1;
            if (d[i - 1][j - 1] + cost < v) v = d[i - 1][j - 1] + cost;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                d[i - 2][j - 2] + 1 < v)
                v = d[i - 2][j - 2] + 1;
            d[i][j] = v;
        }
    }
    return d[la][lb];
}

/* " (did you mean 'x'?)" when one candidate is close, else
 * " (<what>: a, b, c)" listing them all. */
static void suggest(const char *given, const char *const *names, int n, const char *what, char *buf,
                    size_t size) {
    int best = -1, best_d = 99;
    for (int i = 0; i < n; i++) {
        int d = edit_distance(given, names[i]);
        if (d < best_d) best_d = d, best = i;
    }
    /* close: at most 3 edits, and fewer than half the candidate's length so
     * that two-letter names are not "suggested" for anything */
    if (best >= 0 && best_d <= 3 && 2 * best_d <= (int)strlen(names[best])) {
        snprintf(buf, size, " (did you mean '%s'?)", names[best]);
        return;
    }
    if (n == 0) {
        snprintf(buf, size, " (none are defined)");
        return;
    }
    size_t len = (size_t)snprintf(buf, size, " (%s: ", what);
    for (int i = 0; i < n && len < size; i++)
        len += (size_t)snprintf(buf + len, size - len, "%s%s", i ? ", " : "", names[i]);
    if (len < size) snprintf(buf + len, size - len, ")");
}

/* ------------------------------------------------------------------------ */
/* typed access                                                              */
/* ------------------------------------------------------------------------ */

/* Reject members of group g that are not in `keys`. */
static sph_status check_keys(loader *L, const config_setting_t *g, const char *const *keys,
                             int nkeys) {
    int n = config_setting_length(g);
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(g, (unsigned)i);
        bool known = false;
        for (int k = 0; k < nkeys && !known; k++) known = strcmp(m->name, keys[k]) == 0;
        if (!known) {
            char hint[512];
            suggest(m->name, keys, nkeys, "valid keys here", hint, sizeof hint);
            return fail_at(L, m, NULL, "unknown key '%s'%s", m->name, hint);
        }
    }
    return SPH_OK;
}

/* The member `key` of g; an error if it is required and absent. */
static sph_status get_member(loader *L, const config_setting_t *g, const char *key, bool required,
                             const config_setting_t **out) {
    *out = config_setting_get_member(g, key);
    if (!*out && required) return fail_at(L, g, key, "missing required key");
    return SPH_OK;
}

/* The exact value of an integer setting, over [-2^63, 2^64): libconfig
 * keeps 64 signed bits, and a hexadecimal 64-bit integer is read as its
 * unsigned bits (widen_integers writes the values from 2^63 to 2^64 - 1 that
 * way, so that a seed takes the whole unsigned range). */
typedef struct {
    bool negative;
    unsigned long long magnitude;
} wide_int;

static wide_int wide_of(const config_setting_t *s) {
    long long v = config_setting_type(s) == CONFIG_TYPE_INT64 ? config_setting_get_int64(s)
                                                              : config_setting_get_int(s);
    if (v < 0 && config_setting_type(s) == CONFIG_TYPE_INT64 &&
        config_setting_get_format(s) == CONFIG_FORMAT_HEX)
        return (wide_int){false, (unsigned long long)v};
    /* -(v + 1) + 1: no overflow at LLONG_MIN */
    if (v < 0) return (wide_int){true, (unsigned long long)(-(v + 1)) + 1ULL};
    return (wide_int){false, (unsigned long long)v};
}

static double wide_double(wide_int v) {
    return v.negative ? -(double)v.magnitude : (double)v.magnitude;
}

/* v in [lo, hi] (lo <= 0 <= hi or 0 <= lo <= hi) */
static bool wide_in(wide_int v, long long lo, unsigned long long hi) {
    if (v.negative) return lo < 0 && v.magnitude <= (unsigned long long)(-(lo + 1)) + 1ULL;
    return v.magnitude <= hi && (lo <= 0 || v.magnitude >= (unsigned long long)lo);
}

/* The value as written: "-2147483649", "18446744073709551615". */
static const char *wide_text(wide_int v, char buf[24]) {
    snprintf(buf, 24, "%s%llu", v.negative ? "-" : "", v.magnitude);
    return buf;
}

static sph_status as_float(loader *L, const config_setting_t *s, double *out) {
    switch (config_setting_type(s)) {
    case CONFIG_TYPE_INT:
        *out = config_setting_get_int(s);
        break;
    case CONFIG_TYPE_INT64:
        *out = wide_double(wide_of(s));
        break;
    case CONFIG_TYPE_FLOAT:
        *out = config_setting_get_float(s);
        break;
    default:
        return fail_at(L, s, NULL, "expected a number, got %s", type_name(config_setting_type(s)));
    }
    if (!isfinite(*out)) return fail_at(L, s, NULL, "must be a finite number, got %g", *out);
    return SPH_OK;
}

/* A float in a range: lo/hi are bounds (±INFINITY for none), *_open says
 * whether the bound itself is excluded.  `def` is used when the key is
 * absent and not required. */
static sph_status get_float(loader *L, const config_setting_t *g, const char *key, bool required,
                            double def, double lo, bool lo_open, double hi, bool hi_open,
                            double *out) {
    const config_setting_t *s;
    sph_status st = get_member(L, g, key, required, &s);
    if (st) return st;
    if (!s) {
        *out = def;
        return SPH_OK;
    }
    double v = 0.0;
    if ((st = as_float(L, s, &v))) return st;
    bool ok = (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    if (!ok) {
        if (isinf(hi))
            return fail_at(L, s, NULL, "must be %s %g, got %g", lo_open ? ">" : ">=", lo, v);
        if (isinf(lo))
            return fail_at(L, s, NULL, "must be %s %g, got %g", hi_open ? "<" : "<=", hi, v);
        return fail_at(L, s, NULL, "must be in %c%g, %g%c, got %g", lo_open ? '(' : '[', lo, hi,
                       hi_open ? ')' : ']', v);
    }
    *out = v;
    return SPH_OK;
}

/* An integer key, read whole (64 bits: an int and a 64-bit int alike) so
 * that the range check sees the value written, not its low 32 bits.  Absent
 * and not required: *present is false and *out untouched. */
static sph_status get_wide_int(loader *L, const config_setting_t *g, const char *key, bool required,
                               wide_int *out, bool *present, const config_setting_t **where) {
    const config_setting_t *s;
    sph_status st = get_member(L, g, key, required, &s);
    if (st) return st;
    *where = s;
    *present = s != NULL;
    if (!s) return SPH_OK;
    const int type = config_setting_type(s);
    if (type == CONFIG_TYPE_FLOAT) {
        /* an integer literal beyond 64 bits arrives as a number
         * (widen_integers): say that it is too large, not that it is a decimal */
        const double v = config_setting_get_float(s);
        if (isfinite(v) && v == floor(v) && fabs(v) >= 0x1p63)
            return fail_at(L, s, NULL,
                           "expected a 64-bit integer (-9223372036854775808 to "
                           "18446744073709551615), got %.17g",
                           v);
    }
    if (type != CONFIG_TYPE_INT && type != CONFIG_TYPE_INT64)
        return fail_at(L, s, NULL, "expected an integer, got %s", type_name(type));
    *out = wide_of(s);
    return SPH_OK;
}

/* An integer key in [lo, hi]; `def` when absent and not required. */
static sph_status get_int(loader *L, const config_setting_t *g, const char *key, bool required,
                          int def, int lo, int hi, int *out, const config_setting_t **where) {
    wide_int v = {false, 0};
    bool present = false;
    sph_status st = get_wide_int(L, g, key, required, &v, &present, where);
    if (st) return st;
    if (!present) {
        *out = def;
        return SPH_OK;
    }
    char text[24];
    if (!wide_in(v, lo, (unsigned long long)hi))
        return fail_at(L, *where, NULL, "must be in [%d, %d], got %s", lo, hi, wide_text(v, text));
    *out = (int)wide_double(v);
    return SPH_OK;
}

static sph_status get_bool(loader *L, const config_setting_t *g, const char *key, bool def,
                           bool *out) {
    const config_setting_t *s = config_setting_get_member(g, key);
    if (!s) {
        *out = def;
        return SPH_OK;
    }
    if (config_setting_type(s) != CONFIG_TYPE_BOOL)
        return fail_at(L, s, NULL, "expected a boolean (true or false), got %s",
                       type_name(config_setting_type(s)));
    *out = config_setting_get_bool(s) != 0;
    return SPH_OK;
}

static sph_status as_string(loader *L, const config_setting_t *s, const char **out) {
    if (config_setting_type(s) != CONFIG_TYPE_STRING)
        return fail_at(L, s, NULL, "expected a string, got %s", type_name(config_setting_type(s)));
    *out = config_setting_get_string(s);
    return SPH_OK;
}

/* A string naming a table entry (material, shape, observer): not empty and
 * short enough for SPH_NAME_LEN. */
static sph_status get_name(loader *L, const config_setting_t *g, const char *key, const char **out,
                           const config_setting_t **where) {
    sph_status st = get_member(L, g, key, true, where);
    if (st || (st = as_string(L, *where, out))) return st;
    if (!**out) return fail_at(L, *where, NULL, "must not be empty");
    if (strlen(*out) >= SPH_NAME_LEN)
        return fail_at(L, *where, NULL, "names are limited to %d characters", SPH_NAME_LEN - 1);
    return SPH_OK;
}

/* A string from a fixed set; *out is its index.  Absent and not required:
 * *out = def. */
static sph_status get_keyword(loader *L, const config_setting_t *g, const char *key, bool required,
                              int def, const char *const *words, int nwords, int *out,
                              const config_setting_t **where) {
    const config_setting_t *s;
    sph_status st = get_member(L, g, key, required, &s);
    if (st) return st;
    if (where) *where = s;
    if (!s) {
        *out = def;
        return SPH_OK;
    }
    const char *v = "";
    if ((st = as_string(L, s, &v))) return st;
    for (int i = 0; i < nwords; i++) {
        if (strcmp(v, words[i]) == 0) {
            *out = i;
            return SPH_OK;
        }
    }
    char list[256];
    size_t len = 0;
    for (int i = 0; i < nwords && len < sizeof list; i++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s\"%s\"", i ? ", " : "", words[i]);
    return fail_at(L, s, NULL, "must be one of %s, got \"%s\"", list, v);
}

/* A vector of `len` numbers: an array [..] or a list (..) of ints or floats. */
static sph_status as_vector(loader *L, const config_setting_t *s, int len, double out[3]) {
    int type = config_setting_type(s);
    if (type != CONFIG_TYPE_ARRAY && type != CONFIG_TYPE_LIST)
        return fail_at(L, s, NULL, "expected a vector of %d numbers [ ... ], got %s", len,
                       type_name(type));
    int n = config_setting_length(s);
    if (n != len)
        return fail_at(L, s, NULL, "expected a vector of %d numbers, got %d element%s", len, n,
                       n == 1 ? "" : "s");
    for (int i = 0; i < n; i++) {
        sph_status st = as_float(L, config_setting_get_elem(s, (unsigned)i), &out[i]);
        if (st) return st;
    }
    for (int i = n; i < 3; i++) out[i] = 0.0;
    return SPH_OK;
}

static sph_status get_vector(loader *L, const config_setting_t *g, const char *key, bool required,
                             int len, double out[3], const config_setting_t **where) {
    const config_setting_t *s;
    sph_status st = get_member(L, g, key, required, &s);
    if (st) return st;
    if (where) *where = s;
    if (!s) return SPH_OK; /* caller's default stays */
    return as_vector(L, s, len, out);
}

static sph_status get_group(loader *L, const config_setting_t *g, const char *key, bool required,
                            const config_setting_t **out) {
    sph_status st = get_member(L, g, key, required, out);
    if (st || !*out) return st;
    if (!config_setting_is_group(*out))
        return fail_at(L, *out, NULL, "expected a group { ... }, got %s",
                       type_name(config_setting_type(*out)));
    return SPH_OK;
}

static sph_status get_list(loader *L, const config_setting_t *g, const char *key, bool required,
                           const config_setting_t **out) {
    sph_status st = get_member(L, g, key, required, out);
    if (st || !*out) return st;
    if (!config_setting_is_list(*out))
        return fail_at(L, *out, NULL, "expected a list ( { ... }, ... ), got %s",
                       type_name(config_setting_type(*out)));
    return SPH_OK;
}

static const char *const AXES[] = {"x", "y", "z"};

/* The axes of a dimension, quoted, for the messages: "x", "x" or "y", ... */
static const char *axes_text(int dim) {
    return dim == 1 ? "\"x\"" : dim == 2 ? "\"x\" or \"y\"" : "\"x\", \"y\" or \"z\"";
}

/* The variables of the initial-field expressions, for the messages: "x",
 * "x, y", "x, y, z" */
static const char *variables_text(int dim) {
    return dim == 1 ? "x" : dim == 2 ? "x, y" : "x, y, z";
}

static sph_status get_axis(loader *L, const config_setting_t *g, const char *key, bool required,
                           int def, int *out) {
    const config_setting_t *s;
    sph_status st = get_keyword(L, g, key, required, def, AXES, 3, out, &s);
    if (st) return st;
    if (*out >= L->scene->dim)
        return fail_at(L, s, NULL, "must be %s in %dD, got \"%s\"", axes_text(L->scene->dim),
                       L->scene->dim, AXES[*out]);
    return SPH_OK;
}

/* ------------------------------------------------------------------------ */
/* integers beyond 32 bits                                                   */
/* ------------------------------------------------------------------------ */

/* libconfig 1.5 reads an integer literal without the L suffix with atoi()
 * (4294967298 becomes 2, 2147483648 becomes -2147483648) and one with the
 * suffix with atoll() (saturating at 2^63 - 1), silently.  So before text
 * reaches libconfig, every integer literal outside the int range is
 * rewritten into a form libconfig keeps exactly: a decimal with the L suffix
 * up to 2^63 - 1 (a 64-bit integer), a hexadecimal with the suffix from 2^63
 * to 2^64 - 1 (its bits kept; wide_of reads a hexadecimal unsigned), and
 * beyond 64 bits a decimal number (a number key takes it, an integer key
 * calls it out of range).  Comments and strings are copied untouched and no
 * line break moves, so libconfig's line numbers stay those of the text.
 * Literals in @include'd files are read by libconfig itself. */

typedef struct {
    char *buf;
    size_t len, cap;
} text_buf;

static bool put(text_buf *t, const char *s, size_t n) {
    if (t->len + n + 1 > t->cap) {
        size_t cap = t->cap ? t->cap : 256;
        while (t->len + n + 1 > cap) cap *= 2;
        char *b = realloc(t->buf, cap);
        if (!b) return false;
        t->buf = b;
        t->cap = cap;
    }
    memcpy(t->buf + t->len, s, n);
    t->len += n;
    t->buf[t->len] = '\0';
    return true;
}

static bool is_digit(char c) {
    return c >= '0' && c <= '9';
}

static int hex_value(char c) {
    if (is_digit(c)) return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

/* The length of the comment or string at p, else 0 (libconfig's #, //,
 * block comments and "strings" with backslash escapes). */
static size_t skip_opaque(const char *p) {
    const char *q = p;
    if (*q == '#' || (q[0] == '/' && q[1] == '/')) {
        while (*q && *q != '\n') q++;
    } else if (q[0] == '/' && q[1] == '*') {
        const char *end = strstr(q + 2, "*/");
        q = end ? end + 2 : q + strlen(q);
    } else if (*q == '"') {
        for (q++; *q && *q != '"'; q++)
            if (*q == '\\' && q[1]) q++;
        if (*q) q++;
    }
    return (size_t)(q - p);
}

/* One number token at p ([-+] digits, 0x hex, a float, an L or LL suffix),
 * rewritten into t as the comment above says; returns its length. */
static size_t widen_number(const char *p, text_buf *t, bool *ok) {
    const char *q = p;
    const bool negative = *q == '-';
    if (*q == '-' || *q == '+') q++;
    const bool hex =
        !negative && q == p && q[0] == '0' && (q[1] == 'x' || q[1] == 'X') && hex_value(q[2]) >= 0;
    unsigned long long mag = 0;
    bool overflow = false;
    double approx = 0.0; /* the value as a double, for one beyond 64 bits */
    const char *digits = q;
    if (hex) {
        for (q += 2; hex_value(*q) >= 0; q++) {
            overflow |= mag > (ULLONG_MAX >> 4);
            mag = (mag << 4) | (unsigned)hex_value(*q);
            approx = approx * 16.0 + hex_value(*q);
        }
    } else {
        while (is_digit(*q)) {
            const unsigned d = (unsigned)(*q - '0');
            overflow |= mag > (ULLONG_MAX - d) / 10;
            mag = mag * 10 + d;
            q++;
        }
        /* a float ("1.5", "2e6", ".5"): copied as it is */
        bool is_float = *q == '.';
        if (!is_float && (*q == 'e' || *q == 'E')) {
            const char *e = q + 1;
            if (*e == '+' || *e == '-') e++;
            is_float = is_digit(*e);
        }
        if (is_float) {
            if (*q == '.')
                for (q++; is_digit(*q);) q++;
            if (*q == 'e' || *q == 'E') {
                const char *e = q + 1;
                if (*e == '+' || *e == '-') e++;
                if (is_digit(*e))
                    for (q = e; is_digit(*q);) q++;
            }
            *ok = put(t, p, (size_t)(q - p));
            return (size_t)(q - p);
        }
    }
    const char *end_digits = q;
    if (*q == 'L') q += q[1] == 'L' ? 2 : 1;
    const size_t len = (size_t)(q - p);
    const bool fits_int =
        !overflow && (negative ? mag <= (unsigned long long)INT_MAX + 1ULL : mag <= INT_MAX);
    const bool fits_int64 =
        !overflow && (negative ? mag <= (unsigned long long)LLONG_MAX + 1ULL : mag <= LLONG_MAX);
    char out[64];
    if (fits_int || (fits_int64 && q != end_digits && hex) || q == digits) {
        *ok = put(t, p, len); /* libconfig reads it exactly (or it is no number) */
    } else if (fits_int64) {
        snprintf(out, sizeof out, "%s%lluL", negative ? "-" : "", mag);
        *ok = put(t, out, strlen(out));
    } else if (!overflow && !negative) {
        snprintf(out, sizeof out, "0x%llXL", mag);
        *ok = put(t, out, strlen(out));
    } else if (hex) {
        snprintf(out, sizeof out, "%.17e", approx);
        *ok = put(t, out, strlen(out));
    } else {
        /* the digits as written, made a decimal */
        *ok = put(t, p, (size_t)(end_digits - p)) && put(t, ".0", 2);
    }
    return len;
}

/* `text` with its large integer literals rewritten (see above), in a new
 * string (NULL: out of memory). */
static char *widen_integers(const char *text) {
    text_buf t = {NULL, 0, 0};
    bool ok = put(&t, "", 0);
    const char *p = text;
    while (ok && *p) {
        size_t n = skip_opaque(p);
        if (n) {
            ok = put(&t, p, n);
        } else if ((*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z') || *p == '*') {
            /* a name, digits and '-' included (libconfig's [A-Za-z*][-A-Za-z0-9_*]*) */
            const char *q = p + 1;
            while ((*q >= 'A' && *q <= 'Z') || (*q >= 'a' && *q <= 'z') || is_digit(*q) ||
                   *q == '_' || *q == '-' || *q == '*')
                q++;
            n = (size_t)(q - p);
            ok = put(&t, p, n);
        } else if (is_digit(*p) || *p == '.' ||
                   ((*p == '-' || *p == '+') && (is_digit(p[1]) || p[1] == '.'))) {
            n = widen_number(p, &t, &ok);
        } else {
            n = 1;
            ok = put(&t, p, 1);
        }
        p += n;
    }
    if (!ok) {
        free(t.buf);
        return NULL;
    }
    return t.buf;
}

/* ------------------------------------------------------------------------ */
/* overrides                                                                 */
/* ------------------------------------------------------------------------ */

/* Give setting s a new scalar value of src's type, in place (keeps its
 * position in the parent).  libconfig has no type-changing setter, so the
 * old value is released and the type reset first. */
static bool set_scalar(config_setting_t *s, const config_setting_t *src) {
    if (s->type == CONFIG_TYPE_STRING) free(s->value.sval);
    memset(&s->value, 0, sizeof s->value);
    s->type = CONFIG_TYPE_NONE;
    switch (src->type) {
    case CONFIG_TYPE_INT:
        return config_setting_set_int(s, config_setting_get_int(src));
    case CONFIG_TYPE_INT64:
        /* the format too: a hexadecimal 64-bit integer is read unsigned (wide_of) */
        return config_setting_set_int64(s, config_setting_get_int64(src)) &&
               config_setting_set_format(s, config_setting_get_format(src));
    case CONFIG_TYPE_FLOAT:
        return config_setting_set_float(s, config_setting_get_float(src));
    case CONFIG_TYPE_BOOL:
        return config_setting_set_bool(s, config_setting_get_bool(src));
    case CONFIG_TYPE_STRING:
        return config_setting_set_string(s, config_setting_get_string(src));
    default:
        return false;
    }
}

/* Deep copy of src as a new member `name` of parent (name ignored for list
 * and array parents), marked as coming from override `ov`. */
static config_setting_t *copy_setting(config_setting_t *parent, const char *name,
                                      const config_setting_t *src, const char *ov) {
    config_setting_t *s = config_setting_add(parent, name, src->type);
    if (!s) return NULL;
    config_setting_set_hook(s, (void *)ov);
    if (config_setting_is_aggregate(src)) {
        int n = config_setting_length(src);
        for (int i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(src, (unsigned)i);
            if (!copy_setting(s, e->name, e, ov)) return NULL;
        }
        return s;
    }
    s->type = CONFIG_TYPE_NONE; /* so that set_scalar accepts the value */
    return set_scalar(s, src) ? s : NULL;
}

/* Resolve one path component below `cur`: `[n]` is an element index, a name
 * is a group member or, in a list of groups, the element whose `name` is it. */
static config_setting_t *path_step(config_setting_t *cur, const char *comp) {
    if (!config_setting_is_aggregate(cur)) return NULL;
    if (comp[0] == '[') {
        char *end;
        long idx = strtol(comp + 1, &end, 10);
        /* [4294967296] must not wrap to element 0 */
        if (end == comp + 1 || strcmp(end, "]") != 0 || idx < 0 || idx > INT_MAX) return NULL;
        return config_setting_get_elem(cur, (unsigned)idx);
    }
    if (config_setting_is_group(cur)) return config_setting_get_member(cur, comp);
    if (config_setting_is_list(cur)) {
        int n = config_setting_length(cur);
        for (int i = 0; i < n; i++) {
            config_setting_t *e = config_setting_get_elem(cur, (unsigned)i);
            const char *name;
            if (config_setting_is_group(e) && config_setting_lookup_string(e, "name", &name) &&
                strcmp(name, comp) == 0)
                return e;
        }
    }
    return NULL;
}

/* Move the last element of aggregate p to position idx.  libconfig can only
 * append; its element table is public, so a replaced list element or group
 * member is put back in its place by hand (the order of bodies matters). */
static void move_last_to(config_setting_t *p, int idx) {
    config_list_t *list = p->value.list;
    unsigned last = list->length - 1;
    config_setting_t *moved = list->elements[last];
    memmove(&list->elements[idx + 1], &list->elements[idx],
            (last - (unsigned)idx) * sizeof list->elements[0]);
    list->elements[idx] = moved;
}

#define OV_FAIL(...) sph_fail(L->err, SPH_ERR_INPUT, __VA_ARGS__)

/* Apply one "key=value" to the tree. */
static sph_status apply_override(loader *L, config_t *cfg, const char *ov) {
    const char *eq = strchr(ov, '=');
    char key[SPH_SCENE_PATH_LEN];
    if (!eq) return OV_FAIL("--set %s: expected key=value (for example time.end=0.5)", ov);
    size_t klen = (size_t)(eq - ov);
    while (klen > 0 && (ov[klen - 1] == ' ' || ov[klen - 1] == '\t')) klen--;
    if (klen == 0) return OV_FAIL("--set %s: expected key=value, the key is empty", ov);
    if (klen >= sizeof key) return OV_FAIL("--set %s: the key is too long", ov);
    memcpy(key, ov, klen);
    key[klen] = '\0';
    if (key[0] == '.' || key[klen - 1] == '.' || strstr(key, ".."))
        return OV_FAIL("--set %s: the key has an empty component (write a.b.c)", ov);
    const char *value = eq + 1;
    while (*value == ' ' || *value == '\t') value++;

    /* The value in libconfig syntax (numbers, "strings", [vectors],
     * {groups}, true/false); anything else is taken as a bare string so that
     * method.formulation=enog needs no shell-quoted quotes. */
    config_t vcfg;
    config_init(&vcfg);
    size_t need = strlen(value) + 16;
    char *text = malloc(need);
    if (!text) {
        config_destroy(&vcfg);
        return sph_fail(L->err, SPH_ERR_RUNTIME, "out of memory applying --set %s", ov);
    }
    snprintf(text, need, "v = %s;", value);
    const config_setting_t *src = NULL;
    char *wide = widen_integers(text);
    free(text);
    if (!wide) {
        config_destroy(&vcfg);
        return sph_fail(L->err, SPH_ERR_RUNTIME, "out of memory applying --set %s", ov);
    }
    int parsed = config_read_string(&vcfg, wide);
    free(wide);
    if (parsed == CONFIG_TRUE && config_setting_length(config_root_setting(&vcfg)) == 1)
        src = config_setting_get_member(config_root_setting(&vcfg), "v");
    if (!src && parsed != CONFIG_TRUE && strchr("[({\"", value[0]) && value[0]) {
        /* meant as a vector, group or quoted string: a bare string would only
         * hide the real mistake */
        const char *why = config_error_text(&vcfg) ? config_error_text(&vcfg) : "syntax error";
        sph_status fst = OV_FAIL("--set %s: cannot parse the value: %s%s", ov, why,
                                 strstr(why, "mismatched element type")
                                     ? " (write every number of an array as a decimal (0.0, not 0))"
                                     : "");
        config_destroy(&vcfg);
        return fst;
    }
    if (!src) {
        config_destroy(&vcfg);
        config_init(&vcfg);
        config_setting_t *sv =
            config_setting_add(config_root_setting(&vcfg), "v", CONFIG_TYPE_STRING);
        if (!sv || !config_setting_set_string(sv, value)) {
            config_destroy(&vcfg);
            return sph_fail(L->err, SPH_ERR_RUNTIME, "out of memory applying --set %s", ov);
        }
        src = sv;
    }

    /* walk to the parent of the last component */
    sph_status st = SPH_OK;
    config_setting_t *parent = config_root_setting(cfg);
    char walked[SPH_SCENE_PATH_LEN] = "";
    char *save = NULL;
    char *comp = strtok_r(key, ".", &save);
    if (!comp) {
        st = OV_FAIL("--set %s: expected key=value, the key is empty", ov);
        goto done;
    }
    for (char *next = strtok_r(NULL, ".", &save); next; next = strtok_r(NULL, ".", &save)) {
        config_setting_t *child = path_step(parent, comp);
        size_t wl = strlen(walked);
        snprintf(walked + wl, sizeof walked - wl, "%s%s", wl ? "." : "", comp);
        /* optional groups a scene may leave out are created on demand, so
         * that e.g. --set output.snapshot_interval=0 works on any scene */
        static const char *const optional_groups[] = {"output",
                                                      "analysis",
                                                      "analysis.period",
                                                      "monitor",
                                                      "contact",
                                                      "monitor.domain",
                                                      "method.artificial_stress",
                                                      "boundary",
                                                      "boundary.far_field",
                                                      "forces"};
        for (size_t g = 0; !child && config_setting_is_group(parent) &&
                           g < sizeof optional_groups / sizeof optional_groups[0];
             ++g)
            if (strcmp(walked, optional_groups[g]) == 0)
                child = config_setting_add(parent, comp, CONFIG_TYPE_GROUP);
        /* and a body's relaxation group: --set bodies.ring.relaxation.steps=200 */
        if (!child && config_setting_is_group(parent) && strcmp(comp, "relaxation") == 0 &&
            config_setting_parent(parent) == config_lookup(cfg, "bodies")) {
            child = config_setting_add(parent, comp, CONFIG_TYPE_GROUP);
            /* the group is the override's: an error about it names the --set */
            if (child) config_setting_set_hook(child, (void *)ov);
        }
        if (!child) {
            st = OV_FAIL("--set %s: %s: no such setting in the scene, so it cannot hold '%s'", ov,
                         walked, next);
            goto done;
        }
        if (!config_setting_is_aggregate(child)) {
            st = OV_FAIL("--set %s: %s: is %s, not a group or list, so it cannot hold '%s'", ov,
                         walked, type_name(child->type), next);
            goto done;
        }
        parent = child;
        comp = next;
    }
    size_t wl = strlen(walked);
    snprintf(walked + wl, sizeof walked - wl, "%s%s", wl ? "." : "", comp);

    config_setting_t *target = path_step(parent, comp);
    if (!target) {
        /* create a new member; only groups have named members */
        if (!config_setting_is_group(parent) || comp[0] == '[') {
            st = OV_FAIL("--set %s: %s: no such element", ov, walked);
            goto done;
        }
        if (!copy_setting(parent, comp, src, ov))
            st = OV_FAIL("--set %s: %s: '%s' is not a valid setting name", ov, walked, comp);
        goto done;
    }

    if (config_setting_is_scalar(target) && config_setting_is_scalar(src)) {
        /* arrays hold one scalar type: an integer written into an array of
         * decimals becomes a decimal */
        config_setting_t tmp = *src;
        if (config_setting_is_array(parent) && config_setting_length(parent) > 1) {
            const config_setting_t *sib =
                config_setting_get_elem(parent, config_setting_index(target) == 0 ? 1 : 0);
            if (sib->type == CONFIG_TYPE_FLOAT &&
                (src->type == CONFIG_TYPE_INT || src->type == CONFIG_TYPE_INT64)) {
                tmp.type = CONFIG_TYPE_FLOAT;
                tmp.value.fval = wide_double(wide_of(src));
            } else if (sib->type != src->type) {
                st = OV_FAIL("--set %s: %s: every element of this array is %s, got %s", ov, walked,
                             type_name(sib->type), type_name(src->type));
                goto done;
            }
        }
        if (!set_scalar(target, &tmp)) {
            st = sph_fail(L->err, SPH_ERR_RUNTIME, "out of memory applying --set %s", ov);
            goto done;
        }
        config_setting_set_hook(target, (void *)ov);
        goto done;
    }

    /* an aggregate replaces or is replaced: rebuild the setting in place */
    if (config_setting_is_array(parent)) {
        st = OV_FAIL("--set %s: %s: an array element must be a single number, string or boolean",
                     ov, walked);
        goto done;
    }
    int idx = config_setting_index(target);
    char *name = NULL;
    if (config_setting_is_group(parent) && !(name = strdup(target->name))) {
        st = sph_fail(L->err, SPH_ERR_RUNTIME, "out of memory applying --set %s", ov);
        goto done;
    }
    config_setting_remove_elem(parent, (unsigned)idx);
    if (copy_setting(parent, name, src, ov))
        move_last_to(parent, idx);
    else
        st = sph_fail(L->err, SPH_ERR_RUNTIME, "out of memory applying --set %s", ov);
    free(name);

done:
    config_destroy(&vcfg);
    return st;
}

/* ------------------------------------------------------------------------ */
/* schema                                                                    */
/* ------------------------------------------------------------------------ */

static sph_status parse_resolution(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = get_group(L, root, "resolution", true, &g);
    if (st || (st = check_keys(L, g, KEYS("dp", "reference_length", "ratio")))) return st;
    bool has_dp = config_setting_get_member(g, "dp") != NULL;
    bool has_ratio_form = config_setting_get_member(g, "reference_length") != NULL ||
                          config_setting_get_member(g, "ratio") != NULL;
    if (has_dp && has_ratio_form) {
        /* point at an override that brought in the second form, if any */
        const config_setting_t *at = g;
        const char *members[3] = {"dp", "reference_length", "ratio"};
        for (int i = 0; i < 3 && !override_of(at); i++) {
            const config_setting_t *m = config_setting_get_member(g, members[i]);
            if (m && override_of(m)) at = m;
        }
        return fail_at(L, at, NULL,
                       "give either dp or reference_length and ratio (dp = reference_length / "
                       "ratio), not both");
    }
    if (!has_dp && !has_ratio_form)
        return fail_at(L, g, NULL, "missing required key: dp, or reference_length and ratio");
    if (has_dp) return get_float(L, g, "dp", true, 0, 0, true, INFINITY, false, &sc->dp);
    double length = 0.0, ratio = 1.0;
    if ((st = get_float(L, g, "reference_length", true, 0, 0, true, INFINITY, false, &length)) ||
        (st = get_float(L, g, "ratio", true, 0, 0, true, INFINITY, false, &ratio)))
        return st;
    sc->dp = length / ratio;
    return SPH_OK;
}

static const char *const FORMULATION_NAMES[] = {"enog",  "enog-a",      "og",
                                                "oas",   "gnog",        "gnog-a",
                                                "tlsph", "eulerian-wc", "eulerian-compressible"};
static const char *const KERNEL_NAMES[] = {"wendland-c2", "laguerre-gauss", "laguerre-wendland",
                                           "cubic-bspline"};

/* ENOG-A and GNOG-A carry a rotation correction (003 eqs. 38-42, 47); the
 * other formulations have none. */
static bool formulation_rotates(int f) {
    return f == SPH_FORMULATION_ENOG_A || f == SPH_FORMULATION_GNOG_A;
}

static sph_status parse_method(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g, *rot_at;
    sph_status st = get_group(L, root, "method", true, &g);
    if (st || (st = check_keys(L, g,
                               KEYS("formulation", "rotation", "torque_projection", "kernel",
                                    "smoothing_ratio", "xi_e", "xi_g", "riemann_limiter",
                                    "viscous_regularization", "artificial_stress",
                                    "hourglass_alpha", "pairwise_damping"))))
        return st;
    int formulation = 0, rotation = 0, kernel = 0;
    const config_setting_t *form_at;
    if ((st = get_keyword(L, g, "formulation", true, 0, FORMULATION_NAMES,
                          (int)(sizeof FORMULATION_NAMES / sizeof FORMULATION_NAMES[0]),
                          &formulation, &form_at)))
        return st;
    sc->formulation = (sph_formulation)formulation;
    const bool eulerian = SPH_FORMULATION_IS_EULERIAN(formulation);
    if (eulerian) {
        /* seed 004 §3.1: a fluid has no shear stress, so the coefficients of
         * the solid formulations' shear and hourglass terms mean nothing */
        static const char *const solid_keys[] = {
            "torque_projection", "xi_e", "xi_g", "artificial_stress", "hourglass_alpha",
            "pairwise_damping"};
        for (size_t k = 0; k < sizeof solid_keys / sizeof solid_keys[0]; ++k) {
            const config_setting_t *m = config_setting_get_member(g, solid_keys[k]);
            if (m)
                return fail_at(L, m, NULL,
                               "is for the solid formulations; formulation \"%s\" simulates a "
                               "fluid (seed 004, section 3.1), which has no shear stress",
                               FORMULATION_NAMES[formulation]);
        }
    }
    const bool rotates = formulation_rotates(formulation);
    const int def_rot = rotates ? SPH_ROTATION_AVERAGED : SPH_ROTATION_NONE;
    if ((st = get_keyword(L, g, "rotation", false, def_rot,
                          KEYS("none", "averaged", "per-particle"), &rotation, &rot_at)))
        return st;
    const bool rotated_bare = !rotates && rotation != SPH_ROTATION_NONE;
    const bool rotating_none = rotates && rotation == SPH_ROTATION_NONE;
    if ((rotated_bare || rotating_none) && rot_at && override_of(form_at) && !override_of(rot_at)) {
        /* the override of the formulation caused the conflict: say so, and
         * what else to set */
        return fail_at(L, form_at, NULL,
                       "formulation \"%s\" conflicts with method.rotation = \"%s\" (%s:%u); "
                       "add --set method.rotation=%s",
                       sph_formulation_name((sph_formulation)formulation),
                       sph_rotation_name((sph_rotation)rotation), L->file,
                       config_setting_source_line(rot_at), rotated_bare ? "none" : "averaged");
    }
    if (rotated_bare)
        return fail_at(L, rot_at, NULL,
                       "formulation \"%s\" has no rotation correction, so rotation must be "
                       "\"none\", got \"%s\" (the rotation-corrected formulations are \"enog-a\" "
                       "and \"gnog-a\")",
                       sph_formulation_name((sph_formulation)formulation),
                       sph_rotation_name((sph_rotation)rotation));
    if (rotating_none)
        return fail_at(L, rot_at, NULL,
                       "formulation \"%s\" needs a rotation correction, so rotation must be "
                       "\"averaged\" or \"per-particle\", got \"none\" (use \"%s\" for an "
                       "uncorrected run)",
                       sph_formulation_name((sph_formulation)formulation),
                       formulation == SPH_FORMULATION_ENOG_A ? "enog" : "gnog");
    sc->rotation = (sph_rotation)rotation;
    /* SPH-ENOG-A's accumulated shear acceleration kept free of net torque
     * (device/sph_torque_projection.h): our addition to 003, off by default */
    if ((st = get_bool(L, g, "torque_projection", false, &sc->torque_projection))) return st;
    if (sc->torque_projection &&
        (formulation != SPH_FORMULATION_ENOG_A || rotation != SPH_ROTATION_AVERAGED)) {
        const config_setting_t *tp_at = config_setting_get_member(g, "torque_projection");
        return fail_at(L, tp_at, NULL,
                       "only formulation \"enog-a\" with rotation \"averaged\" has it, "
                       "got formulation \"%s\" with rotation \"%s\"",
                       sph_formulation_name((sph_formulation)formulation),
                       sph_rotation_name((sph_rotation)rotation));
    }
    if ((st = get_keyword(L, g, "kernel", false, SPH_KERNEL_WENDLAND_C2, KERNEL_NAMES,
                          (int)(sizeof KERNEL_NAMES / sizeof KERNEL_NAMES[0]), &kernel, NULL)))
        return st;
    sc->kernel = (sph_kernel)kernel;
    if ((st = get_float(L, g, "smoothing_ratio", false, 1.3, 1.0, false, 2.0, false,
                        &sc->smoothing_ratio)))
        return st;
    /* xi_E: the coefficient of the shear-acceleration Laplacian, 0.7 d + 2.1
     * as calibrated in 000 (eq. 23, "zeta"; 003 eq. 25) */
    if ((st = get_float(L, g, "xi_e", false, 0.7 * sc->dim + 2.1, 0, true, INFINITY, false,
                        &sc->xi_e)))
        return st;
    /* xi_G: resolved against the material in parse_scene (NAN: default) */
    if ((st = get_float(L, g, "xi_g", false, NAN, 0, true, INFINITY, false, &sc->xi_g))) return st;
    /* Gray, Monaghan & Swift (2001) artificial stress: epsilon = 0.3 and
     * n = 4 with f = W(r)/W(dp), their values for elastic solids (§4 of
     * that paper, as also used by the SPH-OAS runs of 000 and PySPH) */
    const config_setting_t *art;
    if ((st = get_group(L, g, "artificial_stress", false, &art))) return st;
    sc->art_epsilon = 0.3;
    sc->art_exponent = 4.0;
    if (art &&
        ((st = check_keys(L, art, KEYS("epsilon", "exponent"))) ||
         (st = get_float(L, art, "epsilon", false, 0.3, 0, false, 10, false, &sc->art_epsilon)) ||
         (st = get_float(L, art, "exponent", false, 4.0, 0, true, 16, false, &sc->art_exponent))))
        return st;
    /* Hourglass control of TLSPH (002, f^HG in device/tl_step.cl).  002's own
     * alpha is lost from the seed text (@xmath93); 0.1 is the default of
     * TrixiParticles.jl, whose PenaltyForceGanzenmueller prints 002's
     * formula.  On the 2D plate (H/dp = 10) it cuts a zero-energy
     * checkerboard mode 16-fold (tests/test_tlsph.c) and shortens the period
     * by only 0.13 % against alpha = 0 (alpha = 1: 0.72 %, away from 004's
     * T_W); see docs/scene-format.md */
    if ((st = get_float(L, g, "hourglass_alpha", false, 0.1, 0, false, 100, false,
                        &sc->hourglass_alpha)))
        return st;
    /* TLSPH's pairwise numerical damping (device/tl_step.cl): 0 by default,
     * the elastic TLSPH of 004 as printed; the public code's TLSPH runs
     * c_d = 0.25 (eulerian-sph-reference.md §5.4) */
    const config_setting_t *damping_at = config_setting_get_member(g, "pairwise_damping");
    if (damping_at && formulation != SPH_FORMULATION_TLSPH)
        return fail_at(L, damping_at, NULL,
                       "is the pairwise damping of \"tlsph\" (total-Lagrangian SPH); "
                       "formulation \"%s\" has none",
                       FORMULATION_NAMES[formulation]);
    if ((st = get_float(L, g, "pairwise_damping", false, 0.0, 0, false, 10, false,
                        &sc->pairwise_damping)))
        return st;
    /* The limiter slope eta of beta = min(eta max(u_l - u_r, 0) / c, 1):
     * 0 (unlimited) for the solids; for the fluids the seed's values,
     * eta_linearised = 15 (seed 004 eqs. 21-22, also the public code's) and
     * eta_HLLC = 1 (eqs. 19-20; the public code runs 5) */
    const double limiter = formulation == SPH_FORMULATION_EULERIAN_WC             ? 15.0
                           : formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE ? 1.0
                                                                                  : 0.0;
    if ((st = get_float(L, g, "riemann_limiter", false, limiter, 0, false, INFINITY, false,
                        &sc->riemann_limiter_slope)))
        return st;
    const config_setting_t *visc_at = config_setting_get_member(g, "viscous_regularization");
    if (!eulerian && visc_at)
        return fail_at(L, visc_at, NULL,
                       "is for the fluid formulations (\"eulerian-wc\" and "
                       "\"eulerian-compressible\"), got formulation \"%s\"",
                       FORMULATION_NAMES[formulation]);
    int regularization = SPH_VISCOUS_SQUARED;
    if ((st = get_keyword(L, g, "viscous_regularization", false, SPH_VISCOUS_SQUARED,
                          KEYS("squared", "linear"), &regularization, NULL)))
        return st;
    sc->viscous_regularization = (sph_viscous_regularization)regularization;
    return SPH_OK;
}

static sph_status parse_time(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = get_group(L, root, "time", true, &g);
    if (st || (st = check_keys(L, g,
                               KEYS("end", "output_interval", "stepping", "cfl_advection",
                                    "cfl_acoustic", "reference_speed", "acceleration_criterion",
                                    "frozen_geometry", "integrator"))))
        return st;
    if ((st = get_float(L, g, "end", true, 0, 0, true, INFINITY, false, &sc->end_time)) ||
        (st = get_float(L, g, "output_interval", true, 0, 0, true, INFINITY, false,
                        &sc->output_interval)))
        return st;
    if (sc->output_interval > sc->end_time)
        return fail_at(L, config_setting_get_member(g, "output_interval"), NULL,
                       "must not exceed time.end (%g), got %g", sc->end_time, sc->output_interval);
    /* The eulerian formulations keep their particles where they were placed
     * (seed 004 §3.1): no advection step, no neighbour rebuild, so no
     * advection CFL, no frozen pair geometry and no acceleration criterion;
     * every step is an acoustic one */
    const bool eulerian = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    if (eulerian) {
        static const char *const moving[] = {"cfl_advection", "frozen_geometry",
                                             "acceleration_criterion"};
        for (size_t k = 0; k < sizeof moving / sizeof moving[0]; ++k) {
            const config_setting_t *m = config_setting_get_member(g, moving[k]);
            if (m)
                return fail_at(L, m, NULL,
                               "is for the formulations whose particles move (the advection "
                               "step); formulation \"%s\" keeps its particles fixed and steps "
                               "by time.cfl_acoustic alone",
                               sph_formulation_name(sc->formulation));
        }
    }
    int stepping = 0;
    const config_setting_t *stepping_at = NULL;
    if ((st = get_keyword(L, g, "stepping", false,
                          eulerian ? SPH_STEPPING_SINGLE : SPH_STEPPING_DUAL,
                          KEYS("dual", "single"), &stepping, &stepping_at)))
        return st;
    if (eulerian && stepping == SPH_STEPPING_DUAL)
        return fail_at(L, stepping_at, NULL,
                       "formulation \"%s\" keeps its particles fixed: there is no advection "
                       "step to take dual-criteria steps with, so stepping must be \"single\" "
                       "(its default), got \"dual\"",
                       sph_formulation_name(sc->formulation));
    sc->stepping = (sph_stepping)stepping;
    /* the fluids' update: the public code's two stages, or SSP-RK2 */
    const config_setting_t *integrator_at = config_setting_get_member(g, "integrator");
    if (integrator_at && !eulerian)
        return fail_at(L, integrator_at, NULL,
                       "is for the fluid formulations (\"eulerian-wc\", "
                       "\"eulerian-compressible\"); formulation \"%s\" steps by time.stepping",
                       sph_formulation_name(sc->formulation));
    int integrator = SPH_FLUID_TWO_STAGE;
    if ((st = get_keyword(L, g, "integrator", false, SPH_FLUID_TWO_STAGE,
                          KEYS("two-stage", "ssp-rk2"), &integrator, NULL)))
        return st;
    sc->fluid_integrator = (sph_fluid_integrator)integrator;
    /* The acoustic step's CFL: 0.4 (000, 003), 0.2 with the Laguerre-Wendland
     * kernel, whose stiffest lattice mode is 2.3x Wendland's at the same h:
     * leapfrog's limit is CFL 0.47 there (tools/kernel_lattice_stiffness.py)
     * and the plate (h = 2 dp) blows up at 0.3-0.4 within 5 ms, runs to 1 s at
     * 0.2 (docs/method.md, kernels).  The fluids: 0.6 / d, the public
     * reference code's dt = (0.6 / d) h / max(c + |v|) (the seed gives no
     * step size); in 1D 0.4, not 0.6: the Shu-Osher line (dp = 1/200)
     * loses positive pressure at t = 0.24 with 0.6 and runs with 0.5 (L1
     * density error 0.0298; 0.4: 0.0303, 0.3: 0.0419, docs/fluids.md) */
    const double cfl_acoustic = eulerian && sc->dim == 1                     ? 0.4
                                : eulerian                                   ? 0.6 / sc->dim
                                : sc->kernel == SPH_KERNEL_LAGUERRE_WENDLAND ? 0.2
                                                                             : 0.4;
    if ((st =
             get_float(L, g, "cfl_advection", false, 0.2, 0, true, 1, false, &sc->cfl_advection)) ||
        (st = get_float(L, g, "cfl_acoustic", false, cfl_acoustic, 0, true, 1, false,
                        &sc->cfl_acoustic)))
        return st;
    sc->has_reference_speed = config_setting_get_member(g, "reference_speed") != NULL;
    if ((st = get_float(L, g, "reference_speed", false, 0.0, 0, false, INFINITY, false,
                        &sc->reference_speed)))
        return st;
    int geometry = 0;
    if ((st = get_keyword(L, g, "frozen_geometry", false, 0, KEYS("midpoint", "start"), &geometry,
                          NULL)))
        return st;
    sc->geometry_at_start = geometry == 1;
    return get_bool(L, g, "acceleration_criterion", true, &sc->acceleration_criterion);
}

/* A fluid material (no youngs_modulus) of the eulerian formulations: rho0,
 * and the weakly compressible fluid's c0 (p = c0^2 (rho - rho0), seed 004
 * eq. 11) or the ideal gas's gamma (p = (gamma - 1) rho e, eq. 11, with
 * c = sqrt(gamma p / rho), eq. 12), and the dynamic viscosity mu of eq. 13. */
static sph_status parse_fluid_material(loader *L, const config_setting_t *m, sph_material *mat) {
    const sph_formulation f = L->scene->formulation;
    const char *fname = sph_formulation_name(f);
    static const char *const solid_only[] = {"poisson_ratio", "yield_stress", "hardening_modulus",
                                             "model", "exponential_b"};
    for (size_t k = 0; k < sizeof solid_only / sizeof solid_only[0]; ++k) {
        const config_setting_t *s = config_setting_get_member(m, solid_only[k]);
        if (s)
            return fail_at(L, s, NULL,
                           "is for solid materials; material '%s' is a fluid (it has no "
                           "youngs_modulus), as formulation \"%s\" needs",
                           m->name, fname);
    }
    sph_status st;
    if ((st = get_float(L, m, "density", true, 0, 0, true, INFINITY, false, &mat->density)) ||
        (st = get_float(L, m, "viscosity", false, 0.0, 0, false, INFINITY, false, &mat->viscosity)))
        return st;
    mat->fluid = true;
    mat->youngs_modulus = mat->poisson_ratio = mat->shear_modulus = 0.0;
    const config_setting_t *gamma_at = config_setting_get_member(m, "gamma");
    const config_setting_t *c_at = config_setting_get_member(m, "sound_speed");
    if (f == SPH_FORMULATION_EULERIAN_WC) {
        if (gamma_at)
            return fail_at(L, gamma_at, NULL,
                           "is the ideal gas's ratio of specific heats (formulation "
                           "\"eulerian-compressible\"); the weakly compressible fluid of "
                           "\"eulerian-wc\" has p = c0^2 (rho - rho0) (seed 004 eq. 11), set by "
                           "sound_speed");
        if ((st = get_float(L, m, "sound_speed", true, 0, 0, true, INFINITY, false,
                            &mat->sound_speed)))
            return st;
        mat->bulk_modulus = mat->density * mat->sound_speed * mat->sound_speed;
        mat->gamma = 0.0;
        if (!isfinite(mat->bulk_modulus))
            return fail_at(L, c_at, NULL,
                           "density %g and sound_speed %g give the bulk modulus rho0 c0^2 = %g: "
                           "not finite",
                           mat->density, mat->sound_speed, mat->bulk_modulus);
        return SPH_OK;
    }
    /* the ideal gas: its sound speed is a state variable */
    if (c_at)
        return fail_at(L, c_at, NULL,
                       "an ideal gas's sound speed follows from its state, c = sqrt(gamma p / rho) "
                       "(seed 004 eq. 12); leave sound_speed out and give the bodies' "
                       "initial_pressure (and initial_density)");
    mat->gamma = 1.4;
    if (gamma_at && (st = as_float(L, gamma_at, &mat->gamma))) return st;
    /* 5/3 itself cannot be written in the 15 digits a stored scene keeps
     * (check_resolved): 1.66666666666667 and 1.666667 are accepted as 5/3 */
    if (!(mat->gamma > 1.0 && mat->gamma <= 5.0 / 3.0 + 1e-6))
        return fail_at(L, gamma_at ? gamma_at : m, gamma_at ? NULL : "gamma",
                       "an ideal gas has 1 < gamma <= 5/3 (5/3: monatomic, 7/5: diatomic such "
                       "as air), got %g",
                       mat->gamma);
    mat->sound_speed = 0.0;
    mat->bulk_modulus = 0.0;
    return SPH_OK;
}

/* TLSPH's elastic law (device/tl_step.cl): `model`, and the exponential
 * law's stiffening exponent `exponential_b` (1 by default, the public
 * code's bending column; eulerian-sph-reference.md §5.4).  Which
 * formulations take it is checked with the formulation (check_material_model). */
static sph_status parse_elastic_model(loader *L, const config_setting_t *m, sph_material *mat) {
    static const char *const names[] = {"saint-venant-kirchhoff", "neo-hookean", "exponential"};
    _Static_assert(ELASTIC_MODEL_SVK == 0 && ELASTIC_MODEL_NEO_HOOKEAN == 1 &&
                       ELASTIC_MODEL_EXPONENTIAL == 2,
                   "names[] follows ELASTIC_MODEL_*");
    const config_setting_t *model_at;
    sph_status st = get_keyword(L, m, "model", false, ELASTIC_MODEL_SVK, names, 3,
                                &mat->elastic_model, &model_at);
    if (st) return st;
    if (mat->plastic && model_at && mat->elastic_model != ELASTIC_MODEL_SVK)
        return fail_at(L, model_at, NULL,
                       "material '%s' is J2-plastic (it has a yield_stress), whose elastic range "
                       "is Hencky's (device/sph_plasticity.h); model \"%s\" is for elastic "
                       "materials",
                       m->name, names[mat->elastic_model]);
    const config_setting_t *b_at = config_setting_get_member(m, "exponential_b");
    if (b_at && mat->elastic_model != ELASTIC_MODEL_EXPONENTIAL)
        return fail_at(L, b_at, NULL,
                       "is the stiffening exponent of model \"exponential\"; material '%s' has "
                       "model \"%s\"",
                       m->name, names[mat->elastic_model]);
    return get_float(L, m, "exponential_b", false, 1.0, 0, true, 100, false, &mat->exponential_b);
}

static sph_status parse_materials(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = get_group(L, root, "materials", true, &g);
    if (st) return st;
    int n = config_setting_length(g);
    if (n == 0) return fail_at(L, g, NULL, "define at least one material");
    if (n > SPH_MAX_MATERIALS)
        return fail_at(L, g, NULL, "at most %d materials, got %d", SPH_MAX_MATERIALS, n);
    const bool eulerian = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    if (eulerian && n > 1)
        return fail_at(L, g, NULL,
                       "several materials (%d) are not supported for the eulerian formulations "
                       "yet: define one fluid (several bodies may share it)",
                       n);
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(g, (unsigned)i);
        sph_material *mat = &sc->materials[i];
        if (!config_setting_is_group(m))
            return fail_at(L, m, NULL,
                           "expected a group { density; youngs_modulus; poisson_ratio; }, got %s",
                           type_name(config_setting_type(m)));
        char why[256];
        if (!sph_name_check(m->name, why, sizeof why)) return fail_at(L, m, NULL, "%s", why);
        if ((st = check_keys(L, m,
                             KEYS("density", "youngs_modulus", "poisson_ratio", "sound_speed",
                                  "yield_stress", "hardening_modulus", "model", "exponential_b",
                                  "viscosity", "gamma"))))
            return st;
        snprintf(mat->name, sizeof mat->name, "%s", m->name);
        /* a material without youngs_modulus is a fluid: the eulerian
         * formulations take fluids only, the others solids only */
        const config_setting_t *E_at = config_setting_get_member(m, "youngs_modulus");
        if (eulerian && E_at)
            return fail_at(L, E_at, NULL,
                           "material '%s' is a solid (it has a youngs_modulus), and formulation "
                           "\"%s\" simulates a fluid; a fluid material has density, "
                           "%s and viscosity",
                           m->name, sph_formulation_name(sc->formulation),
                           sc->formulation == SPH_FORMULATION_EULERIAN_WC ? "sound_speed"
                                                                          : "gamma");
        if (eulerian) {
            if ((st = parse_fluid_material(L, m, mat))) return st;
            continue;
        }
        if (!E_at && !config_setting_get_member(m, "poisson_ratio"))
            return fail_at(L, m, NULL,
                           "a material without youngs_modulus is a fluid, which needs "
                           "method.formulation \"eulerian-wc\" or \"eulerian-compressible\", "
                           "got \"%s\"; a solid material gives youngs_modulus and poisson_ratio",
                           sph_formulation_name(sc->formulation));
        static const char *const fluid_only[] = {"viscosity", "gamma"};
        for (size_t k = 0; k < sizeof fluid_only / sizeof fluid_only[0]; ++k) {
            const config_setting_t *s = config_setting_get_member(m, fluid_only[k]);
            if (s)
                return fail_at(L, s, NULL,
                               "is for fluid materials (formulations \"eulerian-wc\" and "
                               "\"eulerian-compressible\"); material '%s' is a solid (it has a "
                               "youngs_modulus)",
                               m->name);
        }
        if ((st = get_float(L, m, "density", true, 0, 0, true, INFINITY, false, &mat->density)) ||
            (st = get_float(L, m, "youngs_modulus", true, 0, 0, true, INFINITY, false,
                            &mat->youngs_modulus)) ||
            (st = get_float(L, m, "poisson_ratio", true, 0, 0, false, 0.5, true,
                            &mat->poisson_ratio)))
            return st;
        mat->plastic = config_setting_get_member(m, "yield_stress") != NULL;
        if ((st = get_float(L, m, "yield_stress", false, 0.0, 0, true, INFINITY, false,
                            &mat->yield_stress)) ||
            (st = get_float(L, m, "hardening_modulus", false, 0.0, 0, false, INFINITY, false,
                            &mat->hardening_modulus)))
            return st;
        if (!mat->plastic && config_setting_get_member(m, "hardening_modulus"))
            return fail_at(L, config_setting_get_member(m, "hardening_modulus"), NULL,
                           "a hardening modulus needs a yield_stress (J2 plasticity)");
        if ((st = parse_elastic_model(L, m, mat))) return st;
        double E = mat->youngs_modulus, nu = mat->poisson_ratio;
        mat->bulk_modulus = E / (3.0 * (1.0 - 2.0 * nu));
        mat->shear_modulus = E / (2.0 * (1.0 + nu));
        /* 000 eq. 5: c0 = sqrt(K / rho0) */
        mat->sound_speed = sqrt(mat->bulk_modulus / mat->density);
        /* A hydrocode material (003 §5.2.3 after Mehra & Chaturvedi 2006)
         * gives its bulk sound speed beside the shear response: then the
         * equation of state takes K = rho0 c0^2 and E, nu set G alone. */
        if (config_setting_get_member(m, "sound_speed")) {
            if ((st = get_float(L, m, "sound_speed", false, 0.0, 0, true, INFINITY, false,
                                &mat->sound_speed)))
                return st;
            mat->bulk_modulus = mat->density * mat->sound_speed * mat->sound_speed;
        }
        /* extreme but finite inputs can overflow (or underflow) the derived
         * constants the solver divides by */
        if (!(isfinite(mat->bulk_modulus) && isfinite(mat->shear_modulus) &&
              isfinite(mat->sound_speed) && mat->shear_modulus > 0 && mat->sound_speed > 0))
            return fail_at(
                L, m, NULL,
                "density %g, youngs_modulus %g and poisson_ratio %.17g give bulk modulus "
                "%g, shear modulus %g and sound speed %g: not finite and positive",
                mat->density, E, nu, mat->bulk_modulus, mat->shear_modulus, mat->sound_speed);
    }
    sc->nmaterials = n;
    return SPH_OK;
}

static int find_named_shape(const loader *L, const char *name) {
    for (int i = 0; i < L->nnamed_shapes; i++)
        if (strcmp(L->scene->shapes[i].name, name) == 0) return i;
    return -1;
}

static sph_status unknown_shape(loader *L, const config_setting_t *at, const char *name) {
    const char *names[SPH_SCENE_MAX_SHAPES];
    for (int i = 0; i < L->nnamed_shapes; i++) names[i] = L->scene->shapes[i].name;
    char hint[1024];
    suggest(name, names, L->nnamed_shapes, "defined shapes", hint, sizeof hint);
    return fail_at(L, at, NULL, "unknown shape '%s'%s", name, hint);
}

static sph_status parse_shape(loader *L, const config_setting_t *s, int index);

/* One element of a union/difference `parts`: a shape name or an inline shape. */
static sph_status parse_part(loader *L, const config_setting_t *e, int *out) {
    if (config_setting_type(e) == CONFIG_TYPE_STRING) {
        const char *name = config_setting_get_string(e);
        *out = find_named_shape(L, name);
        if (*out < 0) return unknown_shape(L, e, name);
        return SPH_OK;
    }
    if (config_setting_is_group(e)) {
        sph_scene *sc = L->scene;
        if (sc->nshapes >= SPH_SCENE_MAX_SHAPES)
            return fail_at(L, e, NULL, "too many shapes (at most %d, inline ones included)",
                           SPH_SCENE_MAX_SHAPES);
        *out = sc->nshapes++;
        sc->shapes[*out].name[0] = '\0';
        return parse_shape(L, e, *out);
    }
    return fail_at(L, e, NULL,
                   "expected a shape name or an inline shape group { type = ...; }, got %s",
                   type_name(config_setting_type(e)));
}

/* disc, ball, annulus, hollow_sphere (kind 3..6: inner <= |x - centre| <=
 * outer) and cylinder (kind 7); the bounding box goes to lower/upper. */
static sph_status parse_round_shape(loader *L, const config_setting_t *s,
                                    const config_setting_t *type_at, int kind, sph_shape *sh) {
    static const char *const names[] = {"disc", "ball", "annulus", "hollow_sphere", "cylinder"};
    static const char *const other[] = {"ball", "disc", "hollow_sphere", "annulus", ""};
    const int dim = L->scene->dim;
    const int need = kind == 3 || kind == 5 ? 2 : 3;
    if (dim == 1)
        return fail_at(L, type_at, NULL,
                       "\"%s\" is a %dD shape; a line (dimension 1) is made of \"box\"es, "
                       "lower = [x0]; upper = [x1]",
                       names[kind - 3], need);
    if (dim != need) {
        if (kind == 7)
            return fail_at(L, type_at, NULL,
                           "\"cylinder\" is a 3D shape; in 2D a rectangle is a \"box\"");
        return fail_at(L, type_at, NULL, "\"%s\" is a %dD shape; in %dD use \"%s\"",
                       names[kind - 3], need, dim, other[kind - 3]);
    }
    const bool hollow = kind == 5 || kind == 6;
    sph_status st;
    if (kind == 7)
        st = check_keys(L, s, KEYS("type", "centre", "axis", "radius", "length"));
    else if (hollow)
        st = check_keys(L, s, KEYS("type", "centre", "inner_radius", "outer_radius"));
    else
        st = check_keys(L, s, KEYS("type", "centre", "radius"));
    if (st || (st = get_vector(L, s, "centre", true, dim, sh->centre, NULL))) return st;
    sh->type = kind == 7 ? SPH_SHAPE_CYLINDER : SPH_SHAPE_SPHERE;
    sh->nparts = 0;
    sh->inner_radius = 0.0;
    sh->length = 0.0;
    for (int a = 0; a < 3; a++) sh->axis[a] = 0.0;
    if (hollow) {
        const config_setting_t *outer_at;
        if ((st = get_float(L, s, "inner_radius", true, 0, 0, true, INFINITY, false,
                            &sh->inner_radius)) ||
            (st = get_float(L, s, "outer_radius", true, 0, 0, true, INFINITY, false,
                            &sh->outer_radius)) ||
            (st = get_member(L, s, "outer_radius", true, &outer_at)))
            return st;
        if (!(sh->outer_radius > sh->inner_radius))
            return fail_at(L, outer_at, NULL, "must exceed inner_radius = %g, got %g",
                           sh->inner_radius, sh->outer_radius);
    } else if ((st = get_float(L, s, "radius", true, 0, 0, true, INFINITY, false,
                               &sh->outer_radius))) {
        return st;
    }
    double half[3] = {sh->outer_radius, sh->outer_radius, sh->outer_radius};
    double lo_end[3] = {0, 0, 0}, hi_end[3] = {0, 0, 0};
    if (kind == 7) {
        const config_setting_t *axis_at;
        if ((st = get_vector(L, s, "axis", true, 3, sh->axis, &axis_at)) ||
            (st = get_float(L, s, "length", true, 0, 0, true, INFINITY, false, &sh->length)))
            return st;
        const double norm =
            sqrt(sh->axis[0] * sh->axis[0] + sh->axis[1] * sh->axis[1] + sh->axis[2] * sh->axis[2]);
        if (!(norm > 0.0) || !isfinite(norm))
            return fail_at(L, axis_at, NULL, "must be a non-zero direction, got (%g, %g, %g)",
                           sh->axis[0], sh->axis[1], sh->axis[2]);
        /* the box of a cylinder: the two end discs of radius R and normal a
         * reach R sqrt(1 - a_k^2) along axis k around their centres */
        for (int a = 0; a < 3; a++) {
            sh->axis[a] /= norm;
            const double end = sh->length * sh->axis[a];
            lo_end[a] = fmin(0.0, end);
            hi_end[a] = fmax(0.0, end);
            half[a] = sh->outer_radius * sqrt(fmax(0.0, 1.0 - sh->axis[a] * sh->axis[a]));
        }
    }
    for (int a = 0; a < 3; a++) {
        sh->lower[a] = a < dim ? sh->centre[a] + lo_end[a] - half[a] : 0.0;
        sh->upper[a] = a < dim ? sh->centre[a] + hi_end[a] + half[a] : 0.0;
        if (a < dim && !(isfinite(sh->lower[a]) && isfinite(sh->upper[a])))
            return fail_at(L, s, NULL, "the shape reaches infinity along %s", AXES[a]);
        if (a < dim && !(sh->upper[a] > sh->lower[a]))
            return fail_at(L, s, NULL,
                           "the shape is too small for the precision of its coordinates along "
                           "%s (%g to %g)",
                           AXES[a], sh->lower[a], sh->upper[a]);
    }
    return SPH_OK;
}

/* `file` as named at `at`, relative to the directory of the scene file
 * (like every path a scene names; an absolute path stays), into out[size]. */
static sph_status scene_relative_path(loader *L, const config_setting_t *at, const char *file,
                                      char *out, size_t size) {
    const char *slash = strrchr(L->file, '/');
    const int dirlen = file[0] == '/' || !slash ? 0 : (int)(slash - L->file) + 1;
    if ((size_t)dirlen + strlen(file) >= size)
        return fail_at(L, at, NULL, "the path is longer than %d characters", (int)size - 1);
    snprintf(out, size, "%.*s%s", dirlen, L->file, file);
    return SPH_OK;
}

/* Mesh files a scene may name: regular files (not a device or a pipe, which
 * could stream forever) of at most this size. */
#define SPH_MESH_MAX_FILE_BYTES (1L << 30)

/* type = "mesh": file (relative to the scene file's directory), scale,
 * rotate (degrees about x, y, z, in that order), translate; read and
 * checked now (host/setup/mesh.c), so that a bad mesh is an error at its key. */
static sph_status parse_mesh_shape(loader *L, const config_setting_t *s,
                                   const config_setting_t *type_at, sph_shape *sh) {
    if (L->scene->dim != 3)
        return fail_at(L, type_at, NULL,
                       "\"mesh\" is a 3D shape (a closed triangle surface); in %dD use boxes, "
                       "discs and annuli",
                       L->scene->dim);
    sph_status st = check_keys(L, s, KEYS("type", "file", "scale", "rotate", "translate"));
    if (st) return st;
    const config_setting_t *file_at;
    const char *file = "";
    if ((st = get_member(L, s, "file", true, &file_at)) || (st = as_string(L, file_at, &file)))
        return st;
    if (!*file) return fail_at(L, file_at, NULL, "must name a mesh file (STL, OBJ)");
    sph_mesh_transform tf = {1.0, {0, 0, 0}, {0, 0, 0}};
    if ((st = get_float(L, s, "scale", false, 1.0, 0, true, INFINITY, false, &tf.scale)) ||
        (st = get_vector(L, s, "rotate", false, 3, tf.rotate_deg, NULL)) ||
        (st = get_vector(L, s, "translate", false, 3, tf.translate, NULL)))
        return st;
    char path[SPH_SCENE_PATH_LEN];
    if ((st = scene_relative_path(L, file_at, file, path, sizeof path))) return st;
    struct stat info;
    if (stat(path, &info) != 0)
        return fail_at(L, file_at, NULL, "mesh file %s: cannot open it: %s", path, strerror(errno));
    if (!S_ISREG(info.st_mode))
        return fail_at(L, file_at, NULL, "mesh file %s: not a regular file", path);
    if (info.st_size == 0) return fail_at(L, file_at, NULL, "mesh file %s is empty", path);
    if (info.st_size > SPH_MESH_MAX_FILE_BYTES)
        return fail_at(L, file_at, NULL, "mesh file %s: %lld bytes, more than the %ld read", path,
                       (long long)info.st_size, SPH_MESH_MAX_FILE_BYTES);
    char why[512];
    sh->mesh = sph_mesh_load(path, NULL, 0, NULL, &tf, why, sizeof why);
    if (!sh->mesh) return fail_at(L, file_at, NULL, "mesh file %s %s", path, why);
    sh->type = SPH_SHAPE_MESH;
    sh->nparts = 0;
    sph_mesh_bounds(sh->mesh, sh->lower, sh->upper);
    return SPH_OK;
}

static sph_status parse_shape(loader *L, const config_setting_t *s, int index) {
    sph_scene *sc = L->scene;
    sph_shape *sh = &sc->shapes[index];
    L->shape_def[index] = s;
    L->shape_parts[index] = NULL;
    sh->line = (int)config_setting_source_line(s);
    if (!config_setting_is_group(s))
        return fail_at(L, s, NULL, "expected a shape group { type = ...; }, got %s",
                       type_name(config_setting_type(s)));
    int type = 0;
    const config_setting_t *type_at;
    sph_status st = get_keyword(L, s, "type", true, 0,
                                KEYS("box", "union", "difference", "disc", "ball", "annulus",
                                     "hollow_sphere", "cylinder", "mesh"),
                                &type, &type_at);
    if (st) return st;
    const int dim = sc->dim;
    if (type == 8) return parse_mesh_shape(L, s, type_at, sh);
    if (type >= 3) return parse_round_shape(L, s, type_at, type, sh);
    if (type == 0) {
        sh->type = SPH_SHAPE_BOX;
        const config_setting_t *upper_at;
        double lpad[3] = {0, 0, 0}, upad[3] = {0, 0, 0};
        if ((st = check_keys(L, s,
                             KEYS("type", "lower", "upper", "lower_pad_dp", "upper_pad_dp"))) ||
            (st = get_vector(L, s, "lower", true, dim, sh->lower, NULL)) ||
            (st = get_vector(L, s, "upper", true, dim, sh->upper, &upper_at)))
            return st;
        const char *pad_keys[2] = {"lower_pad_dp", "upper_pad_dp"};
        double *pads[2] = {lpad, upad};
        for (int k = 0; k < 2; k++) {
            const config_setting_t *at;
            if ((st = get_vector(L, s, pad_keys[k], false, dim, pads[k], &at))) return st;
            for (int a = 0; at && a < dim; a++)
                if (pads[k][a] < 0)
                    return fail_at(L, config_setting_get_elem(at, (unsigned)a), NULL,
                                   "padding must be >= 0, got %g", pads[k][a]);
        }
        /* padding in particle spacings, e.g. the clamp layer of the plate */
        for (int a = 0; a < dim; a++) {
            sh->lower[a] -= lpad[a] * sc->dp;
            sh->upper[a] += upad[a] * sc->dp;
        }
        for (int a = 0; a < dim; a++)
            if (!isfinite(sh->lower[a]) || !isfinite(sh->upper[a]))
                return fail_at(L, s, NULL,
                               "padding by %g and %g spacings (dp = %g) takes the box to infinity "
                               "along %s",
                               lpad[a], upad[a], sc->dp, AXES[a]);
        for (int a = 0; a < dim; a++)
            if (!(sh->upper[a] > sh->lower[a]))
                return fail_at(L, upper_at, NULL,
                               "must exceed lower in every component (padding included), got "
                               "upper.%s = %g <= lower.%s = %g",
                               AXES[a], sh->upper[a], AXES[a], sh->lower[a]);
        sh->nparts = 0;
        return SPH_OK;
    }

    sh->type = type == 1 ? SPH_SHAPE_UNION : SPH_SHAPE_DIFFERENCE;
    const config_setting_t *parts;
    if ((st = check_keys(L, s, KEYS("type", "parts"))) ||
        (st = get_member(L, s, "parts", true, &parts)))
        return st;
    L->shape_parts[index] = parts;
    if (!config_setting_is_array(parts) && !config_setting_is_list(parts))
        return fail_at(L, parts, NULL,
                       "expected an array of shape names [\"a\", \"b\"] or a list, got %s",
                       type_name(config_setting_type(parts)));
    int n = config_setting_length(parts);
    int min = sh->type == SPH_SHAPE_UNION ? 1 : 2;
    if (n < min)
        return fail_at(L, parts, NULL, "a %s needs at least %d part%s, got %d",
                       type == 1 ? "union" : "difference", min, min == 1 ? "" : "s", n);
    if (n > SPH_SCENE_MAX_SHAPE_PARTS)
        return fail_at(L, parts, NULL, "at most %d parts, got %d", SPH_SCENE_MAX_SHAPE_PARTS, n);
    sh->nparts = n;
    for (int i = 0; i < n; i++) {
        int part = -1;
        if ((st = parse_part(L, config_setting_get_elem(parts, (unsigned)i), &part))) return st;
        sh->parts[i] = part;
    }
    return SPH_OK;
}

/* Depth-first search for a shape that contains itself. */
static sph_status check_cycles(loader *L, int u, int *state, int *stack, int depth) {
    const sph_scene *sc = L->scene;
    state[u] = 1;
    stack[depth] = u;
    const sph_shape *sh = &sc->shapes[u];
    for (int i = 0; i < sh->nparts; i++) {
        int v = sh->parts[i];
        if (state[v] == 1) {
            char chain[1024];
            size_t len = 0;
            int from = depth;
            while (from > 0 && stack[from] != v) from--;
            for (int k = from; k <= depth + 1 && len < sizeof chain; k++) {
                int w = k <= depth ? stack[k] : v;
                const char *name = sc->shapes[w].name;
                if (name[0])
                    len += (size_t)snprintf(chain + len, sizeof chain - len, "%s'%s'",
                                            k > from ? " -> " : "", name);
                else
                    len += (size_t)snprintf(chain + len, sizeof chain - len,
                                            "%s(inline shape, line %d)", k > from ? " -> " : "",
                                            sc->shapes[w].line);
            }
            return fail_at(L, L->shape_parts[u] ? L->shape_parts[u] : L->shape_def[u], NULL,
                           "shapes refer to each other in a cycle: %s", chain);
        }
        if (state[v] == 0) {
            sph_status st = check_cycles(L, v, state, stack, depth + 1);
            if (st) return st;
        }
    }
    state[u] = 2;
    return SPH_OK;
}

/* Nodes of the shape's tree with shared parts expanded, memoised in
 * nodes[] (0: not yet known); capped just above the limit.  Needs an acyclic
 * shape table. */
#define SPH_SCENE_MAX_SHAPE_NODES 1024
static long shape_tree_size(const sph_scene *sc, int u, long *nodes) {
    if (nodes[u]) return nodes[u];
    long n = 1;
    for (int i = 0; i < sc->shapes[u].nparts && n <= SPH_SCENE_MAX_SHAPE_NODES; i++)
        n += shape_tree_size(sc, sc->shapes[u].parts[i], nodes);
    return nodes[u] = n;
}

static sph_status parse_shapes(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = get_group(L, root, "shapes", true, &g);
    if (st) return st;
    int n = config_setting_length(g);
    if (n == 0) return fail_at(L, g, NULL, "define at least one shape");
    if (n > SPH_SCENE_MAX_SHAPES)
        return fail_at(L, g, NULL, "at most %d shapes, got %d", SPH_SCENE_MAX_SHAPES, n);
    /* names first, so that a shape may refer to one defined after it */
    for (int i = 0; i < n; i++) {
        const config_setting_t *s = config_setting_get_elem(g, (unsigned)i);
        char why[256];
        if (!sph_name_check(s->name, why, sizeof why)) return fail_at(L, s, NULL, "%s", why);
        snprintf(sc->shapes[i].name, sizeof sc->shapes[i].name, "%s", s->name);
    }
    sc->nshapes = L->nnamed_shapes = n;
    for (int i = 0; i < n; i++)
        if ((st = parse_shape(L, config_setting_get_elem(g, (unsigned)i), i))) return st;
    int state[SPH_SCENE_MAX_SHAPES] = {0}, stack[SPH_SCENE_MAX_SHAPES + 1];
    for (int i = 0; i < sc->nshapes; i++)
        if (state[i] == 0 && (st = check_cycles(L, i, state, stack, 0))) return st;
    /* a shape used more than once is evaluated each time (sph_shape_contains,
     * sph_shape_bounds): bound the expanded tree, which a chain of unions
     * of the previous shape twice would grow as 2^depth */
    long nodes[SPH_SCENE_MAX_SHAPES] = {0};
    for (int i = 0; i < sc->nshapes; i++)
        if (shape_tree_size(sc, i, nodes) > SPH_SCENE_MAX_SHAPE_NODES)
            return fail_at(L, L->shape_parts[i] ? L->shape_parts[i] : L->shape_def[i], NULL,
                           "the shape expands to more than %d boxes, unions and differences "
                           "(a shape used in several places counts each time)",
                           SPH_SCENE_MAX_SHAPE_NODES);
    return SPH_OK;
}

/* An expression as a message shows it: quoted, bytes outside printable
 * ASCII as \xHH (the message stays one line), cut after 160 characters. */
static const char *shown_expression(const char *text, char *buf, size_t size) {
    size_t len = 0;
    len += (size_t)snprintf(buf, size, "\"");
    for (size_t i = 0; text[i] && len + 8 < size; i++) {
        const unsigned char c = (unsigned char)text[i];
        if (i == 160) {
            len += (size_t)snprintf(buf + len, size - len, "...");
            break;
        }
        if (c >= ' ' && c <= '~')
            buf[len++] = (char)c;
        else
            len += (size_t)snprintf(buf + len, size - len, "\\x%02X", c);
        buf[len] = '\0';
    }
    if (len + 2 <= size) snprintf(buf + len, size - len, "\"");
    return buf;
}

/* Compile and drop an expression of an initial field: a syntax error, an
 * unknown variable or an over-long text is an input error at its line now,
 * not when the particles are placed.  The text is kept for particles.c. */
static sph_status parse_expression(loader *L, const config_setting_t *s, char *text_out,
                                   size_t text_size) {
    const char *text = "";
    sph_status st = as_string(L, s, &text);
    if (st) return st;
    const char *vars[3], *names[SPH_SCENE_MAX_CONSTANTS];
    const int nvars = sph_scene_expression_variables(L->scene->dim, vars);
    const sph_expression_constants constants = sph_scene_expression_constants(L->scene, names);
    sph_expression *e = NULL;
    char why[768], shown[200];
    if (!sph_expression_compile(text, vars, nvars, &constants, &e, why, sizeof why))
        return fail_at(L, s, NULL, "the expression %s: %s",
                       shown_expression(text, shown, sizeof shown), why);
    sph_expression_free(e);
    /* sph_expression_compile refuses texts that do not fit */
    snprintf(text_out, text_size, "%s", text);
    return SPH_OK;
}

/* `constants = { U = 1.0; Re = 100.0; }`: named numbers for the expressions. */
static sph_status parse_constants(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = get_group(L, root, "constants", false, &g);
    if (st || !g) return st;
    const int n = config_setting_length(g);
    if (n > SPH_SCENE_MAX_CONSTANTS)
        return fail_at(L, g, NULL, "at most %d constants, got %d", SPH_SCENE_MAX_CONSTANTS, n);
    /* every variable name is reserved, in 2D too: a scene keeps its meaning
     * when it gains a dimension */
    static const char *const reserved[] = {"x", "y", "z", "t"};
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(g, (unsigned)i);
        char why[256];
        if (!sph_expression_name_check(m->name, reserved, 4, why, sizeof why))
            return fail_at(L, m, NULL, "%s", why);
        if (!config_setting_is_number(m))
            return fail_at(L, m, NULL, "expected a number, got %s",
                           type_name(config_setting_type(m)));
        if ((st = as_float(L, m, &sc->constant_value[i]))) return st;
        snprintf(sc->constant_name[i], sizeof sc->constant_name[i], "%s", m->name);
        sc->nconstants = i + 1;
    }
    return SPH_OK;
}

static sph_status parse_velocity(loader *L, const config_setting_t *g, sph_velocity_field *v) {
    const int dim = L->scene->dim;
    int type = 0;
    sph_status st = get_keyword(
        L, g, "type", true, 0,
        KEYS("zero", "uniform", "rigid_rotation", "cantilever_mode", "plate_mode", "expression"),
        &type, NULL);
    if (st) return st;
    v->type = (sph_velocity_type)type;
    if (dim == 1 && v->type != SPH_VELOCITY_EXPRESSION && v->type != SPH_VELOCITY_ZERO &&
        v->type != SPH_VELOCITY_UNIFORM)
        return fail_at(L, config_setting_get_member(g, "type"), NULL,
                       "a line (dimension 1) does not turn or bend: its initial velocity is "
                       "\"zero\", \"uniform\" or an \"expression\"");
    switch (v->type) {
    case SPH_VELOCITY_EXPRESSION: {
        /* v_a = the expression of key AXES[a]; a missing key is 0 */
        if ((st = dim == 1   ? check_keys(L, g, KEYS("type", "x"))
                  : dim == 2 ? check_keys(L, g, KEYS("type", "x", "y"))
                             : check_keys(L, g, KEYS("type", "x", "y", "z"))))
            return st;
        for (int a = 0; a < dim; a++) {
            const config_setting_t *s = config_setting_get_member(g, AXES[a]);
            if (!s) continue;
            if ((st = parse_expression(L, s, v->expression[a], sizeof v->expression[a]))) return st;
            where_of(L, s, v->expression_where[a], sizeof v->expression_where[a]);
        }
        return SPH_OK;
    }
    case SPH_VELOCITY_ZERO:
        return check_keys(L, g, KEYS("type"));
    case SPH_VELOCITY_UNIFORM:
        if ((st = check_keys(L, g, KEYS("type", "vector")))) return st;
        return get_vector(L, g, "vector", true, dim, v->vector, NULL);
    case SPH_VELOCITY_RIGID_ROTATION: {
        const config_setting_t *w;
        if ((st = check_keys(L, g, KEYS("type", "omega", "centre"))) ||
            (st = get_member(L, g, "omega", true, &w)))
            return st;
        if (dim == 2) {
            /* in the plane the rotation is about z */
            if (!config_setting_is_number(w))
                return fail_at(L, w, NULL,
                               "expected a number (the rotation rate about z in 2D), got %s",
                               type_name(config_setting_type(w)));
            if ((st = as_float(L, w, &v->omega[2]))) return st;
        } else if ((st = as_vector(L, w, 3, v->omega))) {
            return st;
        }
        return get_vector(L, g, "centre", false, dim, v->centre, NULL);
    }
    case SPH_VELOCITY_CANTILEVER_MODE:
        /* 003 eqs. 50-51: the first bending mode of a clamped plate */
        if ((st = check_keys(L, g,
                             KEYS("type", "amplitude_c0", "length", "kl", "clamp_x", "axis"))) ||
            (st = get_float(L, g, "amplitude_c0", true, 0, -INFINITY, false, INFINITY, false,
                            &v->amplitude_c0)) ||
            (st = get_float(L, g, "length", true, 0, 0, true, INFINITY, false, &v->length)) ||
            (st = get_float(L, g, "kl", false, 1.875, 0, true, INFINITY, false, &v->kl)) ||
            (st = get_float(L, g, "clamp_x", false, 0.0, -INFINITY, false, INFINITY, false,
                            &v->clamp_x)))
            return st;
        return get_axis(L, g, "axis", false, 1, &v->axis);
    case SPH_VELOCITY_PLATE_MODE: {
        /* 000 eq. 35: a mode of the simply supported plate (3D) */
        const config_setting_t *at = config_setting_get_member(g, "type");
        if (dim != 3)
            return fail_at(L, at, NULL,
                           "\"plate_mode\" is a 3D velocity field (a plate "
                           "in the x-y plane moving along z)");
        double lower[3] = {0, 0, 0}, size[3] = {0, 0, 0}, modes[3] = {0, 0, 0};
        const config_setting_t *ls, *ss, *ms;
        if ((st = check_keys(L, g, KEYS("type", "amplitude", "lower", "size", "modes", "axis"))) ||
            (st = get_float(L, g, "amplitude", true, 0, -INFINITY, false, INFINITY, false,
                            &v->amplitude)) ||
            (st = get_member(L, g, "lower", true, &ls)) || (st = as_vector(L, ls, 2, lower)) ||
            (st = get_member(L, g, "size", true, &ss)) || (st = as_vector(L, ss, 2, size)) ||
            (st = get_member(L, g, "modes", true, &ms)) || (st = as_vector(L, ms, 2, modes)))
            return st;
        for (int a = 0; a < 2; ++a) {
            if (!(size[a] > 0.0))
                return fail_at(L, ss, NULL, "the plate's sides must be > 0, got %g", size[a]);
            if (!(modes[a] >= 1.0 && modes[a] <= 1000.0 && modes[a] == floor(modes[a])))
                return fail_at(L, ms, NULL, "mode numbers are integers from 1 to 1000, got %g",
                               modes[a]);
            v->lower[a] = lower[a];
            v->size[a] = size[a];
            v->modes[a] = (int)modes[a];
        }
        return get_axis(L, g, "axis", false, 2, &v->axis);
    }
    }
    return SPH_OK;
}

static int find_material(const sph_scene *sc, const char *name) {
    for (int i = 0; i < sc->nmaterials; i++)
        if (strcmp(sc->materials[i].name, name) == 0) return i;
    return -1;
}

/* `axes = ["x", "y"]`: the constrained axes of a constraint, as a bit mask;
 * all axes when absent and not required. */
static sph_status parse_axis_list(loader *L, const config_setting_t *c, const char *key,
                                  bool required, int *mask) {
    const config_setting_t *s;
    sph_status st = get_member(L, c, key, required, &s);
    if (st || !s) return st;
    if (!config_setting_is_array(s) && !config_setting_is_list(s))
        return fail_at(L, s, NULL, "expected an array of axes such as [\"x\"], got %s",
                       type_name(config_setting_type(s)));
    const int n = config_setting_length(s);
    if (n == 0) return fail_at(L, s, NULL, "name at least one axis");
    *mask = 0;
    for (int k = 0; k < n; k++) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)k);
        const char *v = config_setting_get_string(e);
        int a = -1;
        for (int d = 0; v && d < L->scene->dim; d++)
            if (strcmp(v, AXES[d]) == 0) a = d;
        if (a < 0)
            return fail_at(L, e, NULL, "expected %s, got %s", axes_text(L->scene->dim),
                           v ? v : type_name(config_setting_type(e)));
        if (*mask & (1 << a)) return fail_at(L, e, NULL, "axis \"%s\" named twice", v);
        *mask |= 1 << a;
    }
    return SPH_OK;
}

static sph_status parse_axes(loader *L, const config_setting_t *c, bool required, int *mask) {
    return parse_axis_list(L, c, "axes", required, mask);
}

/* Element `index` of a list of named groups (bodies, observers, walls): a
 * group of only `keys` whose `name` differs from those of the elements
 * before it, names + k * stride (the name member of an array of structs).
 * `expected` describes the group for the message, `kind` and `list` name
 * the element and its list. */
static sph_status named_group_element(loader *L, const config_setting_t *g, int index,
                                      const char *expected, const char *kind, const char *list,
                                      const char *const *keys, int nkeys, const char *names,
                                      size_t stride, const char **name,
                                      const config_setting_t **at) {
    if (!config_setting_is_group(g))
        return fail_at(L, g, NULL, "expected %s, got %s", expected,
                       type_name(config_setting_type(g)));
    sph_status st;
    if ((st = check_keys(L, g, keys, nkeys)) || (st = get_name(L, g, "name", name, at))) return st;
    char why[256];
    if (!sph_name_check(*name, why, sizeof why)) return fail_at(L, *at, NULL, "%s", why);
    for (int k = 0; k < index; k++)
        if (strcmp(names + (size_t)k * stride, *name) == 0)
            return fail_at(L, *at, NULL, "duplicate %s name '%s' (%s.[%d] has it too)", kind, *name,
                           list, k);
    return SPH_OK;
}

/* bodies[i].placement and bodies[i].relaxation (relax.h). */
static sph_status parse_placement(loader *L, const config_setting_t *b, sph_body *body) {
    int placement = 0;
    const config_setting_t *g, *at;
    sph_status st =
        get_keyword(L, b, "placement", false, 0, KEYS("lattice", "relaxed"), &placement, NULL);
    if (st || (st = get_group(L, b, "relaxation", false, &g))) return st;
    body->placement = (sph_placement)placement;
    if (placement == SPH_PLACEMENT_RELAXED && L->scene->dim == 1)
        return fail_at(L, b, "placement",
                       "a line (dimension 1) is its lattice: there is nothing to relax");
    sph_relaxation *r = &body->relaxation;
    memset(r, 0, sizeof *r);
    r->steps = 1000;
    r->tolerance = 0.0;
    r->perturbation = 0.25;
    r->seed = 1;
    if (!g) return SPH_OK;
    if (body->placement != SPH_PLACEMENT_RELAXED)
        return fail_at(L, g, NULL,
                       "a relaxation group needs placement = \"relaxed\" in the same body (the "
                       "body is placed on the lattice)");
    wide_int seed = {false, r->seed};
    bool has_seed = false;
    char text[24];
    if ((st = check_keys(L, g, KEYS("steps", "tolerance", "perturbation", "seed", "file"))) ||
        (st = get_int(L, g, "steps", false, r->steps, 0, 1000000, &r->steps, &at)) ||
        (st = get_float(L, g, "tolerance", false, r->tolerance, 0.0, false, INFINITY, false,
                        &r->tolerance)) ||
        (st = get_float(L, g, "perturbation", false, r->perturbation, 0.0, false, 0.5, false,
                        &r->perturbation)) ||
        (st = get_wide_int(L, g, "seed", false, &seed, &has_seed, &at)))
        return st;
    /* any 64-bit pattern seeds splitmix64 (docs/scene-format.md) */
    if (seed.negative) return fail_at(L, at, NULL, "must be >= 0, got %s", wide_text(seed, text));
    r->seed = seed.magnitude;
    if ((st = get_member(L, g, "file", false, &at))) return st;
    if (!at) return SPH_OK;
    const char *file = "";
    if ((st = as_string(L, at, &file))) return st;
    if (!*file) return fail_at(L, at, NULL, "must not be empty (leave the key out for no file)");
    return scene_relative_path(L, at, file, r->file, sizeof r->file);
}

/* An initial scalar field of a fluid body: a number (kept as its %.17g
 * text, and then checked > 0 here) or an expression of x, y (, z) and the
 * constants, compiled now and evaluated per particle by particles.c. */
static sph_status parse_initial_scalar(loader *L, const config_setting_t *s, const char *what,
                                       char *text, size_t size, char *where, size_t wsize) {
    where_of(L, s, where, wsize);
    if (config_setting_is_number(s)) {
        double v = 0.0;
        sph_status st = as_float(L, s, &v);
        if (st) return st;
        if (!(v > 0.0)) return fail_at(L, s, NULL, "an initial %s must be > 0, got %g", what, v);
        snprintf(text, size, "%.17g", v);
        return SPH_OK;
    }
    if (config_setting_type(s) != CONFIG_TYPE_STRING)
        return fail_at(L, s, NULL,
                       "expected a number or an expression string of %s and the constants, "
                       "got %s",
                       variables_text(L->scene->dim), type_name(config_setting_type(s)));
    return parse_expression(L, s, text, size);
}

/* bodies[i].initial_density and .initial_pressure: the initial state of a
 * fluid body.  The weakly compressible fluid's pressure follows from its
 * density (p = c0^2 (rho - rho0), seed 004 eq. 11), so only the density is
 * given (default rho0); the ideal gas needs its pressure (its energy
 * E = p / (gamma - 1) + rho |v|^2 / 2 follows), the density defaulting to
 * the material's. */
static sph_status parse_fluid_state(loader *L, const config_setting_t *b, sph_body *body) {
    const sph_formulation f = L->scene->formulation;
    const config_setting_t *rho_at = config_setting_get_member(b, "initial_density");
    const config_setting_t *p_at = config_setting_get_member(b, "initial_pressure");
    body->initial_density[0] = body->initial_density_where[0] = '\0';
    body->initial_pressure[0] = body->initial_pressure_where[0] = '\0';
    if (!SPH_FORMULATION_IS_EULERIAN(f)) {
        if (rho_at || p_at)
            return fail_at(L, rho_at ? rho_at : p_at, NULL,
                           "is for fluid bodies (formulations \"eulerian-wc\" and "
                           "\"eulerian-compressible\"); formulation \"%s\" starts a solid at its "
                           "material's density and zero stress",
                           sph_formulation_name(f));
        return SPH_OK;
    }
    if (f == SPH_FORMULATION_EULERIAN_WC && p_at)
        return fail_at(L, p_at, NULL,
                       "formulation \"eulerian-wc\" derives the pressure from the density, "
                       "p = c0^2 (rho - rho0) (seed 004 eq. 11): give initial_density instead");
    if (f == SPH_FORMULATION_EULERIAN_COMPRESSIBLE && !p_at)
        return fail_at(L, b, "initial_pressure",
                       "missing required key: the ideal gas of formulation "
                       "\"eulerian-compressible\" starts from a pressure (a number or an "
                       "expression of %s), from which its energy follows",
                       variables_text(L->scene->dim));
    sph_status st;
    if (rho_at && (st = parse_initial_scalar(
                       L, rho_at, "density", body->initial_density, sizeof body->initial_density,
                       body->initial_density_where, sizeof body->initial_density_where)))
        return st;
    if (p_at && (st = parse_initial_scalar(
                     L, p_at, "pressure", body->initial_pressure, sizeof body->initial_pressure,
                     body->initial_pressure_where, sizeof body->initial_pressure_where)))
        return st;
    return SPH_OK;
}

/* bodies[i].role and bodies[i].spacing (fluid scenes): a body is matter
 * (the fluid, placed on the scene's lattice) or a rigid wall at rest, the
 * public code's cylinder, whose particles sit spacing * dp apart (default
 * dp/2, its adaptation ratio 2; seed 004 section 4.3). */
static sph_status parse_role(loader *L, const config_setting_t *b, sph_body *body) {
    const sph_scene *sc = L->scene;
    const sph_formulation f = sc->formulation;
    const config_setting_t *role_at = NULL, *spacing_at = config_setting_get_member(b, "spacing");
    int role = SPH_BODY_MATTER;
    sph_status st =
        get_keyword(L, b, "role", false, SPH_BODY_MATTER, KEYS("matter", "wall"), &role, &role_at);
    if (st) return st;
    body->role = (sph_body_role)role;
    body->spacing_ratio = 1.0;
    if (role == SPH_BODY_WALL && L->scene->dim == 1)
        return fail_at(L, role_at, NULL,
                       "a line (dimension 1) has no wall bodies (their normals and relaxation "
                       "need a plane or space): end a line with fixed-state buffers, "
                       "constraints of type \"fixed\"");
    if (!SPH_FORMULATION_IS_EULERIAN(f)) {
        const config_setting_t *at = role_at ? role_at : spacing_at;
        if (at)
            return fail_at(L, at, NULL,
                           "is for the bodies of fluid scenes (formulations \"eulerian-wc\" and "
                           "\"eulerian-compressible\"): a body there is matter or a wall; "
                           "formulation \"%s\" places every body on the scene's lattice, and "
                           "its rigid walls are the `walls` planes",
                           sph_formulation_name(f));
        return SPH_OK;
    }
    if (body->role == SPH_BODY_WALL && f == SPH_FORMULATION_EULERIAN_COMPRESSIBLE)
        return fail_at(L, role_at, NULL,
                       "walls of the compressible formulation are not built yet (formulation "
                       "\"eulerian-compressible\"); wall bodies are implemented for "
                       "\"eulerian-wc\"");
    const bool wall = body->role == SPH_BODY_WALL;
    body->spacing_ratio = wall ? 0.5 : 1.0;
    if (!spacing_at) return SPH_OK;
    double ratio = 0.0;
    if ((st = as_float(L, spacing_at, &ratio))) return st;
    if (!(ratio > 0.0 && ratio <= 1.0))
        return fail_at(L, spacing_at, NULL,
                       "the body's particle spacing over dp must be in (0, 1], got %g", ratio);
    if (!wall && ratio != 1.0)
        return fail_at(L, spacing_at, NULL,
                       "a matter body is placed on the scene's lattice (spacing 1, dp apart); "
                       "other spacings are for wall bodies (role = \"wall\") for now, got %g",
                       ratio);
    body->spacing_ratio = ratio;
    return SPH_OK;
}

/* The material named by key "material" of group g. */
static sph_status get_material(loader *L, const config_setting_t *g, int *out) {
    const sph_scene *sc = L->scene;
    const config_setting_t *at;
    const char *material = "";
    sph_status st = get_name(L, g, "material", &material, &at);
    if (st) return st;
    *out = find_material(sc, material);
    if (*out >= 0) return SPH_OK;
    const char *names[SPH_MAX_MATERIALS];
    for (int i = 0; i < sc->nmaterials; i++) names[i] = sc->materials[i].name;
    char hint[1024];
    suggest(material, names, sc->nmaterials, "defined materials", hint, sizeof hint);
    return fail_at(L, at, NULL, "unknown material '%s'%s", material, hint);
}

/* bodies.X.regions = ( { shape; material; }, ... ): parts of the body's
 * shape made of other materials (scene.h, sph_region).  Solids of the
 * updated-Lagrangian formulations only (checked with the materials in
 * check_material_count). */
static sph_status parse_regions(loader *L, const config_setting_t *b, sph_body *body) {
    const config_setting_t *list, *at;
    body->nregions = 0;
    sph_status st = get_list(L, b, "regions", false, &list);
    if (st || !list) return st;
    if (body->role == SPH_BODY_WALL)
        return fail_at(L, list, NULL,
                       "body '%s' is a wall (role = \"wall\"): a wall has no material of its "
                       "own, so it takes no regions",
                       body->name);
    const int n = config_setting_length(list);
    if (n < 1 || n > SPH_SCENE_MAX_REGIONS)
        return fail_at(L, list, NULL, "expected 1 to %d regions per body, got %d",
                       SPH_SCENE_MAX_REGIONS, n);
    for (int k = 0; k < n; k++) {
        const config_setting_t *r = config_setting_get_elem(list, (unsigned)k);
        if (!config_setting_is_group(r))
            return fail_at(L, r, NULL, "expected a region group { shape; material; }, got %s",
                           type_name(config_setting_type(r)));
        sph_region *region = &body->regions[k];
        const char *shape = "";
        if ((st = check_keys(L, r, KEYS("shape", "material"))) ||
            (st = get_name(L, r, "shape", &shape, &at)))
            return st;
        region->shape = find_named_shape(L, shape);
        if (region->shape < 0) return unknown_shape(L, at, shape);
        where_of(L, r, region->where, sizeof region->where);
        if ((st = get_member(L, r, "material", true, &at)) ||
            (st = get_material(L, r, &region->material)))
            return st;
    }
    body->nregions = n;
    return SPH_OK;
}

static sph_status parse_body(loader *L, const config_setting_t *b, int index) {
    sph_scene *sc = L->scene;
    sph_body *body = &sc->bodies[index];
    const config_setting_t *at, *vel, *cons;
    const char *name = "", *shape = "";
    sph_status st = named_group_element(
        L, b, index, "a body group { name; material; shape; }", "body", "bodies",
        KEYS("name", "material", "shape", "regions", "initial_velocity", "constraints", "placement",
             "relaxation", "initial_density", "initial_pressure", "role", "spacing"),
        sc->bodies[0].name, sizeof sc->bodies[0], &name, &at);
    if (st) return st;
    snprintf(body->name, sizeof body->name, "%s", name);
    where_of(L, b, body->where, sizeof body->where);
    if ((st = parse_role(L, b, body))) return st;
    const bool wall = body->role == SPH_BODY_WALL;

    /* a wall body takes the scene's one fluid material when it names none */
    if ((st = get_member(L, b, "material", !wall, &at))) return st;
    if (at) {
        if ((st = get_material(L, b, &body->material))) return st;
    } else {
        body->material = 0;
    }

    if ((st = get_name(L, b, "shape", &shape, &at))) return st;
    body->shape = find_named_shape(L, shape);
    if (body->shape < 0) return unknown_shape(L, at, shape);

    memset(&body->velocity, 0, sizeof body->velocity);
    body->velocity.type = SPH_VELOCITY_ZERO;
    /* a wall is at rest, in the fluid's reference state */
    static const char *const moving[] = {"initial_velocity", "initial_density", "initial_pressure",
                                         "constraints"};
    for (size_t k = 0; wall && k < sizeof moving / sizeof moving[0]; ++k) {
        const config_setting_t *s = config_setting_get_member(b, moving[k]);
        if (s)
            return fail_at(L, s, NULL,
                           "body '%s' is a wall (role = \"wall\"): a wall is at rest in the "
                           "fluid's reference state (the material's density), so it takes no "
                           "initial state or constraints",
                           name);
    }
    if ((st = get_group(L, b, "initial_velocity", false, &vel))) return st;
    if (vel && (st = parse_velocity(L, vel, &body->velocity))) return st;

    if ((st = parse_placement(L, b, body))) return st;
    if (!wall && (st = parse_fluid_state(L, b, body))) return st;
    if (wall) {
        body->initial_density[0] = body->initial_density_where[0] = '\0';
        body->initial_pressure[0] = body->initial_pressure_where[0] = '\0';
    }

    body->nconstraints = 0;
    if ((st = get_list(L, b, "constraints", false, &cons))) return st;
    int nc = cons ? config_setting_length(cons) : 0;
    /* fluids: type "fixed" holds the state of the region's particles at its
     * initial value, a Dirichlet buffer (device/eulerian_step.cl); the
     * other types move a solid's particles and mean nothing here */
    const bool fluid_body = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    if (nc > SPH_SCENE_MAX_CONSTRAINTS)
        return fail_at(L, cons, NULL, "at most %d constraints per body, got %d",
                       SPH_SCENE_MAX_CONSTRAINTS, nc);
    for (int i = 0; i < nc; i++) {
        const config_setting_t *c = config_setting_get_elem(cons, (unsigned)i);
        if (!config_setting_is_group(c))
            return fail_at(L, c, NULL, "expected a constraint group { type; region; }, got %s",
                           type_name(config_setting_type(c)));
        int type = 0;
        const char *region = "";
        sph_constraint *con = &body->constraints[i];
        memset(con, 0, sizeof *con);
        if ((st = get_keyword(L, c, "type", true, 0, KEYS("fixed", "fixed_axes", "velocity"), &type,
                              NULL)))
            return st;
        if (fluid_body && type != 0)
            return fail_at(L, c, "type",
                           "a fluid body takes constraints of type \"fixed\" only (its region's "
                           "state held at the initial one, a Dirichlet buffer); formulation "
                           "\"%s\" keeps every particle in place",
                           sph_formulation_name(sc->formulation));
        if (type == SPH_CONSTRAINT_FIXED)
            st = check_keys(L, c, KEYS("type", "region"));
        else if (type == SPH_CONSTRAINT_FIXED_AXES)
            st = check_keys(L, c, KEYS("type", "region", "axes"));
        else
            st = check_keys(L, c, KEYS("type", "region", "axes", "velocity"));
        if (st || (st = get_name(L, c, "region", &region, &at))) return st;
        con->type = (sph_constraint_type)type;
        con->region = find_named_shape(L, region);
        if (con->region < 0) return unknown_shape(L, at, region);
        where_of(L, at, con->where, sizeof con->where);
        con->axis_mask = (1 << L->scene->dim) - 1;
        if (type != SPH_CONSTRAINT_FIXED &&
            (st = parse_axes(L, c, type == SPH_CONSTRAINT_FIXED_AXES, &con->axis_mask)))
            return st;
        if (type == SPH_CONSTRAINT_VELOCITY &&
            (st = get_vector(L, c, "velocity", true, L->scene->dim, con->velocity, NULL)))
            return st;
        if (++L->nconstraints_total > SPH_MAX_CONSTRAINTS)
            return fail_at(L, c, NULL, "at most %d constraints in a scene (all bodies together)",
                           SPH_MAX_CONSTRAINTS);
    }
    body->nconstraints = nc;
    return parse_regions(L, b, body);
}

static sph_status parse_bodies(loader *L, const config_setting_t *root) {
    const config_setting_t *list;
    sph_status st = get_list(L, root, "bodies", true, &list);
    if (st) return st;
    int n = config_setting_length(list);
    if (n < 1 || n > SPH_MAX_BODIES)
        return fail_at(L, list, NULL, "expected 1 to %d bodies, got %d", SPH_MAX_BODIES, n);
    for (int i = 0; i < n; i++)
        if ((st = parse_body(L, config_setting_get_elem(list, (unsigned)i), i))) return st;
    sph_scene *sc = L->scene;
    sc->nbodies = n;
    int matter = 0, walls = 0;
    for (int i = 0; i < n; i++) {
        matter += sc->bodies[i].role == SPH_BODY_MATTER;
        walls += sc->bodies[i].role == SPH_BODY_WALL;
    }
    if (matter == 0)
        return fail_at(L, list, NULL,
                       "every body is a wall (role = \"wall\"): a fluid scene needs at least "
                       "one matter body (role = \"matter\", the default), the fluid");
    /* a relaxed fluid keeps off the walls through its own shape (the box
     * minus the cylinder: the relaxation's surface term holds it dp/2 from
     * the wall's surface, as the public code relaxes its fluid against the
     * cylinder) */
    (void)walls;
    return SPH_OK;
}

/* observers.X.quantity ("position", the default, or "traction") and, for a
 * traction, its plane's normal. */
static sph_status parse_observed(loader *L, const config_setting_t *o, sph_observer *obs) {
    const sph_scene *sc = L->scene;
    const config_setting_t *at;
    int quantity = SPH_OBSERVE_POSITION;
    sph_status st = get_keyword(L, o, "quantity", false, SPH_OBSERVE_POSITION,
                                KEYS("position", "traction"), &quantity, &at);
    if (st) return st;
    obs->quantity = (sph_observed)quantity;
    const config_setting_t *normal = config_setting_get_member(o, "normal");
    if (quantity == SPH_OBSERVE_POSITION) {
        if (normal)
            return fail_at(L, normal, NULL,
                           "is the plane of a traction (quantity = \"traction\"); observer '%s' "
                           "reports its position",
                           obs->name);
        return SPH_OK;
    }
    if (SPH_FORMULATION_IS_EULERIAN(sc->formulation) || sc->formulation == SPH_FORMULATION_TLSPH)
        return fail_at(L, at, NULL,
                       "a traction observer reads the Cauchy stress -p I + tau of the "
                       "updated-Lagrangian solids; formulation \"%s\" has no such stress",
                       sph_formulation_name(sc->formulation));
    if ((st = get_vector(L, o, "normal", true, sc->dim, obs->normal, &at))) return st;
    double norm = 0.0;
    for (int a = 0; a < sc->dim; ++a) norm += obs->normal[a] * obs->normal[a];
    norm = sqrt(norm);
    if (!(norm > 0.0) || !isfinite(norm))
        return fail_at(L, at, NULL,
                       "must be a non-zero vector (the normal of the traction's plane)");
    for (int a = 0; a < sc->dim; ++a) obs->normal[a] /= norm;
    return SPH_OK;
}

static sph_status parse_observers(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *list;
    sph_status st = get_list(L, root, "observers", false, &list);
    if (st || !list) return st;
    int n = config_setting_length(list);
    if (n > SPH_SCENE_MAX_OBSERVERS)
        return fail_at(L, list, NULL, "at most %d observers, got %d", SPH_SCENE_MAX_OBSERVERS, n);
    for (int i = 0; i < n; i++) {
        const config_setting_t *o = config_setting_get_elem(list, (unsigned)i), *at;
        const char *name = "";
        if ((st = named_group_element(L, o, i, "an observer group { name; position; }", "observer",
                                      "observers", KEYS("name", "position", "quantity", "normal"),
                                      sc->observers[0].name, sizeof sc->observers[0], &name, &at)))
            return st;
        if (sph_observer_name_reserved(name))
            return fail_at(L, at, NULL,
                           "'%s' is reserved: timeseries.csv has %s_x, ... columns of its own",
                           name, name);
        snprintf(sc->observers[i].name, sizeof sc->observers[i].name, "%s", name);
        if ((st = get_vector(L, o, "position", true, sc->dim, sc->observers[i].position, &at)))
            return st;
        where_of(L, at, sc->observers[i].where, sizeof sc->observers[i].where);
        if ((st = parse_observed(L, o, &sc->observers[i]))) return st;
    }
    sc->nobservers = n;
    return SPH_OK;
}

/* The observer named by key `key` of group g. */
static sph_status get_observer(loader *L, const config_setting_t *g, const char *key, int *out) {
    const sph_scene *sc = L->scene;
    const config_setting_t *at;
    const char *name = "";
    sph_status st = get_name(L, g, key, &name, &at);
    if (st) return st;
    *out = -1;
    for (int i = 0; i < sc->nobservers; i++)
        if (strcmp(sc->observers[i].name, name) == 0) *out = i;
    if (*out >= 0) return SPH_OK;
    const char *names[SPH_SCENE_MAX_OBSERVERS];
    for (int i = 0; i < sc->nobservers; i++) names[i] = sc->observers[i].name;
    char hint[1024];
    suggest(name, names, sc->nobservers, "defined observers", hint, sizeof hint);
    return fail_at(L, at, NULL, "unknown observer '%s'%s", name, hint);
}

/* analysis.wave = { incident; transmitted; }: two traction observers with
 * the same normal, on either side of an interface (host/run/analysis.h). */
static sph_status parse_wave(loader *L, const config_setting_t *w) {
    sph_scene *sc = L->scene;
    sph_status st;
    if ((st = check_keys(L, w, KEYS("incident", "transmitted"))) ||
        (st = get_observer(L, w, "incident", &sc->wave_incident)) ||
        (st = get_observer(L, w, "transmitted", &sc->wave_transmitted)))
        return st;
    const sph_observer *in = &sc->observers[sc->wave_incident],
                       *out = &sc->observers[sc->wave_transmitted];
    const char *key = in->quantity != SPH_OBSERVE_TRACTION ? "incident" : "transmitted";
    if (in->quantity != SPH_OBSERVE_TRACTION || out->quantity != SPH_OBSERVE_TRACTION)
        return fail_at(L, config_setting_get_member(w, key), NULL,
                       "observer '%s' reports a position; the wave analysis reads the traction "
                       "of two observers with quantity = \"traction\"",
                       (in->quantity != SPH_OBSERVE_TRACTION ? in : out)->name);
    if (sc->wave_incident == sc->wave_transmitted)
        return fail_at(L, config_setting_get_member(w, "transmitted"), NULL,
                       "is the incident observer too; the transmitted pulse is read on the other "
                       "side of the interface");
    double dot = 0.0;
    for (int a = 0; a < sc->dim; ++a) dot += in->normal[a] * out->normal[a];
    if (fabs(dot) < 1.0 - 1e-9)
        return fail_at(L, config_setting_get_member(w, "transmitted"), NULL,
                       "observers '%s' and '%s' have different normals; the wave analysis "
                       "compares the normal traction on parallel planes",
                       in->name, out->name);
    return SPH_OK;
}

static sph_status parse_analysis(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g, *p, *w;
    sph_status st = get_group(L, root, "analysis", false, &g);
    if (st || !g) return st;
    if ((st = check_keys(L, g, KEYS("period", "wave"))) ||
        (st = get_group(L, g, "period", false, &p)) || (st = get_group(L, g, "wave", false, &w)))
        return st;
    if (w && (st = parse_wave(L, w))) return st;
    if (!p) return SPH_OK;
    if ((st = check_keys(L, p, KEYS("observer", "axis"))) ||
        (st = get_observer(L, p, "observer", &sc->period_observer)))
        return st;
    if (sc->observers[sc->period_observer].quantity != SPH_OBSERVE_POSITION)
        return fail_at(L, config_setting_get_member(p, "observer"), NULL,
                       "observer '%s' reports a traction; the period is that of an observer's "
                       "position",
                       sc->observers[sc->period_observer].name);
    return get_axis(L, p, "axis", true, 0, &sc->period_axis);
}

static const char *const OUTPUT_FIELD_NAMES[SPH_OUT_COUNT] = {
    "velocity", "displacement", "density",        "pressure",  "von_mises",   "shear_stress",
    "body_id",  "particle_id",  "plastic_strain", "vorticity", "mach_number", "material_id"};

static bool scene_is_plastic(const sph_scene *sc) {
    int row_of[SPH_MAX_MATERIALS];
    sph_scene_material_rows(sc, row_of);
    for (int k = 0; k < sc->nmaterials; ++k)
        if (row_of[k] >= 0 && sc->materials[k].plastic) return true;
    return false;
}

const char *sph_output_field_name(sph_output_field f) {
    return (unsigned)f < SPH_OUT_COUNT ? OUTPUT_FIELD_NAMES[f] : "?";
}

/* output = { snapshot_interval; fields = [...]; } (docs/output-format.md) */
static sph_status parse_output(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g, *at = NULL;
    sph_status st = get_group(L, root, "output", false, &g);
    if (st) return st;
    static const sph_output_field defaults[] = {
        SPH_OUT_VELOCITY,  SPH_OUT_DISPLACEMENT, SPH_OUT_DENSITY,    SPH_OUT_PRESSURE,
        SPH_OUT_VON_MISES, SPH_OUT_BODY_ID,      SPH_OUT_PARTICLE_ID};
    /* a fluid's particles do not move and carry no stress deviator: no
     * displacement, von Mises or shear stress; the flow's own fields instead */
    static const sph_output_field fluid_defaults[] = {SPH_OUT_VELOCITY, SPH_OUT_DENSITY,
                                                      SPH_OUT_PRESSURE, SPH_OUT_VORTICITY,
                                                      SPH_OUT_PARTICLE_ID};
    const bool eulerian = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    const bool compressible = sc->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE;
    if (eulerian) {
        for (size_t k = 0; k < sizeof fluid_defaults / sizeof fluid_defaults[0]; ++k)
            sc->output_field[fluid_defaults[k]] = true;
        sc->output_field[SPH_OUT_MACH_NUMBER] = compressible;
        sc->output_field[SPH_OUT_VORTICITY] = sc->dim > 1; /* a line has none */
    } else {
        for (size_t k = 0; k < sizeof defaults / sizeof defaults[0]; ++k)
            sc->output_field[defaults[k]] = true;
    }
    const bool plastic = scene_is_plastic(sc);
    sc->output_field[SPH_OUT_PLASTIC_STRAIN] = plastic;
    int row_of[SPH_MAX_MATERIALS];
    const bool several_materials = sph_scene_material_rows(sc, row_of) > 1;
    sc->output_field[SPH_OUT_MATERIAL_ID] = several_materials;
    sc->snapshot_interval = 10.0 * sc->output_interval;
    if (g) {
        if ((st = check_keys(L, g, KEYS("snapshot_interval", "fields"))) ||
            (st = get_float(L, g, "snapshot_interval", false, sc->snapshot_interval, 0, false,
                            INFINITY, false, &sc->snapshot_interval)) ||
            (st = get_member(L, g, "fields", false, &at)))
            return st;
    }
    if (at) {
        if (!config_setting_is_array(at) && !config_setting_is_list(at))
            return fail_at(L, at, NULL,
                           "expected an array of field names [\"velocity\", ...], got %s",
                           type_name(config_setting_type(at)));
        memset(sc->output_field, 0, sizeof sc->output_field);
        const int n = config_setting_length(at);
        for (int i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(at, (unsigned)i);
            const char *name = "";
            if ((st = as_string(L, e, &name))) return st;
            int found = -1;
            for (int k = 0; k < SPH_OUT_COUNT; k++)
                if (strcmp(name, OUTPUT_FIELD_NAMES[k]) == 0) found = k;
            if (found < 0) {
                char hint[512];
                suggest(name, OUTPUT_FIELD_NAMES, SPH_OUT_COUNT, "fields", hint, sizeof hint);
                return fail_at(L, e, NULL, "unknown output field '%s'%s", name, hint);
            }
            const bool solid_field = found == SPH_OUT_DISPLACEMENT || found == SPH_OUT_VON_MISES ||
                                     found == SPH_OUT_SHEAR_STRESS ||
                                     found == SPH_OUT_PLASTIC_STRAIN;
            if (eulerian && solid_field)
                return fail_at(L, e, NULL,
                               "%s is a field of the solid formulations; formulation \"%s\" "
                               "keeps its particles fixed and has no stress deviator (fluid "
                               "fields: velocity, density, pressure, vorticity, body_id, "
                               "particle_id%s)",
                               name, sph_formulation_name(sc->formulation),
                               compressible ? ", mach_number" : "");
            if (!eulerian && (found == SPH_OUT_VORTICITY || found == SPH_OUT_MACH_NUMBER))
                return fail_at(L, e, NULL,
                               "%s is a fluid field (formulations \"eulerian-wc\" and "
                               "\"eulerian-compressible\"), and this scene's formulation is "
                               "\"%s\"",
                               name, sph_formulation_name(sc->formulation));
            if (found == SPH_OUT_VORTICITY && sc->dim == 1)
                return fail_at(L, e, NULL,
                               "vorticity is a field of 2D and 3D flows; a line (dimension 1) "
                               "has none");
            if (found == SPH_OUT_MACH_NUMBER && !compressible)
                return fail_at(L, e, NULL,
                               "mach_number is a field of formulation \"eulerian-compressible\", "
                               "whose sound speed c = sqrt(gamma p / rho) varies; the weakly "
                               "compressible fluid's Mach number is |v| / c0 (the velocity field "
                               "over sound_speed)");
            if (found == SPH_OUT_PLASTIC_STRAIN && !plastic)
                return fail_at(L, e, NULL,
                               "plastic_strain needs a plastic material (a yield_stress), and "
                               "this scene's materials are elastic");
            if (sc->output_field[found])
                return fail_at(L, e, NULL, "field '%s' is listed twice", name);
            sc->output_field[found] = true;
        }
    }
    /* snapshots fall on output times: the solver lands exactly on those */
    if (sc->snapshot_interval > 0) {
        const double ratio = sc->snapshot_interval / sc->output_interval;
        const double whole = round(ratio);
        const config_setting_t *si = g ? config_setting_get_member(g, "snapshot_interval") : NULL;
        if (whole < 1 || fabs(ratio - whole) > 1e-9 * whole)
            return fail_at(L, si ? si : (g ? g : root), si ? NULL : "snapshot_interval",
                           "must be a whole multiple of time.output_interval (%g), or 0 for no "
                           "snapshots, got %g",
                           sc->output_interval, sc->snapshot_interval);
        if (whole > INT_MAX)
            return fail_at(L, si ? si : (g ? g : root), si ? NULL : "snapshot_interval",
                           "must be at most %d output intervals (%g), got %g", INT_MAX,
                           sc->output_interval, sc->snapshot_interval);
        sc->snapshot_every = (int)whole;
    }
    return SPH_OK;
}

/* The formulation and the material model must fit: ENOG and ENOG-A have no
 * stress to return to a yield surface (003 §4.2), so they are elastic only
 * (TLSPH takes J2 materials: the finite-strain return map of
 * device/sph_plasticity.h with 002's hourglass switch).
 * Resolves the default xi_G: GNOG 4.0 elastic / 0.2 plastic (the reference
 * code's values), GNOG-A 2.0 for every material (003 §4.3). */
static sph_status check_material_model(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *method = config_setting_get_member(root, "method");
    const config_setting_t *form_at = config_setting_get_member(method, "formulation");
    bool plastic = false;
    const char *plastic_material = "";
    /* every material a body or a region uses */
    int row_of[SPH_MAX_MATERIALS];
    const int rows = sph_scene_material_rows(sc, row_of);
    for (int k = 0; k < sc->nmaterials; ++k) {
        const sph_material *m = &sc->materials[k];
        if (row_of[k] < 0) continue;
        if (m->plastic) {
            plastic = true;
            plastic_material = m->name;
        }
        if (m->elastic_model != ELASTIC_MODEL_SVK && sc->formulation != SPH_FORMULATION_TLSPH)
            return fail_at(L, form_at, NULL,
                           "material '%s' has a hyperelastic model (neo-Hookean or "
                           "exponential), which \"tlsph\" implements; formulation \"%s\" is "
                           "hypoelastic (Jaumann stress rate): use \"tlsph\", or leave the "
                           "material's model out",
                           m->name, sph_formulation_name(sc->formulation));
    }
    /* several materials: the interface terms of device/sph_materials.h are
     * those of the updated-Lagrangian solids */
    if (rows > 1 && (sc->formulation == SPH_FORMULATION_TLSPH ||
                     SPH_FORMULATION_IS_EULERIAN(sc->formulation))) {
        const char *names[2] = {"", ""};
        for (int k = 0; k < sc->nmaterials; ++k)
            if (row_of[k] >= 0 && row_of[k] < 2) names[row_of[k]] = sc->materials[k].name;
        return fail_at(L, form_at, NULL,
                       "the bodies and regions of this scene use %d materials ('%s', '%s', ...); "
                       "formulation \"%s\" runs one material: several materials are "
                       "implemented for the updated-Lagrangian solids (\"enog\", \"enog-a\", "
                       "\"og\", \"oas\", \"gnog\", \"gnog-a\")",
                       rows, names[0], names[1], sph_formulation_name(sc->formulation));
    }
    if (plastic && FORM_IS_ENOG(sc->formulation))
        return fail_at(L, form_at, NULL,
                       "formulation \"%s\" is for elastic materials, but material '%s' is "
                       "plastic (it has a yield_stress); use \"gnog-a\", \"gnog\", \"og\", "
                       "\"oas\" or \"tlsph\"",
                       sph_formulation_name(sc->formulation), plastic_material);
    if (isnan(sc->xi_g))
        sc->xi_g = sc->formulation == SPH_FORMULATION_GNOG ? (plastic ? 0.2 : 4.0) : 2.0;
    return SPH_OK;
}

/* walls = ( { name; point; normal; }, ... ): rigid frictionless planes
 * (device/sph_wall.h), the solid on the side the normal points to. */
static sph_status parse_walls(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *list;
    sph_status st = get_list(L, root, "walls", false, &list);
    if (st || !list) return st;
    const int n = config_setting_length(list);
    if (n > SPH_MAX_WALLS)
        return fail_at(L, list, NULL, "at most %d walls, got %d", SPH_MAX_WALLS, n);
    if (sc->formulation == SPH_FORMULATION_TLSPH) {
        const config_setting_t *method = config_setting_get_member(root, "method");
        return fail_at(L, config_setting_get_member(method, "formulation"), NULL,
                       "\"tlsph\" has no wall contact; walls are implemented for the "
                       "updated-Lagrangian formulations");
    }
    if (n > 0 && SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        return fail_at(L, list, NULL,
                       "walls are not supported for the eulerian formulations yet (formulation "
                       "\"%s\"); a fluid scene is bounded by its periodic boundary, a far "
                       "field (boundary.far_field) or wall bodies (bodies.X.role = \"wall\")",
                       sph_formulation_name(sc->formulation));
    for (int i = 0; i < n; i++) {
        const config_setting_t *w = config_setting_get_elem(list, (unsigned)i), *at;
        const char *name = "";
        sph_wall *wall = &sc->walls[i];
        if ((st = named_group_element(L, w, i, "a wall group { name; point; normal; }", "wall",
                                      "walls", KEYS("name", "point", "normal"), sc->walls[0].name,
                                      sizeof sc->walls[0], &name, &at)))
            return st;
        snprintf(wall->name, sizeof wall->name, "%s", name);
        where_of(L, w, wall->where, sizeof wall->where);
        if ((st = get_vector(L, w, "point", true, sc->dim, wall->point, NULL)) ||
            (st = get_vector(L, w, "normal", true, sc->dim, wall->normal, &at)))
            return st;
        double norm = 0.0;
        for (int a = 0; a < sc->dim; ++a) norm += wall->normal[a] * wall->normal[a];
        norm = sqrt(norm);
        if (!(norm > 0.0))
            return fail_at(L, at, NULL,
                           "must be a non-zero vector (the wall's normal into the "
                           "solid)");
        for (int a = 0; a < sc->dim; ++a) wall->normal[a] /= norm;
    }
    sc->nwalls = n;
    return SPH_OK;
}

/* contact = { impedance; penalty; }: bodies of a scene with several do not
 * merge; particles of different bodies interact only by the contact force
 * (device/sph_contact.h), and particles meet walls by the wall's
 * (device/sph_wall.h).  TLSPH keeps its reference neighbours and has no
 * contact, so it runs scenes of one body. */
static sph_status parse_contact(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    sc->contact_impedance = 1.0;
    sc->contact_penalty = 1.0;
    const config_setting_t *g;
    sph_status st = get_group(L, root, "contact", false, &g);
    if (st) return st;
    if (sc->nbodies > 1 && sc->formulation == SPH_FORMULATION_TLSPH) {
        const config_setting_t *method = config_setting_get_member(root, "method");
        return fail_at(L, config_setting_get_member(method, "formulation"), NULL,
                       "\"tlsph\" runs scenes with one body (the scene has %d): contact between "
                       "bodies is implemented for the updated-Lagrangian formulations",
                       sc->nbodies);
    }
    if (!g) return SPH_OK;
    /* the bodies of a fluid scene are regions of one fluid: no contact */
    if (SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        return fail_at(L, g, NULL,
                       "is for the solid formulations (contact between bodies and against "
                       "walls); the bodies of formulation \"%s\" are regions of one fluid",
                       sph_formulation_name(sc->formulation));
    if (sc->nbodies < 2 && sc->nwalls == 0)
        return fail_at(L, g, NULL,
                       "contact acts between bodies or against walls, and the scene has one body "
                       "and no wall; remove the group");
    if ((st = check_keys(L, g, KEYS("impedance", "penalty"))) ||
        (st = get_float(L, g, "impedance", false, 1.0, 0, false, 100, false,
                        &sc->contact_impedance)) ||
        (st = get_float(L, g, "penalty", false, 1.0, 0, false, 100, false, &sc->contact_penalty)))
        return st;
    return SPH_OK;
}

/* boundary = { periodic = ["x", ...]; far_field = { density; velocity; };
 *              lower = [...]; upper = [...]; }
 * The fluid wraps around along the periodic axes with the period upper -
 * lower (the seed's Taylor-Green vortex, seed 004 §4.2; the Shu-Osher
 * strip's y).  The period must hold a whole number of spacings, so that the
 * lattice continues across the seam dp apart (particles.c anchors it at
 * lower and checks every particle), and at least two cut-off radii, so that
 * no pair meets through two images at once.  The far field (seed 004 §4.3,
 * the public code's NonReflectiveBoundaryCorrection) acts on the faces of
 * the box [lower, upper] across every axis that is not periodic: the fluid
 * there is blended toward the free stream (density, velocity). */
static sph_status parse_far_field(loader *L, const config_setting_t *ff) {
    sph_scene *sc = L->scene;
    if (sc->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE)
        return fail_at(L, ff, NULL,
                       "the far field of the compressible formulation is not built yet "
                       "(formulation \"eulerian-compressible\"); it is implemented for "
                       "\"eulerian-wc\"");
    sph_status st;
    if ((st = check_keys(L, ff, KEYS("density", "velocity"))) ||
        (st = get_float(L, ff, "density", false, sc->materials[0].density, 0, true, INFINITY, false,
                        &sc->far_field_density)) ||
        (st = get_vector(L, ff, "velocity", true, sc->dim, sc->far_field_velocity, NULL)))
        return st;
    sc->has_far_field = true;
    return SPH_OK;
}

static sph_status parse_boundary(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g, *upper_at, *ff = NULL;
    sph_status st = get_group(L, root, "boundary", false, &g);
    if (st || !g) return st;
    if (!SPH_FORMULATION_IS_EULERIAN(sc->formulation)) {
        if (!config_setting_get_member(g, "periodic") && config_setting_get_member(g, "far_field"))
            return fail_at(L, g, NULL,
                           "a far field is implemented for the eulerian formulations "
                           "(\"eulerian-wc\"), got formulation \"%s\"",
                           sph_formulation_name(sc->formulation));
        return fail_at(L, g, NULL,
                       "periodic boundaries are implemented for the eulerian formulations "
                       "(\"eulerian-wc\", \"eulerian-compressible\"), got formulation \"%s\"",
                       sph_formulation_name(sc->formulation));
    }
    int mask = 0;
    if ((st = check_keys(L, g, KEYS("periodic", "far_field", "lower", "upper"))) ||
        (st = get_group(L, g, "far_field", false, &ff)))
        return st;
    if (ff && sc->dim == 1)
        return fail_at(L, ff, NULL,
                       "a line (dimension 1) has no far field here: end it with fixed-state "
                       "buffers, constraints of type \"fixed\" (the far field's blend is "
                       "built and tested for 2D and 3D)");
    if (ff && (st = parse_far_field(L, ff))) return st;
    /* without a far field the group is there for its periodic axes */
    if (!ff && !config_setting_get_member(g, "periodic"))
        return fail_at(L, g, "periodic",
                       "missing required key: a boundary has periodic axes (periodic), a far "
                       "field (far_field) or both");
    if ((st = parse_axis_list(L, g, "periodic", false, &mask)) ||
        (st = get_vector(L, g, "lower", true, sc->dim, sc->periodic_lower, NULL)) ||
        (st = get_vector(L, g, "upper", true, sc->dim, sc->periodic_upper, &upper_at)))
        return st;
    const double dp = sc->dp;
    /* the cut-off radius 2h = 2 smoothing_ratio dp */
    const double cutoff_dp = 2.0 * sc->smoothing_ratio;
    for (int a = 0; a < sc->dim; ++a) {
        const double lo = sc->periodic_lower[a], hi = sc->periodic_upper[a];
        if (!(mask & (1 << a))) {
            if (ff && !(hi > lo))
                return fail_at(L, upper_at, NULL,
                               "must exceed lower along %s (the far field's box [lower, upper]), "
                               "got upper = %g, lower = %g",
                               AXES[a], hi, lo);
            continue;
        }
        if (!(hi > lo))
            return fail_at(L, upper_at, NULL,
                           "must exceed lower along the periodic axis %s, got upper = %g, "
                           "lower = %g",
                           AXES[a], hi, lo);
        const double period = hi - lo, cells = period / dp, whole = round(cells);
        if (!isfinite(cells) || fabs(cells - whole) > 1e-9 * fmax(1.0, cells))
            return fail_at(L, upper_at, NULL,
                           "the period along %s, upper - lower = %.10g, must be a whole number "
                           "of particle spacings (dp = %g), got %.10g dp",
                           AXES[a], period, dp, cells);
        if (whole < 2.0 * cutoff_dp - 1e-9)
            return fail_at(L, upper_at, NULL,
                           "the period along %s (%g) is shorter than two cut-off radii (2 x %g "
                           "dp = %g): a particle would meet a neighbour through two images",
                           AXES[a], period, cutoff_dp, 2.0 * cutoff_dp * dp);
    }
    if (ff && mask == (1 << sc->dim) - 1)
        return fail_at(L, ff, NULL,
                       "the far field acts on the faces across the axes that are not periodic, "
                       "and every axis is periodic: remove one from boundary.periodic or the "
                       "far field");
    /* the relaxation (relax.h) knows nothing of the images */
    const config_setting_t *bodies = config_setting_get_member(root, "bodies");
    for (int b = 0; mask && b < sc->nbodies; ++b) {
        if (sc->bodies[b].placement != SPH_PLACEMENT_RELAXED) continue;
        const config_setting_t *e = config_setting_get_elem(bodies, (unsigned)b);
        const config_setting_t *at = e ? config_setting_get_member(e, "placement") : NULL;
        return fail_at(L, at ? at : g, at ? NULL : "periodic",
                       "a relaxed placement is not supported with a periodic boundary yet: the "
                       "relaxation does not see the particles across the seam; place the body "
                       "on the lattice");
    }
    sc->periodic_mask = mask;
    /* a group that --set created on the way to a member has no line and no
     * override of its own: name the override of upper */
    const bool located = override_of(g) || config_setting_source_line(g) > 0;
    where_of(L, located ? g : upper_at, sc->periodic_where, sizeof sc->periodic_where);
    return SPH_OK;
}

/* forces = { reference_density; reference_speed; reference_length; window; }:
 * the force on the wall bodies as drag and lift coefficients
 * C = 2 F / (rho_ref U_ref^2 L_ref) (seed 004 §4.3, Table 5), and their
 * mean, amplitude and Strouhal number over the trailing window. */
static sph_status parse_forces(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = get_group(L, root, "forces", false, &g);
    if (st || !g) return st;
    if (!SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        return fail_at(L, g, NULL,
                       "is for the wall bodies of fluid scenes (formulation \"eulerian-wc\"), "
                       "got formulation \"%s\"",
                       sph_formulation_name(sc->formulation));
    int walls = 0;
    for (int b = 0; b < sc->nbodies; ++b) walls += sc->bodies[b].role == SPH_BODY_WALL;
    if (walls == 0)
        return fail_at(L, g, NULL,
                       "the forces are those the fluid exerts on the wall bodies, and the scene "
                       "has none: give a body role = \"wall\" (the cylinder) or remove the "
                       "group");
    const double speed = sqrt(sc->far_field_velocity[0] * sc->far_field_velocity[0] +
                              sc->far_field_velocity[1] * sc->far_field_velocity[1] +
                              sc->far_field_velocity[2] * sc->far_field_velocity[2]);
    const double rho_default = sc->has_far_field ? sc->far_field_density : sc->materials[0].density;
    if ((st = check_keys(
             L, g, KEYS("reference_density", "reference_speed", "reference_length", "window"))) ||
        (st = get_float(L, g, "reference_density", false, rho_default, 0, true, INFINITY, false,
                        &sc->force_reference_density)))
        return st;
    const bool speed_given = config_setting_get_member(g, "reference_speed") != NULL;
    if (!speed_given && !(sc->has_far_field && speed > 0.0))
        return fail_at(L, g, "reference_speed", "missing required key: %s",
                       sc->has_far_field ? "the far field's velocity is 0, so it cannot be the "
                                           "default reference speed"
                                         : "without a far field there is no free-stream speed "
                                           "to take as the default");
    if ((st = get_float(L, g, "reference_speed", false, speed, 0, true, INFINITY, false,
                        &sc->force_reference_speed)) ||
        (st = get_float(L, g, "reference_length", true, 0, 0, true, INFINITY, false,
                        &sc->force_reference_length)) ||
        (st = get_float(L, g, "window", false, 0.0, 0, false, INFINITY, false, &sc->force_window)))
        return st;
    if (!isfinite(sc->force_reference_density * sc->force_reference_speed *
                  sc->force_reference_speed * sc->force_reference_length) ||
        !(sc->force_reference_density * sc->force_reference_speed * sc->force_reference_speed *
              sc->force_reference_length >
          0.0))
        return fail_at(L, g, NULL,
                       "rho_ref U_ref^2 L_ref = %g x %g^2 x %g, the coefficients' denominator, "
                       "is not a finite positive number",
                       sc->force_reference_density, sc->force_reference_speed,
                       sc->force_reference_length);
    sc->has_forces = true;
    return SPH_OK;
}

/* monitor = { zigzag_threshold; min_distance_ratio; energy_growth;
 *             speed_limit; domain_margin; domain = { lower; upper; }; action; } */
static sph_status parse_monitor(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = get_group(L, root, "monitor", false, &g);
    /* TLSPH has no Riemann dissipation: its velocity field keeps a steady
     * particle-scale acoustic content (indicator 0.3 to 0.6 on the plate,
     * not growing) that this measure cannot tell from zigzag, so for TLSPH
     * the zigzag check is off unless a threshold is given */
    const double zigzag_default = sc->formulation == SPH_FORMULATION_TLSPH ? INFINITY : 0.3;
    sc->monitor_zigzag = zigzag_default;
    sc->monitor_min_distance = 0.5;
    sc->monitor_action = SPH_MONITOR_STOP;
    sc->monitor_energy_growth = 0.5;
    sc->monitor_speed_limit = 10.0;
    sc->monitor_domain_margin = 1.0;
    sc->monitor_has_domain = false;
    if (st || !g) return st;
    int action = 0;
    const config_setting_t *dom = NULL;
    if ((st = check_keys(L, g,
                         KEYS("zigzag_threshold", "min_distance_ratio", "energy_growth",
                              "speed_limit", "domain_margin", "domain", "action"))) ||
        (st = get_float(L, g, "speed_limit", false, 10.0, 0, true, INFINITY, true,
                        &sc->monitor_speed_limit)) ||
        (st = get_float(L, g, "energy_growth", false, 0.5, 0, true, INFINITY, true,
                        &sc->monitor_energy_growth)) ||
        (st = get_float(L, g, "domain_margin", false, 1.0, 0, false, INFINITY, true,
                        &sc->monitor_domain_margin)) ||
        (st = get_group(L, g, "domain", false, &dom)))
        return st;
    if (dom) {
        const config_setting_t *upper_at;
        if ((st = check_keys(L, dom, KEYS("lower", "upper"))) ||
            (st = get_vector(L, dom, "lower", true, sc->dim, sc->monitor_domain_lower, NULL)) ||
            (st = get_vector(L, dom, "upper", true, sc->dim, sc->monitor_domain_upper, &upper_at)))
            return st;
        for (int a = 0; a < sc->dim; a++)
            if (!(sc->monitor_domain_upper[a] > sc->monitor_domain_lower[a]))
                return fail_at(L, upper_at, NULL,
                               "the domain must have upper > lower along every axis; along %s "
                               "upper = %g, lower = %g",
                               AXES[a], sc->monitor_domain_upper[a], sc->monitor_domain_lower[a]);
        sc->monitor_has_domain = true;
        /* a group that --set created on the way to lower or upper has no
         * line and no override of its own: name the override of upper */
        const bool dom_located = override_of(dom) || config_setting_source_line(dom) > 0;
        where_of(L, dom_located ? dom : upper_at, sc->monitor_domain_where,
                 sizeof sc->monitor_domain_where);
    }
    if ((st = get_float(L, g, "zigzag_threshold", false, zigzag_default, 0, true, INFINITY, false,
                        &sc->monitor_zigzag)) ||
        (st = get_float(L, g, "min_distance_ratio", false, 0.5, 0, false, 1, true,
                        &sc->monitor_min_distance)) ||
        (st = get_keyword(L, g, "action", false, SPH_MONITOR_STOP, KEYS("stop", "report", "off"),
                          &action, NULL)))
        return st;
    sc->monitor_action = (sph_monitor_action)action;
    return SPH_OK;
}

static sph_status parse_scene(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    sph_status st;
    if ((st = check_keys(L, root,
                         KEYS("title", "dimension", "resolution", "method", "time", "materials",
                              "shapes", "bodies", "observers", "analysis", "gravity",
                              "lattice_origin", "output", "monitor", "contact", "walls",
                              "constants", "boundary", "forces"))))
        return st;

    const config_setting_t *at;
    if ((st = get_member(L, root, "title", false, &at))) return st;
    if (at) {
        const char *title = "";
        if ((st = as_string(L, at, &title))) return st;
        if (strlen(title) >= sizeof sc->title)
            return fail_at(L, at, NULL, "titles are limited to %zu characters",
                           sizeof sc->title - 1);
        snprintf(sc->title, sizeof sc->title, "%s", title);
    }
    wide_int dim = {false, 0};
    bool present = false;
    char text[24];
    if ((st = get_wide_int(L, root, "dimension", true, &dim, &present, &at))) return st;
    if (!wide_in(dim, 1, 3))
        return fail_at(L, at, NULL, "must be 1, 2 or 3, got %s", wide_text(dim, text));
    sc->dim = (int)dim.magnitude;
    const config_setting_t *dim_at = at;

    if ((st = parse_resolution(L, root)) || (st = parse_method(L, root))) return st;
    /* 1D: the shock tubes of the fluid formulations (seed 004 §4.1); a solid
     * line has no shear, so none of the solid methods means anything there */
    if (sc->dim == 1 && !SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        return fail_at(L, dim_at, NULL,
                       "dimension 1 is for the fluid formulations (\"eulerian-wc\", "
                       "\"eulerian-compressible\"), got formulation \"%s\"",
                       sph_formulation_name(sc->formulation));
    if ((st = parse_time(L, root)) || (st = parse_materials(L, root)) ||
        (st = parse_shapes(L, root)) || (st = parse_constants(L, root)) ||
        (st = parse_bodies(L, root)) || (st = parse_observers(L, root)) ||
        (st = parse_analysis(L, root)) || (st = parse_output(L, root)) ||
        (st = parse_monitor(L, root)))
        return st;
    if ((st = check_material_model(L, root)) || (st = parse_walls(L, root)) ||
        (st = parse_contact(L, root)) || (st = parse_boundary(L, root)) ||
        (st = parse_forces(L, root)))
        return st;
    if ((st = get_vector(L, root, "gravity", false, sc->dim, sc->gravity, NULL)) ||
        (st = get_vector(L, root, "lattice_origin", false, sc->dim, sc->lattice_origin, &at)))
        return st;
    sc->has_lattice_origin = at != NULL;
    return SPH_OK;
}

/* ------------------------------------------------------------------------ */
/* public API                                                                */
/* ------------------------------------------------------------------------ */

static sph_status read_scene_file(loader *L, config_t *cfg, const char *path) {
    FILE *fp = fopen(path, "r");
    if (!fp)
        return sph_fail(L->err, SPH_ERR_INPUT, "%s: cannot read scene file: %s", path,
                        strerror(errno));
    struct stat stbuf;
    if (fstat(fileno(fp), &stbuf) == 0 && S_ISDIR(stbuf.st_mode)) {
        fclose(fp);
        return sph_fail(L->err, SPH_ERR_INPUT, "%s: cannot read scene file: %s", path,
                        strerror(EISDIR));
    }
    /* @include "x" is resolved next to the scene file */
    char dir[SPH_SCENE_PATH_LEN];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash) {
        *slash = '\0';
        config_set_include_dir(cfg, dir[0] ? dir : "/");
    }
    /* read whole, for widen_integers */
    text_buf raw = {NULL, 0, 0};
    char chunk[4096];
    bool mem_ok = put(&raw, "", 0);
    size_t got;
    while (mem_ok && (got = fread(chunk, 1, sizeof chunk, fp)) > 0) mem_ok = put(&raw, chunk, got);
    int read_errno = ferror(fp) ? errno : 0;
    fclose(fp);
    if (read_errno || !mem_ok) {
        free(raw.buf);
        return sph_fail(L->err, read_errno ? SPH_ERR_INPUT : SPH_ERR_RUNTIME,
                        "%s: cannot read scene file: %s", path,
                        read_errno ? strerror(read_errno) : "out of memory");
    }
    /* libconfig reads text up to a NUL; from a file it took one for a
     * character it does not know: keep that a syntax error */
    const char *nul = memchr(raw.buf, '\0', raw.len);
    if (nul) {
        int line = 1;
        for (const char *c = raw.buf; c < nul; c++) line += *c == '\n';
        free(raw.buf);
        return sph_fail(L->err, SPH_ERR_INPUT, "%s:%d: syntax error: a NUL byte", path, line);
    }
    char *wide = widen_integers(raw.buf);
    free(raw.buf);
    if (!wide) return sph_fail(L->err, SPH_ERR_RUNTIME, "%s: out of memory reading it", path);
    int ok = config_read_string(cfg, wide);
    free(wide);
    if (ok == CONFIG_TRUE) return SPH_OK;
    if (config_error_type(cfg) == CONFIG_ERR_FILE_IO)
        return sph_fail(L->err, SPH_ERR_INPUT, "%s: cannot read scene file: %s", path,
                        config_error_text(cfg));
    const char *text = config_error_text(cfg) ? config_error_text(cfg) : "syntax error";
    const char *file = config_error_file(cfg) ? config_error_file(cfg) : path;
    const char *hint = strstr(text, "mismatched element type")
                           ? " (write every number of an array as a decimal (0.0, not 0), or use "
                             "a list ( ... ))"
                           : "";
    if (strcmp(text, "syntax error") == 0)
        return sph_fail(L->err, SPH_ERR_INPUT, "%s:%d: syntax error", file, config_error_line(cfg));
    return sph_fail(L->err, SPH_ERR_INPUT, "%s:%d: syntax error: %s%s", file,
                    config_error_line(cfg), text, hint);
}

static sph_status write_resolved(sph_scene *scene, const config_t *cfg, sph_error *err) {
    char *buf = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&buf, &len);
    if (!mem)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot record the resolved scene: %s",
                        strerror(errno));
    config_write(cfg, mem);
    if (fclose(mem) != 0 || !buf) {
        free(buf);
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot record the resolved scene: out of memory");
    }
    scene->resolved_text = buf;
    return SPH_OK;
}

/* The first setting of tree `a` whose value the resolved text `b` (the same
 * tree written by libconfig and read back) does not reproduce, else NULL:
 * libconfig writes numbers with 15 significant digits. */
static const config_setting_t *first_changed(const config_setting_t *a, const config_setting_t *b) {
    if (!b || a->type != b->type) return a;
    switch (a->type) {
    case CONFIG_TYPE_GROUP:
    case CONFIG_TYPE_LIST:
    case CONFIG_TYPE_ARRAY: {
        int n = config_setting_length(a);
        if (config_setting_length(b) != n) return a;
        for (int i = 0; i < n; i++) {
            const config_setting_t *d = first_changed(config_setting_get_elem(a, (unsigned)i),
                                                      config_setting_get_elem(b, (unsigned)i));
            if (d) return d;
        }
        return NULL;
    }
    case CONFIG_TYPE_FLOAT:
        return a->value.fval == b->value.fval ? NULL : a;
    case CONFIG_TYPE_STRING:
        return strcmp(a->value.sval, b->value.sval) == 0 ? NULL : a;
    case CONFIG_TYPE_INT64:
        return a->value.llval == b->value.llval ? NULL : a;
    default: /* int, bool */
        return a->value.ival == b->value.ival ? NULL : a;
    }
}

/* A checkpoint stores the resolved text and a restart reloads it: it must
 * give back the same values. */
static sph_status check_resolved(loader *L, const config_t *cfg) {
    config_t again;
    config_init(&again);
    sph_status st = SPH_OK;
    if (config_read_string(&again, L->scene->resolved_text) != CONFIG_TRUE) {
        st = sph_fail(L->err, SPH_ERR_INPUT,
                      "%s: the scene cannot be stored for a restart: its resolved text does not "
                      "parse (line %d: %s)",
                      L->file, config_error_line(&again),
                      config_error_text(&again) ? config_error_text(&again) : "syntax error");
    } else {
        const config_setting_t *d =
            first_changed(config_root_setting(cfg), config_root_setting(&again));
        if (d && d->type == CONFIG_TYPE_FLOAT)
            st = fail_at(L, d, NULL,
                         "%.17g has more significant digits than a stored scene keeps (15), so "
                         "a restart would differ; round it",
                         d->value.fval);
        else if (d)
            st = fail_at(L, d, NULL, "the value does not survive storing the scene for a restart");
    }
    config_destroy(&again);
    return st;
}

/* Load from a file (`text` NULL) or from scene text (restarts: the text
 * stored in a checkpoint, `path` naming where it came from). */
static sph_status load(sph_scene *scene, const char *path, const char *text,
                       const char *const *overrides, int noverrides, sph_error *err) {
    memset(scene, 0, sizeof *scene);
    scene->period_observer = -1;
    scene->wave_incident = scene->wave_transmitted = -1;
    scene->acceleration_criterion = true;
    if (!path) return sph_fail(err, SPH_ERR_INPUT, "no scene file given");
    if (strlen(path) >= sizeof scene->path)
        return sph_fail(err, SPH_ERR_INPUT, "%s: cannot read scene file: path too long", path);
    snprintf(scene->path, sizeof scene->path, "%s", path);

    loader L = {.file = path, .err = err, .scene = scene};
    config_t cfg;
    config_init(&cfg);
    sph_status st = SPH_OK;
    char *wide = text ? widen_integers(text) : NULL;
    if (!text) {
        st = read_scene_file(&L, &cfg, path);
    } else if (!wide) {
        st = sph_fail(err, SPH_ERR_RUNTIME, "%s: out of memory reading the scene", path);
    } else if (config_read_string(&cfg, wide) != CONFIG_TRUE) {
        st = sph_fail(err, SPH_ERR_INPUT, "%s:%d: the stored scene does not parse: %s", path,
                      config_error_line(&cfg),
                      config_error_text(&cfg) ? config_error_text(&cfg) : "syntax error");
    }
    free(wide);
    for (int i = 0; st == SPH_OK && i < noverrides; i++)
        st = apply_override(&L, &cfg, overrides[i]);
    if (st == SPH_OK) st = write_resolved(scene, &cfg, err);
    if (st == SPH_OK) st = parse_scene(&L, config_root_setting(&cfg));
    if (st == SPH_OK) st = check_resolved(&L, &cfg);
    config_destroy(&cfg);
    if (st != SPH_OK) sph_scene_free(scene);
    return st;
}

sph_status sph_scene_load(sph_scene *scene, const char *path, const char *const *overrides,
                          int noverrides, sph_error *err) {
    return load(scene, path, NULL, overrides, noverrides, err);
}

sph_status sph_scene_load_text(sph_scene *scene, const char *origin, const char *text,
                               const char *const *overrides, int noverrides, sph_error *err) {
    return load(scene, origin, text, overrides, noverrides, err);
}

bool sph_scene_key_where(const sph_scene *scene, const char *const *overrides, int noverrides,
                         const char *key, char *buf, size_t size) {
    /* the scene keeps no source lines after loading: read its file again
     * as load() does (the same text preparation and overrides, so that
     * override_of names the --set that made a setting) */
    sph_error ignored;
    loader L = {.file = scene->path, .err = &ignored, .scene = NULL};
    config_t cfg;
    config_init(&cfg);
    sph_status st = read_scene_file(&L, &cfg, scene->path);
    for (int i = 0; st == SPH_OK && i < noverrides; i++)
        st = apply_override(&L, &cfg, overrides[i]);
    const config_setting_t *s = NULL;
    bool given = false;
    if (st == SPH_OK) {
        char path[SPH_SCENE_PATH_LEN];
        snprintf(path, sizeof path, "%s", key);
        for (;;) {
            s = config_lookup(&cfg, path);
            if (s) {
                given = strcmp(path, key) == 0;
                break;
            }
            char *dot = strrchr(path, '.');
            if (!dot) break;
            *dot = '\0';
        }
    }
    const char *ov = s ? override_of(s) : NULL;
    const unsigned line = s ? config_setting_source_line(s) : 0;
    if (ov)
        sph_format(buf, size, "--set %s: %s", ov, key);
    else if (line > 0)
        sph_format(buf, size, "%s:%u: %s", scene->path, line, key);
    else
        sph_format(buf, size, "%s: %s", scene->path, key);
    config_destroy(&cfg);
    return given || ov != NULL;
}

void sph_scene_free(sph_scene *scene) {
    if (!scene) return;
    free(scene->resolved_text);
    scene->resolved_text = NULL;
    /* every shape slot: a load that failed may have read meshes past nshapes' count */
    for (int i = 0; i < SPH_SCENE_MAX_SHAPES; i++) {
        sph_mesh_free(scene->shapes[i].mesh);
        scene->shapes[i].mesh = NULL;
    }
}

/* ------------------------------------------------------------------------ */
/* geometry                                                                  */
/* ------------------------------------------------------------------------ */

bool sph_shape_contains(const sph_scene *scene, int shape, const double x[3]) {
    const sph_shape *sh = &scene->shapes[shape];
    switch (sh->type) {
    case SPH_SHAPE_BOX:
        for (int a = 0; a < scene->dim; a++)
            if (x[a] < sh->lower[a] || x[a] > sh->upper[a]) return false;
        return true;
    case SPH_SHAPE_UNION:
        for (int i = 0; i < sh->nparts; i++)
            if (sph_shape_contains(scene, sh->parts[i], x)) return true;
        return false;
    case SPH_SHAPE_DIFFERENCE:
        if (!sph_shape_contains(scene, sh->parts[0], x)) return false;
        for (int i = 1; i < sh->nparts; i++)
            if (sph_shape_contains(scene, sh->parts[i], x)) return false;
        return true;
    case SPH_SHAPE_SPHERE: {
        double r2 = 0.0;
        for (int a = 0; a < scene->dim; a++) r2 += (x[a] - sh->centre[a]) * (x[a] - sh->centre[a]);
        return r2 >= sh->inner_radius * sh->inner_radius &&
               r2 <= sh->outer_radius * sh->outer_radius;
    }
    case SPH_SHAPE_MESH:
        return sph_mesh_contains(sh->mesh, x);
    case SPH_SHAPE_CYLINDER: {
        double d[3], s = 0.0;
        for (int a = 0; a < 3; a++) {
            d[a] = x[a] - sh->centre[a];
            s += d[a] * sh->axis[a];
        }
        if (s < 0.0 || s > sh->length) return false;
        double r2 = 0.0;
        for (int a = 0; a < 3; a++) r2 += (d[a] - s * sh->axis[a]) * (d[a] - s * sh->axis[a]);
        return r2 <= sh->outer_radius * sh->outer_radius;
    }
    }
    return false;
}

void sph_shape_bounds(const sph_scene *scene, int shape, double lower[3], double upper[3]) {
    const sph_shape *sh = &scene->shapes[shape];
    switch (sh->type) {
    case SPH_SHAPE_BOX:
    case SPH_SHAPE_SPHERE:
    case SPH_SHAPE_CYLINDER:
    case SPH_SHAPE_MESH:
        /* round shapes and meshes store their bounding box */
        for (int a = 0; a < 3; a++) lower[a] = sh->lower[a], upper[a] = sh->upper[a];
        return;
    case SPH_SHAPE_UNION:
        sph_shape_bounds(scene, sh->parts[0], lower, upper);
        for (int i = 1; i < sh->nparts; i++) {
            double lo[3], hi[3];
            sph_shape_bounds(scene, sh->parts[i], lo, hi);
            for (int a = 0; a < 3; a++) {
                if (lo[a] < lower[a]) lower[a] = lo[a];
                if (hi[a] > upper[a]) upper[a] = hi[a];
            }
        }
        return;
    case SPH_SHAPE_DIFFERENCE:
        /* removing parts never grows the first one */
        sph_shape_bounds(scene, sh->parts[0], lower, upper);
        return;
    }
}

/* ------------------------------------------------------------------------ */
/* names                                                                     */
/* ------------------------------------------------------------------------ */

const char *sph_placement_name(sph_placement p) {
    return p == SPH_PLACEMENT_RELAXED ? "relaxed" : "lattice";
}

const char *sph_formulation_name(sph_formulation f) {
    switch (f) {
    case SPH_FORMULATION_ENOG:
    case SPH_FORMULATION_ENOG_A:
    case SPH_FORMULATION_OG:
    case SPH_FORMULATION_OAS:
    case SPH_FORMULATION_GNOG:
    case SPH_FORMULATION_GNOG_A:
    case SPH_FORMULATION_TLSPH:
    case SPH_FORMULATION_EULERIAN_WC:
    case SPH_FORMULATION_EULERIAN_COMPRESSIBLE:
        return FORMULATION_NAMES[f];
    }
    return "?";
}

const char *sph_rotation_name(sph_rotation r) {
    switch (r) {
    case SPH_ROTATION_NONE:
        return "none";
    case SPH_ROTATION_AVERAGED:
        return "averaged";
    case SPH_ROTATION_PER_PARTICLE:
        return "per-particle";
    }
    return "?";
}

const char *sph_kernel_name(sph_kernel k) {
    switch (k) {
    case SPH_KERNEL_WENDLAND_C2:
    case SPH_KERNEL_LAGUERRE_GAUSS:
    case SPH_KERNEL_LAGUERRE_WENDLAND:
    case SPH_KERNEL_CUBIC_BSPLINE:
        return KERNEL_NAMES[k];
    }
    return "?";
}

const char *sph_stepping_name(sph_stepping s) {
    switch (s) {
    case SPH_STEPPING_DUAL:
        return "dual";
    case SPH_STEPPING_SINGLE:
        return "single";
    }
    return "?";
}

/* ------------------------------------------------------------------------ */
/* the constraint table                                                      */
/* ------------------------------------------------------------------------ */

int sph_constraint_index(const sph_scene *scene, int body, int constraint) {
    int k = 0;
    for (int b = 0; b < body; b++) k += scene->bodies[b].nconstraints;
    return k + constraint;
}

int sph_scene_material_rows(const sph_scene *scene, int row_of[SPH_MAX_MATERIALS]) {
    for (int m = 0; m < SPH_MAX_MATERIALS; m++) row_of[m] = -1;
    int rows = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        const sph_body *body = &scene->bodies[b];
        for (int k = -1; k < body->nregions; k++) {
            const int m = k < 0 ? body->material : body->regions[k].material;
            if (m >= 0 && m < SPH_MAX_MATERIALS && row_of[m] < 0) row_of[m] = rows++;
        }
    }
    return rows;
}

int sph_body_material_at(const sph_scene *scene, int body, const double x[3]) {
    const sph_body *b = &scene->bodies[body];
    for (int k = 0; k < b->nregions; k++)
        if (sph_shape_contains(scene, b->regions[k].shape, x)) return b->regions[k].material;
    return b->material;
}

int sph_constraint_count(const sph_scene *scene) {
    return sph_constraint_index(scene, scene->nbodies, 0);
}

const sph_constraint *sph_constraint_at(const sph_scene *scene, int index) {
    for (int b = 0; b < scene->nbodies; b++) {
        if (index < scene->bodies[b].nconstraints) return &scene->bodies[b].constraints[index];
        index -= scene->bodies[b].nconstraints;
    }
    return NULL;
}

bool sph_scene_has_driven_constraint(const sph_scene *scene) {
    for (int k = 0; k < sph_constraint_count(scene); k++) {
        const sph_constraint *c = sph_constraint_at(scene, k);
        for (int a = 0; a < scene->dim; a++)
            if (c->type == SPH_CONSTRAINT_VELOCITY && c->velocity[a] != 0.0) return true;
    }
    return false;
}

int sph_scene_expression_variables(int dim, const char *vars[3]) {
    for (int a = 0; a < 3; a++) vars[a] = AXES[a];
    return dim;
}

sph_expression_constants
sph_scene_expression_constants(const sph_scene *scene, const char *names[SPH_SCENE_MAX_CONSTANTS]) {
    for (int k = 0; k < scene->nconstants; k++) names[k] = scene->constant_name[k];
    return (sph_expression_constants){scene->nconstants, names, scene->constant_value};
}
