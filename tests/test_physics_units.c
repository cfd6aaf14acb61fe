/* test_physics_units.c — unit checks of the shared physics helpers (the
 * device/ source as compiled for the native backend, both precisions):
 *  - the four smoothing kernels (Wendland C2, truncated Laguerre-Gauss,
 *    Laguerre-Wendland, cubic B-spline): int W dV by radial quadrature
 *    against closed forms (1, or the Laguerre-Gauss truncation deficit),
 *    lattice sums, W(0) = alpha_d, support 2h, dW/dr against W (2D, 3D,
 *    both precisions);
 *  - the correction matrix B on a lattice interior (003 eq. 21);
 *  - Rodrigues' rotation (003 eqs. 38-40): orthogonal, det 1, a rotation by
 *    |omega| dt about omega;
 *  - the Riemann pair terms: momentum terms antisymmetric under i <-> j,
 *    continuity symmetric (what makes linear momentum exact);
 *  - the rigid wall's plane integral of the kernel Sigma(d) (sph_wall.h)
 *    against a fine sum over the plane, and int_0^2h Sigma dd = 1/2 (the
 *    half-space holds half the kernel).
 */
#include "physics.h"
#include "test_support.h"

#include <math.h>

#ifndef M_PI
#    define M_PI 3.14159265358979323846
#endif

/* The four smoothing kernels of device/sph_smoothing_kernel.h, selected by
 * prm->smoothing_kernel as the scene key method.kernel does. */
static const int KERNELS[] = {KERNEL_WENDLAND_C2, KERNEL_LAGUERRE_GAUSS, KERNEL_LAGUERRE_WENDLAND,
                              KERNEL_CUBIC_BSPLINE};
static const char *const KERNEL_LABELS[] = {"wendland-c2", "laguerre-gauss", "laguerre-wendland",
                                            "cubic-bspline"};
#define NKERNELS ((int)(sizeof KERNELS / sizeof KERNELS[0]))

/* The published normalisation constants alpha_d h^d (W(0) = alpha_d f(0),
 * f(0) = 1 for all four): Wendland C2 7/(4 pi), 21/(16 pi); Laguerre-Gauss
 * (004 eq. 8) 3/pi, 8/pi^(3/2); Laguerre-Wendland (Litvinov et al. 2015, unit
 * support sigma 1287/(47 pi), 9009/(64 pi), rescaled to support 2h by
 * 2^-d); cubic B-spline (Monaghan & Lattanzio 1985) 10/(7 pi), 1/pi. */
static double published_alpha(int kernel, int dim, double h) {
    const double hd = dim == 2 ? h * h : h * h * h;
    switch (kernel) {
    case KERNEL_LAGUERRE_GAUSS:
        return (dim == 2 ? 3.0 / M_PI : 8.0 / pow(M_PI, 1.5)) / hd;
    case KERNEL_LAGUERRE_WENDLAND:
        return (dim == 2 ? 1287.0 / (47.0 * M_PI) / 4.0 : 9009.0 / (64.0 * M_PI) / 8.0) / hd;
    case KERNEL_CUBIC_BSPLINE:
        return (dim == 2 ? 10.0 / (7.0 * M_PI) : 1.0 / M_PI) / hd;
    default:
        return (dim == 2 ? 7.0 / (4.0 * M_PI) : 21.0 / (16.0 * M_PI)) / hd;
    }
}

/* int W dV over the support, in closed form.  1 for the compactly supported
 * kernels.  The truncated Laguerre-Gauss kernel keeps the alphas of the
 * untruncated one (004 eq. 8), so it integrates to
 *   2D: 2 pi alpha_2 int_0^2 f q dq = 3 int_0^4 (1 - u + u^2/6) e^-u du
 *       = 1 - e^-4  (antiderivative -(1/3 - 2u/3 + u^2/6) e^-u);
 *   3D: 4 pi alpha_3 int_0^2 f q^2 dq = (32/sqrt(pi)) (J2 - J4 + J6/6) with
 *       J_n = int_0^2 q^n e^(-q^2) dq, J0 = (sqrt(pi)/2) erf 2,
 *       J_(n+2) = ((n+1)/2) J_n - 2^n e^-4, i.e. erf 2 - 44 e^-4/(3 sqrt(pi)). */
static double exact_integral(int kernel, int dim) {
    if (kernel != KERNEL_LAGUERRE_GAUSS) return 1.0;
    const double e4 = exp(-4.0);
    if (dim == 2) return 1.0 - e4;
    const double j0 = 0.5 * sqrt(M_PI) * erf(2.0);
    const double j2 = 0.5 * j0 - 1.0 * e4;
    const double j4 = 1.5 * j2 - 4.0 * e4;
    const double j6 = 2.5 * j4 - 16.0 * e4;
    return 32.0 / sqrt(M_PI) * (j2 - j4 + j6 / 6.0);
}

/* int_0^2h W(r) S_d r^(d-1) dr by composite 5-point Gauss-Legendre on 400
 * panels (breakpoints at r = h for the B-spline's pieces; the nodes never
 * touch r = 2h, where the truncated Laguerre-Gauss kernel jumps). */
static double radial_integral(const sph_physics *k, const sph_params_f64 *prm) {
    static const double x[5] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640,
                                0.9061798459386640};
    static const double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                0.2369268850561891, 0.2369268850561891};
    const double rc = 2.0 * prm->h;
    const int panels = 400;
    const double len = rc / panels;
    double sum = 0.0;
    for (int p = 0; p < panels; ++p) {
        const double mid = (p + 0.5) * len;
        for (int g = 0; g < 5; ++g) {
            const double r = mid + 0.5 * len * x[g];
            const double shell = k->dim == 2 ? 2.0 * M_PI * r : 4.0 * M_PI * r * r;
            sum += w[g] * k->kernel_w(prm, r) * shell;
        }
    }
    return sum * 0.5 * len;
}

/* sum over a lattice of spacing delta of W(|x|) delta^d; *inside: delta^d
 * times the number of lattice points with r <= 2h */
static double lattice_integral(const sph_physics *k, const sph_params_f64 *prm, double delta,
                               double *inside) {
    const double cutoff = prm->cutoff, h = prm->h;
    const int m = (int)ceil(cutoff / delta) + 1;
    const double dv = k->dim == 2 ? delta * delta : delta * delta * delta;
    double sum = 0.0;
    long count = 0;
    for (int a = -m; a <= m; ++a)
        for (int b = -m; b <= m; ++b)
            for (int c = (k->dim == 3 ? -m : 0); c <= (k->dim == 3 ? m : 0); ++c) {
                const double r = delta * sqrt((double)(a * a + b * b + c * c));
                sum += k->kernel_w(prm, r);
                count += r / h <= 2.0;
            }
    if (inside) *inside = (double)count * dv;
    return sum * dv;
}

/* |sum W V - int W dV| on the particle lattice itself (delta = dp,
 * h = 1.3 dp): the kernel's own lattice quadrature error.  Bounds are ~1.2x
 * the values measured in a run (double; single agrees to 1e-7):
 *   wendland-c2        2D +1.047e-2   3D +9.50e-3
 *   laguerre-gauss     2D -7.43e-3    3D -4.71e-2   (about the truncated integral)
 *   laguerre-wendland  2D +7.24e-2    3D +3.05e-1   (004 §2.2: too few neighbours
 *                                                    at kappa = 1.3 for its slopes)
 *   cubic-bspline      2D -5.3e-5     3D -2.74e-3 */
static double particle_lattice_bound(int kernel, int dim) {
    switch (kernel) {
    case KERNEL_LAGUERRE_GAUSS:
        return dim == 2 ? 9e-3 : 5.7e-2;
    case KERNEL_LAGUERRE_WENDLAND:
        return dim == 2 ? 8.7e-2 : 3.7e-1;
    case KERNEL_CUBIC_BSPLINE:
        return dim == 2 ? 7e-5 : 3.3e-3;
    default:
        return dim == 2 ? 1.3e-2 : 1.2e-2;
    }
}

static void check_kernels(test_counts *t) {
    for (int kk = 0; kk < NKERNELS; ++kk) {
        const int kernel = KERNELS[kk];
        const char *name = KERNEL_LABELS[kk];
        for (int dim = 2; dim <= 3; ++dim) {
            sph_params_f64 prm[1];
            test_params(prm, dim, 1.0, 1.0);
            prm->smoothing_kernel = kernel;
            const double h = prm->h, dp = prm->dp;
            const double exact = exact_integral(kernel, dim);
            const bool lg = kernel == KERNEL_LAGUERRE_GAUSS;
            char what[160];
            for (int prec = 1; prec >= 0; --prec) {
                const sph_physics *k = sph_physics_for(dim, prec == 1);
                const char *pname = prec ? "double" : "single";
                /* continuous integral: the kernel code integrates to 1 (to
                 * the truncation deficit for Laguerre-Gauss).  Single
                 * precision kernel values carry ~1e-7 relative rounding. */
                const double integral = radial_integral(k, prm);
                snprintf(what, sizeof what, "%s %dD %s: int W dV over r < 2h", name, dim, pname);
                CHECK_NEAR(t, integral, exact, prec ? (lg ? 1e-8 : 1e-6) : 1e-6, what);
                /* a fine lattice (h/delta = 40.3 in 2D, 20.3 in 3D: no
                 * lattice point at exactly r = 2h) converges to the integral.
                 * The truncated Laguerre-Gauss kernel jumps by -W(2h) at the
                 * cut-off, so its lattice sum carries W(2h) times the lattice
                 * miscount of the disc/ball (delta^d N - V_d (2h)^d; measured
                 * 9.4e-5 2D, 3.5e-4 3D); that term is added to the integral,
                 * leaving the quadrature error of a kinked integrand
                 * (measured 1.0e-6 in 3D). */
                double inside = 0.0;
                const double fine = lattice_integral(k, prm, h / (dim == 2 ? 40.3 : 20.3), &inside);
                const double rc = 2.0 * h;
                const double ball = dim == 2 ? M_PI * rc * rc : 4.0 / 3.0 * M_PI * rc * rc * rc;
                const double w_jump = lg ? k->kernel_w(prm, rc) : 0.0;
                snprintf(what, sizeof what, "%s %dD %s: fine-lattice sum W dV", name, dim, pname);
                CHECK_NEAR(t, fine, exact + w_jump * (inside - ball), lg ? 3e-6 : 1e-6, what);
                /* the particle lattice itself, h = 1.3 dp */
                const double coarse = lattice_integral(k, prm, dp, NULL);
                snprintf(what, sizeof what, "%s %dD %s: sum W V at h = 1.3 dp", name, dim, pname);
                CHECK_NEAR(t, coarse, exact, particle_lattice_bound(kernel, dim), what);
                if (prec)
                    printf("%-17s %dD: int W dV = %.12f, fine lattice %.9f, sum W V (h = 1.3 dp) "
                           "= %.9f\n",
                           name, dim, integral, fine, coarse);
                /* W(0) = alpha_d f(0), f(0) = 1: the published constants */
                const double alpha = published_alpha(kernel, dim, h);
                snprintf(what, sizeof what, "%s %dD %s: W(0) = alpha_d", name, dim, pname);
                CHECK_NEAR(t, k->kernel_w(prm, 0.0), alpha, (prec ? 1e-14 : 1e-6) * alpha, what);
                /* support: W = dW = 0 at the cut-off (the truncated Laguerre-
                 * Gauss kernel keeps its formula value there, alpha f(2) with
                 * f(2) = -e^-4/3 and f'(2) = (8/3) e^-4, and is 0 beyond) */
                const double w_cut = k->kernel_w(prm, 2.0 * h);
                const double dw_cut = k->kernel_dw(prm, 2.0 * h);
                if (lg) {
                    const double e4 = exp(-4.0);
                    snprintf(what, sizeof what, "%s %dD %s: W(2h) = -alpha e^-4/3", name, dim,
                             pname);
                    CHECK_NEAR(t, w_cut, -alpha * e4 / 3.0, (prec ? 1e-13 : 1e-6) * alpha * e4,
                               what);
                    snprintf(what, sizeof what, "%s %dD %s: dW/dr(2h) = alpha (8/3) e^-4 / h", name,
                             dim, pname);
                    CHECK_NEAR(t, dw_cut, alpha * 8.0 / 3.0 * e4 / h,
                               (prec ? 1e-13 : 1e-6) * alpha * e4 / h, what);
                } else {
                    CHECK(t, w_cut == 0.0 && dw_cut == 0.0,
                          "%s %dD %s: kernel must vanish at the cut-off (W %g, dW %g)", name, dim,
                          pname, w_cut, dw_cut);
                }
                const double beyond[3] = {2.0 * h * (1.0 + 1e-6), 2.5 * h, 4.0 * h};
                for (int b = 0; b < 3; ++b)
                    CHECK(t,
                          k->kernel_w(prm, beyond[b]) == 0.0 && k->kernel_dw(prm, beyond[b]) == 0.0,
                          "%s %dD %s: W and dW/dr must be 0 at r = %g h > 2h", name, dim, pname,
                          beyond[b] / h);
                CHECK(t, k->kernel_dw(prm, 0.7 * h) < 0.0,
                      "%s %dD %s: dW/dr must be negative at r = 0.7h", name, dim, pname);
            }
            /* dW/dr is the derivative of W: central difference, double
             * precision, at points away from the zeros of f' (Laguerre-Gauss
             * q = sqrt 2; Laguerre-Wendland q = 0.94, 1.55) and from the
             * B-spline's joint at q = 1 */
            const sph_physics *k = sph_physics_for(dim, true);
            const double qs[6] = {0.13, 0.5, 0.83, 1.2, 1.65, 1.9};
            for (int a = 0; a < 6; ++a) {
                const double r = qs[a] * h, e = 1e-6 * h;
                const double fd = (k->kernel_w(prm, r + e) - k->kernel_w(prm, r - e)) / (2 * e);
                snprintf(what, sizeof what, "%s %dD: dW/dr against finite difference at r = %.2fh",
                         name, dim, qs[a]);
                CHECK_NEAR(t, k->kernel_dw(prm, r), fd, 1e-6 * fabs(fd), what);
                /* single precision follows double */
                const sph_physics *kf = sph_physics_for(dim, false);
                snprintf(what, sizeof what, "%s %dD: single-precision dW/dr at r = %.2fh", name,
                         dim, qs[a]);
                CHECK_NEAR(t, kf->kernel_dw(prm, r), k->kernel_dw(prm, r),
                           1e-5 * fabs(k->kernel_dw(prm, r)) +
                               1e-7 * fabs(k->kernel_dw(prm, 0.5 * h)),
                           what);
            }
        }
    }
}

/* B on the interior of a square / cubic lattice from a real rebuild. */
static void check_correction_matrix(test_counts *t, sph_backend_kind kind) {
    for (int dim = 2; dim <= 3; ++dim) {
        const int side = dim == 2 ? 20 : 12;
        const int n = dim == 2 ? side * side : side * side * side;
        const double dp = 0.1;
        sph_particles p;
        if (test_particles_alloc(&p, n, dim, 1000.0, dp)) {
            CHECK(t, 0, "allocation");
            return;
        }
        for (int i = 0; i < n; ++i) {
            int rest = i;
            for (int a = 0; a < dim; ++a) {
                p.pos[(size_t)a * n + i] = (rest % side + 0.5) * dp;
                rest /= side;
            }
        }
        sph_features f;
        test_feature_set(&f, dim, true, SPH_ROTATION_NONE);
        sph_params_f64 prm[1];
        test_params(prm, dim, dp, n);
        sph_backend *be = NULL;
        sph_error err = {0};
        sph_rebuild_info info;
        sph_status st = test_backend(kind, &f, prm, n, &be, &err);
        if (!st) st = be->ops->upload(be, &p, &err);
        if (!st) st = be->ops->rebuild(be, &info, &err);
        const int nsym = dim * (dim + 1) / 2;
        double *b = malloc((size_t)n * nsym * sizeof(double));
        double *x = malloc((size_t)n * dim * sizeof(double));
        if (!st) st = be->ops->download(be, FIELD_BMAT, b, &err);
        if (!st) st = be->ops->download(be, FIELD_POS, x, &err);
        CHECK(t, st == SPH_OK, "rebuild on a lattice: %s", err.msg);
        if (!st) {
            /* The centre particle.  B is the inverse of the discrete second
             * moment A = -sum r dW V e(x)e, which on a lattice equals I only
             * up to the quadrature error of the lattice sum: for h = 1.3 dp it
             * is A = 0.97392 I (2D) and 0.97890 I (3D), so B = 1.02678 I and
             * 1.02156 I (independently summed below; the reference code has
             * the same B).  Checks: B isotropic and symmetric by lattice
             * symmetry, equal to the independently summed A^-1, within 3 % of I. */
            int centre = -1;
            double best = 1e30;
            for (int i = 0; i < n; ++i) {
                double r2 = 0.0;
                for (int a = 0; a < dim; ++a) {
                    const double dx = x[(size_t)a * n + i] - 0.5 * side * dp;
                    r2 += dx * dx;
                }
                if (r2 < best) best = r2, centre = i;
            }
            const double h = prm->h;
            const double alpha =
                dim == 2 ? 7.0 / (4.0 * M_PI * h * h) : 21.0 / (16.0 * M_PI * h * h * h);
            double axx = 0.0;
            for (int a = -4; a <= 4; ++a)
                for (int bb = -4; bb <= 4; ++bb)
                    for (int c = (dim == 3 ? -4 : 0); c <= (dim == 3 ? 4 : 0); ++c) {
                        const double r = dp * sqrt((double)(a * a + bb * bb + c * c));
                        const double q = r / h;
                        if (r == 0.0 || q >= 2.0) continue;
                        const double dw = alpha * (-5.0 * q * pow(1.0 - 0.5 * q, 3)) / h;
                        const double ex = a * dp / r;
                        axx += -r * dw * pow(dp, dim) * ex * ex;
                    }
            const double bxx = b[0 * n + centre];
            const double bxy = b[1 * n + centre];
            const double byy = b[(dim == 2 ? 2 : 3) * n + centre];
            /* Tikhonov inverse (A^2 + eps I)^-1 A with eps = 1e-8 */
            CHECK_NEAR(t, bxx, axx / (axx * axx + 1e-8), 1e-12,
                       "interior B_xx against the lattice sum");
            CHECK_NEAR(t, bxx, 1.0, 0.03, "interior B within the lattice quadrature error of I");
            CHECK_NEAR(t, byy, bxx, 1e-12, "interior B isotropic (B_yy = B_xx)");
            CHECK_NEAR(t, bxy, 0.0, 1e-12, "interior B_xy");
            if (dim == 3) CHECK_NEAR(t, b[5 * n + centre], bxx, 1e-12, "interior B_zz = B_xx");
            printf("dim %d: interior B_xx = %.6f, neighbours capacity %d\n", dim, bxx,
                   info.max_neighbours);
        }
        free(b);
        free(x);
        sph_backend_destroy(be);
        sph_particles_free(&p);
    }
}

static void check_rodrigues(test_counts *t) {
    /* 2D: rotation by w dt counter-clockwise */
    for (int prec = 0; prec < 2; ++prec) {
        const sph_physics *k = sph_physics_for(2, prec == 1);
        const double tol = prec ? 1e-14 : 2e-7;
        const double w = 50.0, dt = 2.5e-5, th = w * dt;
        double rot[4];
        k->rodrigues(&w, dt, rot);
        CHECK_NEAR(t, rot[0], cos(th), tol, "2D R_xx");
        CHECK_NEAR(t, rot[1], -sin(th), tol, "2D R_xy");
        CHECK_NEAR(t, rot[2], sin(th), tol, "2D R_yx");
        CHECK_NEAR(t, rot[3], cos(th), tol, "2D R_yy");
    }
    /* 3D: a finite rotation about a general axis, against the axis-angle matrix */
    const sph_physics *k3 = sph_physics_for(3, true);
    const double w[3] = {3.0, -4.0, 12.0}; /* |w| = 13 */
    const double dt = 0.05, th = 13.0 * dt;
    const double u[3] = {w[0] / 13.0, w[1] / 13.0, w[2] / 13.0};
    double rot[9];
    k3->rodrigues(w, dt, rot);
    double max_err = 0.0, orth_err = 0.0;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            /* R = cos I + sin [u]x + (1 - cos) u u^T */
            double expect = (a == b ? cos(th) : 0.0) + (1.0 - cos(th)) * u[a] * u[b];
            const int c = 3 - a - b;
            if (a != b) expect += sin(th) * u[c] * (((a + 1) % 3 == b) ? -1.0 : 1.0);
            max_err = fmax(max_err, fabs(rot[a * 3 + b] - expect));
            double rtr = 0.0;
            for (int m = 0; m < 3; ++m) rtr += rot[m * 3 + a] * rot[m * 3 + b];
            orth_err = fmax(orth_err, fabs(rtr - (a == b ? 1.0 : 0.0)));
        }
    const double det = rot[0] * (rot[4] * rot[8] - rot[5] * rot[7]) -
                       rot[1] * (rot[3] * rot[8] - rot[5] * rot[6]) +
                       rot[2] * (rot[3] * rot[7] - rot[4] * rot[6]);
    CHECK_NEAR(t, max_err, 0.0, 1e-14, "3D Rodrigues against the axis-angle rotation");
    CHECK_NEAR(t, orth_err, 0.0, 1e-14, "3D R^T R = I");
    CHECK_NEAR(t, det, 1.0, 1e-14, "3D det R");
    /* below machine epsilon the rotation is exactly I */
    const double tiny[3] = {1e-20, 0.0, 0.0};
    k3->rodrigues(tiny, 1.0, rot);
    CHECK(t, rot[0] == 1.0 && rot[4] == 1.0 && rot[8] == 1.0 && rot[1] == 0.0,
          "R = I for |w| dt < eps");
}

static double urand(unsigned *s) {
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / 16777216.0 * 2.0 - 1.0;
}

static void check_riemann_symmetry(test_counts *t) {
    unsigned seed = 12345u;
    for (int dim = 2; dim <= 3; ++dim) {
        const sph_physics *k = sph_physics_for(dim, true);
        double worst = 0.0;
        for (int trial = 0; trial < 1000; ++trial) {
            double vi[3], vj[3], e[3], e_back[3], len = 0.0;
            for (int a = 0; a < dim; ++a) {
                vi[a] = urand(&seed);
                vj[a] = urand(&seed);
                e[a] = urand(&seed);
                len += e[a] * e[a];
            }
            for (int a = 0; a < dim; ++a) {
                e[a] /= sqrt(len);
                e_back[a] = -e[a];
            }
            const double pi = 1e5 * urand(&seed), pj = 1e5 * urand(&seed);
            const double z = 5.7e4, dw = -1e3 * fabs(urand(&seed));
            double fp_ij[3], fd_ij[3], fp_ji[3], fd_ji[3], c_ij, c_ji;
            k->riemann_pair(vi, vj, pi, pj, z, dw, e, fp_ij, fd_ij, &c_ij);
            k->riemann_pair(vj, vi, pj, pi, z, dw, e_back, fp_ji, fd_ji, &c_ji);
            for (int a = 0; a < dim; ++a) {
                worst = fmax(worst, fabs(fp_ij[a] + fp_ji[a]) / (fabs(fp_ij[a]) + 1e-300));
                worst = fmax(worst, fabs(fd_ij[a] + fd_ji[a]) / (fabs(fd_ij[a]) + 1e-300));
            }
            worst = fmax(worst, fabs(c_ij - c_ji) / (fabs(c_ij) + 1e-300));
        }
        /* exact: every operation is mirrored, so the terms cancel bit for bit */
        CHECK(t, worst == 0.0, "Riemann pair terms not (anti)symmetric: worst relative %.3g",
              worst);
    }
}

/* Sigma(d), the kernel integrated over a plane at the distance d, as the
 * rigid wall uses it (device/sph_wall.h, an 8-point Gauss rule), against an
 * independent midpoint sum over the plane (spacing h/400 in 2D, h/100 in
 * 3D), and its integral over d in [0, 2h] against 1/2 of int W dV. */
static void check_wall_plane_kernel(test_counts *t) {
    static const int kernels[] = {KERNEL_WENDLAND_C2, KERNEL_CUBIC_BSPLINE};
    for (int kk = 0; kk < 2; ++kk)
        for (int dim = 2; dim <= 3; ++dim) {
            sph_params_f64 prm[1];
            test_params(prm, dim, 1.0, 1.0);
            prm->smoothing_kernel = kernels[kk];
            const sph_physics *k = sph_physics_for(dim, true);
            const double h = prm->h, rc = prm->cutoff;
            char what[160];
            double max_err = 0.0, peak = 0.0;
            for (int s = 0; s < 8; ++s) {
                const double d = rc * (0.02 + 0.12 * s);
                const double delta = dim == 2 ? h / 400.0 : h / 100.0;
                const int m = (int)ceil(rc / delta) + 1;
                double sum = 0.0;
                for (int a = -m; a < m; ++a)
                    for (int b = (dim == 3 ? -m : 0); b < (dim == 3 ? m : 1); ++b) {
                        const double x = (a + 0.5) * delta, y = (b + 0.5) * delta;
                        const double r = sqrt(d * d + x * x + (dim == 3 ? y * y : 0.0));
                        sum += k->kernel_w(prm, r) * (dim == 3 ? delta * delta : delta);
                    }
                const double sigma = k->wall_plane_kernel(prm, d);
                max_err = fmax(max_err, fabs(sigma - sum));
                peak = fmax(peak, sum);
            }
            snprintf(what, sizeof what, "%s %dD: wall plane integral Sigma(d) against a plane sum",
                     KERNEL_LABELS[kernels[kk] == KERNEL_WENDLAND_C2 ? 0 : 3], dim);
            /* the Wendland integrand is smooth (3D: a polynomial the rule
             * integrates exactly); the B-spline's pieces meet at q = 1 with a
             * jump in the third derivative, which one 8-point rule across the
             * joint resolves to 1.9e-4 (2D) and 4.0e-4 (3D); Wendland 2D: 9e-7 */
            const bool spline = kernels[kk] == KERNEL_CUBIC_BSPLINE;
            printf("%s %dD: wall Sigma(d) relative error %.3g\n",
                   spline ? "cubic-bspline" : "wendland-c2", dim, max_err / peak);
            CHECK_NEAR(t, max_err / peak, 0.0, spline ? 1e-3 : 1e-4, what);
            /* int_0^2h Sigma(d) dd = 1/2 (composite 5-point rule over 200 panels) */
            static const double x5[5] = {0.0, -0.5384693101056831, 0.5384693101056831,
                                         -0.9061798459386640, 0.9061798459386640};
            static const double w5[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                         0.2369268850561891, 0.2369268850561891};
            double half = 0.0;
            const double len = rc / 200.0;
            for (int p = 0; p < 200; ++p)
                for (int g = 0; g < 5; ++g)
                    half += w5[g] * k->wall_plane_kernel(prm, (p + 0.5 + 0.5 * x5[g]) * len);
            half *= 0.5 * len;
            snprintf(what, sizeof what, "%s %dD: int_0^2h Sigma(d) dd = 1/2",
                     KERNEL_LABELS[kernels[kk] == KERNEL_WENDLAND_C2 ? 0 : 3], dim);
            printf("%s %dD: int Sigma dd = %.9f\n", spline ? "cubic-bspline" : "wendland-c2", dim,
                   half);
            CHECK_NEAR(t, half, 0.5, spline ? 1e-4 : 1e-5, what);
            CHECK_NEAR(t, k->wall_plane_kernel(prm, rc), 0.0, 0.0, "Sigma(2h) = 0");
        }
}

int main(void) {
    test_counts t = {0};
    check_kernels(&t);
    check_correction_matrix(&t, SPH_BACKEND_CPU);
    check_rodrigues(&t);
    check_riemann_symmetry(&t);
    check_wall_plane_kernel(&t);
    return test_summary("test_physics_units", &t);
}
