/* test_plasticity.c — J2 plasticity of a single material point (003 eqs.
 * 11-14) and the artificial stress of SPH-OAS, through the device code's own
 * functions (the native f64 instances).
 *
 * J2 patch: an isochoric uniaxial extension, D = e' diag(1, -1/2, -1/2) in
 * 3D (diag(1, -1) in the 2D in-plane model), no spin, applied in N equal
 * steps.  With s = the accumulated |D| (Frobenius) and radius
 * R(alpha) = sqrt(2/3) (sigma_Y + kappa alpha):
 *     elastic:  |tau| = 2 G s                     while 2 G s <= R(0),
 *     plastic:  |tau| = R(0) + 2 G kappa / (3 G + kappa) (s - s_Y),
 *               alpha = (|tau| - R(0)) / (sqrt(2/3) kappa),
 * which in 3D is the uniaxial curve sigma_eq = sigma_Y + 3 G kappa / (3 G +
 * kappa) (eps - sigma_Y / (3 G)), sigma_eq = sqrt(3/2) |tau|.  The radial
 * return is exact for such proportional loading, so the bound is round-off
 * (1e-9 relative), also across the step where yielding starts.
 *
 * TLSPH finite-strain J2 (sph_plasticity.h, tl_j2_kirchhoff: F = F^e F^p,
 * Hencky elasticity, return map in principal log strains, Simo 1992), 2D
 * plane strain and 3D, aluminium-like E = 70 GPa, nu = 0.3, sigma_Y =
 * 300 MPa, kappa = 1 GPa and 0:
 *  a. isochoric stretch F = Q R diag(e^eps, e^-eps[, 1]) R^T, driven
 *     0 -> 0.02 -> -0.02 -> 0 in steps of 1e-4 (fixed principal axes R,
 *     and either no rigid rotation Q or one growing to 1 rad).  The total
 *     log strain is sqrt(2) eps n, n = (1, -1, 0)/sqrt(2); with the plastic
 *     log strain gamma n the Kirchhoff stress is tau = Q R diag(t, -t, 0)
 *     R^T Q^T, t = 2 mu (eps - gamma/sqrt(2)), alpha = sqrt(2/3) * total
 *     |d gamma|, and on a monotone segment starting at (gamma0, alpha0)
 *       loading:   gamma = max(gamma0, (2 sqrt2 mu eps - sqrt(2/3)(sY + k alpha0)
 *                                       + 2k/3 gamma0) / (2 mu + 2k/3)),
 *       unloading: gamma = min(gamma0, (2 sqrt2 mu eps + sqrt(2/3)(sY + k alpha0)
 *                                       + 2k/3 gamma0) / (2 mu + 2k/3))
 *     (the consistency condition |s| = sqrt(2/3)(sY + k alpha) of linear
 *     hardening solved for gamma; the return map is exact for it, the flow
 *     direction being fixed), C_p^-1 = R diag(e^(-sqrt2 gamma), e^(sqrt2 gamma)
 *     [, 1]) R^T.  Bounds: tau to 1e-12 sY, alpha and C_p^-1 to 1e-12
 *     (round-off over 800 steps; measured <= 6e-13 sY, 1e-15 and 1.7e-15);
 *     the elastic unloading slope dt/d eps = 2 mu to 1e-9 relative (a
 *     difference of two stresses; measured 2e-11).  Elastic branch against
 *     Saint Venant-Kirchhoff: for this F, tau_SVK,xx = 2 mu eps + (6 mu +
 *     2 lambda) eps^2 + O(eps^3), so (tau_SVK - tau_Hencky) / tau_Hencky =
 *     (3 + lambda/mu) eps, to 1 % at eps = 1e-4 (Hencky = SVK to first
 *     order).
 *  b. plane-strain uniaxial strain F = diag(e^a, 1[, 1]), a to 0.02: total
 *     log strain (a, 0, 0), deviator sqrt(2/3) a m, m = (2, -1, -1)/sqrt6,
 *     so the flow has an out-of-plane part: tau = K a I + |s| m, |s| =
 *     2 mu (sqrt(2/3) a - gamma), gamma as in (a) with sqrt(2/3) a for
 *     sqrt2 eps, and (C_p^-1)_zz = e^(2 gamma/sqrt6) (the state's
 *     plane-strain zz component), K = lambda + 2 mu/3.  Same bounds.
 */
#include "physics.h"
#include "sph_constants.h"
#include "test_util.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

static void material(sph_params_f64 *prm, double kappa) {
    memset(prm, 0, sizeof *prm);
    /* the square Taylor bar's copper (003 §5.2.2): E 1.17e11, nu 0.35,
     * sigma_Y 4e8 */
    const double e = 1.17e11, nu = 0.35;
    prm->materials[0].shear_modulus = e / (2.0 * (1.0 + nu));
    prm->materials[0].yield = 4e8;
    prm->materials[0].hardening = kappa;
    prm->plastic = 1;
}

static void patch(test_counts *t, int dim, double kappa) {
    const sph_physics *k = sph_physics_for(dim, true);
    sph_params_f64 prm[1];
    material(prm, kappa);
    const double g = prm->materials[0].shear_modulus, sy = prm->materials[0].yield;
    const double rate = 1e3, dt = 1e-7; /* eps' and step: 0.01 % strain per step */
    double d[9] = {0};
    d[0] = rate;
    if (dim == 2) {
        d[3] = -rate;
    } else {
        d[4] = -0.5 * rate;
        d[8] = -0.5 * rate;
    }
    double dnorm = 0;
    for (int a = 0; a < dim * dim; ++a) dnorm += d[a] * d[a];
    dnorm = sqrt(dnorm);
    const double r0 = sqrt(2.0 / 3.0) * sy;
    const double s_y = r0 / (2 * g);
    double tau[9] = {0}, alpha = 0;
    double worst_tau = 0, worst_alpha = 0, final_eq = 0, final_eps = 0;
    int plastic_steps = 0;
    for (int step = 1; step <= 400; ++step) {
        k->stress_update(prm, d, dt, tau, &alpha);
        const double s = dnorm * dt * step;
        double norm = 0;
        for (int a = 0; a < dim * dim; ++a) norm += tau[a] * tau[a];
        norm = sqrt(norm);
        double expect, expect_alpha = 0;
        if (s <= s_y) {
            expect = 2 * g * s;
        } else {
            expect = r0 + 2 * g * kappa / (3 * g + kappa) * (s - s_y);
            expect_alpha = kappa > 0 ? (expect - r0) / (sqrt(2.0 / 3.0) * kappa)
                                     : sqrt(2.0 / 3.0) * (s - s_y); /* perfect plasticity */
            ++plastic_steps;
        }
        worst_tau = fmax(worst_tau, fabs(norm - expect) / expect);
        if (kappa > 0)
            worst_alpha = fmax(worst_alpha, fabs(alpha - expect_alpha) / fmax(expect_alpha, 1e-12));
        final_eq = sqrt(1.5) * norm;
        final_eps = rate * dt * step;
    }
    printf("J2 patch %dD, kappa %.3g: %d of 400 steps plastic, final sigma_eq %.6g Pa at eps %.4g, "
           "worst relative error |tau| %.2e, alpha %.2e\n",
           dim, kappa, plastic_steps, final_eq, final_eps, worst_tau, worst_alpha);
    CHECK(t, plastic_steps > 200 && plastic_steps < 400, "the loading crosses yield (%d)",
          plastic_steps);
    CHECK(t, worst_tau < 1e-9, "|tau| follows the analytical curve, worst %.3g", worst_tau);
    if (kappa > 0)
        CHECK(t, worst_alpha < 1e-9, "alpha follows the analytical curve, worst %.3g", worst_alpha);
    if (dim == 3) {
        /* the uniaxial curve in equivalent stress and strain */
        const double eq = sy + 3 * g * kappa / (3 * g + kappa) * (final_eps - sy / (3 * g));
        CHECK(t, fabs(final_eq - eq) < 1e-9 * eq, "sigma_eq %.9g, analytical %.9g", final_eq, eq);
    }
}

/* The elastic point: no return, and the Jaumann rate rotates tau rigidly
 * under a pure spin (objectivity): |tau| stays, to round-off. */
static void elastic_spin(test_counts *t) {
    const sph_physics *k = sph_physics_for(2, true);
    sph_params_f64 prm[1];
    material(prm, 0);
    prm->plastic = 0;
    double tau[4] = {1e6, 3e5, 3e5, -1e6}, spin[4] = {0, -50, 50, 0};
    const double n0 = sqrt(2e12 + 2 * 9e10);
    for (int step = 0; step < 1000; ++step) k->stress_update(prm, spin, 1e-6, tau, NULL);
    const double n1 = sqrt(tau[0] * tau[0] + tau[1] * tau[1] + tau[2] * tau[2] + tau[3] * tau[3]);
    /* tau' = Omega tau - tau Omega turns a 2D deviator at 2 w: explicit
     * Euler grows its norm by exactly (1 + (2 w dt)^2)^(1/2) per step */
    const double expect = pow(1.0 + pow(2 * 50 * 1e-6, 2), 500);
    CHECK(t, fabs(n1 / n0 - expect) < 1e-12, "|tau| under a pure spin: ratio %.12f, expected %.12f",
          n1 / n0, expect);
}

/* Artificial stress (Gray et al. 2001): only tensile principal stresses,
 * R_a = -eps s_a / rho^2, in the principal frame of sigma = tau - p I. */
static void artificial(test_counts *t, int dim) {
    const sph_physics *k = sph_physics_for(dim, true);
    /* sigma with principal values (3, -1[, 2]) x 1e5 in a rotated frame */
    const double th = 0.3, c = cos(th), s = sin(th);
    double q[9] = {0}, lam[3] = {3e5, -1e5, 2e5}, sigma[9] = {0};
    if (dim == 2) {
        q[0] = c, q[1] = -s, q[2] = s, q[3] = c;
    } else {
        q[0] = c, q[1] = -s, q[3] = s, q[4] = c, q[8] = 1;
    }
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            for (int m = 0; m < dim; ++m)
                sigma[a * dim + b] += q[a * dim + m] * lam[m] * q[b * dim + m];
    const double p = 4e4, rho = 1000, eps = 0.3;
    double tau[9];
    for (int a = 0; a < dim * dim; ++a) tau[a] = sigma[a];
    for (int a = 0; a < dim; ++a) tau[a * dim + a] += p; /* tau = sigma + p I */
    double r[9];
    k->artificial_stress(tau, p, rho, eps, r);
    double worst = 0;
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b) {
            double expect = 0;
            for (int m = 0; m < dim; ++m)
                if (lam[m] > 0)
                    expect += q[a * dim + m] * (-eps * lam[m] / (rho * rho)) * q[b * dim + m];
            worst = fmax(worst, fabs(r[a * dim + b] - expect));
        }
    CHECK(t, worst < 1e-12 * eps * 3e5 / (rho * rho), "artificial stress %dD, worst %.3g", dim,
          worst);
}

/* ---- TLSPH finite-strain J2 ---------------------------------------------- */

typedef struct {
    double e, nu, mu, lambda, k, sy, kappa;
} tl_material;

static tl_material tl_params(sph_params_f64 *prm, double kappa) {
    memset(prm, 0, sizeof *prm);
    tl_material m = {.e = 7e10, .nu = 0.3, .sy = 3e8, .kappa = kappa};
    m.mu = m.e / (2.0 * (1.0 + m.nu));
    m.k = m.e / (3.0 * (1.0 - 2.0 * m.nu));
    m.lambda = m.k - 2.0 * m.mu / 3.0; /* plane strain in 2D, as the TLSPH material */
    prm->materials[0].shear_modulus = m.mu;
    prm->materials[0].bulk_modulus = m.k;
    prm->materials[0].lambda = m.lambda;
    prm->materials[0].yield = m.sy;
    prm->materials[0].hardening = kappa;
    prm->plastic = 1;
    return m;
}

/* 3 x 3 row-major products; c = a b or a b^T */
static void mul3(const double *a, const double *b, double *c, int transpose_b) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0.0;
            for (int k = 0; k < 3; ++k)
                s += a[i * 3 + k] * (transpose_b ? b[j * 3 + k] : b[k * 3 + j]);
            c[i * 3 + j] = s;
        }
}

/* Rotation by `angle` about `axis` (Rodrigues), 3 x 3 row-major. */
static void rotation3(const double axis_in[3], double angle, double *r) {
    const double len =
        sqrt(axis_in[0] * axis_in[0] + axis_in[1] * axis_in[1] + axis_in[2] * axis_in[2]);
    const double u[3] = {axis_in[0] / len, axis_in[1] / len, axis_in[2] / len};
    const double c = cos(angle), s = sin(angle);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r[i * 3 + j] = (i == j ? c : 0.0) + (1.0 - c) * u[i] * u[j];
    r[1] -= s * u[2], r[2] += s * u[1], r[3] += s * u[2];
    r[5] -= s * u[0], r[6] -= s * u[1], r[7] += s * u[0];
}

/* R diag(d) R^T */
static void rotate_diag(const double *r, const double d[3], double *out) {
    double rd[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) rd[i * 3 + j] = r[i * 3 + j] * d[j];
    mul3(rd, r, out, 1);
}

/* The closed-form plastic log strain gamma of a monotone segment that
 * starts at (gamma0, alpha0): `drive` is the total deviatoric log strain
 * along the flow direction (sqrt2 eps in (a), sqrt(2/3) a in (b)). */
static double gamma_exact(const tl_material *m, double drive, double gamma0, double alpha0,
                          bool loading) {
    const double r = sqrt(2.0 / 3.0) * (m->sy + m->kappa * alpha0);
    const double den = 2.0 * m->mu + 2.0 * m->kappa / 3.0;
    const double g =
        (2.0 * m->mu * drive + (loading ? -r : r) + 2.0 * m->kappa / 3.0 * gamma0) / den;
    return loading ? fmax(gamma0, g) : fmin(gamma0, g);
}

/* One TLSPH J2 update through the probe; f and the results 3 x 3 (the
 * probe's d x d block plus, in 2D, the zz components). */
static int tl_update3(const sph_physics *k, const sph_params_f64 *prm, const double f3[9],
                      double cp3[9], double *alpha, double tau3[9]) {
    const int d = k->dim, dd = d * d;
    double f[9], state[11], tau[10];
    for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b) {
            f[a * d + b] = f3[a * 3 + b];
            state[a * d + b] = cp3[a * 3 + b];
        }
    state[dd] = cp3[8];
    state[dd + 1] = *alpha;
    const int yielded = k->tl_j2_update(prm, f, state, tau);
    memset(tau3, 0, 9 * sizeof(double));
    for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b) {
            tau3[a * 3 + b] = tau[a * d + b];
            cp3[a * 3 + b] = state[a * d + b];
        }
    if (d == 2) {
        tau3[8] = tau[dd];
        cp3[8] = state[dd];
    }
    *alpha = state[dd + 1];
    return yielded;
}

static double max_abs_diff(const double *a, const double *b, int n) {
    double m = 0.0;
    for (int i = 0; i < n; ++i) m = fmax(m, fabs(a[i] - b[i]));
    return m;
}

/* (a): the isochoric stretch, loading, unloading, reverse yielding and
 * reloading; `rigid` adds a rigid rotation growing to 1 rad. */
static void tl_isochoric(test_counts *t, int dim, double kappa, double axes_angle, bool rigid) {
    const sph_physics *k = sph_physics_for(dim, true);
    sph_params_f64 prm[1];
    const tl_material m = tl_params(prm, kappa);
    const double axis[3] = {dim == 2 ? 0.0 : 1.0, dim == 2 ? 0.0 : 2.0, 3.0};
    double r[9], q[9];
    rotation3(axis, axes_angle, r);
    double cp[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, alpha = 0.0;
    /* closed form: gamma, alpha at the start of the segment and now */
    double gamma0 = 0.0, alpha0 = 0.0, gamma = 0.0, alpha_exact = 0.0;
    double eps = 0.0, eps_prev = 0.0, t_prev = 0.0;
    const double de = 1e-4;
    const int segment[3] = {200, 400, 200}; /* 0 -> 0.02 -> -0.02 -> 0 */
    double worst_tau = 0.0, worst_alpha = 0.0, worst_cp = 0.0, worst_slope = 0.0;
    int plastic[3] = {0, 0, 0}, elastic_unloading = 0, step = 0, mismatched = 0;
    for (int seg = 0; seg < 3; ++seg) {
        const bool loading = seg != 1;
        gamma0 = gamma;
        alpha0 = alpha_exact;
        for (int s = 0; s < segment[seg]; ++s, ++step) {
            eps += loading ? de : -de;
            rotation3(axis, rigid ? (step + 1) / 800.0 : 0.0, q);
            /* F = Q R diag(e^eps, e^-eps, 1) R^T */
            const double stretch[3] = {exp(eps), exp(-eps), 1.0};
            double u[9], f[9], tau[9];
            rotate_diag(r, stretch, u);
            mul3(q, u, f, 0);
            const int yielded = tl_update3(k, prm, f, cp, &alpha, tau);
            const double gamma_prev = gamma;
            gamma = gamma_exact(&m, sqrt(2.0) * eps, gamma0, alpha0, loading);
            alpha_exact = alpha0 + sqrt(2.0 / 3.0) * fabs(gamma - gamma0);
            const double tp = 2.0 * m.mu * (eps - gamma / sqrt(2.0));
            const double tdiag[3] = {tp, -tp, 0.0};
            double tr_[9], qt[9], tau_exact[9];
            rotate_diag(r, tdiag, tr_);
            mul3(q, tr_, qt, 0);
            mul3(qt, q, tau_exact, 1);
            const double cdiag[3] = {exp(-sqrt(2.0) * gamma), exp(sqrt(2.0) * gamma), 1.0};
            double cp_exact[9];
            rotate_diag(r, cdiag, cp_exact);
            worst_tau = fmax(worst_tau, max_abs_diff(tau, tau_exact, 9) / m.sy);
            worst_alpha = fmax(worst_alpha, fabs(alpha - alpha_exact));
            worst_cp = fmax(worst_cp, max_abs_diff(cp, cp_exact, 9));
            if (yielded != (gamma != gamma_prev)) ++mismatched;
            if (yielded) ++plastic[seg];
            /* elastic unloading: the computed principal stress n1.tau.n1,
             * n1 = Q R e_1, falls at 2 mu */
            double qr[9], t1 = 0.0;
            mul3(q, r, qr, 0);
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) t1 += qr[a * 3] * tau[a * 3 + b] * qr[b * 3];
            if (seg == 1 && s > 0 && gamma == gamma_prev) {
                const double slope = (t1 - t_prev) / (eps - eps_prev);
                worst_slope = fmax(worst_slope, fabs(slope / (2.0 * m.mu) - 1.0));
                ++elastic_unloading;
            }
            t_prev = t1;
            eps_prev = eps;
        }
    }
    printf("TLSPH J2 stretch %dD, kappa %.3g, axes %.2f rad%s: plastic steps %d/%d/%d, %d elastic "
           "unloading; worst |tau - exact| / sY %.2e, alpha %.2e, C_p^-1 %.2e, unloading slope "
           "%.2e; final alpha %.5f\n",
           dim, kappa, axes_angle, rigid ? " + rigid rotation" : "", plastic[0], plastic[1],
           plastic[2], elastic_unloading, worst_tau, worst_alpha, worst_cp, worst_slope, alpha);
    CHECK(t, plastic[0] > 100 && plastic[1] > 200 && plastic[2] > 50 && elastic_unloading > 20,
          "all branches: plastic %d/%d/%d, elastic unloading %d", plastic[0], plastic[1],
          plastic[2], elastic_unloading);
    CHECK(t, mismatched == 0, "yield flag where the closed form yields (%d mismatches)",
          mismatched);
    CHECK(t, worst_tau < 1e-12, "tau against the closed form: %.3g sY", worst_tau);
    CHECK(t, worst_alpha < 1e-12, "alpha against the closed form: %.3g", worst_alpha);
    CHECK(t, worst_cp < 1e-12, "C_p^-1 against the closed form: %.3g", worst_cp);
    CHECK(t, worst_slope < 1e-9, "elastic unloading slope 2 mu: worst relative %.3g", worst_slope);
}

/* (b): plane-strain uniaxial strain, whose plastic flow has a zz part. */
static void tl_uniaxial(test_counts *t, int dim, double kappa) {
    const sph_physics *k = sph_physics_for(dim, true);
    sph_params_f64 prm[1];
    const tl_material m = tl_params(prm, kappa);
    const double kb = m.lambda + 2.0 * m.mu / 3.0, r6 = sqrt(6.0);
    const double dir[3] = {2.0 / r6, -1.0 / r6, -1.0 / r6};
    double cp[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, alpha = 0.0;
    double worst_tau = 0.0, worst_alpha = 0.0, worst_cp = 0.0;
    int plastic = 0;
    for (int step = 1; step <= 200; ++step) {
        const double a = 1e-4 * step;
        const double f[9] = {exp(a), 0, 0, 0, 1, 0, 0, 0, 1};
        double tau[9];
        plastic += tl_update3(k, prm, f, cp, &alpha, tau);
        const double drive = sqrt(2.0 / 3.0) * a;
        const double gamma = gamma_exact(&m, drive, 0.0, 0.0, true);
        const double s_norm = 2.0 * m.mu * (drive - gamma);
        double tau_exact[9] = {0}, cp_exact[9] = {0};
        for (int c = 0; c < 3; ++c) {
            tau_exact[c * 4] = kb * a + s_norm * dir[c];
            cp_exact[c * 4] = exp(-2.0 * gamma * dir[c]);
        }
        worst_tau = fmax(worst_tau, max_abs_diff(tau, tau_exact, 9) / m.sy);
        worst_alpha = fmax(worst_alpha, fabs(alpha - sqrt(2.0 / 3.0) * gamma));
        worst_cp = fmax(worst_cp, max_abs_diff(cp, cp_exact, 9));
    }
    printf("TLSPH J2 uniaxial plane strain %dD, kappa %.3g: %d of 200 steps plastic; worst |tau - "
           "exact| / sY %.2e, alpha %.2e, C_p^-1 %.2e; (C_p^-1)_zz %.9f\n",
           dim, kappa, plastic, worst_tau, worst_alpha, worst_cp, cp[8]);
    CHECK(t, plastic > 100 && plastic < 200, "the loading crosses yield (%d)", plastic);
    CHECK(t, cp[8] > 1.0 + 1e-3, "plastic flow out of plane: (C_p^-1)_zz %.9f", cp[8]);
    CHECK(t, worst_tau < 1e-12, "tau against the closed form: %.3g sY", worst_tau);
    CHECK(t, worst_alpha < 1e-12, "alpha against the closed form: %.3g", worst_alpha);
    CHECK(t, worst_cp < 1e-12, "C_p^-1 against the closed form: %.3g", worst_cp);
}

/* Elastic branch: Hencky against Saint Venant-Kirchhoff for the isochoric
 * stretch at eps = 1e-4 (see the header). */
static void tl_hencky_vs_svk(test_counts *t, int dim) {
    const sph_physics *k = sph_physics_for(dim, true);
    sph_params_f64 prm[1];
    const tl_material m = tl_params(prm, 0.0);
    const double eps = 1e-4;
    const double f[9] = {exp(eps), 0, 0, 0, exp(-eps), 0, 0, 0, 1};
    double cp[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, alpha = 0.0, tau[9];
    const int yielded = tl_update3(k, prm, f, cp, &alpha, tau);
    /* SVK: E = (F^T F - I)/2, S = lambda tr(E) I + 2 mu E, tau = F S F^T */
    const double exx = 0.5 * (exp(2 * eps) - 1.0), eyy = 0.5 * (exp(-2 * eps) - 1.0);
    const double sxx = m.lambda * (exx + eyy) + 2.0 * m.mu * exx;
    const double svk = exp(2 * eps) * sxx;
    const double rel = (svk - tau[0]) / tau[0], expect = (3.0 + m.lambda / m.mu) * eps;
    printf("TLSPH Hencky vs SVK %dD at eps = 1e-4: Hencky tau_xx %.9g (2 mu eps %.9g), "
           "(SVK - Hencky) / Hencky %.6e, second-order prediction %.6e\n",
           dim, tau[0], 2 * m.mu * eps, rel, expect);
    CHECK(t, !yielded && fabs(tau[0] / (2 * m.mu * eps) - 1.0) < 1e-12,
          "Hencky: tau_xx = 2 mu eps (%.12g)", tau[0] / (2 * m.mu * eps));
    CHECK(t, fabs(rel / expect - 1.0) < 0.01, "SVK - Hencky = (3 + lambda/mu) eps: %.4g vs %.4g",
          rel, expect);
}

int main(void) {
    test_counts t = {0};
    patch(&t, 3, 1e8); /* the square Taylor bar's hardening modulus (003 §5.2.2) */
    patch(&t, 2, 1e8);
    patch(&t, 3, 0.0); /* perfect plasticity (round Taylor bar) */
    elastic_spin(&t);
    artificial(&t, 2);
    artificial(&t, 3);
    for (int dim = 2; dim <= 3; ++dim) {
        tl_isochoric(&t, dim, 1e9, 0.0, false);
        tl_isochoric(&t, dim, 1e9, 0.4, false);
        tl_isochoric(&t, dim, 1e9, 0.4, true);
        tl_isochoric(&t, dim, 0.0, 0.4, true); /* perfect plasticity (002) */
        tl_uniaxial(&t, dim, 1e9);
        tl_uniaxial(&t, dim, 0.0);
        tl_hencky_vs_svk(&t, dim);
    }
    return test_summary("test_plasticity", &t);
}
