/* relax.c — particle relaxation towards zeroth-order consistency, with the
 * shape's level set at the surface, and its saved result (see relax.h). */
#include "relax.h"

#include "physics.h"
#include "grid.h"
#include "hdf5_file.h"
#include "sph_constants.h"
#include "shape_sdf.h"
#include "wall_clock.h"

#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define FILE_FORMAT "sphsolid relaxed particles"
/* 2: the step's rule ("step") among the attributes a reused file must match */
#define FILE_VERSION 2

/* ------------------------------------------------------------------------ */
/* the kernel's support beyond a plane                                        */
/* ------------------------------------------------------------------------ */

/* G(d) = int_{z > d} -W'(r) z / r dV: the sum of grad_i W V_j that the
 * particles of a half-space beyond a plane at the distance d would give,
 * along the plane's normal.  With s^2 = r^2 - d^2 (smooth in s):
 *   2D: G = int_0^S -W'(r) 2 s^2 / r ds,   3D: G = pi int_0^S -W'(r) s^3 / r ds,
 * S = sqrt((2h)^2 - d^2); composite Simpson over 2000 intervals. */
static double half_space_integral(const sph_physics *k, const sph_params_f64 *prm, int dim,
                                  double h, double d) {
    const double cutoff = 2.0 * h;
    if (d >= cutoff) return 0.0;
    const double smax = sqrt(cutoff * cutoff - d * d);
    const int m = 2000;
    const double ds = smax / m;
    double sum = 0.0;
    for (int k2 = 0; k2 <= m; k2++) {
        const double s = k2 * ds, r = sqrt(d * d + s * s);
        double f = 0.0;
        if (r > 0.0 && r < cutoff) {
            const double dw = -k->kernel_dw(prm, r);
            f = dim == 2 ? dw * 2.0 * s * s / r : 3.14159265358979323846 * dw * s * s * s / r;
        }
        const double weight = k2 == 0 || k2 == m ? 1.0 : (k2 % 2 ? 4.0 : 2.0);
        sum += weight * f;
    }
    return sum * ds / 3.0;
}

static void kernel_prm(sph_kernel kernel, double h, sph_params_f64 prm[1]) {
    memset(prm, 0, sizeof *prm);
    prm->h = h;
    prm->cutoff = 2.0 * h;
    prm->smoothing_kernel = (int)kernel;
}

void sph_kernel_half_space_init(int dim, sph_kernel kernel, double h, sph_kernel_half_space *t) {
    sph_params_f64 prm[1];
    kernel_prm(kernel, h, prm);
    /* the kernel of the physics source, one definition for the run and here */
    const sph_physics *k = sph_physics_for(dim, true);
    t->dim = dim;
    t->h = h;
    t->step = 2.0 * h / SPH_RELAX_TABLE;
    for (int i = 0; i <= SPH_RELAX_TABLE; i++)
        t->value[i] = half_space_integral(k, prm, dim, h, i * t->step);
}

double sph_kernel_half_space_value(const sph_kernel_half_space *t, double d) {
    const double u = fabs(d) / t->step;
    if (!(u < SPH_RELAX_TABLE)) return 0.0;
    const int i = (int)u;
    const double f = u - i;
    return (1.0 - f) * t->value[i] + f * t->value[i + 1];
}

/* ------------------------------------------------------------------------ */
/* one body's particles: cells, residual, relaxation                          */
/* ------------------------------------------------------------------------ */

typedef struct {
    const sph_scene *scene;
    int dim, n, shape;
    double dp, h, cutoff, volume;
    sph_params_f64 prm[1];
    const sph_physics *k;
    /* the boundary term B(x) = int_outside grad_x W(x - y) dy on a
     * background mesh of spacing `mesh` (build_boundary_mesh) */
    double mesh_origin[3], mesh;
    int mesh_dims[3];
    double *bmesh;       /* [dim][mesh points] */
    sph_cell_list cells; /* rebuilt at every evaluation */
    double *acc;         /* [dim * n] */
    double *res;         /* [n] residual of each particle */
    double *dmin;        /* [n] closest neighbour of each particle */
} relax_state;

static void state_free(relax_state *s) {
    free(s->bmesh);
    sph_cell_list_free(&s->cells);
    free(s->acc);
    free(s->res);
    free(s->dmin);
}

/* The part of the kernel's support outside the shape, as the reference
 * code's level set does it (its kernel-gradient integral on the level-set
 * mesh), so that thin walls, corners and curved surfaces are right:
 *
 *   B(p) = int_{phi(y) > 0} grad_p W(p - y) dy
 *
 * on a mesh of spacing dp/2 (3D) or dp/4 (2D) covering the shape, by a
 * quadrature on a sample lattice twice as fine whose samples count by the
 * fraction of their cell outside the surface, clamp(1/2 + phi/q, 0, 1)
 * (q the sample spacing).  Particles interpolate B (multi-)linearly.  A
 * half-space model G(d) n (sph_kernel_half_space) is exact for a plane but
 * misses the far side of a wall thinner than the support: relaxing the
 * 3D shell r = 0.03..0.04 at dp = 0.005 with it left the mean residual at
 * 0.167 (lattice 0.144); tests/test_relax.c checks the mesh against G(d)
 * at a plane face. */
static sph_status build_boundary_mesh(relax_state *s, sph_error *err) {
    const int dim = s->dim;
    const int per_dp = dim == 2 ? 8 : 4; /* samples per dp */
    const double q = s->dp / per_dp;
    s->mesh = 2.0 * q;
    const int reach = (int)ceil(s->cutoff / q); /* stencil half-width, samples */
    double lo[3], hi[3];
    sph_shape_bounds(s->scene, s->shape, lo, hi);
    long nodes = 1, samples = 1;
    int sdims[3] = {1, 1, 1};
    for (int a = 0; a < 3; a++) {
        s->mesh_origin[a] = a < dim ? lo[a] - 2.0 * s->mesh : 0.0;
        s->mesh_dims[a] = a < dim ? (int)ceil((hi[a] - lo[a]) / s->mesh) + 5 : 1;
        if (a < dim) sdims[a] = 2 * (s->mesh_dims[a] - 1) + 1 + 2 * reach;
        nodes *= s->mesh_dims[a];
        samples *= sdims[a];
    }
    if ((double)samples * sizeof(float) + (double)nodes * dim * sizeof(double) > 4e9)
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "the relaxation's boundary mesh for a shape %g m wide at dp = %g would "
                        "need %ld samples; relax a smaller body or a coarser resolution",
                        hi[0] - lo[0], s->dp, samples);
    float *outside = malloc((size_t)samples * sizeof *outside);
    s->bmesh = calloc((size_t)nodes * (size_t)dim, sizeof *s->bmesh);
    /* the stencil: -W'(r) k q / r q^d for the sample offsets k within 2h */
    const int side = 2 * reach + 1;
    const long nstencil = dim == 2 ? (long)side * side : (long)side * side * side;
    long *offset = malloc((size_t)nstencil * sizeof *offset);
    double *weight = malloc((size_t)nstencil * (size_t)dim * sizeof *weight);
    if (!outside || !s->bmesh || !offset || !weight) {
        free(outside);
        free(offset);
        free(weight);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of memory for the relaxation's boundary mesh");
    }
    const double cell_volume = pow(q, dim);
    long nk = 0;
    const int zr = dim == 3 ? reach : 0;
    for (int kz = -zr; kz <= zr; kz++)
        for (int ky = -reach; ky <= reach; ky++)
            for (int kx = -reach; kx <= reach; kx++) {
                const int k[3] = {kx, ky, kz};
                double r2 = 0.0;
                for (int a = 0; a < dim; a++) r2 += (k[a] * q) * (k[a] * q);
                const double r = sqrt(r2);
                if (!(r > 0.0) || r >= s->cutoff) continue;
                const double dw = s->k->kernel_dw(s->prm, r);
                offset[nk] = kx + (long)sdims[0] * (ky + (long)sdims[1] * kz);
                for (int a = 0; a < dim; a++)
                    weight[nk * dim + a] = -dw * k[a] * q / r * cell_volume;
                nk++;
            }
            /* the samples' outside fractions */
#pragma omp parallel for schedule(static)
    for (long m = 0; m < samples; m++) {
        double y[3] = {0, 0, 0};
        long rest = m;
        for (int a = 0; a < dim; a++) {
            const long idx = rest % sdims[a];
            rest /= sdims[a];
            y[a] = s->mesh_origin[a] + (double)(idx - reach) * q;
        }
        const double phi = sph_shape_sdf(s->scene, s->shape, y, NULL);
        outside[m] = (float)fmin(1.0, fmax(0.0, 0.5 + phi / q));
    }
    /* B at the mesh nodes that may see the outside */
#pragma omp parallel for schedule(dynamic, 64)
    for (long m = 0; m < nodes; m++) {
        double p[3] = {0, 0, 0};
        long rest = m, centre = 0, stride = 1;
        for (int a = 0; a < dim; a++) {
            const long idx = rest % s->mesh_dims[a];
            rest /= s->mesh_dims[a];
            p[a] = s->mesh_origin[a] + (double)idx * s->mesh;
            centre += (2 * idx + reach) * stride;
            stride *= sdims[a];
        }
        /* deep inside, every sample is inside: B = 0; far outside no
         * particle's interpolation reaches (particles keep phi <= -dp/2,
         * their 4^d nodes lie within 2 sqrt(d) mesh spacings = 1.8 dp) */
        const double phi = sph_shape_sdf(s->scene, s->shape, p, NULL);
        if (phi < -(s->cutoff + q) || phi > 2.0 * s->dp) continue;
        double b[3] = {0, 0, 0};
        for (long j = 0; j < nk; j++) {
            const double f = outside[centre + offset[j]];
            if (f == 0.0) continue;
            for (int a = 0; a < dim; a++) b[a] += f * weight[j * dim + a];
        }
        for (int a = 0; a < dim; a++) s->bmesh[(size_t)a * (size_t)nodes + (size_t)m] = b[a];
    }
    free(outside);
    free(offset);
    free(weight);
    return SPH_OK;
}

/* B at x: Catmull-Rom (cubic, C1) interpolation over the 4^d nearest mesh
 * nodes.  Linear interpolation on the dp/2 mesh of 3D was off by up to
 * 0.04/h between the nodes at a plane face (G varies on the scale of dp);
 * the cubic is exact for quadratics. */
static void boundary_term(const relax_state *s, const double x[3], double b[3]) {
    const int dim = s->dim;
    int c[3] = {0, 0, 0};
    double w[3][4] = {{0, 1, 0, 0}, {0, 1, 0, 0}, {0, 1, 0, 0}};
    long nodes = 1;
    for (int a = 0; a < dim; a++) {
        const double u = (x[a] - s->mesh_origin[a]) / s->mesh;
        long i = (long)floor(u);
        if (i < 1) i = 1;
        if (i > s->mesh_dims[a] - 3) i = s->mesh_dims[a] - 3;
        c[a] = (int)i;
        const double t = fmin(1.0, fmax(0.0, u - (double)i)), t2 = t * t, t3 = t2 * t;
        w[a][0] = 0.5 * (-t3 + 2.0 * t2 - t);
        w[a][1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
        w[a][2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
        w[a][3] = 0.5 * (t3 - t2);
        nodes *= s->mesh_dims[a];
    }
    for (int a = 0; a < 3; a++) b[a] = 0.0;
    const int kz = dim == 3 ? 4 : 1;
    for (int k2 = 0; k2 < kz; k2++)
        for (int k1 = 0; k1 < 4; k1++)
            for (int k0 = 0; k0 < 4; k0++) {
                const double wt = w[0][k0] * w[1][k1] * (dim == 3 ? w[2][k2] : 1.0);
                if (wt == 0.0) continue;
                const long m =
                    (c[0] - 1 + k0) +
                    (long)s->mesh_dims[0] *
                        ((c[1] - 1 + k1) + (long)s->mesh_dims[1] * (dim == 3 ? c[2] - 1 + k2 : 0));
                for (int a = 0; a < dim; a++)
                    b[a] += wt * s->bmesh[(size_t)a * (size_t)nodes + (size_t)m];
            }
}

/* The body's particle spacing: dp, or a wall body's spacing_ratio dp (its
 * own lattice, scene.h), at which it relaxes: its volumes, smoothing length
 * and surface offset all follow from it. */
static double body_spacing(const sph_scene *scene, int body) {
    const double ratio = scene->bodies[body].spacing_ratio;
    return ratio > 0.0 && ratio <= 1.0 ? ratio * scene->dp : scene->dp;
}

static sph_status state_init(relax_state *s, const sph_scene *scene, int body, int n,
                             sph_error *err) {
    memset(s, 0, sizeof *s);
    s->scene = scene;
    s->dim = scene->dim;
    s->n = n;
    s->shape = scene->bodies[body].shape;
    s->dp = body_spacing(scene, body);
    s->h = scene->smoothing_ratio * s->dp;
    s->cutoff = 2.0 * s->h;
    s->volume = pow(s->dp, scene->dim);
    kernel_prm(scene->kernel, s->h, s->prm);
    s->k = sph_physics_for(scene->dim, true);
    const size_t un = (size_t)(n > 0 ? n : 1);
    s->acc = malloc((size_t)s->dim * un * sizeof *s->acc);
    s->res = malloc(un * sizeof *s->res);
    s->dmin = malloc(un * sizeof *s->dmin);
    if (!s->acc || !s->res || !s->dmin) {
        state_free(s);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of memory relaxing %d particles of body '%s'", n,
                        scene->bodies[body].name);
    }
    sph_status st = build_boundary_mesh(s, err);
    if (st) state_free(s);
    return st;
}

/* acc_i = -2 (sum_j grad_i W_ij V + G(d_i) n_i), res_i = |...| h, and each
 * particle's closest neighbour. */
static void evaluate(relax_state *s, const double *pos) {
    const int dim = s->dim, n = s->n;
    const sph_grid *g = &s->cells.grid;
#pragma omp parallel for schedule(static)
    for (int i = 0; i < n; i++) {
        double xi[3] = {0, 0, 0}, sum[3] = {0, 0, 0};
        int ci[3] = {0, 0, 0};
        for (int a = 0; a < dim; a++) {
            xi[a] = pos[(size_t)a * n + i];
            ci[a] = sph_grid_coord(g, a, xi[a]);
        }
        double dmin2 = INFINITY;
        const int zr = dim == 3 ? 1 : 0;
        for (int dz = -zr; dz <= zr; dz++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    const int c[3] = {ci[0] + dx, ci[1] + dy, ci[2] + dz};
                    bool inside = true;
                    for (int a = 0; a < dim; a++) inside &= c[a] >= 0 && c[a] < g->dims[a];
                    if (!inside) continue;
                    const long cell = c[0] + (long)g->dims[0] * (c[1] + (long)g->dims[1] * c[2]);
                    for (int q = s->cells.start[cell]; q < s->cells.start[cell + 1]; q++) {
                        const int j = s->cells.order[q];
                        if (j == i) continue;
                        double d[3] = {0, 0, 0}, r2 = 0.0;
                        for (int a = 0; a < dim; a++) {
                            d[a] = xi[a] - pos[(size_t)a * n + j];
                            r2 += d[a] * d[a];
                        }
                        if (r2 >= s->cutoff * s->cutoff) continue;
                        if (r2 < dmin2) dmin2 = r2;
                        const double r = sqrt(r2);
                        if (r <= 0.0) continue;
                        const double f = s->k->kernel_dw(s->prm, r) / r * s->volume;
                        for (int a = 0; a < dim; a++) sum[a] += f * d[a];
                    }
                }
        /* the support beyond the surface */
        double b[3];
        boundary_term(s, xi, b);
        for (int a = 0; a < dim; a++) sum[a] += b[a];
        double norm2 = 0.0;
        for (int a = 0; a < dim; a++) {
            s->acc[(size_t)a * n + i] = -2.0 * sum[a];
            norm2 += sum[a] * sum[a];
        }
        s->res[i] = sqrt(norm2) * s->h;
        s->dmin[i] = sqrt(dmin2);
    }
}

/* In-order reductions (the same bits for any thread count). */
static void summarise(const relax_state *s, double *mean, double *max, double *min_distance) {
    double sum = 0.0, mx = 0.0, dmin = INFINITY;
    for (int i = 0; i < s->n; i++) {
        sum += s->res[i];
        mx = fmax(mx, s->res[i]);
        dmin = fmin(dmin, s->dmin[i]);
    }
    *mean = s->n ? sum / s->n : 0.0;
    *max = mx;
    if (min_distance) *min_distance = dmin / s->dp;
}

/* Keep x at least dp/2 inside the surface (the reference code's
 * ShapeSurfaceBounding): move it along the normal to phi = -dp/2.  Where
 * that would leave the shape (a feature thinner than dp, a concave corner)
 * x goes back to `fallback`, a point known to be inside.  Near a convex
 * edge or corner one move clears only the nearest face and may leave x
 * within dp/2 of the next (a cylinder's rim: 0.95 dp/2 from its end face
 * after one move), so the move repeats, once per face that can meet at a
 * corner. */
static void bound_to_shape(const relax_state *s, double x[3], const double fallback[3]) {
    double normal[3];
    const double half = 0.5 * s->dp;
    for (int pass = 0; pass < s->dim; pass++) {
        const double phi = sph_shape_sdf(s->scene, s->shape, x, normal);
        if (phi <= -half) return;
        double y[3] = {x[0], x[1], x[2]};
        for (int a = 0; a < s->dim; a++) y[a] -= (phi + half) * normal[a];
        if (sph_shape_sdf(s->scene, s->shape, y, NULL) <= 0.0 &&
            sph_shape_contains(s->scene, s->shape, y)) {
            for (int a = 0; a < s->dim; a++) x[a] = y[a];
        } else {
            if (phi > 0.0 || !sph_shape_contains(s->scene, s->shape, x))
                for (int a = 0; a < s->dim; a++) x[a] = fallback[a];
            return;
        }
    }
}

sph_status sph_relax_boundary_term(const sph_scene *scene, int body, int npoints, const double *x,
                                   double *b, sph_error *err) {
    relax_state s;
    sph_status st = state_init(&s, scene, body, 1, err);
    if (st) return st;
    for (int i = 0; i < npoints; i++) boundary_term(&s, x + 3 * (size_t)i, b + 3 * (size_t)i);
    state_free(&s);
    return SPH_OK;
}

sph_status sph_relax_residual(const sph_scene *scene, int body, int n, const double *pos,
                              double *mean, double *max, double *min_distance, sph_error *err) {
    relax_state s;
    sph_status st = state_init(&s, scene, body, n, err);
    if (st) return st;
    st = sph_cell_list_build(&s.cells, s.dim, pos, s.n, s.cutoff, err);
    if (!st) {
        evaluate(&s, pos);
        summarise(&s, mean, max, min_distance);
    }
    state_free(&s);
    return st;
}

/* The largest eigenvalue of the symmetric dim x dim matrix m (row major). */
static double symmetric_max_eigenvalue(int dim, const double m[9]) {
    if (dim == 1) return m[0];
    if (dim == 2) {
        const double mean = 0.5 * (m[0] + m[3]), half = 0.5 * (m[0] - m[3]);
        return mean + sqrt(half * half + m[1] * m[1]);
    }
    /* 3 x 3: the trigonometric solution of the characteristic cubic */
    const double p1 = m[1] * m[1] + m[2] * m[2] + m[5] * m[5];
    const double q = (m[0] + m[4] + m[8]) / 3.0;
    const double p2 =
        (m[0] - q) * (m[0] - q) + (m[4] - q) * (m[4] - q) + (m[8] - q) * (m[8] - q) + 2.0 * p1;
    const double p = sqrt(p2 / 6.0);
    if (!(p > 0.0)) return q;
    double b[9];
    for (int k = 0; k < 9; k++) b[k] = (m[k] - (k % 4 == 0 ? q : 0.0)) / p;
    const double det = b[0] * (b[4] * b[8] - b[5] * b[7]) - b[1] * (b[3] * b[8] - b[5] * b[6]) +
                       b[2] * (b[3] * b[7] - b[4] * b[6]);
    const double r = fmax(-1.0, fmin(1.0, det / 2.0));
    return q + 2.0 * p * cos(acos(r) / 3.0);
}

/* The coefficient of the fixed step (relaxation.step = "fixed"): x += alpha
 * h^2 a, the form of the public code's relaxation tutorial (Delta r_i =
 * -2 alpha h^2 sum_j V_j grad W_ij, alpha about 0.2; seed-digest
 * 001/002/004, eq. 4), with alpha at most 3/4 of the step's stability limit.
 * Linearised about the body's lattice (spacing dp, volumes dp^d), a
 * displacement wave u e^{ik.x} changes a_i by -K(k) u with
 *   K(k) = 2 sum_j H(r_j) (1 - cos k.r_j) V_j,   H = W'' e e^T + (W'/r)(I - e e^T),
 * and the step is stable while alpha h^2 lambda <= 2 for every eigenvalue
 * lambda of K over the Brillouin zone.  At h = 1.3 dp the limit is alpha =
 * 0.133 for Laguerre-Gauss, 0.365 for Wendland C2 and 0.045 for
 * Laguerre-Wendland; the kernel study's disc (dp = 1/60, 1000 steps) blows up
 * between 0.12 and 0.14 and between 0.3 and 0.4 for the first two, as that
 * says (docs/kernel-study.md).  W'' by a central difference of the kernel's
 * W' (the physics source has no second derivative). */
static double fixed_step_alpha(const relax_state *s) {
    const int dim = s->dim, reach = (int)ceil(s->cutoff / s->dp);
    const double volume = pow(s->dp, dim), dr = 1e-6 * s->h;
    /* the lattice neighbours within the cut-off and their H V (2048 hold a
     * 3D support of 2h = 7.8 dp; scenes allow h <= 2 dp, the kernel study
     * h <= 4 dp in 2D) */
    enum { MAX_NEIGHBOURS = 2048 };
    double offset[MAX_NEIGHBOURS][3], hv[MAX_NEIGHBOURS][9];
    int count = 0;
    const int span = 2 * reach + 1, cells = dim == 1   ? span
                                            : dim == 2 ? span * span
                                                       : span * span * span;
    for (int c = 0; c < cells && count < MAX_NEIGHBOURS; c++) {
        int idx[3] = {c % span - reach, dim > 1 ? (c / span) % span - reach : 0,
                      dim > 2 ? c / (span * span) - reach : 0};
        double x[3] = {idx[0] * s->dp, idx[1] * s->dp, idx[2] * s->dp};
        const double r = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        if (!(r > 0.0) || r >= s->cutoff) continue;
        const double w1 = s->k->kernel_dw(s->prm, r);
        const double w2 =
            (s->k->kernel_dw(s->prm, fmin(r + dr, s->cutoff)) - s->k->kernel_dw(s->prm, r - dr)) /
            (fmin(r + dr, s->cutoff) - (r - dr));
        for (int a = 0; a < dim; a++) {
            offset[count][a] = x[a];
            for (int b = 0; b < dim; b++) {
                const double ee = x[a] * x[b] / (r * r);
                hv[count][a * 3 + b] = (w2 * ee + w1 / r * ((a == b) - ee)) * volume;
            }
        }
        count++;
    }
    /* lambda_max over k in [0, pi/dp]^d (K is even in each component of k
     * on the square lattice) */
    const int nk = dim == 1 ? 401 : dim == 2 ? 41 : 17;
    const int points = dim == 1 ? nk : dim == 2 ? nk * nk : nk * nk * nk;
    double lambda = 0.0;
    for (int p = 0; p < points; p++) {
        const int kk[3] = {p % nk, dim > 1 ? (p / nk) % nk : 0, dim > 2 ? p / (nk * nk) : 0};
        double kvec[3], m[9] = {0};
        for (int a = 0; a < 3; a++) kvec[a] = kk[a] * 3.14159265358979323846 / ((nk - 1) * s->dp);
        for (int j = 0; j < count; j++) {
            double phase = 0.0;
            for (int a = 0; a < dim; a++) phase += kvec[a] * offset[j][a];
            const double f = 2.0 * (1.0 - cos(phase));
            for (int a = 0; a < dim; a++)
                for (int b = 0; b < dim; b++) m[a * dim + b] += f * hv[j][a * 3 + b];
        }
        lambda = fmax(lambda, symmetric_max_eigenvalue(dim, m));
    }
    const double limit = lambda > 0.0 ? 2.0 / (s->h * s->h * lambda) : INFINITY;
    return fmin(0.2, 0.75 * limit);
}

/* splitmix64 (Steele, Lea & Flood 2014): a counter-based stream, so the
 * offset of particle i depends only on the seed and i. */
static uint64_t splitmix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

sph_status sph_relax_positions(const sph_scene *scene, int body, int n, double *pos,
                               sph_relax_report *rep, sph_error *err) {
    const double t0 = sph_wall_seconds();
    const sph_relaxation *rx = &scene->bodies[body].relaxation;
    relax_state s;
    sph_status st = state_init(&s, scene, body, n, err);
    if (st) return st;
    const int dim = s.dim;
    rep->relaxed = true;
    rep->particles = n;
    if ((st = sph_cell_list_build(&s.cells, s.dim, pos, s.n, s.cutoff, err))) goto done;
    evaluate(&s, pos);
    summarise(&s, &rep->lattice_mean, &rep->lattice_max, NULL);

    /* the seeded offset, up to perturbation * dp per axis, kept inside */
    for (int i = 0; i < n; i++) {
        double x[3] = {0, 0, 0}, lattice[3] = {0, 0, 0};
        for (int a = 0; a < dim; a++) {
            const uint64_t bits = splitmix64((uint64_t)rx->seed * 0x100000001b3ULL ^
                                             ((uint64_t)i * 4u + (uint64_t)a));
            const double u = (double)(bits >> 11) * 0x1.0p-53 * 2.0 - 1.0; /* [-1, 1) */
            lattice[a] = pos[(size_t)a * n + i];
            x[a] = lattice[a] + u * rx->perturbation * s.dp;
        }
        bound_to_shape(&s, x, lattice);
        for (int a = 0; a < dim; a++) pos[(size_t)a * n + i] = x[a];
    }

    int step = 0;
    double amax_start = 0.0;
    rep->step_alpha = rx->step == SPH_RELAX_STEP_FIXED ? fixed_step_alpha(&s) : 0.0;
    for (;; step++) {
        if ((st = sph_cell_list_build(&s.cells, s.dim, pos, s.n, s.cutoff, err))) goto done;
        evaluate(&s, pos);
        double mean, max, dmin;
        summarise(&s, &mean, &max, &dmin);
        if (step == 0) rep->start_mean = mean, rep->start_max = max;
        rep->mean = mean, rep->max = max, rep->min_distance = dmin;
        if (step >= rx->steps || mean <= rx->tolerance) break;
        /* dt^2 = h / (16 max|a|), the reference code's step: the largest
         * move is h/32.  Once max|a| has fallen below a tenth of its start,
         * dt stays where it is, so the moves shrink with the forces and the
         * particles settle instead of jittering by h/32 for ever (annulus,
         * dp = 0.002, 1000 steps: mean residual 0.0049 against 0.0119, and
         * the same at 2000 steps) */
        double amax2 = 0.0;
        for (int i = 0; i < n; i++) {
            double a2 = 0.0;
            for (int a = 0; a < dim; a++) a2 += s.acc[(size_t)a * n + i] * s.acc[(size_t)a * n + i];
            amax2 = fmax(amax2, a2);
        }
        if (!(amax2 > 0.0)) break;
        if (step == 0) amax_start = sqrt(amax2);
        const double dt2 = rx->step == SPH_RELAX_STEP_FIXED
                               ? 2.0 * rep->step_alpha * s.h * s.h
                               : 0.0625 * s.h / fmax(sqrt(amax2), 0.1 * amax_start);
#pragma omp parallel for schedule(static)
        for (int i = 0; i < n; i++) {
            double x[3] = {0, 0, 0}, old[3] = {0, 0, 0};
            for (int a = 0; a < dim; a++) {
                old[a] = pos[(size_t)a * n + i];
                x[a] = old[a] + 0.5 * dt2 * s.acc[(size_t)a * n + i];
            }
            bound_to_shape(&s, x, old);
            for (int a = 0; a < dim; a++) pos[(size_t)a * n + i] = x[a];
        }
    }
    rep->steps = step;
    rep->seconds = sph_wall_seconds() - t0;
done:
    state_free(&s);
    return st;
}

/* ------------------------------------------------------------------------ */
/* the saved result                                                           */
/* ------------------------------------------------------------------------ */

/* The scene's word for a step rule (bodies.relaxation.step). */
static const char *relax_step_name(sph_relax_step step) {
    return step == SPH_RELAX_STEP_FIXED ? "fixed" : "normalised";
}

static void hash_hex(uint64_t h, char buf[17]) {
    snprintf(buf, 17, "%016" PRIx64, h);
}

/* Does the file at rx->file hold this body's relaxed particles?  On a
 * match the positions go to pos and the report gets the file's figures;
 * otherwise rep->note says why not. */
static bool read_matching(const sph_scene *scene, int body, const double origin[3], int n,
                          double *pos, sph_relax_report *rep) {
    const sph_body *b = &scene->bodies[body];
    const sph_relaxation *rx = &b->relaxation;
    const char *path = rx->file;
    sph_error err = {0};
    hid_t f = -1;
    if (access(path, F_OK) != 0) {
        sph_format(rep->note, sizeof rep->note, "no file yet");
        return false;
    }
    if (sph_h5_open_read(path, &f, &err)) {
        sph_format(rep->note, sizeof rep->note, "%s", err.msg);
        return false;
    }
    bool ok = false;
    char *format = NULL, *kernel = NULL, *shape_hash = NULL, *step_rule = NULL;
    double *rows = NULL;
    int64_t version = 0, dimension = 0, count = 0, seed = 0, steps = 0, taken = 0;
    double dp = 0, ratio = 0, tolerance = 0, perturbation = 0, o[3] = {0, 0, 0};
    static const char *const origin_names[3] = {"lattice_origin_x", "lattice_origin_y",
                                                "lattice_origin_z"};
    sph_status st = sph_h5_read_attr_string(f, path, "format", &format, &err);
    if (!st && strcmp(format, FILE_FORMAT) != 0) {
        sph_format(rep->note, sizeof rep->note, "%s is not a relaxed-particle file (format '%s')",
                   path, format);
        goto out;
    }
    if (!st) st = sph_h5_read_attr_int64(f, path, "version", &version, &err);
    if (!st) st = sph_h5_read_attr_int64(f, path, "dimension", &dimension, &err);
    if (!st) st = sph_h5_read_attr_int64(f, path, "particle_count", &count, &err);
    if (!st) st = sph_h5_read_attr_double(f, path, "dp", &dp, &err);
    if (!st) st = sph_h5_read_attr_double(f, path, "smoothing_ratio", &ratio, &err);
    if (!st) st = sph_h5_read_attr_string(f, path, "kernel", &kernel, &err);
    if (!st) st = sph_h5_read_attr_int64(f, path, "seed", &seed, &err);
    if (!st) st = sph_h5_read_attr_int64(f, path, "steps", &steps, &err);
    if (!st) st = sph_h5_read_attr_double(f, path, "tolerance", &tolerance, &err);
    if (!st) st = sph_h5_read_attr_double(f, path, "perturbation", &perturbation, &err);
    if (!st) st = sph_h5_read_attr_string(f, path, "shape_hash", &shape_hash, &err);
    for (int a = 0; a < scene->dim && !st; a++)
        st = sph_h5_read_attr_double(f, path, origin_names[a], &o[a], &err);
    if (st) {
        sph_format(rep->note, sizeof rep->note, "%s", err.msg);
        goto out;
    }
    char hash[17];
    hash_hex(sph_shape_hash(scene, b->shape), hash);
    /* the first difference, in words */
#define DIFFERS(cond, ...)                                                                         \
    if (cond) {                                                                                    \
        sph_format(rep->note, sizeof rep->note, __VA_ARGS__);                                      \
        goto out;                                                                                  \
    }
    DIFFERS(version != FILE_VERSION, "file version %" PRId64 ", this program writes %d", version,
            FILE_VERSION);
    DIFFERS(dimension != scene->dim, "dimension differs (file %" PRId64 ", scene %d)", dimension,
            scene->dim);
    DIFFERS(dp != body_spacing(scene, body), "dp differs (file %.17g, scene %.17g)", dp,
            body_spacing(scene, body));
    DIFFERS(ratio != scene->smoothing_ratio, "smoothing ratio differs (file %.17g, scene %.17g)",
            ratio, scene->smoothing_ratio);
    DIFFERS(strcmp(kernel, sph_kernel_name(scene->kernel)) != 0,
            "kernel differs (file %s, scene %s)", kernel, sph_kernel_name(scene->kernel));
    DIFFERS(strcmp(shape_hash, hash) != 0,
            "the shape '%s' differs from the one relaxed (shape hash %s in the file, %s now)",
            scene->shapes[b->shape].name, shape_hash, hash);
    /* the file keeps the seed's 64 bits in a signed attribute */
    DIFFERS((uint64_t)seed != rx->seed, "seed differs (file %" PRIu64 ", scene %" PRIu64 ")",
            (uint64_t)seed, rx->seed);
    DIFFERS(perturbation != rx->perturbation, "perturbation differs (file %.17g, scene %.17g)",
            perturbation, rx->perturbation);
    DIFFERS(steps != rx->steps, "steps differ (file %" PRId64 ", scene %d)", steps, rx->steps);
    /* a version-2 file has it */
    if (sph_h5_read_attr_string(f, path, "step", &step_rule, &err)) {
        sph_format(rep->note, sizeof rep->note, "%s", err.msg);
        goto out;
    }
    DIFFERS(strcmp(step_rule, relax_step_name(rx->step)) != 0,
            "the step's rule differs (file %s, scene %s)", step_rule, relax_step_name(rx->step));
    DIFFERS(tolerance != rx->tolerance, "tolerance differs (file %.17g, scene %.17g)", tolerance,
            rx->tolerance);
    for (int a = 0; a < scene->dim; a++)
        DIFFERS(o[a] != origin[a], "lattice origin differs along %c (file %.17g, scene %.17g)",
                "xyz"[a], o[a], origin[a]);
    DIFFERS(count != n, "particle count differs (file %" PRId64 ", lattice %d)", count, n);
#undef DIFFERS
    rows = malloc((size_t)n * (size_t)scene->dim * sizeof *rows + 1);
    if (!rows) {
        sph_format(rep->note, sizeof rep->note, "out of memory reading %s", path);
        goto out;
    }
    if (sph_h5_read(f, path, "position", H5T_NATIVE_DOUBLE, rows, (size_t)n * (size_t)scene->dim,
                    &err)) {
        sph_format(rep->note, sizeof rep->note, "%s", err.msg);
        goto out;
    }
    for (int i = 0; i < n; i++) {
        double x[3] = {0, 0, 0};
        for (int a = 0; a < scene->dim; a++) x[a] = rows[(size_t)i * scene->dim + a];
        if (!(isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2])) ||
            !sph_shape_contains(scene, b->shape, x)) {
            sph_format(rep->note, sizeof rep->note,
                       "%s: particle %d at (%g, %g, %g) lies outside the shape", path, i, x[0],
                       x[1], x[2]);
            goto out;
        }
    }
    for (int i = 0; i < n; i++)
        for (int a = 0; a < scene->dim; a++)
            pos[(size_t)a * n + i] = rows[(size_t)i * scene->dim + a];
    /* the file's record of its relaxation (for the report only) */
    if (!sph_h5_read_attr_int64(f, path, "steps_taken", &taken, &err)) rep->steps = (int)taken;
    sph_h5_read_attr_double(f, path, "residual_lattice_mean", &rep->lattice_mean, &err);
    sph_h5_read_attr_double(f, path, "residual_lattice_max", &rep->lattice_max, &err);
    sph_h5_read_attr_double(f, path, "residual_start_mean", &rep->start_mean, &err);
    sph_h5_read_attr_double(f, path, "residual_start_max", &rep->start_max, &err);
    sph_h5_read_attr_double(f, path, "residual_mean", &rep->mean, &err);
    sph_h5_read_attr_double(f, path, "residual_max", &rep->max, &err);
    sph_h5_read_attr_double(f, path, "min_distance", &rep->min_distance, &err);
    ok = true;
out:
    free(rows);
    free(format);
    free(kernel);
    free(step_rule);
    free(shape_hash);
    H5Fclose(f);
    return ok;
}

static sph_status write_file(const sph_scene *scene, int body, const double origin[3], int n,
                             const double *pos, const sph_relax_report *rep, sph_error *err) {
    const sph_body *b = &scene->bodies[body];
    const sph_relaxation *rx = &b->relaxation;
    const int dim = scene->dim;
    double *rows = malloc((size_t)n * (size_t)dim * sizeof *rows + 1);
    if (!rows) return sph_fail(err, SPH_ERR_RUNTIME, "out of memory writing %s", rx->file);
    for (int i = 0; i < n; i++)
        for (int a = 0; a < dim; a++) rows[(size_t)i * dim + a] = pos[(size_t)a * n + i];
    sph_h5_writer w;
    sph_status st = sph_h5_create(&w, rx->file, err);
    if (st) {
        free(rows);
        return st;
    }
    char hash[17];
    hash_hex(sph_shape_hash(scene, b->shape), hash);
    const hsize_t dims[2] = {(hsize_t)n, (hsize_t)dim};
    const int64_t version = FILE_VERSION, dimension = dim, count = n, seed = (int64_t)rx->seed,
                  steps = rx->steps, taken = rep->steps;
    static const char *const origin_names[3] = {"lattice_origin_x", "lattice_origin_y",
                                                "lattice_origin_z"};
    const hid_t root = w.file;
    st = sph_h5_write(&w, root, "position", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 2, dims, rows, err);
    if (!st) st = sph_h5_attr_string(&w, root, "format", FILE_FORMAT, err);
    if (!st) st = sph_h5_attr_int64s(&w, root, "version", &version, 1, err);
    if (!st) st = sph_h5_attr_int64s(&w, root, "dimension", &dimension, 1, err);
    if (!st) st = sph_h5_attr_int64s(&w, root, "particle_count", &count, 1, err);
    if (!st) st = sph_h5_attr_double(&w, root, "dp", body_spacing(scene, body), err);
    if (!st) st = sph_h5_attr_double(&w, root, "smoothing_ratio", scene->smoothing_ratio, err);
    if (!st) st = sph_h5_attr_string(&w, root, "kernel", sph_kernel_name(scene->kernel), err);
    if (!st) st = sph_h5_attr_int64s(&w, root, "seed", &seed, 1, err);
    if (!st) st = sph_h5_attr_int64s(&w, root, "steps", &steps, 1, err);
    if (!st) st = sph_h5_attr_string(&w, root, "step", relax_step_name(rx->step), err);
    if (!st) st = sph_h5_attr_double(&w, root, "tolerance", rx->tolerance, err);
    if (!st) st = sph_h5_attr_double(&w, root, "perturbation", rx->perturbation, err);
    if (!st) st = sph_h5_attr_string(&w, root, "shape_hash", hash, err);
    if (!st) st = sph_h5_attr_string(&w, root, "shape", scene->shapes[b->shape].name, err);
    if (!st) st = sph_h5_attr_string(&w, root, "body", b->name, err);
    for (int a = 0; a < dim && !st; a++)
        st = sph_h5_attr_double(&w, root, origin_names[a], origin[a], err);
    if (!st) st = sph_h5_attr_int64s(&w, root, "steps_taken", &taken, 1, err);
    if (!st) st = sph_h5_attr_double(&w, root, "residual_lattice_mean", rep->lattice_mean, err);
    if (!st) st = sph_h5_attr_double(&w, root, "residual_lattice_max", rep->lattice_max, err);
    if (!st) st = sph_h5_attr_double(&w, root, "residual_start_mean", rep->start_mean, err);
    if (!st) st = sph_h5_attr_double(&w, root, "residual_start_max", rep->start_max, err);
    if (!st) st = sph_h5_attr_double(&w, root, "residual_mean", rep->mean, err);
    if (!st) st = sph_h5_attr_double(&w, root, "residual_max", rep->max, err);
    if (!st) st = sph_h5_attr_double(&w, root, "min_distance", rep->min_distance, err);
    free(rows);
    if (st) {
        sph_h5_abandon(&w);
        return st;
    }
    return sph_h5_commit(&w, true, err);
}

sph_status sph_relax_body(const sph_scene *scene, int body, const double origin[3], int n,
                          double *pos, bool force, sph_relax_report *rep, sph_error *err) {
    memset(rep, 0, sizeof *rep);
    rep->relaxed = true;
    rep->particles = n;
    const sph_relaxation *rx = &scene->bodies[body].relaxation;
    if (rx->file[0]) {
        if (force)
            sph_format(rep->note, sizeof rep->note, "regeneration forced");
        else if (read_matching(scene, body, origin, n, pos, rep)) {
            rep->reused = true;
            return SPH_OK;
        }
    }
    char note[sizeof rep->note];
    memcpy(note, rep->note, sizeof note);
    sph_status st = sph_relax_positions(scene, body, n, pos, rep, err);
    if (st) return st;
    memcpy(rep->note, note, sizeof note);
    if (!rx->file[0]) return SPH_OK;
    st = write_file(scene, body, origin, n, pos, rep, err);
    if (st)
        return sph_error_prefix(err,
                                "%s: saving the relaxed particles: ", scene->bodies[body].where);
    rep->written = true;
    return SPH_OK;
}

void sph_relax_report_format(const sph_relax_report *rep, const char *body, const char *file,
                             char *buf, size_t len) {
    char what[1400];
    if (rep->reused)
        sph_format(what, sizeof what, "reused from %s", file);
    else if (rep->written)
        sph_format(what, sizeof what, "saved to %s%s%s%s", file, rep->note[0] ? " (" : "",
                   rep->note, rep->note[0] ? ")" : "");
    else
        sph_format(what, sizeof what, "not saved (no relaxation.file)");
    sph_format(buf, len,
               "body '%s': %d relaxed particles, %d steps; residual mean %.4g, max %.4g "
               "(lattice %.4g, %.4g; perturbed start %.4g, %.4g); closest pair %.3f dp; %s",
               body, rep->particles, rep->steps, rep->mean, rep->max, rep->lattice_mean,
               rep->lattice_max, rep->start_mean, rep->start_max, rep->min_distance, what);
    if (!rep->reused) {
        const size_t used = strlen(buf);
        if (used < len) sph_format(buf + used, len - used, "; %.2f s", rep->seconds);
    }
}
