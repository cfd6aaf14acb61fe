/* expression.c — scalar expressions over muParser's C interface (see
 * expression.h). */
#include "expression.h"

#include <muParserDLL.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct sph_expression {
    muParserHandle_t parser;
    int nvars;
    /* muParser reads the variables through these addresses: the struct is
     * on the heap, so they stay valid for the handle's life */
    double vars[SPH_EXPRESSION_MAX_VARS];
};

/* The library keeps one pending error per handle; mupError reads and
 * clears it.  The message stays readable until the next error. */
static bool library_failed(muParserHandle_t p, char *why, size_t size) {
    if (!mupError(p)) return false;
    snprintf(why, size, "%s", mupGetErrorMsg(p));
    return true;
}

/* A parser with the constants every expression has.  muParser 2.3.3's own
 * `_pi` is 3.141592653589 (13 digits): a mode shape written with it differs
 * from the built-in field by 1e-12 relative.  `pi` and `_pi` here are the
 * double nearest pi, as in particles.c. */
static muParserHandle_t new_parser(void) {
    muParserHandle_t p = mupCreate(muBASETYPE_FLOAT);
    if (!p) return NULL;
    mupDefineConst(p, "pi", 3.14159265358979323846);
    mupDefineConst(p, "_pi", 3.14159265358979323846);
    if (mupError(p)) {
        mupRelease(p);
        return NULL;
    }
    return p;
}

/* The checks made before the text reaches the library: what the fuzzer
 * may throw at the scene parser stays within these bounds. */
static bool text_acceptable(const char *text, char *why, size_t size) {
    const size_t len = strlen(text);
    if (len >= SPH_EXPRESSION_MAX_LEN) {
        snprintf(why, size, "an expression is limited to %d characters, got %zu",
                 SPH_EXPRESSION_MAX_LEN - 1, len);
        return false;
    }
    for (size_t i = 0; i < len; i++) {
        const unsigned char c = (unsigned char)text[i];
        if (c < ' ' || c > '~') {
            snprintf(why, size,
                     "byte \\x%02X at position %zu: expressions are printable ASCII "
                     "(write a line break as a space)",
                     c, i);
            return false;
        }
        /* "<=", ">=", "==", "!=" are comparisons; a lone '=' is muParser's
         * assignment, which would overwrite a variable (x = 3) */
        if (c == '=' || ((c == '<' || c == '>' || c == '!') && text[i + 1] == '=')) {
            if (text[i + 1] == '=') {
                i++;
                continue;
            }
            /* positions count from 0, as in the library's messages */
            snprintf(why, size,
                     "'=' at position %zu: assignments are not allowed (compare with '==')", i);
            return false;
        }
    }
    if (len == 0) {
        snprintf(why, size, "the expression is empty");
        return false;
    }
    return true;
}

/* "x, y, z; constants: U, Re" into buf, for the unknown-variable message */
static void list_names(const char *const *vars, int nvars, const sph_expression_constants *c,
                       char *buf, size_t size) {
    size_t len = 0;
    buf[0] = '\0';
    for (int k = 0; k < nvars && len < size; k++)
        len += (size_t)snprintf(buf + len, size - len, "%s%s", k ? ", " : "", vars[k]);
    for (int k = 0; c && k < c->n && len < size; k++)
        len += (size_t)snprintf(buf + len, size - len, "%s%s",
                                k ? ", " : "; constants: ", c->names[k]);
}

bool sph_expression_compile(const char *text, const char *const *vars, int nvars,
                            const sph_expression_constants *constants, sph_expression **out,
                            char *why, size_t size) {
    *out = NULL;
    if (nvars < 0 || nvars > SPH_EXPRESSION_MAX_VARS) {
        snprintf(why, size, "at most %d variables, got %d", SPH_EXPRESSION_MAX_VARS, nvars);
        return false;
    }
    if (!text_acceptable(text, why, size)) return false;
    sph_expression *e = calloc(1, sizeof *e);
    if (!e) {
        snprintf(why, size, "out of memory compiling an expression");
        return false;
    }
    e->nvars = nvars;
    e->parser = new_parser();
    if (!e->parser) {
        free(e);
        snprintf(why, size, "out of memory compiling an expression");
        return false;
    }
    muParserHandle_t p = e->parser;
    bool ok = true;
    for (int k = 0; k < nvars && ok; k++) {
        mupDefineVar(p, vars[k], &e->vars[k]);
        ok = !library_failed(p, why, size);
    }
    for (int k = 0; constants && k < constants->n && ok; k++) {
        mupDefineConst(p, constants->names[k], constants->values[k]);
        ok = !library_failed(p, why, size);
    }
    if (ok) {
        mupSetExpr(p, text);
        ok = !library_failed(p, why, size);
    }
    /* the used variables: muParser lists the undefined ones too, so that an
     * unknown name gets its own message rather than "Unexpected token" */
    const int nused = ok ? mupGetExprVarNum(p) : 0;
    if (ok) ok = !library_failed(p, why, size);
    for (int k = 0; k < nused && ok; k++) {
        const muChar_t *name = NULL;
        muFloat_t *addr = NULL;
        mupGetExprVar(p, (unsigned)k, &name, &addr);
        if ((ok = !library_failed(p, why, size)) && !(addr >= e->vars && addr < e->vars + nvars)) {
            char known[512];
            list_names(vars, nvars, constants, known, sizeof known);
            snprintf(why, size, "unknown variable '%s' (variables: %s)", name ? name : "?", known);
            ok = false;
        }
    }
    if (ok) {
        /* a full parse and one evaluation: `a, b` parses as two results */
        int nresults = 0;
        mupEvalMulti(p, &nresults);
        ok = !library_failed(p, why, size);
        if (ok && nresults != 1) {
            snprintf(why, size, "the expression has %d comma-separated results; give one",
                     nresults);
            ok = false;
        }
    }
    if (!ok) {
        sph_expression_free(e);
        return false;
    }
    *out = e;
    return true;
}

bool sph_expression_eval(sph_expression *e, const double *values, double *result, char *why,
                         size_t size) {
    for (int k = 0; k < e->nvars; k++) e->vars[k] = values[k];
    *result = mupEval(e->parser);
    return !library_failed(e->parser, why, size);
}

void sph_expression_free(sph_expression *e) {
    if (!e) return;
    mupRelease(e->parser);
    free(e);
}

bool sph_expression_name_check(const char *name, const char *const *vars, int nvars, char *why,
                               size_t size) {
    const size_t len = strlen(name);
    bool plain =
        len > 0 && ((name[0] >= 'a' && name[0] <= 'z') || (name[0] >= 'A' && name[0] <= 'Z'));
    for (size_t i = 1; plain && i < len; i++) {
        const char c = name[i];
        plain =
            (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    }
    if (!plain) {
        snprintf(why, size,
                 "a constant's name is a letter, then letters, digits or '_' (an identifier "
                 "of the expressions)");
        return false;
    }
    if (len > 63) {
        snprintf(why, size, "a constant's name is limited to 63 characters");
        return false;
    }
    for (int k = 0; k < nvars; k++)
        if (strcmp(name, vars[k]) == 0) {
            snprintf(why, size, "'%s' is a variable of the expressions, not a constant", name);
            return false;
        }
    /* a name the library knows: a constant (pi) does not parse as a lone
     * undefined variable, a function (sin, atan2, sum) parses when called
     * with one or two arguments */
    muParserHandle_t p = new_parser();
    if (!p) {
        snprintf(why, size, "out of memory checking a constant's name");
        return false;
    }
    mupSetExpr(p, name);
    const int nused = mupGetExprVarNum(p);
    bool taken = mupError(p) || nused != 1;
    for (int args = 1; args <= 2 && !taken; args++) {
        char call[96];
        snprintf(call, sizeof call, "%s(%s)", name, args == 1 ? "1" : "1, 1");
        mupSetExpr(p, call);
        mupGetExprVarNum(p);
        taken = !mupError(p);
    }
    mupRelease(p);
    if (taken) {
        snprintf(why, size, "'%s' is a function or constant of the expressions already", name);
        return false;
    }
    return true;
}

bool sph_expression_field_compile(sph_expression_field *f, const char *const *texts, int n,
                                  const char *const *vars, int nvars,
                                  const sph_expression_constants *constants, int *bad, char *why,
                                  size_t size) {
    memset(f, 0, sizeof *f);
    *bad = -1;
    if (n < 0 || n > SPH_EXPRESSION_FIELD_MAX) {
        snprintf(why, size, "at most %d expressions in a field, got %d", SPH_EXPRESSION_FIELD_MAX,
                 n);
        return false;
    }
    f->n = n;
    for (int k = 0; k < n; k++) {
        if (!texts[k] || !texts[k][0]) continue;
        if (!sph_expression_compile(texts[k], vars, nvars, constants, &f->e[k], why, size)) {
            *bad = k;
            sph_expression_field_free(f);
            return false;
        }
    }
    return true;
}

bool sph_expression_field_eval(sph_expression_field *f, const double *values, bool allow_nonfinite,
                               double *out, int *bad, char *why, size_t size) {
    *bad = -1;
    for (int k = 0; k < f->n; k++) {
        out[k] = 0.0;
        if (!f->e[k]) continue;
        if (!sph_expression_eval(f->e[k], values, &out[k], why, size)) {
            *bad = k;
            return false;
        }
        if (!allow_nonfinite && !isfinite(out[k])) {
            /* "nan", not printf's "-nan": the sign of a NaN means nothing */
            snprintf(why, size, "gives %s", isnan(out[k]) ? "nan" : out[k] > 0 ? "inf" : "-inf");
            *bad = k;
            return false;
        }
    }
    return true;
}

void sph_expression_field_free(sph_expression_field *f) {
    for (int k = 0; k < SPH_EXPRESSION_FIELD_MAX; k++) sph_expression_free(f->e[k]);
    memset(f, 0, sizeof *f);
}
