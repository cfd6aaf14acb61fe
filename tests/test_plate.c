/* test_plate.c — the 2D oscillating plate (000 §6.1, 003 §5.1.1) with
 * SPH-ENOG-A at H/dp = 10, v_f = 0.05, run to t = 1 s on one backend.
 *
 * Bounds and where they come from:
 *  - 1612 particles including the 312-particle clamp layer and the initial
 *    kinetic energy 4.0647984104 J/m: the reference code's lattice and
 *    regression data (reference notes §0.6, §6.1), relative 1e-6;
 *  - first period in [0.27, 0.30] s: the reference code gets 0.286-0.289 s at
 *    this resolution (its regression series and our rerun of it, §6.1, §11);
 *    the papers' converged H/dp = 30 values are 0.265-0.269 (003 Table 1) and
 *    thin-plate theory 0.254 (003 eq. 52);
 *  - stable to t = 1 s: the run completes with finite energies, the tip
 *    amplitude stays near the reference's 0.116-0.117 m (§11: "extremes stay
 *    about +-0.116-0.117 m over 1 s"; we allow 0.09-0.14), and the total energy
 *    neither grows nor collapses (the Riemann dissipation only removes energy:
 *    E(1)/E(0) in [0.5, 1.01]).
 *
 * Under the sanitizers (test_sanitized) the run ends at t = 0.3 s, past the
 * first period and the first swing's largest deflection, and every bound is
 * checked there (E(0.3)/E(0) measured 1.004); the run to 1 s is the release
 * build's.
 */
#include "test_support.h"

#include <math.h>

int main(int argc, char **argv) {
    test_counts t = {0};
    const sph_backend_kind kind = test_backend_kind(argc, argv);
    sph_simulation sim;
    sph_error err = {0};
    const double end = test_sanitized() ? 0.3 : 1.0; /* the case's end: 1 s */
    char end_set[48];
    const char *overrides[] = {test_end_override(end_set, sizeof end_set, end)};
    const sph_status st = test_run_case("oscillating_plate_2d", overrides, 1, kind,
                                        SPH_PRECISION_DOUBLE, 0, &sim, &err);
    CHECK(&t, st == SPH_OK, "plate run failed: %s", err.msg);
    if (st == SPH_OK) {
        const sph_metrics *m = &sim.metrics;
        printf("plate %s: %d particles (%d fixed), KE0 %.10f, first period %.5f s, max tip "
               "displacement %.5f m, E(%g)/E(0) %.4f, %ld acoustic / %ld advection steps, %.2f s\n",
               sim.backend->kind_name, sim.particles.n, sim.particles.fixed_count,
               m->initial_kinetic_energy, m->first_period, m->max_observer_displacement, end,
               m->final_total_energy_ratio, sim.stats.acoustic_steps, sim.stats.advection_steps,
               sim.stats.wall_seconds);
        CHECK(&t, sim.particles.n == 1612, "particle count %d", sim.particles.n);
        CHECK(&t, sim.particles.fixed_count == 312, "clamp particles %d",
              sim.particles.fixed_count);
        CHECK_NEAR(&t, m->initial_kinetic_energy, 4.0647984104106447, 4.0647984104106447 * 1e-6,
                   "initial kinetic energy (J/m)");
        CHECK_RANGE(&t, m->first_period, 0.27, 0.30, "first period (s)");
        CHECK_NEAR(&t, sim.stats.end_time, end, 1e-12, "simulated to the end");
        CHECK_RANGE(&t, m->max_observer_displacement, 0.09, 0.14, "tip amplitude (m)");
        CHECK_RANGE(&t, m->final_total_energy_ratio, 0.5, 1.01, "E(end)/E(0)");
        /* dual-criteria stepping: 5-10 acoustic steps per advection step (000 §5) */
        const double ratio = (double)sim.stats.acoustic_steps / (double)sim.stats.advection_steps;
        CHECK_RANGE(&t, ratio, 5.0, 12.0, "acoustic steps per advection step");
    }
    sph_simulation_close(&sim);
    return test_summary("test_plate", &t);
}
