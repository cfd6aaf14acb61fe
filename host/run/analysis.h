/* analysis.h — the recorded time series and the case metrics derived from it.
 *
 * first_period: the first oscillation period of an observer coordinate
 *   (003 Table 1, 000 Table 1): the motion starts at the rest position with
 *   its largest speed, so one full period ends at the second zero crossing of
 *   the displacement; crossings are located by linear interpolation between
 *   samples.
 * max_angular_momentum_error: max over the samples of |L(t) - L(0)| / |L(0)|
 *   (003 Fig. 13), L about the origin.  Reported only where the scene
 *   conserves angular momentum (no constraint, wall or gravity: anything else
 *   makes |L - L0| / |L0| a measure of the external torque, 200 % on the
 *   clamped 2D plate, not an error) and where the body spins: |L(0)| above
 *   1e-9 of sum m |x| |v|, both taken in double from the initial particles on
 *   the host, so that the decision is the same in every precision (the
 *   device's own L(0) of a body without spin is its round-off, 1e-8 of the
 *   scale in single precision).
 * scales: the physical size of the quantities `sphsolid compare` checks; a
 *   quantity that is zero in theory (the linear momentum of a spinning plate)
 *   differs between two runs by round-off of this size, not of its own.
 */
#ifndef SPH_ANALYSIS_H
#define SPH_ANALYSIS_H

#include "backend.h"
#include "particles.h"
#include "scene.h"

#include <stdbool.h>
#include <stddef.h>

#include <math.h>

typedef struct {
    int dim, nobservers;
    int count, capacity;
    double *time;
    sph_diagnostics *diag;
    double *observers; /* [count][nobservers * dim] */
} sph_timeseries;

sph_status sph_timeseries_init(sph_timeseries *ts, int dim, int nobservers, sph_error *err);
sph_status sph_timeseries_append(sph_timeseries *ts, double t, const sph_diagnostics *d,
                                 const double *observers, sph_error *err);
void sph_timeseries_free(sph_timeseries *ts);

/* The initial particles' sums, in double on the host (before any device
 * rounding), about the origin, the point the diagnostics take L about. */
typedef struct {
    double total_mass;    /* sum m */
    double momentum_sum;  /* sum m |v| */
    double angular[3];    /* L(0) = sum m x cross v (2D: angular[2]) */
    double angular_sum;   /* sum m |x| |v|: the scale of |L(0)| and of its round-off */
    double polar_inertia; /* sum m |x|^2 */
} sph_initial_sums;

void sph_initial_sums_compute(const sph_particles *p, sph_initial_sums *s);

/* Whether the scene conserves angular momentum: false, with the reasons in
 * `why` ("constraint 'fixed' on region 'clamp' of body 'plate'; gravity"),
 * when a constraint, a wall or gravity acts on the bodies. */
bool sph_angular_momentum_conserved(const sph_scene *scene, char *why, size_t size);

typedef struct {
    double first_period;               /* NAN when not requested or not found */
    double max_angular_momentum_error; /* NAN when not conserved or L(0) = 0 */
    /* "" where the scene conserves angular momentum, else why it does not */
    char angular_momentum_not_conserved[256];
    double initial_angular_momentum; /* |L(0)| from sph_initial_sums */
    /* max |P(t) - P(0)| / sum m |v(0)|; NAN when not conserved (the same
     * reasons as the angular momentum) */
    double max_linear_momentum_drift;
    double initial_kinetic_energy;
    double final_total_energy_ratio;  /* E(end) / E(0) */
    double max_observer_displacement; /* of the period observer along its axis */
    /* summary.json "scales" (docs/output-format.md), for `sphsolid compare`:
     *   momentum: sqrt(2 M max_t E_kin), the largest sum m |v| the kinetic
     *     energy allows (Cauchy-Schwarz), >= sum m |v| at every sample;
     *   angular_momentum: sqrt(2 sum m |x(0)|^2 max_t E_kin), the same bound
     *     of sum m |x| |v| at the initial positions;
     *   energy: max_t (E_kin + E_strain). */
    double total_mass, momentum_scale, angular_momentum_scale, energy_scale;
} sph_metrics;

/* Fluids (the eulerian formulations): conservation and the forces on the
 * wall bodies (004 §4.3, Table 5). */
typedef struct {
    double max_mass_drift;         /* max |M(t) - M(0)| / M(0) */
    double max_total_energy_drift; /* compressible: max |E(t) - E(0)| / E(0) */
    /* with `forces`, over the trailing window [force_window_start, end]:
     * the mean C_D, half the peak-to-peak C_L, and St = f L / U from the
     * mean spacing of C_L's upward crossings of its mean */
    double mean_drag_coefficient, lift_amplitude, strouhal_number;
    double force_window_start;
} sph_fluid_metrics;

void sph_fluid_metrics_compute(const sph_timeseries *ts, const sph_scene *scene,
                               sph_fluid_metrics *m);
/* C_D and C_L of one sample: 2 F / (rho_ref U_ref^2 L_ref), F the force on
 * the walls along x and y. */
void sph_force_coefficients(const sph_scene *scene, const sph_diagnostics *d, double *drag,
                            double *lift);

/* analysis.wave: a stress pulse through an interface (cases/bimaterial_bar).
 * The normal traction s(t) = t . n of observer `incident` shows the
 * incident pulse and later the reflected one, that of observer
 * `transmitted` the transmitted pulse.  A pulse is the first run of samples
 * (from a given one on) where s keeps the sign of, and at least half of,
 * the largest |s| from there on; its amplitude is the mean of s over the
 * middle half of the run, which leaves out the fronts and their overshoot.
 * The reflected pulse is the first one after the incident pulse has fallen
 * below a tenth of its largest value.  Theory:
 * the one-dimensional relations T = 2 Z2/(Z1 + Z2), R = (Z2 - Z1)/(Z2 + Z1)
 * with Z = sqrt(rho0 M) of the material at each observer, M = K + 2G(1 -
 * 1/d) the modulus of a uniaxial strain of the model (its deviator is that
 * of d dimensions: K + G in 2D, K + 4G/3 in 3D).  NaN where a pulse is
 * missing. */
typedef struct {
    double incident, reflected, transmitted; /* amplitudes of t . n (Pa) */
    double transmitted_ratio, reflected_ratio;
    double transmitted_ratio_theory, reflected_ratio_theory;
    double impedance_incident, impedance_transmitted; /* Z1, Z2 (kg m^-2 s^-1) */
} sph_wave_metrics;

/* The amplitude of the first pulse of traction observer o's normal
 * traction, as above (summary.json: <name>_first_pulse); NaN without one. */
double sph_first_pulse(const sph_timeseries *ts, const sph_scene *scene, int o);

/* NaN everywhere unless the scene has analysis.wave. */
void sph_wave_metrics_compute(const sph_timeseries *ts, const sph_scene *scene,
                              sph_wave_metrics *m);

/* Period from samples y(t) (displacement from the start value). */
double sph_first_period(const double *t, const double *y, int count);

/* `not_conserved`: NULL or "" where the scene conserves angular momentum,
 * else the reason (sph_angular_momentum_conserved). */
void sph_metrics_compute(const sph_timeseries *ts, int period_observer, int period_axis,
                         const sph_initial_sums *initial, const char *not_conserved,
                         sph_metrics *m);

#endif
