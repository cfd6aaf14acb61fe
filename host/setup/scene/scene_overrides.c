/* scene_overrides.c — `--set key=value` on the libconfig tree, and integer
 * literals beyond 32 bits kept exact before libconfig reads them. */
#include "scene_loader.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* Appends n bytes of s to t, NUL-terminated; false when out of memory. */
bool scene_text_put(scene_text *t, const char *s, size_t n) {
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
static size_t widen_number(const char *p, scene_text *t, bool *ok) {
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
            *ok = scene_text_put(t, p, (size_t)(q - p));
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
        *ok = scene_text_put(t, p, len); /* libconfig reads it exactly (or it is no number) */
    } else if (fits_int64) {
        snprintf(out, sizeof out, "%s%lluL", negative ? "-" : "", mag);
        *ok = scene_text_put(t, out, strlen(out));
    } else if (!overflow && !negative) {
        snprintf(out, sizeof out, "0x%llXL", mag);
        *ok = scene_text_put(t, out, strlen(out));
    } else if (hex) {
        snprintf(out, sizeof out, "%.17e", approx);
        *ok = scene_text_put(t, out, strlen(out));
    } else {
        /* the digits as written, made a decimal */
        *ok = scene_text_put(t, p, (size_t)(end_digits - p)) && scene_text_put(t, ".0", 2);
    }
    return len;
}

/* `text` with its large integer literals rewritten (see above), in a new
 * string (NULL: out of memory). */
char *scene_widen_integers(const char *text) {
    scene_text t = {NULL, 0, 0};
    bool ok = scene_text_put(&t, "", 0);
    const char *p = text;
    while (ok && *p) {
        size_t n = skip_opaque(p);
        if (n) {
            ok = scene_text_put(&t, p, n);
        } else if ((*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z') || *p == '*') {
            /* a name, digits and '-' included (libconfig's [A-Za-z*][-A-Za-z0-9_*]*) */
            const char *q = p + 1;
            while ((*q >= 'A' && *q <= 'Z') || (*q >= 'a' && *q <= 'z') || is_digit(*q) ||
                   *q == '_' || *q == '-' || *q == '*')
                q++;
            n = (size_t)(q - p);
            ok = scene_text_put(&t, p, n);
        } else if (is_digit(*p) || *p == '.' ||
                   ((*p == '-' || *p == '+') && (is_digit(p[1]) || p[1] == '.'))) {
            n = widen_number(p, &t, &ok);
        } else {
            n = 1;
            ok = scene_text_put(&t, p, 1);
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
sph_status scene_apply_override(loader *L, config_t *cfg, const char *ov) {
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
    char *wide = scene_widen_integers(text);
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
                         walked, scene_type_name(child->type), next);
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
                tmp.value.fval = scene_integer_value(src);
            } else if (sib->type != src->type) {
                st = OV_FAIL("--set %s: %s: every element of this array is %s, got %s", ov, walked,
                             scene_type_name(sib->type), scene_type_name(src->type));
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
