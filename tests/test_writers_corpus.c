/* test_writers_corpus — replay the writers' fuzzing seed corpus
 * (tests/fuzz/writers_corpus) through the harness's entry point
 * (tests/fuzz/fuzz_writers.c), without libFuzzer, in the normal build: each
 * input must keep the harness's invariants (timeseries.csv read back by
 * `sphsolid compare` column for column, or the names refused by the scene's
 * rule; summary.json valid UTF-8 JSON).  A few inputs written here also pin
 * down which way they go, so that a harness that checks nothing fails. */
#include "fuzz_writers.h"
#include "corpus_replay.h"

/* One corpus input: the harness's invariants hold. */
static void replay_writers(test_counts *c, const char *name, const char *path, const uint8_t *data,
                           size_t size) {
    (void)name;
    fuzz_writers_result res;
    fuzz_writers_run(data, size, &res);
    CHECK(c, res.violation[0] == '\0', "%s: %s", path, res.violation);
}

/* One input given as text with embedded NULs (`size` bytes). */
static fuzz_writers_result run(const char *data, size_t size) {
    fuzz_writers_result res;
    fuzz_writers_run((const uint8_t *)data, size, &res);
    return res;
}

int main(void) {
    test_counts c = {0, 0};
    /* 2D, 3 rows; title, path, observers "tip" and "base": written */
    static const char ok[] = "\x06title\0scene.cfg\0tip\0base";
    fuzz_writers_result r = run(ok, sizeof ok - 1);
    CHECK(&c,
          !r.violation[0] && r.nobservers == 2 && r.names_valid && r.csv_written &&
              r.json_strings >= 5,
          "plain names: %s (%d observers, written %d, %d strings)", r.violation, r.nobservers,
          (int)r.csv_written, r.json_strings);
    /* an observer "ti,p" (issue 34, item 4): refused */
    static const char comma[] = "\x07t\0p\0ti,p";
    r = run(comma, sizeof comma - 1);
    CHECK(&c, !r.violation[0] && !r.names_valid && !r.csv_written, "'ti,p': %s", r.violation);
    /* "momentum": valid, but its columns repeat momentum_x, momentum_y */
    static const char reserved[] = "\x02t\0p\0momentum";
    r = run(reserved, sizeof reserved - 1);
    CHECK(&c, !r.violation[0] && r.names_valid && !r.csv_written, "'momentum': %s", r.violation);
    /* bytes that are not UTF-8 in the title and the path (item 5) */
    static const char bytes[] = "\x02\xff\xfe title \xed\xa0\x80\0path \xc0\xaf\xe2\x82";
    r = run(bytes, sizeof bytes - 1);
    CHECK(&c, !r.violation[0] && r.json_strings >= 4, "not UTF-8: %s", r.violation);

    const int ncorpus = corpus_replay_dir(&c, "tests/fuzz/writers_corpus", replay_writers);
    CHECK(&c, ncorpus >= 5, "only %d corpus inputs", ncorpus);
    printf("replayed %d corpus inputs\n", ncorpus);
    return test_summary("test_writers_corpus", &c);
}
