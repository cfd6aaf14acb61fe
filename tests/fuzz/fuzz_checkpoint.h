/* fuzz_checkpoint.h — one fuzz input through the checkpoint reader
 * (tests/fuzz/fuzz_checkpoint.c): a valid checkpoint of a small fluid scene
 * with a wall body and a far field, edited as the input says, then read as
 * a restart reads it (sph_checkpoint_read_info, sph_checkpoint_read).
 *
 * An input is a list of edits of FUZZ_CHECKPOINT_EDIT_BYTES bytes each (a
 * trailing partial edit is ignored, at most FUZZ_CHECKPOINT_MAX_EDITS):
 *   byte 0     the target (FUZZ_TARGET_*): an attribute of the file or one
 *              of its datasets (the series, the carried state, the
 *              snapshot times, each field), modulo their number;
 *   byte 1     bits 0-1, the operation (FUZZ_EDIT_*): 0 set one value,
 *              1 resize the dataset (or rewrite the attribute) holding
 *              `index` values of the one given, 2 delete it, 3 rewrite it
 *              as a string; bits 2-3, how the value is read (FUZZ_VALUE_*):
 *              0 the eight bytes as a double
 *              (an integer target: as an int64), 1 the value there times
 *              (1 + int8 / 16), 2 the int8 itself, 3 a special value
 *              (NaN, +-Inf, -0, the largest and smallest doubles, INT64
 *              extremes) chosen by the int8;
 *   bytes 2-3  the index (little endian), modulo the dataset's length when
 *              setting one value;
 *   bytes 4-11 the value (the int8 is byte 4).
 *
 * The same entry point runs under libFuzzer (fuzz_checkpoint) and in the
 * normal test build (test_checkpoint_corpus replays
 * tests/fuzz/checkpoint_corpus). */
#ifndef SPH_FUZZ_CHECKPOINT_H
#define SPH_FUZZ_CHECKPOINT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define FUZZ_CHECKPOINT_EDIT_BYTES 12
#define FUZZ_CHECKPOINT_MAX_EDITS  16

/* byte 1, bits 0-1: the operation */
enum { FUZZ_EDIT_SET, FUZZ_EDIT_RESIZE, FUZZ_EDIT_DELETE, FUZZ_EDIT_STRING };
/* byte 1, bits 2-3: how the value is read */
enum { FUZZ_VALUE_RAW, FUZZ_VALUE_SCALE, FUZZ_VALUE_SMALL, FUZZ_VALUE_SPECIAL };
/* byte 0: the targets, the attributes first, then the datasets, then the
 * stored fields in the registry's order (fuzz_checkpoint.c) */
enum {
    FUZZ_TARGET_FORMAT,
    FUZZ_TARGET_PARTICLES,
    FUZZ_TARGET_OUTPUT_INDEX,
    FUZZ_TARGET_ACOUSTIC_STEPS,
    FUZZ_TARGET_ADVECTION_STEPS,
    FUZZ_TARGET_SNAPSHOT_COUNT,
    FUZZ_TARGET_TIME,
    FUZZ_TARGET_MAX_SPEED2,
    FUZZ_TARGET_CHECKPOINT_EVERY,
    FUZZ_TARGET_CHECKPOINT_WALL,
    FUZZ_TARGET_BACKEND,
    FUZZ_TARGET_PRECISION,
    FUZZ_TARGET_ATTRIBUTES, /* the number of attribute targets */
    FUZZ_TARGET_CARRIED = FUZZ_TARGET_ATTRIBUTES,
    FUZZ_TARGET_SNAPSHOT_TIMES,
    FUZZ_TARGET_SERIES_TIME,
    FUZZ_TARGET_SERIES_DIAGNOSTICS,
    FUZZ_TARGET_SERIES_FLUID,
    FUZZ_TARGET_FIRST_FIELD /* then the fields */
};

typedef struct {
    int edits;           /* edits applied */
    bool accepted;       /* the reader accepted the edited checkpoint */
    char message[1024];  /* the reader's error, when it refused */
    char violation[512]; /* "" or the broken invariant (see fuzz_checkpoint.c) */
} fuzz_checkpoint_result;

/* Run one input; the checkpoint lives in a directory under $TMPDIR (or
 * /tmp), made once per process and removed at exit. */
void fuzz_checkpoint_run(const uint8_t *data, size_t size, fuzz_checkpoint_result *res);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#endif
