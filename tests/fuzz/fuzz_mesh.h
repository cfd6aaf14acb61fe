/* fuzz_mesh.h — one fuzz input through the mesh reader (host/setup/mesh.c,
 * tests/fuzz/fuzz_mesh.c).
 *
 * An input is bytes: the first byte's low bit chooses the format the bytes
 * are read as (0: STL, ASCII or binary; 1: OBJ), the rest is the file.
 *
 * The same entry point runs under libFuzzer (fuzz_mesh) and in the normal
 * test build (test_mesh_corpus replays tests/fuzz/mesh_corpus). */
#ifndef SPH_FUZZ_MESH_H
#define SPH_FUZZ_MESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    bool accepted;       /* the reader took the mesh */
    int triangles;       /* its triangles when accepted */
    char why[512];       /* the reader's reason when refused */
    char violation[512]; /* "" or the broken invariant (see fuzz_mesh.c) */
} fuzz_mesh_result;

void fuzz_mesh_run(const uint8_t *data, size_t size, fuzz_mesh_result *res);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#endif
