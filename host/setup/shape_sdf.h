/* shape_sdf.h — signed distance to the scene's shapes.
 *
 * phi(x) < 0 inside, > 0 outside, |phi| the distance to the surface (exact
 * for boxes, discs, annuli, balls, hollow spheres and cylinders; for unions
 * min(phi_a, phi_b) and for differences max(phi_a, -phi_b), the usual
 * constructive-solid-geometry bounds, exact wherever one part's surface is
 * the nearest).  The outward unit normal is the gradient of phi, analytic
 * per primitive and taken from the part that decides the min/max.  Box
 * padding (lower_pad_dp, upper_pad_dp) is already in the stored corners.
 *
 * Used by the particle relaxation (relax.c): the level-set of the
 * reference code's ShapeSurfaceBounding and kernel-integral correction.
 */
#ifndef SPH_SHAPE_SDF_H
#define SPH_SHAPE_SDF_H

#include "scene.h"

#include <stdint.h>

/* Signed distance of x to shape `shape`; `normal` (may be NULL) receives
 * the outward unit normal (the gradient of phi; a fixed unit vector at the
 * rare points where it is undefined, e.g. the centre of a disc). */
double sph_shape_sdf(const sph_scene *scene, int shape, const double x[3], double normal[3]);

/* A 64-bit FNV-1a hash of the shape's definition (types and the exact bits
 * of every coordinate and radius, parts recursively): identifies what a
 * saved relaxed particle set belongs to. */
uint64_t sph_shape_hash(const sph_scene *scene, int shape);

#endif
