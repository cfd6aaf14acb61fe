/* test_spinning_plate.c — the 2D spinning plate (003 §5.1.3) to t = 0.5 s on
 * one backend: the rotation of SPH-ENOG-A does what the paper claims.
 *
 *  - initial kinetic energy 228593.75 (the rigid-body value of the 20x20
 *    lattice, reference notes §6.4), relative 1e-9;
 *  - SPH-ENOG-A (averaged rotation, 003 eq. 41): maximum angular-momentum
 *    error <= 3 % (paper 2.58 %, 003 Fig. 13; measured 1.05 %);
 *  - plain SPH-ENOG: >= 20 % (paper 59.17 %): without the rotation the
 *    accumulated shear acceleration keeps its old direction and produces a
 *    net torque (003 §4.1, eq. 31);
 *  - SPH-GNOG (003 eqs. 43-45, xi_G = 4): <= 1.5 % (paper 1.12 %; 0.52 %);
 *  - SPH-GNOG-A (003 eqs. 46-49, xi_G = 2, averaged rotation): <= 0.8 %
 *    (paper 0.55 %; measured 0.026 %), with the pair geometry frozen at the
 *    middle of each step (time.frozen_geometry, device/neighbour_build.cl);
 *    frozen at its start, the directions lag the rotation and spin the plate
 *    up: at least 10x more (1.51 %);
 *  - SPH-GNOG-A with per-particle R_i and the geometry frozen at the start of
 *    the step, as in the public reference code: its kinetic-energy history equals the reference
 *    code's regression data for this case (reference notes §6.4: 226767,
 *    226892, 226503, 226357 J/m at t = 0.01 ... 0.04 s, 220414 at 0.5 s,
 *    given to 6 digits) within 1e-4 relative (measured 8e-5 at 0.5 s);
 *  - SPH-ENOG-A at nu = 0.3 (the spinning cube's material, 003 §5.1.4):
 *    the paper's algorithm leaves the accumulated shear acceleration a net
 *    torque that spins the plate up steadily, >= 10 % by 0.5 s (measured
 *    16.1 %); with method.torque_projection (device/sph_torque_projection.h)
 *    <= 0.01 % (measured 0.0011 %; 0.0005 % at nu = 0.45), ten times the
 *    measurement and far below every published error;
 *  - linear momentum: conserved to round-off with the averaged rotation and
 *    without rotation (every pair term is antisymmetric and R-bar is the same
 *    for all particles): drift below 1e-9 of sum m|v|, for every formulation.
 *
 * Under the sanitizers (test_sanitized) every run ends at t = 0.05 s, a tenth:
 * the upper bounds on the maximum errors hold for any prefix of a run, and
 * ENOG's error (39 % by 0.05 s), the start-frozen spin-up (32 times the
 * midpoint's), ENOG's energy trip (1.63 E(0) by 0.04 s) and the reference
 * code's kinetic energies at 0.01-0.04 s are checked as in full; ENOG-A's
 * spin-up at nu = 0.3 (0.94 % by 0.05 s) and the kinetic energy at 0.5 s
 * need the whole run and are the release build's.
 */
#include "test_support.h"

#include <math.h>
#include <string.h>

/* every run's end: the case's 0.5 s, a tenth under the sanitizers */
static double run_end(void) {
    return test_sanitized() ? 0.05 : 0.5;
}

/* `trip`: when not NULL, the monitor only reports, and the quantity of its
 * first trip is copied there ("" when none) */
static void run_with(test_counts *t, sph_backend_kind kind, const char *formulation,
                     const char *rotation, const char *geometry, const char *extra[2],
                     double *error_out, double *ke_out, char *trip) {
    char f[64], r[64], g[64], end_set[48];
    const double end = run_end();
    snprintf(f, sizeof f, "method.formulation=%s", formulation);
    snprintf(r, sizeof r, "method.rotation=%s", rotation);
    snprintf(g, sizeof g, "time.frozen_geometry=%s", geometry);
    const char *overrides[7] = {f, r, g, test_end_override(end_set, sizeof end_set, end)};
    int count = 4;
    for (int k = 0; extra && k < 2; ++k)
        if (extra[k]) overrides[count++] = extra[k];
    if (trip) overrides[count++] = "monitor.action=report";
    sph_simulation sim;
    sph_error err = {0};
    const sph_status st = test_run_case("spinning_plate_2d", overrides, count, kind,
                                        SPH_PRECISION_DOUBLE, 0, &sim, &err);
    if (trip)
        snprintf(trip, 48, "%s",
                 st == SPH_OK && !isnan(sim.stats.instability_time) ? sim.stats.instability_quantity
                                                                    : "");
    CHECK(t, st == SPH_OK, "%s run failed: %s", formulation, err.msg);
    *error_out = NAN;
    if (st == SPH_OK) {
        const sph_metrics *m = &sim.metrics;
        printf("spinning plate %s (%s, geometry at the %s%s%s%s%s) on %s: KE0 %.4f, max "
               "angular-momentum error %.4f %%, linear momentum drift %.3g, %ld steps, %.2f s\n",
               formulation, rotation, geometry, extra && extra[0] ? ", " : "",
               extra && extra[0] ? extra[0] : "", extra && extra[1] ? ", " : "",
               extra && extra[1] ? extra[1] : "", sim.backend->kind_name, m->initial_kinetic_energy,
               100.0 * m->max_angular_momentum_error, m->max_linear_momentum_drift,
               sim.stats.acoustic_steps, sim.stats.wall_seconds);
        CHECK(t, sim.particles.n == 400, "particle count %d", sim.particles.n);
        CHECK_NEAR(t, m->initial_kinetic_energy, 228593.75, 228593.75 * 1e-9, "initial KE");
        CHECK(t, fabs(sim.stats.end_time - end) <= 1e-12, "simulated to t = %.10g s, not %g s",
              sim.stats.end_time, end);
        CHECK(t, m->max_linear_momentum_drift < 1e-9, "linear momentum drift %.3g",
              m->max_linear_momentum_drift);
        *error_out = m->max_angular_momentum_error;
        /* kinetic energy at t = 0.01, 0.02, 0.03, 0.04 and 0.5 s */
        const int rows[5] = {1, 2, 3, 4, 50};
        for (int k = 0; ke_out && k < 5; ++k)
            ke_out[k] = rows[k] < sim.series.count ? sim.series.diag[rows[k]].kinetic : NAN;
    }
    sph_simulation_close(&sim);
}

static void run(test_counts *t, sph_backend_kind kind, const char *formulation,
                const char *rotation, const char *geometry, double *error_out, double *ke_out,
                char *trip) {
    run_with(t, kind, formulation, rotation, geometry, NULL, error_out, ke_out, trip);
}

int main(int argc, char **argv) {
    test_counts t = {0};
    const sph_backend_kind kind = test_backend_kind(argc, argv);
    double enog_a, enog, gnog, gnog_a, gnog_a_avg, gnog_a_start;
    double ke[5];
    char enog_trip[48];
    run(&t, kind, "enog-a", "averaged", "midpoint", &enog_a, NULL, NULL);
    /* plain ENOG accumulates its shear acceleration unrotated: the rigid
     * rotation strains it, and the monitor's energy-growth check sees the
     * spurious strain energy (1.63 E(0) at t = 0.04 s) */
    run(&t, kind, "enog", "none", "midpoint", &enog, NULL, enog_trip);
    run(&t, kind, "gnog", "none", "midpoint", &gnog, NULL, NULL);
    run(&t, kind, "gnog-a", "averaged", "midpoint", &gnog_a_avg, NULL, NULL);
    /* the reference code freezes the pair geometry at the start of the step */
    run(&t, kind, "gnog-a", "per-particle", "start", &gnog_a, ke, NULL);
    run(&t, kind, "gnog-a", "averaged", "start", &gnog_a_start, NULL, NULL);
    CHECK(&t, strncmp(enog_trip, "total energy", 12) == 0,
          "ENOG: the monitor reports the energy growth (first trip: '%s')", enog_trip);
    CHECK(&t, enog_a <= 0.03, "ENOG-A max angular-momentum error %.4f > 3 %%", enog_a);
    const bool full = !test_sanitized();
    CHECK(&t, enog >= 0.20, "ENOG max angular-momentum error %.4f < 20 %%", enog);
    CHECK(&t, gnog <= 0.015, "GNOG max angular-momentum error %.4f > 1.5 %%", gnog);
    CHECK(&t, gnog_a_avg <= 0.008, "GNOG-A max angular-momentum error %.4f > 0.8 %%", gnog_a_avg);
    /* frozen at the start, the directions lag the rotation and spin the plate
     * up (neighbour_build.cl): 1.51 % against 0.026 % at the midpoint */
    CHECK(&t, gnog_a_start >= 10.0 * gnog_a_avg,
          "GNOG-A with the geometry frozen at the start %.4f: not the lag's spin-up (midpoint "
          "%.4f)",
          gnog_a_start, gnog_a_avg);
    /* nu = 0.3: the paper's ENOG-A spins the plate up; the torque
     * projection holds its angular momentum */
    double enog_a_soft, enog_a_soft_projected, enog_a_projected;
    const char *soft[2] = {"materials.rubber.poisson_ratio=0.3", NULL};
    const char *soft_projected[2] = {"materials.rubber.poisson_ratio=0.3",
                                     "method.torque_projection=true"};
    const char *projected[2] = {"method.torque_projection=true", NULL};
    run_with(&t, kind, "enog-a", "averaged", "midpoint", soft, &enog_a_soft, NULL, NULL);
    run_with(&t, kind, "enog-a", "averaged", "midpoint", soft_projected, &enog_a_soft_projected,
             NULL, NULL);
    run_with(&t, kind, "enog-a", "averaged", "midpoint", projected, &enog_a_projected, NULL, NULL);
    CHECK(&t, !full || enog_a_soft >= 0.10,
          "ENOG-A at nu = 0.3 max angular-momentum error %.4f < 10 %%: no spin-up to remove",
          enog_a_soft);
    CHECK(
        &t, enog_a_soft_projected <= 1e-4,
        "ENOG-A at nu = 0.3 with the torque projection: max angular-momentum error %.6f > 0.01 %%",
        enog_a_soft_projected);
    CHECK(&t, enog_a_projected <= 1e-4,
          "ENOG-A with the torque projection: max angular-momentum error %.6f > 0.01 %%",
          enog_a_projected);
    static const double reference[5] = {226767, 226892, 226503, 226357, 220414};
    for (int k = 0; k < (full ? 5 : 4); ++k)
        CHECK(&t, fabs(ke[k] - reference[k]) <= 1e-4 * reference[k],
              "GNOG-A kinetic energy %.1f against the reference code's %.0f", ke[k], reference[k]);
    if (!full)
        printf("sanitized: runs to t = %g s; ENOG-A's spin-up at nu = 0.3 and the kinetic energy "
               "at 0.5 s are the release build's\n",
               run_end());
    return test_summary("test_spinning_plate", &t);
}
