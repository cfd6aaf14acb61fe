/* scene_method.c — the sections `resolution`, `method` and `time`. */
#include "scene_loader.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* how near, in output intervals, an end time is to the output grid to be on it */
#define OUTPUT_GRID_ROUNDING 1e-9

/* ------------------------------------------------------------------------ */
/* schema                                                                    */
/* ------------------------------------------------------------------------ */

sph_status scene_parse_resolution(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = scene_group(L, root, SK_RESOLUTION, &g);
    if (st || (st = scene_check_keys(L, g, SECTIONS("resolution")))) return st;
    bool has_dp = config_setting_get_member(g, "dp") != NULL;
    bool has_ratio_form = config_setting_get_member(g, "reference_length") != NULL ||
                          config_setting_get_member(g, "ratio") != NULL;
    if (has_dp && has_ratio_form) {
        /* point at an override that brought in the second form, if any */
        const config_setting_t *at = g;
        const char *members[3] = {"dp", "reference_length", "ratio"};
        for (int i = 0; i < 3 && !scene_override_of(at); i++) {
            const config_setting_t *m = config_setting_get_member(g, members[i]);
            if (m && scene_override_of(m)) at = m;
        }
        return scene_fail_at(
            L, at, NULL,
            "give either dp or reference_length and ratio (dp = reference_length / "
            "ratio), not both");
    }
    if (!has_dp && !has_ratio_form)
        return scene_fail_at(L, g, NULL, "missing required key: dp, or reference_length and ratio");
    if (has_dp) return scene_number(L, g, SK_RESOLUTION_DP, &sc->dp);
    double length = 0.0, ratio = 1.0;
    const config_setting_t *at;
    if ((st = scene_require(L, g, SK_RESOLUTION_REFERENCE_LENGTH, &at)) ||
        (st = scene_number(L, g, SK_RESOLUTION_REFERENCE_LENGTH, &length)) ||
        (st = scene_require(L, g, SK_RESOLUTION_RATIO, &at)) ||
        (st = scene_number(L, g, SK_RESOLUTION_RATIO, &ratio)))
        return st;
    sc->dp = length / ratio;
    return SPH_OK;
}

/* ENOG-A and GNOG-A carry a rotation correction (003 eqs. 38-42, 47); the
 * other formulations have none. */
static bool formulation_rotates(int f) {
    return f == SPH_FORMULATION_ENOG_A || f == SPH_FORMULATION_GNOG_A;
}

sph_status scene_parse_method(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g, *rot_at;
    sph_status st = scene_group(L, root, SK_METHOD, &g);
    if (st || (st = scene_check_keys(L, g, SECTIONS("method")))) return st;
    int formulation = 0, rotation = 0, kernel = 0;
    const config_setting_t *form_at;
    if ((st = scene_keyword(L, g, SK_METHOD_FORMULATION, &formulation, &form_at))) return st;
    sc->formulation = (sph_formulation)formulation;
    const bool eulerian = SPH_FORMULATION_IS_EULERIAN(formulation);
    if (eulerian) {
        /* seed 004 §3.1: a fluid has no shear stress, so the coefficients of
         * the solid formulations' shear and hourglass terms mean nothing */
        const config_setting_t *m = scene_first_member(
            g, KEY_NAMES("torque_projection", "xi_e", "xi_g", "artificial_stress",
                         "hourglass_alpha", "pairwise_damping"));
        if (m)
            return scene_fail_at(L, m, NULL,
                                 "is for the solid formulations; formulation \"%s\" simulates a "
                                 "fluid (seed 004, section 3.1), which has no shear stress",
                                 sph_formulation_name((sph_formulation)formulation));
    }
    const bool rotates = formulation_rotates(formulation);
    const int def_rot = rotates ? SPH_ROTATION_AVERAGED : SPH_ROTATION_NONE;
    if ((st = scene_keyword_or(L, g, SK_METHOD_ROTATION, def_rot, &rotation, &rot_at))) return st;
    const bool rotated_bare = !rotates && rotation != SPH_ROTATION_NONE;
    const bool rotating_none = rotates && rotation == SPH_ROTATION_NONE;
    if ((rotated_bare || rotating_none) && rot_at && scene_override_of(form_at) &&
        !scene_override_of(rot_at)) {
        /* the override of the formulation caused the conflict: say so, and
         * what else to set */
        return scene_fail_at(L, form_at, NULL,
                             "formulation \"%s\" conflicts with method.rotation = \"%s\" (%s:%u); "
                             "add --set method.rotation=%s",
                             sph_formulation_name((sph_formulation)formulation),
                             sph_rotation_name((sph_rotation)rotation), L->file,
                             config_setting_source_line(rot_at),
                             rotated_bare ? "none" : "averaged");
    }
    if (rotated_bare)
        return scene_fail_at(
            L, rot_at, NULL,
            "formulation \"%s\" has no rotation correction, so rotation must be "
            "\"none\", got \"%s\" (the rotation-corrected formulations are \"enog-a\" "
            "and \"gnog-a\")",
            sph_formulation_name((sph_formulation)formulation),
            sph_rotation_name((sph_rotation)rotation));
    if (rotating_none)
        return scene_fail_at(L, rot_at, NULL,
                             "formulation \"%s\" needs a rotation correction, so rotation must be "
                             "\"averaged\" or \"per-particle\", got \"none\" (use \"%s\" for an "
                             "uncorrected run)",
                             sph_formulation_name((sph_formulation)formulation),
                             formulation == SPH_FORMULATION_ENOG_A ? "enog" : "gnog");
    sc->rotation = (sph_rotation)rotation;
    /* SPH-ENOG-A's accumulated shear acceleration kept free of net torque
     * (device/sph_torque_projection.h): our addition to 003, off by default */
    if ((st = scene_boolean(L, g, SK_METHOD_TORQUE_PROJECTION, &sc->torque_projection))) return st;
    if (sc->torque_projection &&
        (formulation != SPH_FORMULATION_ENOG_A || rotation != SPH_ROTATION_AVERAGED)) {
        const config_setting_t *tp_at = config_setting_get_member(g, "torque_projection");
        return scene_fail_at(L, tp_at, NULL,
                             "only formulation \"enog-a\" with rotation \"averaged\" has it, "
                             "got formulation \"%s\" with rotation \"%s\"",
                             sph_formulation_name((sph_formulation)formulation),
                             sph_rotation_name((sph_rotation)rotation));
    }
    const config_setting_t *kernel_at;
    if ((st = scene_keyword(L, g, SK_METHOD_KERNEL, &kernel, &kernel_at))) return st;
    sc->kernel = (sph_kernel)kernel;
    if (eulerian && sc->dim == 3 &&
        (kernel == SPH_KERNEL_LAGUERRE_GAUSS || kernel == SPH_KERNEL_LAGUERRE_WENDLAND))
        /* The Laguerre kernels' dW/dr is positive over part of the support,
         * and a pair's Riemann dissipation, quadratic in its velocity jump
         * under the limiter, weighs the pairs by q^(d+2) dW: for
         * Laguerre-Gauss that moment is 0 in 2D and positive in 3D, so there
         * the dissipation feeds the flow (docs/fluids.md, "Kernels in 3D") */
        return scene_fail_at(
            L, kernel_at, NULL,
            "\"%s\" is unstable for the fluid formulations in 3D: its gradient is positive "
            "between %s h and %s h, and in 3D the pairs there turn the Riemann solver's "
            "dissipation into a source of kinetic energy (the Taylor-Green vortex extruded in z "
            "gains energy instead of decaying, and blows up); use \"wendland-c2\" "
            "(docs/fluids.md, \"Kernels in 3D\")",
            sph_kernel_name((sph_kernel)kernel),
            kernel == SPH_KERNEL_LAGUERRE_GAUSS ? "1.41" : "0.94",
            kernel == SPH_KERNEL_LAGUERRE_GAUSS ? "2" : "1.55");
    if ((st = scene_number(L, g, SK_METHOD_SMOOTHING_RATIO, &sc->smoothing_ratio))) return st;
    /* xi_E: the coefficient of the shear-acceleration Laplacian, 0.7 d + 2.1
     * as calibrated in 000 (eq. 23, "zeta"; 003 eq. 25) */
    if ((st = scene_number_or(L, g, SK_METHOD_XI_E, 0.7 * sc->dim + 2.1, &sc->xi_e))) return st;
    /* xi_G: resolved against the material in parse_scene (NAN: default) */
    if ((st = scene_number_or(L, g, SK_METHOD_XI_G, NAN, &sc->xi_g))) return st;
    /* Gray, Monaghan & Swift (2001) artificial stress: epsilon = 0.3 and
     * n = 4 with f = W(r)/W(dp), their values for elastic solids (§4 of
     * that paper, as also used by the SPH-OAS runs of 000 and PySPH) */
    const config_setting_t *art;
    if ((st = scene_group(L, g, SK_METHOD_ARTIFICIAL_STRESS, &art))) return st;
    sc->art_epsilon = 0.3;
    sc->art_exponent = 4.0;
    if (art && ((st = scene_check_keys(L, art, SECTIONS("method.artificial_stress"))) ||
                (st = scene_number(L, art, SK_ARTIFICIAL_STRESS_EPSILON, &sc->art_epsilon)) ||
                (st = scene_number(L, art, SK_ARTIFICIAL_STRESS_EXPONENT, &sc->art_exponent))))
        return st;
    /* Hourglass control of TLSPH (002, f^HG in device/tl_step.cl).  002's own
     * alpha is lost from the seed text (@xmath93); 0.1 is the default of
     * TrixiParticles.jl, whose PenaltyForceGanzenmueller prints 002's
     * formula.  On the 2D plate (H/dp = 10) it cuts a zero-energy
     * checkerboard mode 16-fold (tests/test_tlsph.c) and shortens the period
     * by only 0.13 % against alpha = 0 (alpha = 1: 0.72 %, away from 004's
     * T_W); see docs/scene-format.md */
    if ((st = scene_number(L, g, SK_METHOD_HOURGLASS_ALPHA, &sc->hourglass_alpha))) return st;
    /* TLSPH's pairwise numerical damping (device/tl_step.cl): 0 by default,
     * the elastic TLSPH of 004 as printed; the public code's TLSPH runs
     * c_d = 0.25 (eulerian-sph-reference.md §5.4) */
    const config_setting_t *damping_at = config_setting_get_member(g, "pairwise_damping");
    if (damping_at && formulation != SPH_FORMULATION_TLSPH)
        return scene_fail_at(L, damping_at, NULL,
                             "is the pairwise damping of \"tlsph\" (total-Lagrangian SPH); "
                             "formulation \"%s\" has none",
                             sph_formulation_name((sph_formulation)formulation));
    if ((st = scene_number(L, g, SK_METHOD_PAIRWISE_DAMPING, &sc->pairwise_damping))) return st;
    /* The limiter slope eta of beta = min(eta max(u_l - u_r, 0) / c, 1):
     * 0 (unlimited) for the solids; for the fluids the seed's values,
     * eta_linearised = 15 (seed 004 eqs. 21-22, also the public code's) and
     * eta_HLLC = 1 (eqs. 19-20; the public code runs 5) */
    const double limiter = formulation == SPH_FORMULATION_EULERIAN_WC             ? 15.0
                           : formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE ? 1.0
                                                                                  : 0.0;
    if ((st =
             scene_number_or(L, g, SK_METHOD_RIEMANN_LIMITER, limiter, &sc->riemann_limiter_slope)))
        return st;
    /* The background pressure p_b of the compressible momentum fluxes
     * (device/eulerian_step.cl, SOLVER_BACKGROUND); the weakly compressible
     * pressure p = c0^2 (rho - rho0) is already the departure from rho0's */
    const config_setting_t *background_at = config_setting_get_member(g, "background_pressure");
    if (background_at && formulation != SPH_FORMULATION_EULERIAN_COMPRESSIBLE)
        return scene_fail_at(L, background_at, NULL,
                             "is for the ideal gas (formulation \"eulerian-compressible\"); "
                             "formulation \"%s\" %s",
                             sph_formulation_name((sph_formulation)formulation),
                             formulation == SPH_FORMULATION_EULERIAN_WC
                                 ? "has p = c0^2 (rho - rho0), already 0 at rest"
                                 : "has no fluid pressure");
    sc->background_pressure_given = background_at != NULL;
    if ((st = scene_number_or(L, g, SK_METHOD_BACKGROUND_PRESSURE, 0.0, &sc->background_pressure)))
        return st;
    const config_setting_t *visc_at = config_setting_get_member(g, "viscous_regularization");
    if (!eulerian && visc_at)
        return scene_fail_at(L, visc_at, NULL,
                             "is for the fluid formulations (\"eulerian-wc\" and "
                             "\"eulerian-compressible\"), got formulation \"%s\"",
                             sph_formulation_name((sph_formulation)formulation));
    int regularization = SPH_VISCOUS_SQUARED;
    if ((st = scene_keyword(L, g, SK_METHOD_VISCOUS_REGULARIZATION, &regularization, NULL)))
        return st;
    sc->viscous_regularization = (sph_viscous_regularization)regularization;
    return SPH_OK;
}

sph_status scene_parse_time(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = scene_group(L, root, SK_TIME, &g);
    if (st || (st = scene_check_keys(L, g, SECTIONS("time")))) return st;
    if ((st = scene_number(L, g, SK_TIME_END, &sc->end_time)) ||
        (st = scene_number(L, g, SK_TIME_OUTPUT_INTERVAL, &sc->output_interval)))
        return st;
    if (sc->output_interval > sc->end_time)
        return scene_fail_at(L, config_setting_get_member(g, "output_interval"), NULL,
                             "must not exceed time.end (%g), got %g", sc->end_time,
                             sc->output_interval);
    /* An end on the output grid (within rounding) becomes the grid's own time
     * k * interval, the time that the k-th output of a longer run lands on:
     * with outputs every 0.05 s a run to 0.3 s then ends at 6 * 0.05 =
     * 0.30000000000000004 s, where a run to 0.4 s passes its sixth output, so
     * the two agree bit for bit there, and a restart from the first's last
     * checkpoint continues as the longer run (with 0.3 itself the last step
     * was 6e-17 s shorter and the states differed in round-off). */
    const double outputs = nearbyint(sc->end_time / sc->output_interval);
    if (outputs >= 1 && fabs(outputs * sc->output_interval - sc->end_time) <=
                            OUTPUT_GRID_ROUNDING * sc->output_interval)
        sc->end_time = outputs * sc->output_interval;
    /* The eulerian formulations keep their particles where they were placed
     * (seed 004 §3.1): no advection step, no neighbour rebuild, so no
     * advection CFL, no frozen pair geometry and no acceleration criterion;
     * every step is an acoustic one */
    const bool eulerian = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    if (eulerian) {
        const config_setting_t *m = scene_first_member(
            g, KEY_NAMES("cfl_advection", "frozen_geometry", "acceleration_criterion"));
        if (m)
            return scene_fail_at(L, m, NULL,
                                 "is for the formulations whose particles move (the advection "
                                 "step); formulation \"%s\" keeps its particles fixed and steps "
                                 "by time.cfl_acoustic alone",
                                 sph_formulation_name(sc->formulation));
    }
    int stepping = 0;
    const config_setting_t *stepping_at = NULL;
    if ((st = scene_keyword_or(L, g, SK_TIME_STEPPING,
                               eulerian ? SPH_STEPPING_SINGLE : SPH_STEPPING_DUAL, &stepping,
                               &stepping_at)))
        return st;
    if (eulerian && stepping == SPH_STEPPING_DUAL)
        return scene_fail_at(
            L, stepping_at, NULL,
            "formulation \"%s\" keeps its particles fixed: there is no advection "
            "step to take dual-criteria steps with, so stepping must be \"single\" "
            "(its default), got \"dual\"",
            sph_formulation_name(sc->formulation));
    sc->stepping = (sph_stepping)stepping;
    /* the fluids' update: the public code's two stages, SSP-RK2 or SSP-RK3 */
    const config_setting_t *integrator_at = config_setting_get_member(g, "integrator");
    if (integrator_at && !eulerian)
        return scene_fail_at(
            L, integrator_at, NULL,
            "is for the fluid formulations (\"eulerian-wc\", "
            "\"eulerian-compressible\"); formulation \"%s\" steps by time.stepping",
            sph_formulation_name(sc->formulation));
    int integrator = SPH_FLUID_TWO_STAGE;
    if ((st = scene_keyword(L, g, SK_TIME_INTEGRATOR, &integrator, NULL))) return st;
    sc->fluid_integrator = (sph_fluid_integrator)integrator;
    /* The acoustic step's CFL: 0.4 (000, 003), 0.2 with the Laguerre-Wendland
     * kernel, whose stiffest lattice mode is 2.3x Wendland's at the same h:
     * leapfrog's limit is CFL 0.47 there (tools/kernel_lattice_stiffness.py)
     * and the plate (h = 2 dp) blows up at 0.3-0.4 within 5 ms, runs to 1 s at
     * 0.2 (docs/method.md, kernels).  The fluids: 0.6 / d, the public
     * reference code's dt = (0.6 / d) h / max(c + |v|) (the seed gives no
     * step size); in 1D 0.4, not 0.6: the Shu-Osher line (dp = 1/200)
     * loses positive pressure at t = 0.24 with 0.6 and runs with 0.5 (L1
     * density error 0.0298; 0.4: 0.0303, 0.3: 0.0419, docs/fluids.md) */
    const double cfl_acoustic = eulerian && sc->dim == 1                     ? 0.4
                                : eulerian                                   ? 0.6 / sc->dim
                                : sc->kernel == SPH_KERNEL_LAGUERRE_WENDLAND ? 0.2
                                                                             : 0.4;
    if ((st = scene_number(L, g, SK_TIME_CFL_ADVECTION, &sc->cfl_advection)) ||
        (st = scene_number_or(L, g, SK_TIME_CFL_ACOUSTIC, cfl_acoustic, &sc->cfl_acoustic)))
        return st;
    sc->has_reference_speed = config_setting_get_member(g, "reference_speed") != NULL;
    if ((st = scene_number_or(L, g, SK_TIME_REFERENCE_SPEED, 0.0, &sc->reference_speed))) return st;
    int geometry = 0;
    if ((st = scene_keyword(L, g, SK_TIME_FROZEN_GEOMETRY, &geometry, NULL))) return st;
    sc->geometry_at_start = geometry == 1;
    return scene_boolean(L, g, SK_TIME_ACCELERATION_CRITERION, &sc->acceleration_criterion);
}
