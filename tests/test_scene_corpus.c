/* test_scene_corpus — replay the fuzzing seed corpus and every input the
 * fuzzer ever failed on (tests/fuzz/corpus, tests/fuzz/regressions) through
 * the fuzz harness's entry point, without libFuzzer, in the normal build.
 *
 * Each input must load or fail with SPH_ERR_INPUT and a message that names
 * the input file (or the `--set` override), and keep the harness's
 * invariants (tests/fuzz/fuzz_scene.c); under the sanitizer build also
 * without leaks or undefined behaviour.  The shipped cases, copied into the
 * corpus, must also load. */
#include "fuzz_scene.h"
#include "corpus_replay.h"

/* One input: loads or fails as an input error naming it, keeping the
 * harness's invariants. */
static void replay_scene(test_counts *c, const char *name, const char *path, const uint8_t *data,
                         size_t size) {
    /* the origin names the file, as the CLI names a scene path */
    fuzz_scene_result res;
    fuzz_scene_run(data, size, name, &res);
    CHECK(c, res.violation[0] == '\0', "%s: %s", path, res.violation);
    CHECK(c, res.skipped || res.load == SPH_OK || res.load == SPH_ERR_INPUT, "%s: status %d", path,
          (int)res.load);
    if (strncmp(name, "case_", 5) == 0 || strncmp(name, "valid_", 6) == 0)
        CHECK(c, res.load == SPH_OK && res.generated && res.particles == SPH_OK,
              "%s: a valid scene: %s", path, res.err.msg);
}

int main(void) {
    test_counts c = {0, 0};
    int ncorpus = corpus_replay_dir(&c, "tests/fuzz/corpus", replay_scene);
    int nregressions = corpus_replay_dir(&c, "tests/fuzz/regressions", replay_scene);
    CHECK(&c, ncorpus >= 20, "only %d corpus inputs", ncorpus);
    CHECK(&c, nregressions >= 1, "no regression inputs");
    printf("replayed %d corpus and %d regression inputs\n", ncorpus, nregressions);
    return test_summary("test_scene_corpus", &c);
}
