/* test_tlsph.c — total-Lagrangian SPH (device/tl_step.cl) on one backend.
 *
 *  1. Patch test (002 §2.2.1 without its irregular set): a 20 x 20 lattice
 *     with its reference configuration built at t = 0 is mapped by a uniform
 *     deformation F0 (stretch plus shear) and one substep is taken at rest.
 *     On particles whose support is complete (>= 2.6 dp from the edge) the
 *     SPH deformation gradient equals F0 to 1e-12 (the corrected gradient of
 *     the reference configuration is first-order complete; B0 is refined to
 *     round-off for TLSPH, neighbour_build.cl) and P equals the Saint
 *     Venant-Kirchhoff P = F S (004 eq. 24) to 1e-12 relative.  Particles a
 *     further support away (>= 5.2 dp) feel no force, the hourglass term
 *     included (uniform P B, and the error vectors vanish for a linear map):
 *     |a| <= 1e-9 of the largest (edge) acceleration.  Released, the patch
 *     keeps its total momentum: every pair term is anti-symmetric (004 eq. 25,
 *     002's hourglass force), |sum m v| <= 1e-12 sum m |v| after 20 steps.
 *  2. The 2D oscillating plate of 004 §3.2.5 (H/dp = 10, v_f = 0.05,
 *     nu = 0.3975, Wendland C2) run to t = 0.29 s, past its first period:
 *     004 Table 6 / Fig. 8 give T_W = 0.282 s, 11.0 % above the 0.25406 s of
 *     thin-plate theory (eq. 33); the benchmark's acceptance band is +-1.5
 *     percentage points of that error, T in [0.2782, 0.2858] s, asserted here
 *     (measured 0.28006 s, 10.23 %).  Stable through the period: the run ends
 *     with finite energies, a tip amplitude near the ULSPH one (0.09-0.14 m,
 *     test_plate.c) and, without dissipation, E(t)/E(0) within 3 %.
 *  3. With the Laguerre-Gauss kernel (004 eq. 8; native backend only, the
 *     OpenCL one gives the same period): T_LG = 0.271 s, 6.7 %
 *     (004 Fig. 8); the same +-1.5-point band, T in [0.2673, 0.2749] s
 *     (measured 0.27101 s, 6.67 %).
 *  4. Hourglass control (002): the patch at rest with a checkerboard velocity,
 *     a zero-energy mode of the SPH deformation gradient on the lattice
 *     interior.  The indicator is the RMS over all reference pairs of the
 *     symmetrised 002 error vector ((F_i + F_j) X_ij - 2 x_ij) / 2 relative
 *     to |X_ij|; after 200 steps it is at least HOURGLASS_RATIO times smaller
 *     with the default alpha than with alpha = 0.
 *  5. 002's plasticity switch (E -> sigma_Y + kappa alpha in the hourglass
 *     force of particles with alpha > 0) on the patch displaced by the
 *     checkerboard, where deep particles feel the hourglass force alone:
 *     exactly scaled by the switched modulus, unchanged without plastic
 *     strain, momentum-conserving with mixed moduli (hourglass_switch);
 *     plastic buffers and kernel arguments only in a plastic program.
 *  6. Finite-strain J2 (sph_plasticity.h) on the plate at H/dp = 5: a low
 *     yield stress yields the root, dissipates energy, keeps it bounded; a
 *     yield stress above any reachable stress leaves no plastic state and
 *     gives Hencky elasticity, within a derived second-order bound of the
 *     SVK run (plastic_plate).
 *
 * Under the sanitizers (test_sanitized) the two plates of 2 and 3 run to
 * t = 0.1 s, past the first swing's largest deflection: E(t)/E(0) and the
 * tip amplitude are held to the same bounds; the periods are the release
 * build's.
 */
#include "physics.h"
#include "scene_schema.h"
#include "test_support.h"

#include <math.h>

#define PATCH_N 20
/* the scene default of method.hourglass_alpha (the schema, scene_keys.def) */
#define HOURGLASS_ALPHA (sph_scene_key_at(SK_METHOD_HOURGLASS_ALPHA)->def)
/* checkerboard patch after 200 steps: the indicator with alpha = 0 over the
 * one with HOURGLASS_ALPHA measured 15.7 (native backend); the bound keeps a
 * factor 3 of margin and still means "much smaller" */
#define HOURGLASS_RATIO 5.0
/* the exponential law's b in the patch tests: 2, so that a b wrongly taken
 * as 1 (the column's) would show */
#define EXPONENTIAL_B 2.0

/* P = F S, S = lambda tr(E) I + 2 mu E, E = (F^T F - I)/2 (2D, row-major). */
static void svk_pk1(const double f[4], double lambda, double mu, double p[4]) {
    double e[4];
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
            double s = 0.0;
            for (int k = 0; k < 2; ++k) s += f[k * 2 + a] * f[k * 2 + b];
            e[a * 2 + b] = 0.5 * (s - (a == b ? 1.0 : 0.0));
        }
    const double tr = e[0] + e[3];
    double s[4];
    for (int k = 0; k < 4; ++k) s[k] = 2.0 * mu * e[k];
    s[0] += lambda * tr;
    s[3] += lambda * tr;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) p[a * 2 + b] = f[a * 2] * s[b] + f[a * 2 + 1] * s[2 + b];
}

/* The hyperelastic laws of device/tl_step.cl in 2D plane strain (C_zz = 1),
 * written from their strain energies (docs/method.md, "TLSPH"):
 * neo-Hookean S = mu (I - C^-1) + lambda ln J C^-1 (Bonet & Wood), and
 * the exponential law S = a exp(b (I1 - 3)) I + (lambda (J - 1) - a) J C^-1,
 * I1 = tr C + 1, a = mu.  P = F S (row-major 2 x 2). */
static void hyperelastic_pk1(int model, const double f[4], double lambda, double mu, double b,
                             double p[4]) {
    double c[4];
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) c[i * 2 + j] = f[i] * f[j] + f[2 + i] * f[2 + j];
    const double det_c = c[0] * c[3] - c[1] * c[2];
    const double c_inv[4] = {c[3] / det_c, -c[1] / det_c, -c[2] / det_c, c[0] / det_c};
    const double jac = f[0] * f[3] - f[1] * f[2];
    double s[4];
    for (int k = 0; k < 4; ++k) {
        const double id = (k == 0 || k == 3) ? 1.0 : 0.0;
        if (model == ELASTIC_MODEL_NEO_HOOKEAN)
            s[k] = mu * (id - c_inv[k]) + lambda * log(jac) * c_inv[k];
        else
            s[k] = mu * exp(b * (c[0] + c[3] + 1.0 - 3.0)) * id +
                   (lambda * (jac - 1.0) - mu) * jac * c_inv[k];
    }
    for (int a = 0; a < 2; ++a)
        for (int k = 0; k < 2; ++k) p[a * 2 + k] = f[a * 2] * s[k] + f[a * 2 + 1] * s[2 + k];
}

/* A PATCH_N x PATCH_N lattice (dp = 0.01 m, the plate's material) whose
 * reference configuration is built at rest, then mapped by x = c + F0 (X - c)
 * (c the centre); returns the backend, the particles and the slot ids.
 * `plastic` = {yield stress, hardening modulus} makes the material J2-plastic
 * (NULL: elastic). */
static sph_backend *patch_backend_law(sph_backend_kind kind, double alpha, const double f0[4],
                                      const double *plastic, int elastic_model, double damping,
                                      sph_particles *p, sph_params_f64 *prm, int32_t *id,
                                      sph_error *err) {
    const int n = PATCH_N * PATCH_N, d = 2;
    const double dp = 0.01;
    if (test_particles_alloc(p, n, d, 1000.0, dp) != 0) {
        sph_fail(err, SPH_ERR_RUNTIME, "out of memory");
        return NULL;
    }
    for (int i = 0; i < n; ++i) {
        p->pos[i] = (i % PATCH_N + 0.5) * dp;
        p->pos[n + i] = (i / PATCH_N + 0.5) * dp;
    }
    sph_features f;
    test_feature_set(&f, d, true, SPH_ROTATION_NONE);
    f.formulation = SPH_FORMULATION_TLSPH;
    test_params(prm, d, dp, n);
    prm->materials[0].lambda = prm->materials[0].bulk_modulus -
                               prm->materials[0].shear_modulus; /* the 2D in-plane model */
    prm->hourglass = alpha;
    f.elastic_model = prm->elastic_model = elastic_model;
    prm->materials[0].exponential_b = EXPONENTIAL_B;
    f.tl_damping = damping > 0;
    prm->pair_damping = damping;
    if (plastic) {
        f.plastic = true;
        prm->plastic = 1;
        prm->materials[0].yield = plastic[0];
        prm->materials[0].hardening = plastic[1];
    }
    sph_backend *be = NULL;
    sph_rebuild_info info;
    sph_status st = test_backend(kind, &f, prm, n, &be, err);
    if (!st) st = be->ops->upload(be, p, err);
    if (!st) st = be->ops->rebuild(be, &info, err);
    if (!st) st = be->ops->download(be, FIELD_ID, id, err);
    double *x = malloc(sizeof(double) * (size_t)(d * n));
    if (!st && !x) st = sph_fail(err, SPH_ERR_RUNTIME, "out of memory");
    const double c = 0.5 * PATCH_N * dp;
    for (int i = 0; !st && i < n; ++i) {
        const double dx = p->pos[id[i]] - c, dy = p->pos[n + id[i]] - c;
        x[i] = c + f0[0] * dx + f0[1] * dy;
        x[n + i] = c + f0[2] * dx + f0[3] * dy;
    }
    if (!st) st = be->ops->upload_field(be, FIELD_POS, x, err);
    free(x);
    if (st && be) {
        sph_backend_destroy(be);
        be = NULL;
    }
    return be;
}

static sph_backend *patch_backend(sph_backend_kind kind, double alpha, const double f0[4],
                                  const double *plastic, sph_particles *p, sph_params_f64 *prm,
                                  int32_t *id, sph_error *err) {
    return patch_backend_law(kind, alpha, f0, plastic, ELASTIC_MODEL_SVK, 0.0, p, prm, id, err);
}

static void patch_test(test_counts *t, sph_backend_kind kind) {
    const int n = PATCH_N * PATCH_N, d = 2;
    const double alpha = HOURGLASS_ALPHA;
    /* stretch plus shear */
    const double f0[4] = {1.1, 0.03, -0.02, 0.96};
    sph_particles p;
    sph_params_f64 prm[1];
    int32_t *id = malloc(sizeof(int32_t) * (size_t)n);
    sph_error err = {0};
    sph_backend *be = patch_backend(kind, alpha, f0, NULL, &p, prm, id, &err);
    CHECK(t, be != NULL, "patch backend: %s", err.msg);
    if (!be) {
        free(id);
        sph_particles_free(&p);
        return;
    }
    const double dp = prm->dp;
    sph_status st = SPH_OK;
    double *defgrad = malloc(sizeof(double) * (size_t)(4 * n));
    double *pk1 = malloc(sizeof(double) * (size_t)(4 * n));
    double *acc = malloc(sizeof(double) * (size_t)(d * n));
    double *vel = malloc(sizeof(double) * (size_t)(d * n));
    double v2 = 0.0;
    if (!st) st = be->ops->substep(be, 1e-7, &v2, &err);
    if (!st) st = be->ops->download(be, FIELD_DEFGRAD, defgrad, &err);
    if (!st) st = be->ops->download(be, FIELD_PK1, pk1, &err);
    if (!st) st = be->ops->download(be, FIELD_ACC_SHEAR, acc, &err);
    CHECK(t, st == SPH_OK, "patch test run: %s", err.msg);
    if (!st) {
        double p_svk[4], p_max = 0.0, f_err = 0.0, p_err = 0.0, a_edge = 0.0, a_deep = 0.0;
        svk_pk1(f0, prm->materials[0].lambda, prm->materials[0].shear_modulus, p_svk);
        for (int k = 0; k < 4; ++k) p_max = fmax(p_max, fabs(p_svk[k]));
        int interior = 0, deep = 0;
        for (int i = 0; i < n; ++i) {
            const double gx = p.pos[id[i]] / dp - 0.5, gy = p.pos[n + id[i]] / dp - 0.5;
            const double edge = fmin(fmin(gx, gy), fmin(PATCH_N - 1 - gx, PATCH_N - 1 - gy));
            const double a = hypot(acc[i], acc[n + i]);
            a_edge = fmax(a_edge, a);
            if (edge >= 2.6) {
                ++interior;
                for (int k = 0; k < 4; ++k) {
                    f_err = fmax(f_err, fabs(defgrad[k * n + i] - f0[k]));
                    p_err = fmax(p_err, fabs(pk1[k * n + i] - p_svk[k]));
                }
            }
            if (edge >= 5.2) {
                ++deep;
                a_deep = fmax(a_deep, a);
            }
        }
        printf("patch (%s): %d interior particles: max |F - F0| %.3g, max |P - P_svk| / |P| "
               "%.3g; %d deep: max |a| %.3g of the edge's %.3g\n",
               be->kind_name, interior, f_err, p_err / p_max, deep, a_deep, a_edge);
        CHECK(t, interior == 14 * 14 && deep == 8 * 8, "interior %d, deep %d", interior, deep);
        /* an SVK program without damping has neither the hyperelastic laws nor the damping */
        if (kind == SPH_BACKEND_OPENCL)
            CHECK(t,
                  !strstr(be->build_options, "SPH_ELASTIC_MODEL") &&
                      !strstr(be->build_options, "SPH_TL_DAMPING"),
                  "SVK TLSPH program: %s", be->build_options);
        CHECK(t, f_err <= 1e-12, "F on interior particles: max error %.3g", f_err);
        CHECK(t, p_err <= 1e-12 * p_max, "P against SVK: max error %.3g of %.3g", p_err, p_max);
        CHECK(t, a_deep <= 1e-9 * a_edge, "deep acceleration %.3g, edge %.3g", a_deep, a_edge);
    }
    /* release the stretched patch: momentum stays zero */
    const double dt = 0.4 * prm->h / prm->materials[0].c0;
    for (int s = 0; !st && s < 20; ++s) st = be->ops->substep(be, dt, &v2, &err);
    sph_diagnostics diag;
    if (!st) st = be->ops->diagnostics(be, &diag, &err);
    if (!st) st = be->ops->download(be, FIELD_VEL, vel, &err);
    CHECK(t, st == SPH_OK, "released patch: %s", err.msg);
    if (!st) {
        double mv = 0.0;
        for (int i = 0; i < n; ++i) mv += p.mass[id[i]] * hypot(vel[i], vel[n + i]);
        const double drift = hypot(diag.momentum[0], diag.momentum[1]);
        printf("patch (%s): released 20 steps: |sum m v| %.3g of sum m |v| %.3g\n", be->kind_name,
               drift, mv);
        CHECK(t, mv > 0 && drift <= 1e-12 * mv, "momentum %.3g of %.3g", drift, mv);
    }
    free(defgrad);
    free(pk1);
    free(acc);
    free(vel);
    free(id);
    sph_backend_destroy(be);
    sph_particles_free(&p);
}

/* The hourglass indicator: RMS over all reference pairs of the symmetrised
 * 002 error vector ((F_i + F_j) X_ij - 2 x_ij) / 2, relative to the RMS of
 * |X_ij| (F the SPH deformation gradient, recomputed here from the current
 * positions exactly as tl_deformation does; the stored F is the half-step one
 * of the last substep).  For a smooth motion the sum of the two particles'
 * errors cancels to third order in |X_ij| (midpoint rule), so what remains
 * is the particle-scale, zero-energy part the hourglass force acts on.
 * Returns a negative value on failure. */
static double hourglass_indicator(sph_backend *be, const sph_particles *p0,
                                  const sph_params_f64 *prm, sph_error *err) {
    const int n = be->n;
    const sph_physics *k = sph_physics_for(2, true);
    double *x = malloc(sizeof(double) * (size_t)(2 * n));
    double *bmat = malloc(sizeof(double) * (size_t)(3 * n));
    int32_t *id = malloc(sizeof(int32_t) * (size_t)n);
    sph_neighbour_lists nl = {0};
    sph_status st = x && bmat && id ? SPH_OK : sph_fail(err, SPH_ERR_RUNTIME, "out of memory");
    if (!st) st = be->ops->download(be, FIELD_POS, x, err);
    if (!st) st = be->ops->download(be, FIELD_BMAT, bmat, err);
    if (!st) st = be->ops->download(be, FIELD_ID, id, err);
    if (!st) st = be->ops->download_neighbours(be, &nl, err);
    double *f = malloc(sizeof(double) * (size_t)(4 * n));
    if (!st && !f) st = sph_fail(err, SPH_ERR_RUNTIME, "out of memory");
    for (int i = 0; !st && i < n; ++i) {
        const double xi[2] = {p0->pos[id[i]], p0->pos[p0->n + id[i]]};
        const double b[2][2] = {{bmat[i], bmat[n + i]}, {bmat[n + i], bmat[2 * n + i]}};
        double *fi = f + 4 * i;
        for (int c = 0; c < 4; ++c) fi[c] = 0.0;
        for (int s = 0; s < nl.count[i]; ++s) {
            const int j = nl.j[(size_t)i * nl.cap + s];
            const double xij[2] = {xi[0] - p0->pos[id[j]], xi[1] - p0->pos[p0->n + id[j]]};
            const double r = hypot(xij[0], xij[1]);
            const double e[2] = {xij[0] / r, xij[1] / r};
            const double be_[2] = {b[0][0] * e[0] + b[0][1] * e[1],
                                   b[1][0] * e[0] + b[1][1] * e[1]};
            const double dwv = k->kernel_dw(prm, r) * p0->mass[id[j]] / prm->materials[0].rho0;
            for (int a = 0; a < 2; ++a)
                for (int c = 0; c < 2; ++c)
                    fi[a * 2 + c] += dwv * (x[a * n + j] - x[a * n + i]) * be_[c];
        }
    }
    double num = 0.0, den = 0.0;
    for (int i = 0; !st && i < n; ++i)
        for (int s = 0; s < nl.count[i]; ++s) {
            const int j = nl.j[(size_t)i * nl.cap + s];
            const double xij[2] = {p0->pos[id[i]] - p0->pos[id[j]],
                                   p0->pos[p0->n + id[i]] - p0->pos[p0->n + id[j]]};
            for (int a = 0; a < 2; ++a) {
                const double fx = (f[4 * i + a * 2] + f[4 * j + a * 2]) * xij[0] +
                                  (f[4 * i + a * 2 + 1] + f[4 * j + a * 2 + 1]) * xij[1];
                const double eps = 0.5 * fx - (x[a * n + i] - x[a * n + j]);
                num += eps * eps;
                den += xij[a] * xij[a];
            }
        }
    free(f);
    free(x);
    free(bmat);
    free(id);
    sph_neighbour_lists_free(&nl);
    return st ? -1.0 : sqrt(num / den);
}

/* Hourglass control on the patch at rest, seeded with the checkerboard
 * velocity v_i = v0 (-1)^(ix + iy) e_y: on the lattice interior this is a
 * zero-energy mode of the SPH deformation gradient (every nearest-neighbour
 * difference cancels in F by symmetry and the others vanish), so without
 * control nothing restores it and it drifts, while the 002 force turns it
 * into a bounded oscillation.  Returns the hourglass indicator after `steps`
 * acoustic steps (negative on failure). */
static double checkerboard_patch(sph_backend_kind kind, double alpha, int steps, sph_error *err) {
    const int n = PATCH_N * PATCH_N;
    const double f0[4] = {1.0, 0.0, 0.0, 1.0}, v0 = 0.01; /* m/s, 2e-4 c0 */
    sph_particles p;
    sph_params_f64 prm[1];
    int32_t *id = malloc(sizeof(int32_t) * (size_t)n);
    double *vel = calloc((size_t)(2 * n), sizeof(double));
    sph_backend *be = patch_backend(kind, alpha, f0, NULL, &p, prm, id, err);
    sph_status st = be && vel ? SPH_OK : SPH_ERR_RUNTIME;
    for (int i = 0; !st && i < n; ++i)
        vel[n + i] = (id[i] % PATCH_N + id[i] / PATCH_N) % 2 ? -v0 : v0;
    if (!st) st = be->ops->upload_field(be, FIELD_VEL, vel, err);
    const double dt = 0.4 * prm->h / prm->materials[0].c0;
    double v2 = 0.0, indicator = -1.0;
    for (int s = 0; !st && s < steps; ++s) st = be->ops->substep(be, dt, &v2, err);
    if (!st) indicator = hourglass_indicator(be, &p, prm, err);
    if (be) sph_backend_destroy(be);
    free(id);
    free(vel);
    sph_particles_free(&p);
    return indicator;
}

typedef struct {
    double period, amplitude, energy_ratio, wall;
    long steps;
    bool ok;
} plate_result;

/* The plate of 004 §3.2.5 with TLSPH and the scene's default alpha, to
 * t = `end` (0.29 s: past the first period, the second zero crossing of the
 * tip's displacement, analysis.c). */
static plate_result run_plate(test_counts *t, sph_backend_kind kind, const char *kernel,
                              double end) {
    char kernel_set[64], end_set[48];
    snprintf(kernel_set, sizeof kernel_set, "method.kernel=%s", kernel);
    test_end_override(end_set, sizeof end_set, end);
    /* monitor off: TLSPH has no dissipation, and the particle-scale velocity
     * content it keeps trips the zigzag monitor (0.41 at t = 0.01 s, above
     * its 0.3) while the positions stay smooth (hourglass indicator, below) */
    const char *overrides[] = {"method.formulation=tlsph", "method.rotation=none", end_set,
                               "monitor.action=off", kernel_set};
    sph_simulation sim;
    sph_error err = {0};
    plate_result r = {0};
    const sph_status st = test_run_case("oscillating_plate_2d", overrides, 5, kind,
                                        SPH_PRECISION_DOUBLE, 0, &sim, &err);
    CHECK(t, st == SPH_OK, "plate (%s): %s", kernel, err.msg);
    if (st == SPH_OK) {
        const sph_metrics *m = &sim.metrics;
        r.period = m->first_period;
        r.amplitude = m->max_observer_displacement;
        r.energy_ratio = m->final_total_energy_ratio;
        r.steps = sim.stats.acoustic_steps;
        r.wall = sim.stats.wall_seconds;
        r.ok = fabs(sim.stats.end_time - end) < 1e-12;
        printf("plate (%s, %s): T %.5f s (%+.2f %% of 0.25406), tip amplitude %.4f m, E/E0 %.4f, "
               "%ld steps, %.2f s\n",
               sim.backend->kind_name, kernel, r.period, 100.0 * (r.period / 0.25406 - 1.0),
               r.amplitude, r.energy_ratio, r.steps, r.wall);
        CHECK(t, r.ok, "plate ran to t = %g s, got %g", end, sim.stats.end_time);
    }
    sph_simulation_close(&sim);
    return r;
}

/* ---- 5. the 002 plasticity switch on the patch ---------------------------- */

/* the switch patch's material: yield stress and hardening modulus (Pa), and
 * the plastic strain given to switched particles: their hourglass modulus
 * sigma_Y + kappa alpha = 2e5 Pa, 1/10 of E = 2e6 Pa */
#define SWITCH_YIELD     1e5
#define SWITCH_HARDENING 1e6
#define SWITCH_STRAIN    0.1

/* One substep at rest of the patch displaced by the checkerboard
 * u_i = u0 (-1)^(ix + iy) e_y, u0 = 0.01 dp; with a plastic material
 * (`plastic` != NULL) particles whose id is a multiple of `every` start with
 * the plastic strain a0.  Accelerations and the distance from the patch edge
 * (in dp) come back in id order; *compiled says whether the plastic buffers
 * (and, on OpenCL, the kernel arguments) exist exactly when the material is
 * plastic. */
static sph_status switch_patch(sph_backend_kind kind, const double *plastic, double a0, int every,
                               double *acc_by_id, double *edge_by_id, bool *compiled,
                               sph_error *err) {
    const int n = PATCH_N * PATCH_N;
    const double f0[4] = {1.0, 0.0, 0.0, 1.0};
    sph_particles p;
    sph_params_f64 prm[1];
    int32_t *id = malloc(sizeof(int32_t) * (size_t)n);
    double *x = malloc(sizeof(double) * (size_t)(2 * n));
    double *acc = malloc(sizeof(double) * (size_t)(2 * n));
    double *strain = malloc(sizeof(double) * (size_t)n);
    sph_backend *be = NULL;
    sph_status st = id && x && acc && strain ? SPH_OK : sph_fail(err, SPH_ERR_RUNTIME, "no memory");
    if (!st) {
        be = patch_backend(kind, HOURGLASS_ALPHA, f0, plastic, &p, prm, id, err);
        if (!be) st = SPH_ERR_RUNTIME;
    }
    const double u0 = 0.01 * prm->dp;
    for (int i = 0; !st && i < n; ++i) {
        const int ix = id[i] % PATCH_N, iy = id[i] / PATCH_N;
        x[i] = p.pos[id[i]];
        x[n + i] = p.pos[n + id[i]] + ((ix + iy) % 2 ? -u0 : u0);
        strain[i] = id[i] % every == 0 ? a0 : 0.0;
        edge_by_id[id[i]] = fmin(fmin(ix, iy), fmin(PATCH_N - 1 - ix, PATCH_N - 1 - iy));
    }
    if (!st) {
        const bool want = plastic != NULL;
        *compiled = test_has_buffer(be, "plastic_strain") == want &&
                    test_has_buffer(be, "plastic_cinv") == want;
        if (kind == SPH_BACKEND_OPENCL)
            *compiled = *compiled &&
                        (strstr(be->program_kernels, " plastic_cinv") != NULL) == want &&
                        (strstr(be->program_kernels, " plastic_strain") != NULL) == want;
    }
    double v2 = 0.0;
    if (!st) st = be->ops->upload_field(be, FIELD_POS, x, err);
    if (!st && plastic) st = be->ops->upload_field(be, FIELD_PLASTIC_STRAIN, strain, err);
    if (!st) st = be->ops->substep(be, 1e-7, &v2, err);
    if (!st) st = be->ops->download(be, FIELD_ACC_SHEAR, acc, err);
    for (int i = 0; !st && i < n; ++i) {
        acc_by_id[id[i]] = acc[i];
        acc_by_id[n + id[i]] = acc[n + i];
    }
    if (be) {
        sph_backend_destroy(be);
        sph_particles_free(&p);
    }
    free(id);
    free(x);
    free(acc);
    free(strain);
    return st;
}

/* On the lattice interior the checkerboard leaves F = I (a zero-energy mode
 * of the SPH deformation gradient, test 4), so P = 0 there and a particle
 * whose whole support has F = I (>= 5.2 dp from the edge: "deep") feels
 * the hourglass force alone, linear in the moduli of its pairs.  Hence, from
 * 002's switch (E -> sigma_Y + kappa alpha where alpha > 0) and the
 * per-side form of tl_step.cl:
 *  - plastic material, no plastic strain: the elastic program's
 *    accelerations (to 1e-12 of the largest deep one: the same force, summed
 *    as E d_i + E d_j instead of E (d_i + d_j); measured 5e-13);
 *  - every particle switched: the deep accelerations times
 *    (sigma_Y + kappa alpha) / E = 0.1 exactly (to 1e-10 relative; measured
 *    1.7e-11: the residual stress force of F = I to round-off);
 *  - every third particle switched (pairs with E_i != E_j): total force
 *    sum m a = 0 to 1e-12 of sum m |a| (each pair term anti-symmetric;
 *    measured 2e-18 native, 8e-18 OpenCL). */
static void hourglass_switch(test_counts *t, sph_backend_kind kind) {
    const int n = PATCH_N * PATCH_N;
    const double plastic[2] = {SWITCH_YIELD, SWITCH_HARDENING};
    double *acc[4], *edge = malloc(sizeof(double) * (size_t)n);
    for (int r = 0; r < 4; ++r) acc[r] = malloc(sizeof(double) * (size_t)(2 * n));
    sph_error err = {0};
    bool compiled[4] = {false, false, false, false};
    sph_status st = switch_patch(kind, NULL, 0.0, 1, acc[0], edge, &compiled[0], &err);
    if (!st) st = switch_patch(kind, plastic, 0.0, 1, acc[1], edge, &compiled[1], &err);
    if (!st) st = switch_patch(kind, plastic, SWITCH_STRAIN, 1, acc[2], edge, &compiled[2], &err);
    if (!st) st = switch_patch(kind, plastic, SWITCH_STRAIN, 3, acc[3], edge, &compiled[3], &err);
    CHECK(t, st == SPH_OK, "switch patch runs: %s", err.msg);
    CHECK(t, compiled[0] && compiled[1],
          "plastic_strain, plastic_cinv buffers%s: elastic none (%d), plastic both (%d)",
          kind == SPH_BACKEND_OPENCL ? " and kernel arguments" : "", (int)compiled[0],
          (int)compiled[1]);
    if (!st) {
        sph_params_f64 prm[1];
        test_params(prm, 2, 0.01, n);
        const double k = prm->materials[0].bulk_modulus, g = prm->materials[0].shear_modulus,
                     youngs = 9 * k * g / (3 * k + g);
        const double ratio = (SWITCH_YIELD + SWITCH_HARDENING * SWITCH_STRAIN) / youngs;
        double a_deep = 0.0, d_unswitched = 0.0, d_switched = 0.0, sum[2] = {0, 0}, sum_abs = 0.0;
        int deep = 0;
        for (int i = 0; i < n; ++i) {
            for (int c = 0; c < 2; ++c) {
                sum[c] += acc[3][c * n + i];
                sum_abs += fabs(acc[3][c * n + i]);
            }
            if (edge[i] < 5.2) continue;
            ++deep;
            for (int c = 0; c < 2; ++c) {
                const double a = acc[0][c * n + i];
                a_deep = fmax(a_deep, fabs(a));
                d_unswitched = fmax(d_unswitched, fabs(acc[1][c * n + i] - a));
                d_switched = fmax(d_switched, fabs(acc[2][c * n + i] - ratio * a));
            }
        }
        const double drift = hypot(sum[0], sum[1]);
        printf("switch patch (%s): %d deep particles, max |a| %.4g m/s^2; plastic, no strain: max "
               "|a - a_elastic| %.3g; all switched: max |a - %.4f a_elastic| %.3g; every third "
               "switched: |sum m a| %.3g of sum m |a| %.3g\n",
               kind == SPH_BACKEND_CPU ? "cpu" : "opencl", deep, a_deep, d_unswitched, ratio,
               d_switched, drift, sum_abs);
        CHECK(t, deep == 8 * 8 && a_deep > 0, "deep particles %d, max |a| %.3g", deep, a_deep);
        CHECK(t, d_unswitched <= 1e-12 * a_deep, "unswitched plastic = elastic: %.3g of %.3g",
              d_unswitched, a_deep);
        CHECK(t, d_switched <= 1e-10 * ratio * a_deep,
              "switched: hourglass force x (sigma_Y + kappa alpha)/E: %.3g of %.3g", d_switched,
              ratio * a_deep);
        CHECK(t, sum_abs > 0 && drift <= 1e-12 * sum_abs, "mixed switch, momentum %.3g of %.3g",
              drift, sum_abs);
    }
    for (int r = 0; r < 4; ++r) free(acc[r]);
    free(edge);
}

/* ---- 6. the J2-plastic plate ----------------------------------------------- */

/* The TLSPH plate at H/dp = 5 with v_f = 0.01 c0 (tip amplitude 0.027 m),
 * elastic (yield NULL) or J2-plastic with that yield stress, to t_end. */
static sph_status small_plate(sph_backend_kind kind, const char *yield, const char *t_end,
                              sph_simulation *sim, sph_error *err) {
    char yield_set[64], end_set[64];
    snprintf(yield_set, sizeof yield_set, "materials.plate.yield_stress=%s", yield ? yield : "");
    snprintf(end_set, sizeof end_set, "time.end=%s", t_end);
    const char *overrides[] = {"method.formulation=tlsph",
                               "method.rotation=none",
                               "monitor.action=off",
                               "resolution.ratio=5",
                               "bodies.plate.initial_velocity.amplitude_c0=0.01",
                               end_set,
                               yield_set};
    return test_run_case("oscillating_plate_2d", overrides, yield ? 7 : 6, kind,
                         SPH_PRECISION_DOUBLE, 0, sim, err);
}

/* E(t)/E(0): the largest over the run, and the last */
static void energy_ratios(const sph_timeseries *ts, double *max_ratio, double *end_ratio) {
    const double e0 = ts->diag[0].kinetic + ts->diag[0].strain;
    *max_ratio = 0.0;
    for (int k = 0; k < ts->count; ++k)
        *max_ratio = fmax(*max_ratio, (ts->diag[k].kinetic + ts->diag[k].strain) / e0);
    *end_ratio = (ts->diag[ts->count - 1].kinetic + ts->diag[ts->count - 1].strain) / e0;
}

/* Plastic strain and C_p^-1 - I of a finished run (id order); returns the
 * number of particles with alpha > 0 and fills their largest alpha, the
 * reference x of the yielded particles (min, max), and the count of particles
 * whose C_p^-1 - I is non-zero exactly where alpha is. */
typedef struct {
    int yielded, consistent;
    double alpha_max, x_min, x_max, cinv_max;
    bool ok;
} plastic_state_summary;

static plastic_state_summary plastic_state(const sph_simulation *sim, sph_error *err) {
    plastic_state_summary r = {.x_min = INFINITY, .x_max = -INFINITY};
    const sph_backend *be = sim->backend;
    const int n = be->n, nc = be->fields[FIELD_PLASTIC_CINV].components;
    double *alpha = malloc(sizeof(double) * (size_t)n);
    double *cinv = malloc(sizeof(double) * (size_t)(nc * n));
    int32_t *id = malloc(sizeof(int32_t) * (size_t)n);
    sph_status st = alpha && cinv && id ? SPH_OK : sph_fail(err, SPH_ERR_RUNTIME, "no memory");
    if (!st) st = be->ops->download((sph_backend *)be, FIELD_PLASTIC_STRAIN, alpha, err);
    if (!st) st = be->ops->download((sph_backend *)be, FIELD_PLASTIC_CINV, cinv, err);
    if (!st) st = be->ops->download((sph_backend *)be, FIELD_ID, id, err);
    for (int i = 0; !st && i < n; ++i) {
        double c = 0.0;
        for (int k = 0; k < nc; ++k) c = fmax(c, fabs(cinv[k * n + i]));
        r.cinv_max = fmax(r.cinv_max, c);
        r.consistent += (alpha[i] > 0) == (c > 0);
        if (alpha[i] > 0) {
            const double x0 = sim->particles.pos[id[i]];
            ++r.yielded;
            r.alpha_max = fmax(r.alpha_max, alpha[i]);
            r.x_min = fmin(r.x_min, x0);
            r.x_max = fmax(r.x_max, x0);
        }
    }
    r.ok = st == SPH_OK;
    free(alpha);
    free(cinv);
    free(id);
    return r;
}

/* The plate of test 2 at H/dp = 5 and a fifth of its amplitude (v_f =
 * 0.01 c0, tip amplitude 0.027 m), 002's elastic-perfectly plastic model:
 *  a. sigma_Y = 2e4 Pa, to t = 0.1 s (past the first maximum deflection at
 *     ~0.07 s), both backends.  The elastic root stress is about E eps_max,
 *     eps_max = (H/2) kappa_root = 0.024 (first-mode root curvature
 *     kappa_root = 2 k^2 (sin kL + sinh kL) / |f(L)| = 88 /m per metre of tip
 *     deflection, 003 eqs. 50-51), i.e. ~5e4 Pa, 2.4 sigma_Y: the root yields.
 *     Where: the first-mode moment falls to 20 % of the root's at x = L/2 and
 *     the root moment is capped near the plane-strain plastic moment, whose
 *     elastic fibre stress is 1.5 x 2/sqrt3 sigma_Y = 1.73 sigma_Y, so
 *     beyond L/2 the stress stays below 0.35 sigma_Y: every yielded particle
 *     lies in x0 < L/2 = 0.1 m, and some at the root, x0 < 0.02 m.  The
 *     switch (E -> sigma_Y in the hourglass force) is on for exactly the
 *     yielded particles (alpha > 0; its effect: test 5), C_p^-1 - I is
 *     non-zero exactly there.  Energy: without dissipation E(t)/E(0) stays
 *     within 3 % (test 2; the strain-energy diagnostic is the small-strain
 *     one), so E(0.1)/E(0) < 0.8 is plastic dissipation (measured 0.65) and
 *     max E(t)/E(0) <= 1.03 says it stays bounded.
 *  b. (native backend) sigma_Y = 1e8 Pa, to t = 0.15 s: yielding would need
 *     |dev eps| = sqrt(2/3) sigma_Y / 2 mu ~ 57, so no particle yields, the
 *     state stays exactly zero and the run is Hencky elastic.  Against the
 *     elastic (SVK) run: the two laws differ at second order, tau_SVK -
 *     tau_Hencky ~ (3 + lambda/mu) eps^2 2 mu (test_plasticity), even in the
 *     strain, so in bending it adds no first-order moment and the tip
 *     histories differ by at most (3 + lambda/mu) eps_max^2 of the amplitude
 *     (0.4 %, 1.1e-4 m here; measured 1.8e-6 m), and both keep E(t)/E(0)
 *     within 3 %. */
static void plastic_plate(test_counts *t, sph_backend_kind kind) {
    sph_simulation sim;
    sph_error err = {0};
    sph_status st = small_plate(kind, "2.0e4", "0.1", &sim, &err);
    CHECK(t, st == SPH_OK, "plastic plate: %s", err.msg);
    if (!st) {
        const sph_backend *be = sim.backend;
        CHECK(t,
              sim.features.plastic && test_has_buffer(be, "plastic_strain") &&
                  test_has_buffer(be, "plastic_cinv"),
              "plastic TLSPH: feature set and buffers (plastic %d)", (int)sim.features.plastic);
        if (kind == SPH_BACKEND_OPENCL)
            CHECK(t,
                  strstr(be->program_kernels, " plastic_cinv") != NULL &&
                      strstr(be->build_options, "-DSPH_PLASTIC=1") != NULL,
                  "plastic TLSPH program: %s", be->build_options);
        double e_max, e_end;
        energy_ratios(&sim.series, &e_max, &e_end);
        const plastic_state_summary ps = plastic_state(&sim, &err);
        printf("plastic plate (%s, sigma_Y 2e4 Pa, t = 0.1 s): %d particles yielded (switched), "
               "max plastic strain %.4g, reference x in [%.4f, %.4f] m, max |C_p^-1 - I| %.4g; "
               "E/E0 end %.4f, max %.4f; %ld steps, %.2f s\n",
               be->kind_name, ps.yielded, ps.alpha_max, ps.x_min, ps.x_max, ps.cinv_max, e_end,
               e_max, sim.stats.acoustic_steps, sim.stats.wall_seconds);
        CHECK(t, ps.ok, "plastic state download: %s", err.msg);
        CHECK(t, ps.yielded >= 10 && ps.alpha_max > 1e-3, "the root yields: %d, max %.3g",
              ps.yielded, ps.alpha_max);
        CHECK(t, ps.x_min < 0.02 && ps.x_max < 0.1, "yielded at x0 in [%.4f, %.4f]", ps.x_min,
              ps.x_max);
        CHECK(t, ps.consistent == be->n, "C_p^-1 - I non-zero exactly where alpha > 0 (%d of %d)",
              ps.consistent, be->n);
        CHECK(t, e_end < 0.8, "plastic dissipation: E(0.1)/E(0) %.4f", e_end);
        CHECK(t, e_max <= 1.03, "energy bounded: max E(t)/E(0) %.4f", e_max);
    }
    sph_simulation_close(&sim);
    if (kind != SPH_BACKEND_CPU) return; /* b: the same program as a; CI time */

    sph_simulation el, hi;
    sph_error err2 = {0};
    st = small_plate(kind, NULL, "0.15", &el, &err);
    const sph_status st2 = small_plate(kind, "1.0e8", "0.15", &hi, &err2);
    CHECK(t, st == SPH_OK && st2 == SPH_OK, "elastic / high-yield plates: %s / %s", err.msg,
          err2.msg);
    if (!st && !st2) {
        CHECK(t,
              !test_has_buffer(el.backend, "plastic_cinv") &&
                  !test_has_buffer(el.backend, "plastic_strain"),
              "elastic TLSPH allocates no plastic buffer");
        const plastic_state_summary ps = plastic_state(&hi, &err);
        const sph_timeseries *a = &el.series, *b = &hi.series;
        double amp = 0.0, diff = 0.0;
        const int count = a->count < b->count ? a->count : b->count;
        for (int k = 0; k < count; ++k) {
            const double ya = a->observers[2 * k + 1] - a->observers[1];
            const double yb = b->observers[2 * k + 1] - b->observers[1];
            amp = fmax(amp, fabs(ya));
            diff = fmax(diff, fabs(ya - yb));
        }
        /* material and mode shape of the plate case: E 2e6 Pa, nu 0.3975,
         * L = 0.2 m, H = 0.02 m, kL = 1.875 */
        const double nu = 0.3975, lambda_over_mu = 2 * nu / (1 - 2 * nu);
        const double kl = 1.875, kk = kl / 0.2;
        const double fl = (sin(kl) + sinh(kl)) * (cos(kl) - cosh(kl)) -
                          (cos(kl) + cosh(kl)) * (sin(kl) - sinh(kl));
        const double eps_max = 0.01 * 2 * kk * kk * (sin(kl) + sinh(kl)) / fabs(fl) * amp;
        const double bound = (3 + lambda_over_mu) * eps_max * eps_max * amp;
        double ea_max, ea_end, eb_max, eb_end;
        energy_ratios(a, &ea_max, &ea_end);
        energy_ratios(b, &eb_max, &eb_end);
        printf("plate to 0.15 s: sigma_Y 1e8: %d yielded, max |C_p^-1 - I| %.3g; tip amplitude "
               "%.5f m, root strain %.4f; max |y_Hencky - y_SVK| %.3g m (bound %.3g); E/E0 end "
               "SVK %.4f, Hencky %.4f; %.2f s + %.2f s\n",
               ps.yielded, ps.cinv_max, amp, eps_max, diff, bound, ea_end, eb_end,
               el.stats.wall_seconds, hi.stats.wall_seconds);
        CHECK(t, ps.ok && ps.yielded == 0 && ps.cinv_max == 0.0,
              "sigma_Y 1e8: no plastic state (%d yielded, |C_p^-1 - I| %.3g)", ps.yielded,
              ps.cinv_max);
        CHECK(t, count > 10 && diff <= bound, "Hencky vs SVK tip: %.3g > %.3g", diff, bound);
        CHECK_RANGE(t, ea_end, 0.97, 1.03, "SVK E(0.15)/E(0)");
        CHECK_RANGE(t, eb_end, 0.97, 1.03, "Hencky E(0.15)/E(0)");
        CHECK(t, ea_max <= 1.03 && eb_max <= 1.03, "energies bounded: %.4f, %.4f", ea_max, eb_max);
    }
    sph_simulation_close(&el);
    sph_simulation_close(&hi);
}

/* 7. The hyperelastic laws (materials.X.model) on the patch mapped by a
 * large uniform deformation (30 % stretch, 15 % compression, shear): on the
 * interior P equals the law's closed form (hyperelastic_pk1) to 1e-12
 * relative, a law that differs from Saint Venant-Kirchhoff's there by more
 * than 5 %, and the deep particles feel no force. */
static void hyperelastic_patch(test_counts *t, sph_backend_kind kind, int model) {
    const int n = PATCH_N * PATCH_N;
    const double f0[4] = {1.3, 0.2, -0.1, 0.85};
    const char *name = model == ELASTIC_MODEL_NEO_HOOKEAN ? "neo-Hookean" : "exponential";
    sph_particles p = {0};
    sph_params_f64 prm[1];
    int32_t *id = malloc(sizeof(int32_t) * (size_t)n);
    double *pk1 = malloc(sizeof(double) * (size_t)(4 * n));
    double *acc = malloc(sizeof(double) * (size_t)(2 * n));
    sph_error err = {0};
    sph_backend *be = patch_backend_law(kind, 0.0, f0, NULL, model, 0.0, &p, prm, id, &err);
    sph_status st = be && id && pk1 && acc ? SPH_OK : SPH_ERR_RUNTIME;
    double v2 = 0.0;
    if (!st) st = be->ops->substep(be, 1e-7, &v2, &err);
    if (!st) st = be->ops->download(be, FIELD_PK1, pk1, &err);
    if (!st) st = be->ops->download(be, FIELD_ACC_SHEAR, acc, &err);
    CHECK(t, st == SPH_OK, "%s patch: %s", name, err.msg);
    if (!st && kind == SPH_BACKEND_OPENCL) {
        char option[64];
        snprintf(option, sizeof option, "-DSPH_ELASTIC_MODEL=%d", model);
        CHECK(t, strstr(be->build_options, option) != NULL, "%s program: %s", name,
              be->build_options);
    }
    if (!st) {
        const double lambda = prm->materials[0].lambda, mu = prm->materials[0].shear_modulus;
        double p_law[4], p_svk[4], p_max = 0.0, law_svk = 0.0, p_err = 0.0, a_edge = 0.0,
                                   a_deep = 0.0;
        hyperelastic_pk1(model, f0, lambda, mu, EXPONENTIAL_B, p_law);
        svk_pk1(f0, lambda, mu, p_svk);
        for (int k = 0; k < 4; ++k) {
            p_max = fmax(p_max, fabs(p_law[k]));
            law_svk = fmax(law_svk, fabs(p_law[k] - p_svk[k]));
        }
        const double dp = prm->dp;
        for (int i = 0; i < n; ++i) {
            const double gx = p.pos[id[i]] / dp - 0.5, gy = p.pos[n + id[i]] / dp - 0.5;
            const double edge = fmin(fmin(gx, gy), fmin(PATCH_N - 1 - gx, PATCH_N - 1 - gy));
            const double a = hypot(acc[i], acc[n + i]);
            a_edge = fmax(a_edge, a);
            if (edge >= 2.6)
                for (int k = 0; k < 4; ++k) p_err = fmax(p_err, fabs(pk1[k * n + i] - p_law[k]));
            if (edge >= 5.2) a_deep = fmax(a_deep, a);
        }
        printf("%s patch (%s): max |P - P_law| / |P| %.3g (the law differs from SVK by %.3g); "
               "deep max |a| %.3g of the edge's %.3g\n",
               name, be->kind_name, p_err / p_max, law_svk / p_max, a_deep, a_edge);
        CHECK(t, p_err <= 1e-12 * p_max, "%s: P error %.3g of %.3g", name, p_err, p_max);
        CHECK(t, law_svk >= 0.05 * p_max, "%s: the law is SVK's here (%.3g of %.3g)", name, law_svk,
              p_max);
        CHECK(t, a_deep <= 1e-9 * a_edge, "%s: deep acceleration %.3g, edge %.3g", name, a_deep,
              a_edge);
    }
    if (be) sph_backend_destroy(be);
    sph_particles_free(&p);
    free(id);
    free(pk1);
    free(acc);
}

/* the damping patch's substep, s */
#define DAMPING_PATCH_DT 1e-10

/* The acceleration of the patch at F = I with velocity field `field` (0: a
 * uniform expansion v = rate (x - c), 1: a rigid rotation v = rate e_z x
 * (x - c)), after one substep of DAMPING_PATCH_DT (the half-step
 * positions barely move), with pairwise damping c_d.
 * acc (2n, slot order) and id (n) are filled; returns the status. */
static sph_status damping_patch_run(sph_backend_kind kind, double damping, int field, double rate,
                                    sph_particles *p, sph_params_f64 *prm, int32_t *id, double *acc,
                                    sph_error *err) {
    const int n = PATCH_N * PATCH_N;
    const double f0[4] = {1.0, 0.0, 0.0, 1.0};
    sph_backend *be =
        patch_backend_law(kind, 0.0, f0, NULL, ELASTIC_MODEL_SVK, damping, p, prm, id, err);
    if (!be) return SPH_ERR_RUNTIME;
    /* the damping is compiled into the OpenCL program only when it acts */
    if (kind == SPH_BACKEND_OPENCL &&
        (strstr(be->build_options, "-DSPH_TL_DAMPING=1") != NULL) != (damping > 0)) {
        sph_fail(err, SPH_ERR_RUNTIME, "damping %g, program %s", damping, be->build_options);
        sph_backend_destroy(be);
        return SPH_ERR_RUNTIME;
    }
    double *vel = malloc(sizeof(double) * (size_t)(2 * n));
    sph_status st = vel ? SPH_OK : sph_fail(err, SPH_ERR_RUNTIME, "out of memory");
    const double c = 0.5 * PATCH_N * prm->dp;
    for (int i = 0; !st && i < n; ++i) {
        const double dx = p->pos[id[i]] - c, dy = p->pos[n + id[i]] - c;
        vel[i] = field == 0 ? rate * dx : -rate * dy;
        vel[n + i] = field == 0 ? rate * dy : rate * dx;
    }
    double v2 = 0.0;
    if (!st) st = be->ops->upload_field(be, FIELD_VEL, vel, err);
    if (!st) st = be->ops->substep(be, DAMPING_PATCH_DT, &v2, err);
    if (!st) st = be->ops->download(be, FIELD_ACC_SHEAR, acc, err);
    free(vel);
    sph_backend_destroy(be);
    return st;
}

/* 8. TLSPH's pairwise damping (method.pairwise_damping, tl_step.cl) on the
 * patch at F = I: under a uniform expansion v = rate (x - c) every pair's
 * eps_ij = d^2 rate, so particle i's damping acceleration (the run with
 * damping minus the one without) is
 *   a_i = c_d 1/2 c0 h d^2 rate sum_j (W_ij / W(0)) dW_ij V0_j e_ij,
 * recomputed here from the kernel for a corner particle and an edge
 * particle (1e-12 relative); it vanishes on the deep particles, conserves
 * momentum (1e-12 of sum m |a|) and takes energy out (sum m a.v < 0).  A
 * rigid rotation at the same rate is not damped: its damping acceleration is
 * below 1e-6 of the expansion's. */
static void damping_patch(test_counts *t, sph_backend_kind kind) {
    const int n = PATCH_N * PATCH_N;
    const double cd = 0.25, rate = 10.0; /* 1/s */
    sph_particles p0 = {0}, p1 = {0}, p2 = {0}, p3 = {0};
    sph_params_f64 prm[1];
    int32_t *id = malloc(sizeof(int32_t) * (size_t)n);
    double *a_on = malloc(sizeof(double) * (size_t)(2 * n));
    double *a_off = malloc(sizeof(double) * (size_t)(2 * n));
    double *r_on = malloc(sizeof(double) * (size_t)(2 * n));
    double *r_off = malloc(sizeof(double) * (size_t)(2 * n));
    sph_error err = {0};
    sph_status st = id && a_on && a_off && r_on && r_off ? SPH_OK : SPH_ERR_RUNTIME;
    if (!st) st = damping_patch_run(kind, cd, 0, rate, &p0, prm, id, a_on, &err);
    if (!st) st = damping_patch_run(kind, 0.0, 0, rate, &p1, prm, id, a_off, &err);
    if (!st) st = damping_patch_run(kind, cd, 1, rate, &p2, prm, id, r_on, &err);
    if (!st) st = damping_patch_run(kind, 0.0, 1, rate, &p3, prm, id, r_off, &err);
    CHECK(t, st == SPH_OK, "damping patch: %s", err.msg);
    if (!st) {
        const double dp = prm->dp, c = 0.5 * PATCH_N * dp, rho0 = prm->materials[0].rho0;
        const double mass = rho0 * dp * dp;
        const sph_physics *k = sph_physics_for(2, true);
        const double w0 = k->kernel_w(prm, 0.0);
        /* the substep's half-step positions x + dt/2 v = (1 + dt/2 rate) x
         * scale both x_ij . v_ij and F = (1 + dt/2 rate) I */
        const double half = 1.0 + 0.5 * DAMPING_PATCH_DT * rate;
        const double scale = cd * 0.5 * prm->materials[0].c0 * prm->h * 4.0 * rate * half * half;
        double mom[2] = {0, 0}, mag = 0.0, power = 0.0, a_deep = 0.0, a_max = 0.0, r_max = 0.0,
               formula_err = 0.0;
        int checked = 0;
        for (int i = 0; i < n; ++i) {
            const double ax = a_on[i] - a_off[i], ay = a_on[n + i] - a_off[n + i];
            const double xi = p0.pos[id[i]], yi = p0.pos[n + id[i]];
            mom[0] += mass * ax;
            mom[1] += mass * ay;
            mag += mass * hypot(ax, ay);
            power += mass * (ax * rate * (xi - c) + ay * rate * (yi - c));
            a_max = fmax(a_max, hypot(ax, ay));
            r_max = fmax(r_max, hypot(r_on[i] - r_off[i], r_on[n + i] - r_off[n + i]));
            const double gx = xi / dp - 0.5, gy = yi / dp - 0.5;
            const double edge = fmin(fmin(gx, gy), fmin(PATCH_N - 1 - gx, PATCH_N - 1 - gy));
            if (edge >= 2.6) a_deep = fmax(a_deep, hypot(ax, ay));
            /* the corner (0, 0) and the edge particle (0, 10) */
            const bool probe = (gx < 0.5 && gy < 0.5) || (gx < 0.5 && fabs(gy - 10) < 0.5);
            if (!probe) continue;
            double sum[2] = {0, 0};
            for (int j = 0; j < n; ++j) {
                const double dx = xi - p0.pos[id[j]], dy = yi - p0.pos[n + id[j]];
                const double r = hypot(dx, dy);
                if (j == i || r >= prm->cutoff) continue;
                const double g = k->kernel_w(prm, r) / w0 * k->kernel_dw(prm, r) * dp * dp / r;
                sum[0] += g * dx;
                sum[1] += g * dy;
            }
            const double ex = scale * sum[0], ey = scale * sum[1];
            formula_err = fmax(formula_err, hypot(ax - ex, ay - ey) / hypot(ex, ey));
            ++checked;
        }
        printf("damping patch (%s): expansion: probes against the formula %.3g (%d), deep |a| "
               "%.3g of %.3g, |sum m a| %.3g of %.3g, power %.4g W/m; rotation: max |a| %.3g\n",
               kind == SPH_BACKEND_CPU ? "cpu" : "opencl", formula_err, checked, a_deep, a_max,
               hypot(mom[0], mom[1]), mag, power, r_max);
        CHECK(t, checked == 2 && formula_err <= 1e-12, "damping formula: %.3g (%d probes)",
              formula_err, checked);
        CHECK(t, a_max > 0 && a_deep <= 1e-9 * a_max, "deep damping %.3g of %.3g", a_deep, a_max);
        CHECK(t, hypot(mom[0], mom[1]) <= 1e-12 * mag, "damping momentum %.3g of %.3g",
              hypot(mom[0], mom[1]), mag);
        CHECK(t, power < 0, "damping power %.4g, not negative", power);
        CHECK(t, r_max <= 1e-6 * a_max, "rigid rotation damped: %.3g of %.3g", r_max, a_max);
    }
    sph_particles_free(&p0);
    sph_particles_free(&p1);
    sph_particles_free(&p2);
    sph_particles_free(&p3);
    free(id);
    free(a_on);
    free(a_off);
    free(r_on);
    free(r_off);
}

int main(int argc, char **argv) {
    test_counts t = {0};
    const sph_backend_kind kind = test_backend_kind(argc, argv);
    patch_test(&t, kind);
    /* hourglass control: the checkerboard mode after 200 steps (0.018 s) */
    sph_error err = {0};
    const double bare = checkerboard_patch(kind, 0.0, 200, &err);
    const double controlled = checkerboard_patch(kind, HOURGLASS_ALPHA, 200, &err);
    printf("checkerboard patch (%s): hourglass indicator alpha = 0: %.3e, alpha = %.2f: %.3e "
           "(ratio %.1f)\n",
           kind == SPH_BACKEND_CPU ? "cpu" : "opencl", bare, HOURGLASS_ALPHA, controlled,
           bare / controlled);
    CHECK(&t, bare >= 1e-3 && controlled > 0, "checkerboard runs: %.3e, %.3e: %s", bare, controlled,
          err.msg);
    CHECK(&t, bare >= HOURGLASS_RATIO * controlled,
          "hourglass indicator alpha = 0: %.3e, alpha = %.2f: %.3e (ratio %.2f < %.1f)", bare,
          HOURGLASS_ALPHA, controlled, bare / controlled, HOURGLASS_RATIO);

    hourglass_switch(&t, kind);
    plastic_plate(&t, kind);
    hyperelastic_patch(&t, kind, ELASTIC_MODEL_NEO_HOOKEAN);
    hyperelastic_patch(&t, kind, ELASTIC_MODEL_EXPONENTIAL);
    damping_patch(&t, kind);

    const double t_theory = 0.25406; /* 004 eq. 33, nu = 0.3975 */
    const bool full = !test_sanitized();
    const double end = full ? 0.29 : 0.1;
    const plate_result w = run_plate(&t, kind, "wendland-c2", end);
    if (w.ok) {
        CHECK_RANGE(&t, w.energy_ratio, 0.97, 1.03, "E(end)/E(0)");
        CHECK_RANGE(&t, w.amplitude, 0.09, 0.14, "tip amplitude (m)");
        if (full) /* 004: T_W 0.282 s, 11.0 %; +-1.5 points */
            CHECK_RANGE(&t, w.period, t_theory * 1.095, t_theory * 1.125, "T Wendland (s)");
    }
    /* the kernel is the only difference: run once, on the native backend
     * (both backends gave the same periods to 5 digits; CI time) */
    if (kind == SPH_BACKEND_CPU) {
        const plate_result lg = run_plate(&t, kind, "laguerre-gauss", end);
        if (lg.ok) {
            CHECK_RANGE(&t, lg.energy_ratio, 0.97, 1.03, "Laguerre-Gauss E(end)/E(0)");
            if (full) /* 004: T_LG 0.271 s, 6.7 %; +-1.5 points */
                CHECK_RANGE(&t, lg.period, t_theory * 1.052, t_theory * 1.082,
                            "T Laguerre-Gauss (s)");
        }
    }
    if (!full)
        printf("sanitized: the plates run to t = %g s; their periods are the release build's\n",
               end);
    return test_summary("test_tlsph", &t);
}
