/* relax.h — particle relaxation: irregular, body-fitted initial particles.
 *
 * A body with placement = "relaxed" starts from its lattice particles (the
 * same count and volume dp^d each, so masses and energies are those of the
 * lattice), offset by a seeded pseudo-random displacement, and relaxes
 * them towards zeroth-order consistency, sum_j grad W_ij V_j = 0: 004 eq. 4
 * (a_i = -(2/rho_i) sum_j V_j grad W_ij, after Litvinov et al. 2015), the
 * level-set pre-processing of Yu et al. 2023 that 000 cites ([55]) for its
 * initial particles, and the reference code's RelaxationStepInner with a
 * level-set shape.  Each step:
 *
 *   a_i = -2 [ sum_j grad_i W_ij V_j + B(x_i) ],  B(x) = int_outside grad_x W(x - y) dy
 *
 * a constant unit "pressure" pushing particles apart, plus the part of the
 * kernel's support that lies outside the shape.  B comes from the shape's
 * signed distance (shape_sdf.h) on a background mesh, like the reference
 * code's kernel-gradient integral on its level-set mesh; the half-space
 * integral G(d) (sph_kernel_half_space, exact beyond a plane at the depth
 * d) checks it and is what B reduces to at a flat face.  The step is
 * x += a dt^2 / 2 with dt = 0.25 sqrt(h / max|a|), i.e. no particle moves
 * more than h/32, dt frozen once max|a| falls below a tenth of its start
 * (relaxation.step = "normalised"), or x += alpha h^2 a with alpha =
 * min(0.2, 3/4 of the step's stability limit on the body's lattice)
 * (relaxation.step = "fixed", relax.c: fixed_step_alpha);
 * a particle closer than dp/2 to the surface is then put back on
 * phi = -dp/2 along the normal (the reference code's ShapeSurfaceBounding):
 * a particle stands for a cell of width dp, so the outermost particles sit
 * half a spacing inside, as on the lattice.
 *
 * The residual of particle i is |sum_j grad_i W_ij V_j + B(x_i)| h
 * (dimensionless; 0 for a perfectly consistent distribution).
 *
 * Throughout, dp is the body's own particle spacing: the scene's dp, or a
 * wall body's spacing_ratio dp (scene.h, bodies.X.spacing), and h is
 * smoothing_ratio times it; the saved file's "dp" attribute is that spacing.
 *
 * Relaxed positions are saved to and reused from an HDF5 file
 * (bodies[i].relaxation.file): dataset "position" [n][dim] and attributes
 * naming what it belongs to (docs/scene-format.md, "Relaxed placement").
 */
#ifndef SPH_RELAX_H
#define SPH_RELAX_H

#include "scene.h"

#include <stdbool.h>
#include <stddef.h>

#define SPH_RELAX_TABLE 512

/* G(d), d in [0, 2h], at SPH_RELAX_TABLE + 1 equally spaced depths. */
typedef struct {
    int dim;
    double h, step;
    double value[SPH_RELAX_TABLE + 1];
} sph_kernel_half_space;

/* Tabulate G for the scene's kernel (device/sph_smoothing_kernel.h through
 * the native backend's kernel probe) and smoothing length h. */
void sph_kernel_half_space_init(int dim, sph_kernel kernel, double h, sph_kernel_half_space *t);
/* G(|d|) by linear interpolation; 0 beyond 2h. */
double sph_kernel_half_space_value(const sph_kernel_half_space *t, double d);

typedef struct {
    bool relaxed;  /* the body has placement = "relaxed" */
    bool reused;   /* its positions came from its file */
    bool written;  /* ... or were relaxed here and written to it */
    int steps;     /* relaxation steps taken (read from the file when reused) */
    int particles; /* the body's particle count */
    /* residuals, mean and max over the body's particles: of the lattice, of
     * the perturbed start, and of the result */
    double lattice_mean, lattice_max, start_mean, start_max, mean, max;
    double min_distance; /* the closest pair of the result, over dp */
    double step_alpha;   /* relaxation.step = "fixed": its alpha (else 0) */
    double seconds;      /* wall time of the relaxation (0 when reused) */
    /* why the file was not reused ("no file yet", "dp differs: ...") */
    char note[640];
} sph_relax_report;

/* Residual of the `n` particles of body `body` at positions pos (component
 * major: pos[a * n + i]), each of volume dp^d: mean and max over the
 * particles, and the closest pair over dp. */
sph_status sph_relax_residual(const sph_scene *scene, int body, int n, const double *pos,
                              double *mean, double *max, double *min_distance, sph_error *err);

/* The boundary term B(x) = int_outside grad W(x - y) dy of body `body`'s
 * shape at `npoints` points (x and b: 3 values per point), from the
 * relaxation's background mesh: for tests (against sph_kernel_half_space
 * at a plane face). */
sph_status sph_relax_boundary_term(const sph_scene *scene, int body, int npoints, const double *x,
                                   double *b, sph_error *err);

/* Perturb and relax the body's n lattice particles in place (pos as above);
 * fills the report's residuals, steps and time.  Deterministic: the same
 * input gives the same bits whatever the number of OpenMP threads. */
sph_status sph_relax_positions(const sph_scene *scene, int body, int n, double *pos,
                               sph_relax_report *rep, sph_error *err);

/* The body's placement with its file: reuse the file when it matches the
 * scene (dimension, dp, smoothing ratio, kernel, relaxation settings, shape
 * definition, lattice origin, particle count) unless `force`, else relax
 * (sph_relax_positions) and, when the body names a file, write it (under a
 * temporary name, renamed when complete).  `origin` is the lattice origin
 * of the scene's placement. */
sph_status sph_relax_body(const sph_scene *scene, int body, const double origin[3], int n,
                          double *pos, bool force, sph_relax_report *rep, sph_error *err);

/* One line for the log: particles, steps, residuals, closest pair, and
 * whether the file was reused, written (and why it was regenerated) or not
 * named. */
void sph_relax_report_format(const sph_relax_report *rep, const char *body, const char *file,
                             char *buf, size_t len);

#endif
