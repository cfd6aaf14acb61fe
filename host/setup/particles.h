/* particles.h — the initial particle set of a scene, on the host.
 *
 * Lattice placement as in the reference code: particles sit at the centres
 * of a dp-grid anchored at the lattice origin (default: the lower corner of
 * the union of the matter bodies' bounding boxes; along a periodic axis the
 * boundary's lower corner); a grid point belongs to the first body (in scene
 * order) whose shape contains it.  A fluid scene's wall bodies have lattices
 * of their own spacing (bodies.X.spacing dp, aligned with the origin), and a
 * matter point inside a wall's shape is dropped.  Particles are numbered body
 * by body, then z, y, x with x running fastest; `id` is that number and stays
 * with the particle when the backends reorder particles by cell.
 *
 * Storage is structure-of-arrays in double precision, component-major:
 * component c of particle i is at pos[c * n + i].
 */
#ifndef SPH_PARTICLES_H
#define SPH_PARTICLES_H

#include "relax.h"
#include "scene.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    int n, dim;
    double *pos;  /* [dim * n] */
    double *vel;  /* [dim * n] */
    double *mass; /* [n]  rho0 dp^d */
    double *rho;  /* [n]  rho0; fluid bodies: bodies.X.initial_density */
    /* [n] fluid bodies of the compressible formulation: the initial pressure
     * (bodies.X.initial_pressure); NULL in every other scene (the weakly
     * compressible pressure follows from rho by the EOS on the device) */
    double *pressure;
    /* Fluid scenes with walls or a far field (NULL otherwise):
     * kind[i] is SPH_PARTICLE_FLUID, _WALL (sph_constants.h) (a particle of a wall body),
     * _INFLOW or _OUTFLOW (fluid within one cut-off 2h of a far-field face
     * of the boundary box: outflow where U_inf . n > 0, else inflow, the
     * public code's rule); normal[a * n + i] is a wall particle's unit
     * normal into the fluid (the outward normal of its body's shape, from
     * the shape's distance function) or a far-field particle's outward
     * normal of its nearest face, 0 for the others. */
    uint8_t *kind;
    double *normal;
    int32_t *id;   /* [n] */
    uint8_t *body; /* [n]  index into scene->bodies */
    /* [n] the row of the run's material table (sph_scene_material_rows);
     * NULL in a scene of one material */
    uint8_t *material;
    /* [n] 0: free; k + 1: constrained by entry k of the scene's constraint
     * table (sph_constraint_index); NULL if the scene has no constraint */
    uint8_t *fixed;
    int body_count[SPH_MAX_BODIES];
    int fixed_count;
    /* bodies with placement = "relaxed": what their relaxation did */
    sph_relax_report relax[SPH_MAX_BODIES];
} sph_particles;

/* Place the particles.  Input errors (SPH_ERR_INPUT, naming the body or
 * observer with its file and line): bodies that overlap (they may touch),
 * a body without particles, an observer with no particle within 2h.
 * Runtime errors (SPH_ERR_RUNTIME): more particles than the memory holds
 * (checked before allocating, against sph_host_memory_available) or than an
 * int32 indexes. */
sph_status sph_particles_generate(const sph_scene *scene, sph_particles *out, sph_error *err);
/* The same; `force_relax` relaxes the bodies with placement = "relaxed"
 * even when their files match (`sphsolid relax --force`).  Relaxed bodies
 * start from their lattice particles (same count, mass rho0 dp^d), whose
 * overlap and count checks above apply unchanged; their velocities and
 * constraint flags are evaluated at the relaxed positions.  A failure to
 * write a relaxation file is SPH_ERR_RUNTIME. */
sph_status sph_particles_generate_ex(const sph_scene *scene, sph_particles *out, bool force_relax,
                                     sph_error *err);
void sph_particles_free(sph_particles *p);

/* Host bytes of one particle in sph_particles. */
size_t sph_particles_bytes_each(int dim, bool constrained);

/* The host memory this process can use, in bytes: the physical memory, or
 * less under a data-size or address-space limit (ulimit -d, -v).
 * `describe` gets the sentence that says so ("this machine has 23.4 GiB of
 * physical memory"), for messages. */
double sph_host_memory_available(char *describe, size_t len);
/* "12.3 GiB" */
void sph_format_bytes(double bytes, char *buf, size_t len);

/* The initial velocity of a body's velocity field at point x; 0 for an
 * expression field, which sph_particles_generate evaluates (compiled once
 * per body, expression.h). */
void sph_velocity_field_eval(const sph_scene *scene, const sph_body *body, const double x[3],
                             double v[3]);

#endif
