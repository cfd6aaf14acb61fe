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
 */
#include "backend_cpu.h"
#include "sph_constants.h"
#include "test_util.h"

#include <math.h>
#include <string.h>

static void material(double *prm, double kappa) {
    memset(prm, 0, PRM_COUNT * sizeof(double));
    /* the square Taylor bar's copper (003 §5.2.2): E 1.17e11, nu 0.35,
     * sigma_Y 4e8 */
    const double e = 1.17e11, nu = 0.35;
    prm[PRM_G] = e / (2.0 * (1.0 + nu));
    prm[PRM_YIELD] = 4e8;
    prm[PRM_HARDENING] = kappa;
    prm[PRM_PLASTIC] = 1.0;
}

static void patch(test_counts *t, int dim, double kappa) {
    const cpu_kernels *k = cpu_kernels_for(dim, true);
    double prm[PRM_COUNT];
    material(prm, kappa);
    const double g = prm[PRM_G], sy = prm[PRM_YIELD];
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
    const cpu_kernels *k = cpu_kernels_for(2, true);
    double prm[PRM_COUNT];
    material(prm, 0);
    prm[PRM_PLASTIC] = 0.0;
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
    const cpu_kernels *k = cpu_kernels_for(dim, true);
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

int main(void) {
    test_counts t = {0};
    patch(&t, 3, 1e8); /* the square Taylor bar's hardening modulus (003 §5.2.2) */
    patch(&t, 2, 1e8);
    patch(&t, 3, 0.0); /* perfect plasticity (round Taylor bar) */
    elastic_spin(&t);
    artificial(&t, 2);
    artificial(&t, 3);
    return test_summary("test_plasticity", &t);
}
