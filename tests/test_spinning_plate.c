/* test_spinning_plate.c — the 2D spinning plate (003 §5.1.3) to t = 0.5 s on
 * one backend: the rotation of SPH-ENOG-A does what the paper claims.
 *
 *  - initial kinetic energy 228593.75 (the rigid-body value of the 20x20
 *    lattice, reference notes §6.4), relative 1e-9;
 *  - SPH-ENOG-A (averaged rotation, 003 eq. 41): maximum angular-momentum
 *    error <= 3 % (paper 2.58 %, 003 Fig. 13);
 *  - plain SPH-ENOG: >= 20 % (paper 59.17 %): without the rotation the
 *    accumulated shear acceleration keeps its old direction and produces a
 *    net torque (003 §4.1, eq. 31);
 *  - linear momentum: conserved to round-off with the averaged rotation and
 *    without rotation (every pair term is antisymmetric and R-bar is the same
 *    for all particles): drift below 1e-9 of sum m|v|.
 */
#include "test_support.h"

#include <math.h>

static void run(test_counts *t, sph_backend_kind kind, const char *formulation,
                const char *rotation, double *error_out) {
    char f[64], r[64];
    snprintf(f, sizeof f, "method.formulation=%s", formulation);
    snprintf(r, sizeof r, "method.rotation=%s", rotation);
    const char *overrides[] = {f, r};
    sph_simulation sim;
    sph_error err = {0};
    const sph_status st =
        test_run_case("spinning_plate_2d", overrides, 2, kind, true, 0, &sim, &err);
    CHECK(t, st == SPH_OK, "%s run failed: %s", formulation, err.msg);
    *error_out = NAN;
    if (st == SPH_OK) {
        const sph_metrics *m = &sim.metrics;
        printf("spinning plate %s (%s) on %s: KE0 %.4f, max angular-momentum error %.3f %%, "
               "linear momentum drift %.3g, %ld steps, %.2f s\n",
               formulation, rotation, sim.backend->kind_name, m->initial_kinetic_energy,
               100.0 * m->max_angular_momentum_error, m->max_linear_momentum_drift,
               sim.stats.acoustic_steps, sim.stats.wall_seconds);
        CHECK(t, sim.particles.n == 400, "particle count %d", sim.particles.n);
        CHECK_NEAR(t, m->initial_kinetic_energy, 228593.75, 228593.75 * 1e-9, "initial KE");
        CHECK_NEAR(t, sim.stats.end_time, 0.5, 1e-12, "simulated to t = 0.5 s");
        CHECK(t, m->max_linear_momentum_drift < 1e-9, "linear momentum drift %.3g",
              m->max_linear_momentum_drift);
        *error_out = m->max_angular_momentum_error;
    }
    sph_simulation_close(&sim);
}

int main(int argc, char **argv) {
    test_counts t = {0};
    const sph_backend_kind kind = test_backend_kind(argc, argv);
    double enog_a, enog;
    run(&t, kind, "enog-a", "averaged", &enog_a);
    run(&t, kind, "enog", "none", &enog);
    CHECK(&t, enog_a <= 0.03, "ENOG-A max angular-momentum error %.4f > 3 %%", enog_a);
    CHECK(&t, enog >= 0.20, "ENOG max angular-momentum error %.4f < 20 %%", enog);
    return test_summary("test_spinning_plate", &t);
}
