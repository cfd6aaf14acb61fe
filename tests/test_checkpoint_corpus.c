/* test_checkpoint_corpus — replay the checkpoint reader's fuzzing seed corpus
 * (tests/fuzz/checkpoint_corpus) through the harness's entry point
 * (tests/fuzz/fuzz_checkpoint.c), without libFuzzer, in the normal build:
 * each edited checkpoint is refused as an input error naming the file, or
 * accepted with the state a restart may start from.  A few inputs written
 * here also pin down which way they go and why, so that a harness (or a
 * reader) that checks nothing fails. */
#include "fuzz_checkpoint.h"
#include "corpus_replay.h"

/* One corpus input: the harness's invariants hold. */
static void replay_checkpoint(test_counts *c, const char *name, const char *path,
                              const uint8_t *data, size_t size) {
    (void)name;
    fuzz_checkpoint_result res;
    fuzz_checkpoint_run(data, size, &res);
    CHECK(c, res.violation[0] == '\0', "%s: %s", path, res.violation);
}

/* One edit (fuzz_checkpoint.h): target, operation | mode << 2, index, int8. */
static fuzz_checkpoint_result run_edit(int target, int op, int mode, int index, int8_t small) {
    uint8_t e[FUZZ_CHECKPOINT_EDIT_BYTES] = {(uint8_t)target, (uint8_t)(op | mode << 2),
                                             (uint8_t)(index & 0xff), (uint8_t)(index >> 8),
                                             (uint8_t)small};
    fuzz_checkpoint_result res;
    fuzz_checkpoint_run(e, sizeof e, &res);
    return res;
}

/* refused, keeping the invariants, with `needle` in the message */
static void expect_refused(test_counts *c, const char *what, fuzz_checkpoint_result r,
                           const char *needle) {
    CHECK(c, !r.violation[0] && r.edits == 1 && !r.accepted && strstr(r.message, needle),
          "%s: refused naming '%s' (violation '%s', accepted %d, message '%s')", what, needle,
          r.violation, (int)r.accepted, r.message);
}

int main(void) {
    test_counts c = {0, 0};
    fuzz_checkpoint_result r;
    fuzz_checkpoint_run(NULL, 0, &r);
    CHECK(&c, !r.violation[0] && r.accepted, "the unedited checkpoint: accepted (%s%s)",
          r.violation, r.message);
    /* the value it has, rewritten (times 1 + 0/16): still accepted */
    r = run_edit(FUZZ_TARGET_TIME, FUZZ_EDIT_SET, FUZZ_VALUE_SCALE, 0, 0);
    CHECK(&c, !r.violation[0] && r.accepted, "the time rewritten as it was: accepted (%s%s)",
          r.violation, r.message);
    expect_refused(&c, "a NaN time",
                   run_edit(FUZZ_TARGET_TIME, FUZZ_EDIT_SET, FUZZ_VALUE_SPECIAL, 0, 0),
                   "attribute 'time' is nan");
    expect_refused(&c, "negative steps",
                   run_edit(FUZZ_TARGET_ACOUSTIC_STEPS, FUZZ_EDIT_SET, FUZZ_VALUE_SMALL, 0, -3),
                   "'acoustic_steps' -3");
    expect_refused(&c, "a huge snapshot count",
                   run_edit(FUZZ_TARGET_SNAPSHOT_COUNT, FUZZ_EDIT_SET, FUZZ_VALUE_SPECIAL, 0, 2),
                   "'snapshot_count'");
    /* an attribute of three values where one is read overran the reader's
     * int64 before the check */
    expect_refused(&c, "output_index as three values",
                   run_edit(FUZZ_TARGET_OUTPUT_INDEX, FUZZ_EDIT_RESIZE, FUZZ_VALUE_SMALL, 3, 6),
                   "attribute 'output_index' holds 3 values, not one");
    expect_refused(&c, "a series shorter than the outputs",
                   run_edit(FUZZ_TARGET_SERIES_TIME, FUZZ_EDIT_RESIZE, FUZZ_VALUE_SMALL, 2, 0),
                   "dataset 'series_time' has 2 rows, attribute 'output_index' 6");
    expect_refused(&c, "a NaN in the carried state",
                   run_edit(FUZZ_TARGET_CARRIED, FUZZ_EDIT_SET, FUZZ_VALUE_SPECIAL, 0, 0),
                   "dataset 'carried'[0] is nan");
    expect_refused(&c, "the carried state as a string",
                   run_edit(FUZZ_TARGET_CARRIED, FUZZ_EDIT_STRING, FUZZ_VALUE_RAW, 0, 0),
                   "carried");

    const int ncorpus = corpus_replay_dir(&c, "tests/fuzz/checkpoint_corpus", replay_checkpoint);
    CHECK(&c, ncorpus >= 5, "only %d corpus inputs", ncorpus);
    printf("replayed %d corpus inputs\n", ncorpus);
    return test_summary("test_checkpoint_corpus", &c);
}
