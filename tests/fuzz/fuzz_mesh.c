/* fuzz_mesh.c — libFuzzer harness over the mesh reader (host/setup/mesh.c; the
 * input convention is in fuzz_mesh.h): arbitrary bytes as an STL or OBJ
 * file through assimp, the welding, the checks and the search tree.
 *
 * Besides "no crash, no leak, no undefined behaviour", every input must keep
 * these invariants, checked here so that the fuzzer reports a violation as a
 * crash:
 *   - refused: a reason is given (non-empty);
 *   - accepted: at least 4 triangles (a closed surface has at least a
 *     tetrahedron's), a positive finite volume, a finite bounding box; a
 *     point outside the box by its size is outside (positive signed
 *     distance at least that far, not contained); the signed distance at
 *     the box's centre and its normal are finite.
 *
 * Build: cmake -DCMAKE_C_COMPILER=clang -DSPHSOLID_FUZZ=ON (README, Tests). */
#include "fuzz_mesh.h"

#include "mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void fuzz_mesh_run(const uint8_t *data, size_t size, fuzz_mesh_result *res) {
    memset(res, 0, sizeof *res);
    if (size < 2) return;
    const char *hint = (data[0] & 1) ? "obj" : "stl";
    const sph_mesh_transform tf = {1.0, {0, 0, 0}, {0, 0, 0}};
    sph_mesh *m = sph_mesh_load(NULL, data + 1, size - 1, hint, &tf, res->why, sizeof res->why);
    if (!m) {
        if (!res->why[0])
            snprintf(res->violation, sizeof res->violation, "refused without a reason");
        return;
    }
    res->accepted = true;
    res->triangles = sph_mesh_triangles(m);
    double lo[3], hi[3], centre[3], far[3], n[3];
    sph_mesh_bounds(m, lo, hi);
    double size_max = 0.0;
    bool finite = true;
    for (int a = 0; a < 3; a++) {
        finite = finite && isfinite(lo[a]) && isfinite(hi[a]) && hi[a] >= lo[a];
        size_max = fmax(size_max, hi[a] - lo[a]);
        centre[a] = 0.5 * (lo[a] + hi[a]);
    }
    const double volume = sph_mesh_volume(m);
    if (res->triangles < 4 || !(volume > 0.0) || !isfinite(volume) || !finite) {
        snprintf(res->violation, sizeof res->violation,
                 "accepted with %d triangles, volume %g, bounds (%g %g %g) (%g %g %g)",
                 res->triangles, volume, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    } else {
        for (int a = 0; a < 3; a++) far[a] = centre[a];
        far[0] = hi[0] + size_max;
        const double phi_far = sph_mesh_sdf(m, far, n);
        const double phi_c = sph_mesh_sdf(m, centre, n);
        if (!(phi_far >= 0.999 * size_max) || sph_mesh_contains(m, far))
            snprintf(res->violation, sizeof res->violation,
                     "a point %g outside the box: signed distance %g, contained %d", size_max,
                     phi_far, (int)sph_mesh_contains(m, far));
        else if (!isfinite(phi_c) || !isfinite(n[0]) || !isfinite(n[1]) || !isfinite(n[2]))
            snprintf(res->violation, sizeof res->violation,
                     "signed distance %g, normal (%g %g %g) at the centre", phi_c, n[0], n[1],
                     n[2]);
    }
    sph_mesh_free(m);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fuzz_mesh_result res;
    fuzz_mesh_run(data, size, &res);
    if (res.violation[0]) {
        fprintf(stderr, "fuzz_mesh: %s\n", res.violation);
        abort();
    }
    return 0;
}
