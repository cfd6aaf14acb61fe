/* expression.h — scalar expressions of named variables (initial fields).
 *
 * A thin owner of muParser's C interface (muParserDLL.h, Debian
 * libmuparser-dev): an expression is compiled once over a fixed list of
 * variables (x, y, z for an initial field) and named constants (the scene's
 * `constants` group), then evaluated point by point.  muParser was chosen
 * over GNU libmatheval because the fluid cases' initial states are
 * piecewise (Shu-Osher: `x <= 1 ? ... : ...`) and muParser has comparisons,
 * && / || and the ternary operator; libmatheval has only step(), its flex
 * parser keeps global state, and an unknown variable evaluates to an
 * undetermined value instead of an error (docs/scene-format.md, "Initial
 * fields as expressions").
 *
 * Every expression knows `pi` (and muParser's `_pi`, redefined): the double
 * nearest pi, where muParser 2.3.3's `_pi` has 13 digits only.
 *
 * What reaches the library is bounded: at most SPH_EXPRESSION_MAX_LEN - 1
 * printable ASCII characters, no assignment '=' (muParser's `x = 3` would
 * write into the variable), one result (no `a, b` lists).  Every failure is
 * a false return with one line in `why`; nothing is printed.  Handles are
 * independent (no shared state), one owner each.
 */
#ifndef SPH_EXPRESSION_H
#define SPH_EXPRESSION_H

#include <stdbool.h>
#include <stddef.h>

#define SPH_EXPRESSION_MAX_LEN  1024 /* characters of an expression, with the NUL */
#define SPH_EXPRESSION_MAX_VARS 4    /* variables of one expression (x, y, z, t) */

typedef struct sph_expression sph_expression; /* opaque, owns a muParser handle */

/* Named constants usable in an expression, `n` names and values. */
typedef struct {
    int n;
    const char *const *names;
    const double *values;
} sph_expression_constants;

/* Compile `text` over the variables `vars[0 .. nvars)` (values given at each
 * evaluation, in this order) and the constants.  False, with `*out` NULL and
 * the reason in `why` ("unknown variable 'q' (variables: x, y; constants:
 * U)", "Unexpected end of expression at position 5"), when the text is too
 * long, has characters outside printable ASCII, does not parse, assigns, has
 * several results or names a variable that is neither given nor a constant.
 * On success `*out` is owned by the caller (sph_expression_free). */
bool sph_expression_compile(const char *text, const char *const *vars, int nvars,
                            const sph_expression_constants *constants, sph_expression **out,
                            char *why, size_t size);
/* The value at `values` (one per variable).  False, with the library's
 * message in `why`, if the library reports an error; a non-finite value
 * (1/0, sqrt(-1)) is a true return: the caller decides what it means. */
bool sph_expression_eval(sph_expression *e, const double *values, double *result, char *why,
                         size_t size);
void sph_expression_free(sph_expression *e);

/* Whether `name` may name a constant next to the variables `vars`: a
 * letter, then letters, digits or '_' (muParser's identifiers), at most
 * 63 characters, not one of `vars` and not a name the library already
 * knows (sin, max, ...).  False with the reason in `why`. */
bool sph_expression_name_check(const char *name, const char *const *vars, int nvars, char *why,
                               size_t size);

/* A field of named expressions over the same variables, for initial fields
 * (the components x, y, z of a velocity; later density and pressure):
 * compiled together, evaluated together at one point. */
#define SPH_EXPRESSION_FIELD_MAX 8
typedef struct {
    int n;
    sph_expression *e[SPH_EXPRESSION_FIELD_MAX]; /* NULL: the entry is 0 everywhere */
} sph_expression_field;

/* Compile texts[k] for k < n ("" or NULL: zero everywhere).  False with the
 * failing entry in `*bad` and the reason in `why`; nothing stays allocated. */
bool sph_expression_field_compile(sph_expression_field *f, const char *const *texts, int n,
                                  const char *const *vars, int nvars,
                                  const sph_expression_constants *constants, int *bad, char *why,
                                  size_t size);
/* out[k] for k < f->n at `values`.  False with the failing entry in `*bad`:
 * a library error (reason in `why`) or, unless allow_nonfinite, a value that
 * is not finite (`why`: "gives nan"). */
bool sph_expression_field_eval(sph_expression_field *f, const double *values, bool allow_nonfinite,
                               double *out, int *bad, char *why, size_t size);
void sph_expression_field_free(sph_expression_field *f);

#endif
