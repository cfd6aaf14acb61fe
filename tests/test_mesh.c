/* test_mesh.c — closed triangle meshes as shapes (host/setup/mesh.c).
 *
 *  1. A unit cube as 12 triangles (ASCII STL, binary STL, and OBJ whose
 *     corners are split by face normals, so that they only meet after
 *     welding), scaled by 2, turned 30 degrees about z and moved: the signed
 *     distance equals the rotated box's exact one at 2 000 random points
 *     inside, outside and near edges and corners (1e-12), its normal the
 *     box's outward gradient away from the medial axes (1e-9), the inside
 *     test its sign, the volume 8 and the bounding box the turned cube's.
 *  2. The equal-volume icosphere of cases/mesh_ball_3d (5 120 triangles):
 *     volume 4 pi / 3 (1e-6 relative after the file's float rounding), and
 *     the signed distance within the facets' sagitta (0.1 % of R) of the
 *     sphere's at random points.
 *  3. Bad meshes refused with what and where: an unreadable file, bytes that
 *     are no mesh, a mesh without triangles, an open surface (one triangle
 *     removed: 3 boundary edges), a degenerate triangle, one triangle turned
 *     over (inconsistent winding), the whole surface inside out, edges
 *     shared by three triangles (a face doubled, reversed).
 *  4. Two parts in one file: two cubes apart, and a cube with a cavity
 *     (volume 0.875, the cavity outside), are accepted; two cubes
 *     overlapping, a half-size cube against a face of the other (no vertex
 *     shared), and a cube holding a sheet of
 *     no thickness (which passes the edge checks) are refused as
 *     intersecting themselves, the first pair named with a point of both.
 */
#include "mesh.h"
#include "particles.h"
#include "scene.h"
#include "sph_constants.h"
#include "test_support.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PI 3.14159265358979323846

/* the unit cube [0, 1]^3 as 12 counter-clockwise (outward) triangles */
static const double CUBE_V[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                    {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
static const int CUBE_T[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                  {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};

static void write_ascii_stl(const char *path, const int (*t)[3], int nt) {
    FILE *f = fopen(path, "w");
    fprintf(f, "solid cube\n");
    for (int k = 0; k < nt; k++) {
        fprintf(f, " facet normal 0 0 0\n  outer loop\n");
        for (int c = 0; c < 3; c++)
            fprintf(f, "   vertex %g %g %g\n", CUBE_V[t[k][c]][0], CUBE_V[t[k][c]][1],
                    CUBE_V[t[k][c]][2]);
        fprintf(f, "  endloop\n endfacet\n");
    }
    fprintf(f, "endsolid cube\n");
    fclose(f);
}

static void write_binary_stl(const char *path, const int (*t)[3], int nt) {
    FILE *f = fopen(path, "wb");
    char header[80] = "binary cube";
    fwrite(header, 1, 80, f);
    const uint32_t n = (uint32_t)nt;
    fwrite(&n, 4, 1, f);
    for (int k = 0; k < nt; k++) {
        float rec[12] = {0, 0, 0};
        for (int c = 0; c < 3; c++)
            for (int a = 0; a < 3; a++) rec[3 + 3 * c + a] = (float)CUBE_V[t[k][c]][a];
        fwrite(rec, 4, 12, f);
        const uint16_t attr = 0;
        fwrite(&attr, 2, 1, f);
    }
    fclose(f);
}

/* OBJ with one normal per face, so that each face has its own vertices in
 * assimp's output and only welding joins them */
static void write_obj(const char *path) {
    FILE *f = fopen(path, "w");
    for (int v = 0; v < 8; v++)
        fprintf(f, "v %g %g %g\n", CUBE_V[v][0], CUBE_V[v][1], CUBE_V[v][2]);
    for (int k = 0; k < 12; k++) fprintf(f, "vn 0 0 %d\n", k + 1);
    for (int k = 0; k < 12; k++)
        fprintf(f, "f %d//%d %d//%d %d//%d\n", CUBE_T[k][0] + 1, k + 1, CUBE_T[k][1] + 1, k + 1,
                CUBE_T[k][2] + 1, k + 1);
    fclose(f);
}

/* The unit cube and a second one (the cube scaled by `scale`, moved by
 * `offset`, its winding reversed when `inward`: a cavity) in one OBJ file,
 * or the cube and a sheet (one triangle in both windings) when scale is 0. */
static void write_two_parts(const char *path, const double offset[3], double scale, bool inward) {
    FILE *f = fopen(path, "w");
    for (int part = 0; part < 2; part++)
        for (int v = 0; v < 8; v++)
            fprintf(f, "v %.17g %.17g %.17g\n",
                    part ? offset[0] + scale * CUBE_V[v][0] : CUBE_V[v][0],
                    part ? offset[1] + scale * CUBE_V[v][1] : CUBE_V[v][1],
                    part ? offset[2] + scale * CUBE_V[v][2] : CUBE_V[v][2]);
    for (int k = 0; k < 12; k++)
        fprintf(f, "f %d %d %d\n", CUBE_T[k][0] + 1, CUBE_T[k][1] + 1, CUBE_T[k][2] + 1);
    if (scale == 0.0) {
        fprintf(f, "v 0.2 0.2 0.5\nv 0.8 0.2 0.5\nv 0.2 0.8 0.5\nf 17 18 19\nf 17 19 18\n");
    } else {
        for (int k = 0; k < 12; k++)
            fprintf(f, "f %d %d %d\n", CUBE_T[k][0] + 9, CUBE_T[k][inward ? 2 : 1] + 9,
                    CUBE_T[k][inward ? 1 : 2] + 9);
    }
    fclose(f);
}

static void expect_accepted(test_counts *t, const char *path, double volume, const double in[3],
                            const double out[3]) {
    const sph_mesh_transform tf = {1.0, {0, 0, 0}, {0, 0, 0}};
    char why[512] = "";
    sph_mesh *m = sph_mesh_load(path, NULL, 0, NULL, &tf, why, sizeof why);
    CHECK(t, m != NULL, "%s: %s", path, why);
    if (!m) return;
    CHECK(t, fabs(sph_mesh_volume(m) - volume) < 1e-12, "%s: volume %.15g, expected %g", path,
          sph_mesh_volume(m), volume);
    CHECK(t, sph_mesh_contains(m, in) && !sph_mesh_contains(m, out),
          "%s: (%g, %g, %g) inside %d, (%g, %g, %g) inside %d", path, in[0], in[1], in[2],
          (int)sph_mesh_contains(m, in), out[0], out[1], out[2], (int)sph_mesh_contains(m, out));
    sph_mesh_free(m);
}

/* the exact signed distance of the box [0, 2]^3 at y (box frame), and its gradient */
static double box_sdf(const double y[3], double grad[3]) {
    double q[3], out2 = 0.0, inside = -INFINITY;
    int nearest = 0;
    for (int a = 0; a < 3; a++) {
        q[a] = fabs(y[a] - 1.0) - 1.0;
        if (q[a] > 0) out2 += q[a] * q[a];
        if (q[a] > inside) inside = q[a], nearest = a;
    }
    for (int a = 0; a < 3; a++) grad[a] = 0.0;
    if (out2 > 0) {
        const double d = sqrt(out2);
        for (int a = 0; a < 3; a++)
            if (q[a] > 0) grad[a] = q[a] / d * (y[a] > 1.0 ? 1.0 : -1.0);
        return d;
    }
    grad[nearest] = y[nearest] > 1.0 ? 1.0 : -1.0;
    return inside;
}

static uint64_t rng_state = 88172645463325252ULL;
static double uniform(double lo, double hi) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return lo + (hi - lo) * (double)(rng_state >> 11) / 9007199254740992.0;
}

static void cube_checks(test_counts *t, const char *path, const char *what) {
    const sph_mesh_transform tf = {2.0, {0, 0, 30.0}, {0.5, -1.0, 3.0}};
    char why[512] = "";
    sph_mesh *m = sph_mesh_load(path, NULL, 0, NULL, &tf, why, sizeof why);
    CHECK(t, m != NULL, "%s: %s", what, why);
    if (!m) return;
    const double c = cos(PI / 6), s = sin(PI / 6);
    double lo[3], hi[3];
    sph_mesh_bounds(m, lo, hi);
    /* the turned square's x extent: [-2 s, 2 c], y: [0, 2 (s + c)] */
    CHECK(t,
          fabs(lo[0] - (0.5 - 2 * s)) < 1e-6 && fabs(hi[0] - (0.5 + 2 * c)) < 1e-6 &&
              fabs(lo[1] + 1.0) < 1e-6 && fabs(hi[1] - (-1.0 + 2 * (s + c))) < 1e-6 &&
              fabs(lo[2] - 3.0) < 1e-12 && fabs(hi[2] - 5.0) < 1e-12,
          "%s: bounds (%g %g %g) (%g %g %g)", what, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    CHECK(t, sph_mesh_triangles(m) == 12 && fabs(sph_mesh_volume(m) - 8.0) < 1e-5,
          "%s: %d triangles, volume %.9g", what, sph_mesh_triangles(m), sph_mesh_volume(m));
    double worst = 0.0, worst_n = 0.0;
    int wrong_side = 0;
    for (int k = 0; k < 2000; k++) {
        /* box frame point, then to the mesh's frame */
        double y[3], x[3], g[3], n[3];
        for (int a = 0; a < 3; a++) y[a] = uniform(-0.5, 2.5);
        if (k % 4 == 0) y[k % 3] = (k % 8 == 0) ? 2.0 + 1e-7 : -1e-7; /* near a face */
        x[0] = 0.5 + c * y[0] - s * y[1];
        x[1] = -1.0 + s * y[0] + c * y[1];
        x[2] = 3.0 + y[2];
        const double exact = box_sdf(y, g);
        const double phi = sph_mesh_sdf(m, x, n);
        /* the float vertices of the STL: 1e-7 of the size */
        worst = fmax(worst, fabs(phi - exact));
        wrong_side += sph_mesh_contains(m, x) != (exact <= 0.0) && fabs(exact) > 1e-6;
        /* the normal: the box's gradient in the mesh frame, where unique
         * (away from the medial surfaces: compare only clear cases) */
        const double gx = c * g[0] - s * g[1], gy = s * g[0] + c * g[1], gz = g[2];
        double second = INFINITY; /* the gap to the next-nearest face, inside */
        if (exact < 0)
            for (int a = 0; a < 3; a++)
                for (int side = 0; side < 2; side++) {
                    const double d = side ? 2.0 - y[a] : y[a];
                    if (d > -exact + 1e-9) second = fmin(second, d + exact);
                }
        if (exact > 0 || second > 1e-3)
            worst_n = fmax(worst_n, fabs(n[0] - gx) + fabs(n[1] - gy) + fabs(n[2] - gz));
    }
    printf("%s: 2000 points: max |phi - phi_box| %.3g, normal %.3g, %d on the wrong side\n", what,
           worst, worst_n, wrong_side);
    CHECK(t, worst < 1e-6, "%s: signed distance off by %.3g", what, worst);
    CHECK(t, worst_n < 1e-5, "%s: normal off by %.3g", what, worst_n);
    CHECK(t, wrong_side == 0, "%s: %d points on the wrong side", what, wrong_side);
    sph_mesh_free(m);
}

static void expect_refused(test_counts *t, const char *path, const char *fragment) {
    const sph_mesh_transform tf = {1.0, {0, 0, 0}, {0, 0, 0}};
    char why[512] = "";
    sph_mesh *m = sph_mesh_load(path, NULL, 0, NULL, &tf, why, sizeof why);
    printf("refused %s: %s\n", path, why);
    CHECK(t, m == NULL && strstr(why, fragment) != NULL, "%s: expected '%s', got '%s'", path,
          fragment, m ? "(accepted)" : why);
    sph_mesh_free(m);
}

int main(void) {
    test_counts t = {0};
    test_scene_dir tmp;
    if (test_scene_dir_open(&tmp, "test_mesh")) return 1;
    const char *dir = tmp.dir;
    char path[512];

    snprintf(path, sizeof path, "%s/cube_ascii.stl", dir);
    write_ascii_stl(path, CUBE_T, 12);
    cube_checks(&t, path, "ASCII STL cube");
    snprintf(path, sizeof path, "%s/cube_binary.stl", dir);
    write_binary_stl(path, CUBE_T, 12);
    cube_checks(&t, path, "binary STL cube");
    snprintf(path, sizeof path, "%s/cube.obj", dir);
    write_obj(path);
    cube_checks(&t, path, "OBJ cube, corners split by normals");

    /* the icosphere of cases/mesh_ball_3d */
    {
        test_repo_path("cases/mesh_ball_3d/ball.stl", path, sizeof path);
        const sph_mesh_transform tf = {0.05, {0, 0, 0}, {0, 0.0525, 0}};
        char why[512] = "";
        sph_mesh *m = sph_mesh_load(path, NULL, 0, NULL, &tf, why, sizeof why);
        CHECK(&t, m != NULL, "icosphere: %s", why);
        if (m) {
            const double r = 0.05, v = 4.0 / 3.0 * PI * r * r * r;
            double worst = 0.0;
            for (int k = 0; k < 2000; k++) {
                double x[3];
                for (int a = 0; a < 3; a++) x[a] = uniform(-0.07, 0.07);
                const double rho = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
                x[1] += 0.0525;
                worst = fmax(worst, fabs(sph_mesh_sdf(m, x, NULL) - (rho - r)));
            }
            printf("icosphere: %d triangles, volume %.9g (ball %.9g), max |phi - (|x| - R)| "
                   "%.3g m (R = %g)\n",
                   sph_mesh_triangles(m), sph_mesh_volume(m), v, worst, r);
            CHECK(&t, sph_mesh_triangles(m) == 5120, "icosphere triangles %d",
                  sph_mesh_triangles(m));
            CHECK(&t, fabs(sph_mesh_volume(m) / v - 1.0) < 1e-6, "icosphere volume %.9g of %.9g",
                  sph_mesh_volume(m), v);
            /* the facets' sagitta: vertices 0.072 % out, face centres up to
             * 0.042 % in (make_ball_stl.py) */
            CHECK(&t, worst < 1e-3 * r, "icosphere distance off by %.3g", worst);
            sph_mesh_free(m);
        }
    }

    /* bad meshes */
    snprintf(path, sizeof path, "%s/missing.stl", dir);
    expect_refused(&t, path, "cannot open it");
    snprintf(path, sizeof path, "%s/garbage.stl", dir);
    FILE *f = fopen(path, "w");
    fprintf(f, "this is not a mesh\n");
    fclose(f);
    expect_refused(&t, path, "cannot read it as a mesh");
    snprintf(path, sizeof path, "%s/empty.stl", dir);
    f = fopen(path, "w");
    fprintf(f, "solid empty\nendsolid empty\n");
    fclose(f);
    expect_refused(&t, path, "cannot read it as a mesh");
    snprintf(path, sizeof path, "%s/open.stl", dir);
    write_ascii_stl(path, CUBE_T, 11);
    expect_refused(&t, path, "is not closed: 3 boundary edges");
    int tri[13][3];
    memcpy(tri, CUBE_T, sizeof CUBE_T);
    tri[3][2] = tri[3][1]; /* a repeated vertex */
    snprintf(path, sizeof path, "%s/degenerate.stl", dir);
    write_ascii_stl(path, (const int(*)[3])tri, 12);
    expect_refused(&t, path, "1 degenerate triangle");
    memcpy(tri, CUBE_T, sizeof CUBE_T);
    const int swap = tri[5][1];
    tri[5][1] = tri[5][2], tri[5][2] = swap; /* one triangle turned over */
    snprintf(path, sizeof path, "%s/flipped.stl", dir);
    write_ascii_stl(path, (const int(*)[3])tri, 12);
    expect_refused(&t, path, "has inverted triangles: 3 edges");
    for (int k = 0; k < 12; k++) {
        const int v1 = CUBE_T[k][1];
        tri[k][0] = CUBE_T[k][0], tri[k][1] = CUBE_T[k][2], tri[k][2] = v1;
    }
    snprintf(path, sizeof path, "%s/inside_out.stl", dir);
    write_ascii_stl(path, (const int(*)[3])tri, 12);
    expect_refused(&t, path, "is inside out");
    memcpy(tri, CUBE_T, sizeof CUBE_T);
    tri[12][0] = 0, tri[12][1] = 1, tri[12][2] = 2; /* a third triangle on 0-1, 1-2, 2-0 */
    snprintf(path, sizeof path, "%s/fin.stl", dir);
    write_ascii_stl(path, (const int(*)[3])tri, 13);
    expect_refused(&t, path, "more than two triangles");

    /* two parts in one file: apart, and a cavity inside the cube, are one
     * closed surface; overlapping, touching along a face, and a sheet of no
     * thickness inside (each edge of its two triangles runs both ways, so
     * only the self-intersection test sees it) are refused */
    {
        static const struct {
            const char *name;
            double offset[3], scale;
            bool inward;
            const char *why;
        } parts[] = {
            {"apart.obj", {2.0, 0.0, 0.0}, 1.0, false, NULL},
            {"cavity.obj", {0.25, 0.25, 0.25}, 0.5, true, NULL},
            {"overlapping.obj", {0.5, 0.5, 0.5}, 1.0, false, "intersects itself: "},
            {"touching.obj", {1.0, 0.25, 0.25}, 0.5, false, "intersects itself: "},
            {"sheet.obj", {0.0, 0.0, 0.0}, 0.0, false, "intersects itself: 1 pair of triangles"},
        };
        for (size_t k = 0; k < sizeof parts / sizeof parts[0]; k++) {
            snprintf(path, sizeof path, "%s/%s", dir, parts[k].name);
            write_two_parts(path, parts[k].offset, parts[k].scale, parts[k].inward);
            if (parts[k].why) {
                expect_refused(&t, path, parts[k].why);
                continue;
            }
            const double in[3] = {0.1, 0.1, 0.1}, out[3] = {0.5, 0.5, 0.5};
            const double outside[3] = {1.5, 0.5, 0.5};
            if (k == 0)
                expect_accepted(&t, path, 2.0, in, outside);
            else
                expect_accepted(&t, path, 1.0 - 0.125, in, out);
        }
        /* the overlap's first pair and where they meet */
        const sph_mesh_transform tf = {1.0, {0, 0, 0}, {0, 0, 0}};
        char why[512] = "";
        snprintf(path, sizeof path, "%s/overlapping.obj", dir);
        sph_mesh *m = sph_mesh_load(path, NULL, 0, NULL, &tf, why, sizeof why);
        int first = -1, second = -1;
        double at[3] = {-1, -1, -1};
        const char *p = strstr(why, "the first triangles ");
        CHECK(&t,
              !m && p &&
                  sscanf(p, "the first triangles %d and %d at (%lf, %lf, %lf)", &first, &second,
                         &at[0], &at[1], &at[2]) == 5,
              "overlap: cannot read the first pair from '%s'", why);
        /* a point of both triangles, in both cubes' surfaces: on a face of
         * the first cube and of the second */
        bool on_both = first >= 0 && first < 12 && second >= 12;
        for (int a = 0; a < 3; a++) on_both = on_both && at[a] >= 0.5 - 1e-9 && at[a] <= 1.0 + 1e-9;
        CHECK(&t, on_both, "overlap: triangles %d and %d at (%g, %g, %g)", first, second, at[0],
              at[1], at[2]);
        sph_mesh_free(m);
    }

    /* a mesh in a union and in a difference: the unit cube of
     * cube_ascii.stl with a box half its size cut away, and with a box as
     * large added beside it; dp = 0.1 puts the lattice's cell centres off
     * every face, so the counts are exact: 500 and 2000 against the cube's 1000 */
    {
        static const char *const parts[2] = {
            "carved = { type = \"difference\"; parts = [\"cube\", \"half\"]; };",
            "carved = { type = \"union\"; parts = [\"cube\", \"extra\"]; };"};
        static const int expected[2] = {500, 2000};
        for (int k = 0; k < 2; k++) {
            char text[2048], scene_path[512];
            snprintf(text, sizeof text,
                     "dimension = 3;\nresolution = { dp = 0.1; };\n"
                     "method = { formulation = \"enog-a\"; };\n"
                     "time = { end = 1e-4; output_interval = 1e-4; };\n"
                     "materials = { m = { density = 1000.0; youngs_modulus = 1e6; "
                     "poisson_ratio = 0.3; }; };\n"
                     "shapes = {\n  cube = { type = \"mesh\"; file = \"cube_ascii.stl\"; };\n"
                     "  half = { type = \"box\"; lower = [0.5, 0.0, 0.0]; upper = [1.0, 1.0, "
                     "1.0]; };\n"
                     "  extra = { type = \"box\"; lower = [1.0, 0.0, 0.0]; upper = [2.0, 1.0, "
                     "1.0]; };\n  %s\n};\n"
                     "bodies = ( { name = \"part\"; material = \"m\"; shape = \"carved\"; } );\n",
                     parts[k]);
            test_scene_write(&tmp, text, scene_path, sizeof scene_path);
            sph_scene sc;
            sph_error err = {0};
            sph_status st = sph_scene_load(&sc, scene_path, NULL, 0, &err);
            CHECK(&t, st == SPH_OK, "mesh %s: %s", k ? "union" : "difference", err.msg);
            if (st) continue;
            sph_particles p = {0};
            st = sph_particles_generate(&sc, &p, &err);
            CHECK(&t, st == SPH_OK && p.n == expected[k], "mesh %s: %d particles (%s), expected %d",
                  k ? "union" : "difference", p.n, st ? err.msg : "", expected[k]);
            printf("the cube mesh in a %s: %d particles\n", k ? "union" : "difference", p.n);
            sph_particles_free(&p);
            sph_scene_free(&sc);
        }
    }

    /* a mesh as a fluid's wall body: the icosphere of cases/mesh_ball_3d
     * as a ball at rest in a periodic box of weakly compressible fluid,
     * against the built-in ball: the same particles to the facets'
     * sagitta (fluid and wall counts within 1 %), wall normals from the
     * mesh's pseudonormals within 2 degrees of the ball's on average */
    {
        /* absolute: the scene resolves a relative file against its own directory */
        char ball_rel[512], ball_stl[PATH_MAX];
        test_repo_path("cases/mesh_ball_3d/ball.stl", ball_rel, sizeof ball_rel);
        char cwd[PATH_MAX - 600] = ".";
        if (ball_rel[0] != '/' && getcwd(cwd, sizeof cwd))
            snprintf(ball_stl, sizeof ball_stl, "%s/%s", cwd, ball_rel);
        else
            snprintf(ball_stl, sizeof ball_stl, "%s", ball_rel);
        static const char *const wall_shape[2] = {
            "wall = { type = \"ball\"; centre = [0.15, 0.15, 0.15]; radius = 0.05; };",
            "wall = { type = \"mesh\"; file = \"%s\"; scale = 0.05; translate = [0.15, 0.15, "
            "0.15]; };"};
        int nfluid[2] = {0, 0}, nwall[2] = {0, 0};
        double *normals[2] = {NULL, NULL}, *positions[2] = {NULL, NULL};
        for (int k = 0; k < 2; k++) {
            char shape[1024], text[4096], scene_path[512];
            snprintf(shape, sizeof shape, wall_shape[k], ball_stl);
            snprintf(text, sizeof text,
                     "dimension = 3;\nresolution = { dp = 0.01; };\n"
                     "method = { formulation = \"eulerian-wc\"; kernel = \"wendland-c2\"; };\n"
                     "time = { end = 1e-3; output_interval = 1e-3; };\n"
                     "materials = { water = { density = 1.0; sound_speed = 10.0; viscosity = "
                     "0.01; }; };\n"
                     "shapes = {\n  box = { type = \"box\"; lower = [0.0, 0.0, 0.0]; upper = "
                     "[0.3, 0.3, 0.3]; };\n  %s\n"
                     "  flow = { type = \"difference\"; parts = [\"box\", \"wall\"]; };\n};\n"
                     "bodies = ( { name = \"fluid\"; material = \"water\"; shape = \"flow\"; },\n"
                     "  { name = \"ball\"; role = \"wall\"; shape = \"wall\"; } );\n"
                     "boundary = { periodic = [\"x\", \"y\", \"z\"]; lower = [0.0, 0.0, 0.0]; "
                     "upper = [0.3, 0.3, 0.3]; };\n",
                     shape);
            test_scene_write(&tmp, text, scene_path, sizeof scene_path);
            sph_scene sc;
            sph_error err = {0};
            sph_status st = sph_scene_load(&sc, scene_path, NULL, 0, &err);
            CHECK(&t, st == SPH_OK, "fluid wall %s: %s", k ? "mesh" : "ball", err.msg);
            if (st) continue;
            sph_particles p = {0};
            st = sph_particles_generate(&sc, &p, &err);
            CHECK(&t, st == SPH_OK && p.kind != NULL, "fluid wall %s: %s", k ? "mesh" : "ball",
                  err.msg);
            if (!st && p.kind) {
                normals[k] = malloc((size_t)p.n * 3 * sizeof(double));
                positions[k] = malloc((size_t)p.n * 3 * sizeof(double));
                for (int i = 0; i < p.n; i++) {
                    if (p.kind[i] != SPH_PARTICLE_WALL) {
                        nfluid[k]++;
                        continue;
                    }
                    for (int a = 0; a < 3; a++) {
                        normals[k][nwall[k] * 3 + a] =
                            p.normal[(size_t)a * (size_t)p.n + (size_t)i];
                        positions[k][nwall[k] * 3 + a] = p.pos[(size_t)a * (size_t)p.n + (size_t)i];
                    }
                    nwall[k]++;
                }
            }
            sph_particles_free(&p);
            sph_scene_free(&sc);
        }
        /* each mesh wall particle's normal against the ball's radial
         * direction at its position (the ball's own normal there) */
        double mean_angle = 0.0;
        for (int q = 0; q < nwall[1] && normals[1]; q++) {
            double r[3], rn = 0.0, dot = 0.0;
            for (int a = 0; a < 3; a++) {
                r[a] = positions[1][q * 3 + a] - 0.15;
                rn += r[a] * r[a];
            }
            rn = sqrt(rn);
            for (int a = 0; a < 3; a++) dot += normals[1][q * 3 + a] * r[a] / rn;
            mean_angle += acos(fmin(1.0, fmax(-1.0, dot))) / nwall[1];
        }
        printf("fluid around a wall ball: built-in %d fluid + %d wall particles, mesh %d + %d; "
               "mesh wall normals %.3f degrees from radial on average\n",
               nfluid[0], nwall[0], nfluid[1], nwall[1], mean_angle * 180.0 / PI);
        CHECK(&t,
              nwall[0] > 0 && abs(nwall[1] - nwall[0]) <= nwall[0] / 100 &&
                  abs(nfluid[1] - nfluid[0]) <= nfluid[0] / 100,
              "fluid wall: counts %d/%d against %d/%d", nfluid[1], nwall[1], nfluid[0], nwall[0]);
        CHECK(&t, nwall[1] > 0 && mean_angle * 180.0 / PI < 2.0,
              "fluid wall: mean normal angle %.3f degrees", mean_angle * 180.0 / PI);
        for (int k = 0; k < 2; k++) {
            free(normals[k]);
            free(positions[k]);
        }
    }

    static const char *const written[] = {
        "cube_ascii.stl", "cube_binary.stl", "cube.obj",    "garbage.stl",    "empty.stl",
        "open.stl",       "degenerate.stl",  "flipped.stl", "inside_out.stl", "fin.stl"};
    for (size_t k = 0; k < sizeof written / sizeof written[0]; k++) {
        snprintf(path, sizeof path, "%s/%s", dir, written[k]);
        unlink(path);
    }
    test_scene_dir_close(&tmp);
    return test_summary("test_mesh", &t);
}
