/* mesh.h — closed triangle meshes as scene shapes (shapes.X.type = "mesh").
 *
 * A mesh file (STL, ASCII or binary, OBJ, and whatever else the Open Asset
 * Import Library reads) is read with assimp, its vertices welded by exact
 * position, transformed (scale, then rotations about x, y and z in that
 * order, then translation) and checked: it must hold triangles, none of
 * them degenerate, and form a closed, consistently oriented, outward-facing
 * surface (every edge shared by exactly two triangles that run along it in
 * opposite directions, positive enclosed volume) that does not meet itself
 * (no two triangles share a point other than their common edge or vertex).
 * A mesh that fails is refused with a message that says what and where (the
 * first offending triangle, edge or pair, in the transformed coordinates).
 *
 * Queries, in the transformed coordinates: sph_mesh_sdf, the distance to
 * the nearest triangle (found through a bounding-volume hierarchy of the
 * triangles), signed by the angle-weighted pseudonormal of the nearest
 * feature, face, edge or vertex (Baerentzen & Aanaes, IEEE TVCG 11, 2005:
 * exact for the closed, consistently oriented manifolds without
 * self-intersection accepted here, where ray parity and a winding number are needed only for
 * defective surfaces, which are refused), and the outward unit normal, the gradient of the signed
 * distance; sph_mesh_contains, its sign (the surface counts as inside).
 *
 * A mesh is owned by the shape that loaded it (sph_scene_free releases it).
 */
#ifndef SPH_MESH_H
#define SPH_MESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct sph_mesh sph_mesh;

/* x' = translate + Rz Ry Rx (scale x), angles in degrees */
typedef struct {
    double scale;
    double rotate_deg[3];
    double translate[3];
} sph_mesh_transform;

/* Read the file at `path` (`data`/`size` instead when data is not NULL, with
 * `hint` the format's extension, e.g. "stl"), transform and check it.  On
 * failure returns NULL and writes why into why[len] (no file name: the
 * caller names the file and the scene key). */
sph_mesh *sph_mesh_load(const char *path, const void *data, size_t size, const char *hint,
                        const sph_mesh_transform *tf, char *why, size_t len);
void sph_mesh_free(sph_mesh *mesh);

int sph_mesh_triangles(const sph_mesh *mesh);
/* the axis-aligned bounding box of the transformed vertices */
void sph_mesh_bounds(const sph_mesh *mesh, double lower[3], double upper[3]);
/* the enclosed volume */
double sph_mesh_volume(const sph_mesh *mesh);
bool sph_mesh_contains(const sph_mesh *mesh, const double x[3]);
/* signed distance (< 0 inside); normal (may be NULL): outward unit normal */
double sph_mesh_sdf(const sph_mesh *mesh, const double x[3], double normal[3]);
/* FNV-1a over the transformed vertices and triangles */
uint64_t sph_mesh_hash(const sph_mesh *mesh, uint64_t h);

#endif
