/* compare.h — cross-check two run directories (`sphsolid compare RUN_A RUN_B`).
 *
 * Compares timeseries.csv row by row and column by column, and the snapshots
 * listed in snapshots.hdf.series matched by time: /VTKHDF/Points and every
 * point-data field present in both (row k = particle id k, see
 * docs/output-format.md).  A field or column fails when
 *     max |a - b| > atol + rtol * scale,
 * scale = the largest finite |value| of that field in both runs (per snapshot
 * for point data, over the compared rows for a time-series column), and for
 * the momentum, angular momentum and energy columns at least the physical
 * scale each run states in summary.json "scales" (the larger of the two): a
 * quantity that is zero in theory (the linear momentum of a spinning plate,
 * |p| ~ 1e-11 against sum m |v| ~ 2e4) differs between two correct runs by
 * round-off of that scale, not of its own size.
 * Structural differences (row or particle counts) are failures too; a column,
 * field or snapshot present in only one run is reported but is not one.
 * An incomplete run (killed or still running: no summary.json, only
 * timeseries.csv.partial) fails the comparison, what both runs have still
 * compared and reported, unless common_prefix asks for the part both runs
 * have (then row counts may differ too).  A run the instability monitor
 * stopped (status "unstable") is complete: it is noted.
 */
#ifndef SPH_COMPARE_H
#define SPH_COMPARE_H

#include "sph_error.h"

#include <stdbool.h>
#include <stdio.h>

/* Exit status of `sphsolid compare` when a difference exceeds the tolerance
 * or a run is incomplete (0, 1 and 2 keep their usual meaning). */
#define SPH_COMPARE_DIFFERS 3

typedef struct {
    double rtol;               /* relative tolerance, default 1e-9 */
    double atol;               /* absolute tolerance, default 0 */
    const char *const *fields; /* point-data fields to compare ("Points" too); NULL: all in both */
    int nfields;
    bool common_prefix; /* --common-prefix: an incomplete run is no failure */
} sph_compare_options;

/* The physical scales of summary.json "scales" (docs/output-format.md). */
enum {
    SPH_COMPARE_SCALE_MOMENTUM,
    SPH_COMPARE_SCALE_ANGULAR_MOMENTUM,
    SPH_COMPARE_SCALE_ENERGY,
    SPH_COMPARE_NSCALES
};

typedef enum {
    SPH_COMPARE_COLUMN, /* a timeseries.csv column */
    SPH_COMPARE_FIELD,  /* /VTKHDF/Points or a /VTKHDF/PointData dataset */
} sph_compare_kind;

/* One difference and where it occurs. */
typedef struct {
    double abs;    /* |a - b| (inf when exactly one of them is NaN) */
    double rel;    /* abs / scale; 0 when abs is 0 */
    double scale;  /* the scale the tolerance is relative to */
    double time;   /* time of the row or snapshot */
    long particle; /* particle id (fields only) */
    int component; /* component of a vector/tensor field (fields only) */
} sph_compare_where;

typedef struct {
    char name[128];
    sph_compare_kind kind;
    int ncompared;         /* rows (columns) or snapshots (fields) compared */
    sph_compare_where max; /* the largest |a - b| */
    bool failed;
    /* the worst violation of the tolerance, by abs / (atol + rtol * scale);
     * differs from `max` when a field fails in a snapshot of smaller scale */
    sph_compare_where worst;
    double worst_excess;
    /* SPH_COMPARE_SCALE_* when a physical scale larger than the values was
     * used (a time-series column), else -1 */
    int physical_scale;
} sph_compare_item;

/* Something reported besides the table: a column, field or snapshot in only
 * one run (failure = false), or a count mismatch (failure = true). */
typedef struct {
    char text[512];
    bool failure;
} sph_compare_note;

typedef struct {
    sph_compare_item *items;
    int nitems, items_cap;
    sph_compare_note *notes;
    int nnotes, notes_cap;
    int nrows;           /* time-series rows compared */
    int nsnapshots;      /* snapshot pairs compared */
    double time_tol;     /* tolerance used to match times */
    bool has_timeseries; /* both runs have timeseries.csv */
    bool has_snapshots;  /* both runs have snapshots */
    bool failed;         /* an item out of tolerance or a failure note */
    /* the physical scales applied to the time-series columns: the larger of
     * the two runs' summary.json "scales" (NaN: neither run states it) */
    double scales[SPH_COMPARE_NSCALES];
    /* "run B (DIR) is incomplete: ..." when a run is, else "" */
    char incomplete[1024];
} sph_compare_result;

void sph_compare_options_default(sph_compare_options *opt);

/* Compare two run directories into `res` (free with sph_compare_result_free,
 * also after an error).  Returns SPH_ERR_INPUT for a missing or empty run
 * directory, unknown --fields or runs that share nothing comparable, and
 * SPH_ERR_RUNTIME for an unreadable file; differences are not errors, they
 * are in `res`. */
sph_status sph_compare_runs(const char *dir_a, const char *dir_b, const sph_compare_options *opt,
                            sph_compare_result *res, sph_error *err);
void sph_compare_result_free(sph_compare_result *res);

/* The report: one line per column and field, the notes and the final
 * `compare: PASS ...` / `compare: FAIL: ...` line. */
void sph_compare_print(FILE *f, const char *dir_a, const char *dir_b,
                       const sph_compare_options *opt, const sph_compare_result *res);

/* `sphsolid compare` with argv after the word "compare": prints the report on
 * stdout and errors on stderr; returns the exit status (0 within tolerance,
 * SPH_COMPARE_DIFFERS also for an incomplete run without --common-prefix,
 * SPH_ERR_INPUT or SPH_ERR_RUNTIME). */
int sph_compare_main(int argc, char **argv);

#endif
