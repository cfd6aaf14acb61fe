/* corpus_replay.h — what the corpus tests share: every file of a fuzzing
 * corpus directory (relative to SPHSOLID_SOURCE_DIR), in name order, handed
 * to a fuzz harness's entry point without libFuzzer (test_scene_corpus,
 * test_writers_corpus). */
#ifndef SPH_CORPUS_REPLAY_H
#define SPH_CORPUS_REPLAY_H

#include "test_util.h"

#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>

/* One input: its file name, path and bytes. */
typedef void (*corpus_input_fn)(test_counts *c, const char *name, const char *path,
                                const uint8_t *data, size_t size);

static int corpus_compare_names(const void *a, const void *b) {
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

static uint8_t *corpus_read_file(const char *path, size_t *size) {
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
static int corpus_replay_dir(test_counts *c, const char *rel, corpus_input_fn each) {
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
    qsort(names, (size_t)n, sizeof names[0], corpus_compare_names);
    for (int i = 0; i < n; i++) {
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        size_t size = 0;
        uint8_t *data = corpus_read_file(path, &size);
        CHECK(c, data != NULL, "cannot read %s", path);
        if (data) {
            each(c, names[i], path, data, size);
            free(data);
        }
        free(names[i]);
    }
    return n;
}

#endif
