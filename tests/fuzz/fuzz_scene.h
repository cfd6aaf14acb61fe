/* fuzz_scene.h — one fuzz input through the scene loader, the validator and
 * the particle generator (tests/fuzz/fuzz_scene.c).
 *
 * An input is scene text in libconfig syntax.  Lines that begin with "#set "
 * also carry an override: the rest of the line is passed as a `--set
 * key=value` (at most FUZZ_SCENE_MAX_OVERRIDES of them, in order).  Since `#`
 * starts a comment, every input is also a scene file that `sphsolid run
 * --set ...` reads the same way.  Inputs containing "@include" are skipped:
 * libconfig would read files from the working directory.
 *
 * The same entry point runs under libFuzzer (fuzz_scene) and in the normal
 * test build (test_scene_corpus replays tests/fuzz/corpus and
 * tests/fuzz/regressions). */
#ifndef SPH_FUZZ_SCENE_H
#define SPH_FUZZ_SCENE_H

#include "sph_error.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define FUZZ_SCENE_MAX_OVERRIDES 8
/* Scenes whose bodies' bounding boxes hold more lattice points than this are
 * validated but not turned into particles (keeps one input well under 1 ms). */
#define FUZZ_SCENE_PARTICLE_BUDGET 20000

typedef struct {
    bool skipped;    /* the input contains "@include" */
    sph_status load; /* sph_scene_load_text */
    bool generated;  /* sph_particles_generate ran (within the budget) */
    sph_status particles;
    int nparticles;
    sph_error err;       /* the first failure's message */
    char violation[256]; /* "" or the broken invariant (see fuzz_scene.c) */
} fuzz_scene_result;

/* Run one input; `origin` names it in the loader's messages. */
void fuzz_scene_run(const uint8_t *data, size_t size, const char *origin, fuzz_scene_result *res);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#endif
