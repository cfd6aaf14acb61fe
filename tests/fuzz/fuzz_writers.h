/* fuzz_writers.h — one fuzz input through the writers of a run directory
 * (tests/fuzz/fuzz_writers.c): timeseries.csv (sph_output_open/row/close)
 * and the strings of summary.json (sph_json_string, sph_output_write_json),
 * read back by `sphsolid compare`'s readers (sph_compare_runs) and by
 * json-c's parser.
 *
 * An input is bytes: the first byte chooses the dimension (bit 0: 2 or 3)
 * and the number of rows (bits 1-2: 0 to 3); the rest is fields separated
 * by NUL bytes: the title, the scene path, then up to
 * SPH_SCENE_MAX_OBSERVERS observer names (each cut to SPH_NAME_LEN - 1
 * bytes); every field, and the whole input with its NUL bytes, also goes
 * into summary.json as a string.
 *
 * The same entry point runs under libFuzzer (fuzz_writers) and in the normal
 * test build (test_writers_corpus replays tests/fuzz/writers_corpus). */
#ifndef SPH_FUZZ_WRITERS_H
#define SPH_FUZZ_WRITERS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    int nobservers;
    bool names_valid;    /* every observer name passes sph_name_check */
    bool csv_written;    /* the writer accepted the names */
    int json_strings;    /* strings checked in summary.json */
    char violation[512]; /* "" or the broken invariant (see fuzz_writers.c) */
} fuzz_writers_result;

/* Run one input; files go to a new directory under $TMPDIR (or /tmp),
 * removed afterwards. */
void fuzz_writers_run(const uint8_t *data, size_t size, fuzz_writers_result *res);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#endif
