/* test_util.h — a minimal test harness: CHECK macros that count and report,
 * and a summary line "N passed, M failed" whose failure count is the exit
 * status.  Numbers in checks come from the papers, analytical solutions or
 * documented runs; each check says which. */
#ifndef SPH_TEST_UTIL_H
#define SPH_TEST_UTIL_H

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct {
    int passed, failed;
} test_counts;

#define CHECK(counts, cond, ...)                                                                   \
    do {                                                                                           \
        if (cond) {                                                                                \
            (counts)->passed++;                                                                    \
        } else {                                                                                   \
            (counts)->failed++;                                                                    \
            fprintf(stderr, "%s:%d: CHECK(%s) failed: ", __FILE__, __LINE__, #cond);               \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fputc('\n', stderr);                                                                   \
        }                                                                                          \
    } while (0)

/* |actual - expected| <= tol */
#define CHECK_NEAR(counts, actual, expected, tol, what)                                            \
    CHECK(counts, fabs((double)(actual) - (double)(expected)) <= (tol),                            \
          "%s: got %.10g, expected %.10g +- %.3g", what, (double)(actual), (double)(expected),     \
          (double)(tol))

/* lo <= actual <= hi */
#define CHECK_RANGE(counts, actual, lo, hi, what)                                                  \
    CHECK(counts, (double)(actual) >= (lo) && (double)(actual) <= (hi),                            \
          "%s: got %.10g, expected in [%.6g, %.6g]", what, (double)(actual), (double)(lo),         \
          (double)(hi))

static inline int test_summary(const char *name, const test_counts *c) {
    printf("%s: %d passed, %d failed\n", name, c->passed, c->failed);
    return c->failed > 0 ? 1 : 0;
}

#endif
