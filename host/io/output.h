/* output.h — the files of a run directory.
 *
 * Every file is written under a temporary name and renamed only when it is
 * complete, and a new run first removes the previous run's results from the
 * directory: an interrupted or failed run never leaves a file that looks like
 * a valid result (timeseries.csv.partial stays for inspection).  Write errors
 * (disk full, permissions) are runtime errors naming the file.
 */
#ifndef SPH_OUTPUT_H
#define SPH_OUTPUT_H

#include "analysis.h"
#include "backend.h"
#include "scene.h"

#include <json-c/json.h>
#include <stdbool.h>
#include <stdio.h>

typedef struct {
    char dir[1024];
    char csv_partial[1100], csv_final[1100];
    FILE *csv;
    int dim, nobservers;
    bool fluid;             /* the fluid columns (internal energy, mass; no monitor columns) */
    bool forces;            /* fluids with `forces`: C_D, C_L and the wall forces */
    const sph_scene *scene; /* the reference values of the coefficients */
} sph_output;

/* Create `dir` and its parents (exit-1 messages naming the path that could
 * not be made; a path that is not a directory is refused).  The run's
 * directory lock (run.c) is taken in it before sph_output_open clears it. */
sph_status sph_output_make_dirs(const char *dir, sph_error *err);

/* Create the directory (with parents), clear old results, start the CSV.
 * A fresh run (`resumed` NULL) also removes an old checkpoint; a restart
 * writes the rows recorded before its checkpoint first. */
sph_status sph_output_open(sph_output *out, const char *dir, const sph_scene *scene,
                           const sph_timeseries *resumed, sph_error *err);
sph_status sph_output_row(sph_output *out, double t, const sph_diagnostics *d,
                          const double *observers, sph_error *err);
/* Close the CSV; on success rename it to timeseries.csv.  A failed run
 * (`success` false, or a failure here) leaves no result that looks complete:
 * timeseries.csv, the snapshots and their .series index get the suffix
 * .partial (the checkpoint stays: it is where a restart continues). */
sph_status sph_output_close(sph_output *out, bool success, sph_error *err);
/* Write `name` in `dir` through `name.partial` and rename.  A summary.json
 * that cannot be written fails the run: its results are marked .partial as
 * in sph_output_close. */
sph_status sph_output_write_json(const char *dir, const char *name, json_object *obj,
                                 sph_error *err);

/* A JSON string of any bytes: every string that goes into summary.json (and
 * the snapshots' "parameters") is made through these.  json-c writes a
 * string's bytes as they are, and a title, a path or an override may hold
 * any bytes: here each ill-formed UTF-8 subsequence (a stray byte, a
 * truncated or overlong sequence, a surrogate, beyond U+10FFFF) becomes
 * U+FFFD, one per maximal subpart as Unicode recommends (what Python's
 * bytes.decode("utf-8", "replace") gives), so the file is valid UTF-8 JSON
 * (docs/output-format.md).  NULL `s` is "". */
json_object *sph_json_string(const char *s);
json_object *sph_json_string_len(const char *s, size_t len);
/* The same as text: `s` (len bytes) as valid UTF-8 into a new NUL-terminated
 * string of *out_len bytes (at most 3 * len: NUL bytes of `s` are kept);
 * NULL when out of memory. */
char *sph_utf8_repair(const char *s, size_t len, size_t *out_len);

#endif
