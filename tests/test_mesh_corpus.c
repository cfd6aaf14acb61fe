/* test_mesh_corpus — replay the mesh reader's fuzzing seed corpus
 * (tests/fuzz/mesh_corpus) and its regressions (tests/fuzz/mesh_regressions) through the harness's
 * entry point (tests/fuzz/fuzz_mesh.c), without libFuzzer, in the normal build: each input must
 * keep the harness's invariants.  The seeds also pin down which way they go (the cube in each
 * format accepted with 12 triangles, the bad ones refused with their reason), so that a harness
 * that checks nothing fails. */
#include "corpus_replay.h"
#include "fuzz_mesh.h"

static void replay_mesh(test_counts *c, const char *name, const char *path, const uint8_t *data,
                        size_t size) {
    fuzz_mesh_result res;
    fuzz_mesh_run(data, size, &res);
    CHECK(c, res.violation[0] == '\0', "%s: %s", path, res.violation);
    if (strncmp(name, "cube", 4) == 0)
        CHECK(c, res.accepted && res.triangles == 12, "%s: accepted %d, %d triangles (%s)", path,
              (int)res.accepted, res.triangles, res.why);
    static const struct {
        const char *name, *why;
    } refused[] = {{"open.stl", "is not closed: 3 boundary edges"},
                   {"inside_out.stl", "is inside out"},
                   {"flipped.obj", "has inverted triangles"},
                   {"garbage", "cannot read it as a mesh"},
                   {"self_intersecting_cube", "intersects itself: "}};
    for (size_t k = 0; k < sizeof refused / sizeof refused[0]; k++)
        if (strcmp(name, refused[k].name) == 0)
            CHECK(c, !res.accepted && strstr(res.why, refused[k].why) != NULL,
                  "%s: expected '%s', got '%s'", path, refused[k].why, res.why);
}

int main(void) {
    test_counts c = {0, 0};
    const int n = corpus_replay_dir(&c, "tests/fuzz/mesh_corpus", replay_mesh);
    CHECK(&c, n >= 7, "only %d corpus inputs", n);
    /* inputs the fuzzer found trouble with (assimp's leaks: tests/fuzz/lsan.supp) */
    const int r = corpus_replay_dir(&c, "tests/fuzz/mesh_regressions", replay_mesh);
    CHECK(&c, r >= 1, "only %d regression inputs", r);
    printf("replayed %d corpus and %d regression inputs\n", n, r);
    return test_summary("test_mesh_corpus", &c);
}
