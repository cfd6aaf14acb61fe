/* scene_values.c — typed access to a scene's settings through the schema
 * (scene_schema.h), and the messages that name a setting by file, line and
 * key path. */
#include "scene_loader.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------ */
/* loader state and error reporting                                          */
/* ------------------------------------------------------------------------ */

const char *scene_type_name(int type) {
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
const char *scene_override_of(const config_setting_t *s) {
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
sph_status scene_fail_at(loader *L, const config_setting_t *s, const char *key, const char *fmt,
                         ...) {
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
    const char *ov = scene_override_of(s);
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
void scene_where_of(const loader *L, const config_setting_t *s, char *buf, size_t size) {
    char path[768];
    setting_path(s, path, sizeof path);
    const char *ov = scene_override_of(s);
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
void scene_suggest(const char *given, const char *const *names, int n, const char *what, char *buf,
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
/* typed access through the schema                                          */
/* ------------------------------------------------------------------------ */

const char *const SCENE_AXES[3] = {"x", "y", "z"};

static const sph_scene_key *key_of(sph_scene_key_id k) {
    return sph_scene_key_at(k);
}

const char *scene_word(sph_scene_key_id k, int index) {
    const sph_scene_key *key = key_of(k);
    return index >= 0 && index < sph_scene_key_words(key) ? key->words[index] : "?";
}

/* Reject members of group g that are not keys of `sections` (those of a
 * higher dimension than the scene's count as unknown). */
sph_status scene_check_keys(loader *L, const config_setting_t *g, const char *const *sections) {
    const char *keys[SK_COUNT];
    int nkeys = 0;
    for (int s = 0; sections[s]; s++) {
        for (int i = 0; i < SK_COUNT; i++) {
            const sph_scene_key *k = key_of((sph_scene_key_id)i);
            if (strcmp(k->section, sections[s]) != 0 || k->min_dimension > L->scene->dim) continue;
            bool seen = false;
            for (int j = 0; j < nkeys && !seen; j++) seen = strcmp(keys[j], k->key) == 0;
            if (!seen) keys[nkeys++] = k->key;
        }
    }
    const int n = config_setting_length(g);
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(g, (unsigned)i);
        bool known = false;
        for (int k = 0; k < nkeys && !known; k++) known = strcmp(m->name, keys[k]) == 0;
        if (!known) {
            char hint[512];
            scene_suggest(m->name, keys, nkeys, "valid keys here", hint, sizeof hint);
            return scene_fail_at(L, m, NULL, "unknown key '%s'%s", m->name, hint);
        }
    }
    return SPH_OK;
}

/* The member k of g; an error if the schema requires it and it is absent. */
sph_status scene_member(loader *L, const config_setting_t *g, sph_scene_key_id k,
                        const config_setting_t **out) {
    const sph_scene_key *key = key_of(k);
    *out = config_setting_get_member(g, key->key);
    if (!*out && key->required) return scene_fail_at(L, g, key->key, "missing required key");
    return SPH_OK;
}

const config_setting_t *scene_first_member(const config_setting_t *g, const char *const *names) {
    for (int k = 0; names[k]; ++k) {
        const config_setting_t *m = config_setting_get_member(g, names[k]);
        if (m) return m;
    }
    return NULL;
}

/* The member k of g, required here whatever the schema's default (a key
 * that some scenes need: a fixed_axes constraint's axes). */
sph_status scene_require(loader *L, const config_setting_t *g, sph_scene_key_id k,
                         const config_setting_t **out) {
    const sph_scene_key *key = key_of(k);
    *out = config_setting_get_member(g, key->key);
    if (!*out) return scene_fail_at(L, g, key->key, "missing required key");
    return SPH_OK;
}

/* The exact value of an integer setting, over [-2^63, 2^64): libconfig
 * keeps 64 signed bits, and a hexadecimal 64-bit integer is read as its
 * unsigned bits (widen_integers writes the values from 2^63 to 2^64 - 1 that
 * way, so that a seed takes the whole unsigned range). */
static scene_wide_int wide_of(const config_setting_t *s) {
    long long v = config_setting_type(s) == CONFIG_TYPE_INT64 ? config_setting_get_int64(s)
                                                              : config_setting_get_int(s);
    if (v < 0 && config_setting_type(s) == CONFIG_TYPE_INT64 &&
        config_setting_get_format(s) == CONFIG_FORMAT_HEX)
        return (scene_wide_int){false, (unsigned long long)v};
    /* -(v + 1) + 1: no overflow at LLONG_MIN */
    if (v < 0) return (scene_wide_int){true, (unsigned long long)(-(v + 1)) + 1ULL};
    return (scene_wide_int){false, (unsigned long long)v};
}

static double wide_double(scene_wide_int v) {
    return v.negative ? -(double)v.magnitude : (double)v.magnitude;
}

/* The value of an integer setting as a double (rounded beyond 2^53). */
double scene_integer_value(const config_setting_t *s) {
    return wide_double(wide_of(s));
}

/* v in [lo, hi] (lo <= 0 <= hi or 0 <= lo <= hi) */
bool scene_wide_in(scene_wide_int v, long long lo, unsigned long long hi) {
    if (v.negative) return lo < 0 && v.magnitude <= (unsigned long long)(-(lo + 1)) + 1ULL;
    return v.magnitude <= hi && (lo <= 0 || v.magnitude >= (unsigned long long)lo);
}

/* The value as written: "-2147483649", "18446744073709551615". */
const char *scene_wide_text(scene_wide_int v, char buf[24]) {
    snprintf(buf, 24, "%s%llu", v.negative ? "-" : "", v.magnitude);
    return buf;
}

sph_status scene_as_float(loader *L, const config_setting_t *s, double *out) {
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
        return scene_fail_at(L, s, NULL, "expected a number, got %s",
                             scene_type_name(config_setting_type(s)));
    }
    if (!isfinite(*out)) return scene_fail_at(L, s, NULL, "must be a finite number, got %g", *out);
    return SPH_OK;
}

sph_status scene_as_string(loader *L, const config_setting_t *s, const char **out) {
    if (config_setting_type(s) != CONFIG_TYPE_STRING)
        return scene_fail_at(L, s, NULL, "expected a string, got %s",
                             scene_type_name(config_setting_type(s)));
    *out = config_setting_get_string(s);
    return SPH_OK;
}

/* A vector of `len` numbers: an array [..] or a list (..) of ints or floats. */
sph_status scene_as_vector(loader *L, const config_setting_t *s, int len, double out[3]) {
    int type = config_setting_type(s);
    if (type != CONFIG_TYPE_ARRAY && type != CONFIG_TYPE_LIST)
        return scene_fail_at(L, s, NULL, "expected a vector of %d numbers [ ... ], got %s", len,
                             scene_type_name(type));
    int n = config_setting_length(s);
    if (n != len)
        return scene_fail_at(L, s, NULL, "expected a vector of %d numbers, got %d element%s", len,
                             n, n == 1 ? "" : "s");
    for (int i = 0; i < n; i++) {
        sph_status st = scene_as_float(L, config_setting_get_elem(s, (unsigned)i), &out[i]);
        if (st) return st;
    }
    for (int i = n; i < 3; i++) out[i] = 0.0;
    return SPH_OK;
}

/* A number in the key's range; `def` when it is absent (and not required). */
sph_status scene_number_or(loader *L, const config_setting_t *g, sph_scene_key_id k, double def,
                           double *out) {
    const sph_scene_key *key = key_of(k);
    const config_setting_t *s;
    sph_status st = scene_member(L, g, k, &s);
    if (st) return st;
    if (!s) {
        *out = def;
        return SPH_OK;
    }
    double v = 0.0;
    if ((st = scene_as_float(L, s, &v))) return st;
    const double lo = key->lo.set ? key->lo.value : -INFINITY;
    const double hi = key->hi.set ? key->hi.value : INFINITY;
    const bool lo_open = key->lo.set && key->lo.open, hi_open = key->hi.set && key->hi.open;
    bool ok = (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    if (!ok) {
        if (isinf(hi))
            return scene_fail_at(L, s, NULL, "must be %s %g, got %g", lo_open ? ">" : ">=", lo, v);
        if (isinf(lo))
            return scene_fail_at(L, s, NULL, "must be %s %g, got %g", hi_open ? "<" : "<=", hi, v);
        return scene_fail_at(L, s, NULL, "must be in %c%g, %g%c, got %g", lo_open ? '(' : '[', lo,
                             hi, hi_open ? ')' : ']', v);
    }
    *out = v;
    return SPH_OK;
}

/* A number with the schema's default (0 where it states none: the key is
 * then required, or its absence is handled by the caller). */
sph_status scene_number(loader *L, const config_setting_t *g, sph_scene_key_id k, double *out) {
    const sph_scene_key *key = key_of(k);
    return scene_number_or(L, g, k, key->has_default ? key->def : 0.0, out);
}

/* An integer key, read whole (64 bits: an int and a 64-bit int alike) so
 * that the range check sees the value written, not its low 32 bits.  Absent
 * and not required: *present is false and *out untouched. */
sph_status scene_wide_integer(loader *L, const config_setting_t *g, sph_scene_key_id k,
                              scene_wide_int *out, bool *present, const config_setting_t **where) {
    const config_setting_t *s;
    sph_status st = scene_member(L, g, k, &s);
    if (st) return st;
    *where = s;
    *present = s != NULL;
    if (!s) return SPH_OK;
    const int type = config_setting_type(s);
    if (type == CONFIG_TYPE_FLOAT) {
        /* an integer literal beyond 64 bits arrives as a number
         * (scene_widen_integers): say that it is too large, not that it is a
         * decimal */
        const double v = config_setting_get_float(s);
        if (isfinite(v) && v == floor(v) && fabs(v) >= 0x1p63)
            return scene_fail_at(L, s, NULL,
                                 "expected a 64-bit integer (-9223372036854775808 to "
                                 "18446744073709551615), got %.17g",
                                 v);
    }
    if (type != CONFIG_TYPE_INT && type != CONFIG_TYPE_INT64)
        return scene_fail_at(L, s, NULL, "expected an integer, got %s", scene_type_name(type));
    *out = wide_of(s);
    return SPH_OK;
}

/* An integer in the key's range [lo, hi]; its default when absent. */
sph_status scene_integer(loader *L, const config_setting_t *g, sph_scene_key_id k, int *out,
                         const config_setting_t **where) {
    const sph_scene_key *key = key_of(k);
    scene_wide_int v = {false, 0};
    bool present = false;
    sph_status st = scene_wide_integer(L, g, k, &v, &present, where);
    if (st) return st;
    if (!present) {
        *out = (int)key->def;
        return SPH_OK;
    }
    const int lo = (int)key->lo.value, hi = (int)key->hi.value;
    char text[24];
    if (!scene_wide_in(v, lo, (unsigned long long)hi))
        return scene_fail_at(L, *where, NULL, "must be in [%d, %d], got %s", lo, hi,
                             scene_wide_text(v, text));
    *out = (int)wide_double(v);
    return SPH_OK;
}

sph_status scene_boolean(loader *L, const config_setting_t *g, sph_scene_key_id k, bool *out) {
    const sph_scene_key *key = key_of(k);
    const config_setting_t *s = config_setting_get_member(g, key->key);
    if (!s) {
        *out = key->def != 0.0;
        return SPH_OK;
    }
    if (config_setting_type(s) != CONFIG_TYPE_BOOL)
        return scene_fail_at(L, s, NULL, "expected a boolean (true or false), got %s",
                             scene_type_name(config_setting_type(s)));
    *out = config_setting_get_bool(s) != 0;
    return SPH_OK;
}

/* A string naming a table entry (material, shape, observer): not empty and
 * short enough for SPH_NAME_LEN.  Always required. */
sph_status scene_name(loader *L, const config_setting_t *g, sph_scene_key_id k, const char **out,
                      const config_setting_t **where) {
    sph_status st = scene_require(L, g, k, where);
    if (st || (st = scene_as_string(L, *where, out))) return st;
    if (!**out) return scene_fail_at(L, *where, NULL, "must not be empty");
    if (strlen(*out) >= SPH_NAME_LEN)
        return scene_fail_at(L, *where, NULL, "names are limited to %d characters",
                             SPH_NAME_LEN - 1);
    return SPH_OK;
}

/* One of the key's words; *out is its index, `def` when absent. */
sph_status scene_keyword_or(loader *L, const config_setting_t *g, sph_scene_key_id k, int def,
                            int *out, const config_setting_t **where) {
    const sph_scene_key *key = key_of(k);
    const config_setting_t *s;
    sph_status st = scene_member(L, g, k, &s);
    if (st) return st;
    if (where) *where = s;
    if (!s) {
        *out = def;
        return SPH_OK;
    }
    const char *v = "";
    if ((st = scene_as_string(L, s, &v))) return st;
    const int nwords = sph_scene_key_words(key);
    for (int i = 0; i < nwords; i++) {
        if (strcmp(v, key->words[i]) == 0) {
            *out = i;
            return SPH_OK;
        }
    }
    char list[256];
    size_t len = 0;
    for (int i = 0; i < nwords && len < sizeof list; i++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s\"%s\"", i ? ", " : "",
                                key->words[i]);
    return scene_fail_at(L, s, NULL, "must be one of %s, got \"%s\"", list, v);
}

sph_status scene_keyword(loader *L, const config_setting_t *g, sph_scene_key_id k, int *out,
                         const config_setting_t **where) {
    const sph_scene_key *key = key_of(k);
    return scene_keyword_or(L, g, k, key->has_default ? (int)key->def : 0, out, where);
}

/* A vector of `len` numbers; absent and not required: out[] untouched (the
 * caller's default stays). */
sph_status scene_vector(loader *L, const config_setting_t *g, sph_scene_key_id k, int len,
                        double out[3], const config_setting_t **where) {
    const config_setting_t *s;
    sph_status st = scene_member(L, g, k, &s);
    if (st) return st;
    if (where) *where = s;
    if (!s) return SPH_OK;
    return scene_as_vector(L, s, len, out);
}

sph_status scene_group(loader *L, const config_setting_t *g, sph_scene_key_id k,
                       const config_setting_t **out) {
    sph_status st = scene_member(L, g, k, out);
    if (st || !*out) return st;
    if (!config_setting_is_group(*out))
        return scene_fail_at(L, *out, NULL, "expected a group { ... }, got %s",
                             scene_type_name(config_setting_type(*out)));
    return SPH_OK;
}

sph_status scene_list(loader *L, const config_setting_t *g, sph_scene_key_id k,
                      const config_setting_t **out) {
    sph_status st = scene_member(L, g, k, out);
    if (st || !*out) return st;
    if (!config_setting_is_list(*out))
        return scene_fail_at(L, *out, NULL, "expected a list ( { ... }, ... ), got %s",
                             scene_type_name(config_setting_type(*out)));
    return SPH_OK;
}

/* The axes of a dimension, quoted, for the messages: "x", "x" or "y", ... */
const char *scene_axes_text(int dim) {
    return dim == 1 ? "\"x\"" : dim == 2 ? "\"x\" or \"y\"" : "\"x\", \"y\" or \"z\"";
}

/* The variables of the initial-field expressions, for the messages: "x",
 * "x, y", "x, y, z" */
const char *scene_variables_text(int dim) {
    return dim == 1 ? "x" : dim == 2 ? "x, y" : "x, y, z";
}

/* An axis of the scene's dimension (a keyword key whose words are
 * SCENE_AXES). */
sph_status scene_axis(loader *L, const config_setting_t *g, sph_scene_key_id k, int *out) {
    const config_setting_t *s;
    sph_status st = scene_keyword(L, g, k, out, &s);
    if (st) return st;
    if (*out >= L->scene->dim)
        return scene_fail_at(L, s, NULL, "must be %s in %dD, got \"%s\"",
                             scene_axes_text(L->scene->dim), L->scene->dim, SCENE_AXES[*out]);
    return SPH_OK;
}
