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
#include "test_util.h"

#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>

static int compare_names(const void *a, const void *b) {
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

static uint8_t *read_file(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, len = 0;
    uint8_t *buf = malloc(cap);
    for (size_t got; buf && (got = fread(buf + len, 1, cap - len, f)) > 0;) {
        len += got;
        if (len == cap) {
            uint8_t *grown = realloc(buf, cap *= 2);
            if (!grown) free(buf);
            buf = grown;
        }
    }
    fclose(f);
    *size = len;
    return buf;
}

/* Replay every file of one directory (in name order); returns the count. */
static int replay_dir(test_counts *c, const char *rel) {
    const char *src = getenv("SPHSOLID_SOURCE_DIR");
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/%s", src ? src : ".", rel);
    DIR *d = opendir(dir);
    CHECK(c, d != NULL, "cannot open %s", dir);
    if (!d) return 0;
    char *names[1024];
    int n = 0;
    for (struct dirent *e; (e = readdir(d)) && n < 1024;)
        if (e->d_name[0] != '.') names[n++] = strdup(e->d_name);
    closedir(d);
    qsort(names, (size_t)n, sizeof names[0], compare_names);

    for (int i = 0; i < n; i++) {
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        size_t size = 0;
        uint8_t *data = read_file(path, &size);
        CHECK(c, data != NULL, "cannot read %s", path);
        if (data) {
            /* the origin names the file, as the CLI names a scene path */
            fuzz_scene_result res;
            fuzz_scene_run(data, size, names[i], &res);
            CHECK(c, res.violation[0] == '\0', "%s: %s", path, res.violation);
            CHECK(c, res.skipped || res.load == SPH_OK || res.load == SPH_ERR_INPUT,
                  "%s: status %d", path, (int)res.load);
            if (strncmp(names[i], "case_", 5) == 0 || strncmp(names[i], "valid_", 6) == 0)
                CHECK(c, res.load == SPH_OK && res.generated && res.particles == SPH_OK,
                      "%s: a valid scene: %s", path, res.err.msg);
            free(data);
        }
        free(names[i]);
    }
    return n;
}

int main(void) {
    test_counts c = {0, 0};
    int ncorpus = replay_dir(&c, "tests/fuzz/corpus");
    int nregressions = replay_dir(&c, "tests/fuzz/regressions");
    CHECK(&c, ncorpus >= 20, "only %d corpus inputs", ncorpus);
    CHECK(&c, nregressions >= 1, "no regression inputs");
    printf("replayed %d corpus and %d regression inputs\n", ncorpus, nregressions);
    return test_summary("test_scene_corpus", &c);
}
