/* scene_boundaries.c — the sections `walls` and `contact` (solids) and
 * `boundary` and `forces` (fluids). */
#include "scene_loader.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* walls = ( { name; point; normal; }, ... ): rigid frictionless planes
 * (device/sph_wall.h), the solid on the side the normal points to. */
sph_status scene_parse_walls(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *list;
    sph_status st = scene_list(L, root, SK_WALLS, &list);
    if (st || !list) return st;
    const int n = config_setting_length(list);
    if (n > SPH_MAX_WALLS)
        return scene_fail_at(L, list, NULL, "at most %d walls, got %d", SPH_MAX_WALLS, n);
    if (sc->formulation == SPH_FORMULATION_TLSPH) {
        const config_setting_t *method = config_setting_get_member(root, "method");
        return scene_fail_at(L, config_setting_get_member(method, "formulation"), NULL,
                             "\"tlsph\" has no wall contact; walls are implemented for the "
                             "updated-Lagrangian formulations");
    }
    if (n > 0 && SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        return scene_fail_at(
            L, list, NULL,
            "walls are not supported for the eulerian formulations yet (formulation "
            "\"%s\"); a fluid scene is bounded by its periodic boundary, a far "
            "field (boundary.far_field) or wall bodies (bodies.X.role = \"wall\")",
            sph_formulation_name(sc->formulation));
    for (int i = 0; i < n; i++) {
        const config_setting_t *w = config_setting_get_elem(list, (unsigned)i), *at;
        const char *name = "";
        sph_wall *wall = &sc->walls[i];
        if ((st = scene_named_element(L, w, i, "a wall group { name; point; normal; }", "wall",
                                      "walls", SK_WALL_NAME, sc->walls[0].name, sizeof sc->walls[0],
                                      &name, &at)))
            return st;
        snprintf(wall->name, sizeof wall->name, "%s", name);
        scene_where_of(L, w, wall->where, sizeof wall->where);
        if ((st = scene_vector(L, w, SK_WALL_POINT, sc->dim, wall->point, NULL)) ||
            (st = scene_vector(L, w, SK_WALL_NORMAL, sc->dim, wall->normal, &at)))
            return st;
        double norm = 0.0;
        for (int a = 0; a < sc->dim; ++a) norm += wall->normal[a] * wall->normal[a];
        norm = sqrt(norm);
        if (!(norm > 0.0))
            return scene_fail_at(L, at, NULL,
                                 "must be a non-zero vector (the wall's normal into the "
                                 "solid)");
        for (int a = 0; a < sc->dim; ++a) wall->normal[a] /= norm;
    }
    sc->nwalls = n;
    return SPH_OK;
}

/* contact = { impedance; penalty; }: bodies of a scene with several do not
 * merge; particles of different bodies interact only by the contact force
 * (device/sph_contact.h), and particles meet walls by the wall's
 * (device/sph_wall.h).  TLSPH keeps its reference neighbours and has no
 * contact, so it runs scenes of one body. */
sph_status scene_parse_contact(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    sc->contact_impedance = sph_scene_key_at(SK_CONTACT_IMPEDANCE)->def;
    sc->contact_penalty = sph_scene_key_at(SK_CONTACT_PENALTY)->def;
    const config_setting_t *g;
    sph_status st = scene_group(L, root, SK_CONTACT, &g);
    if (st) return st;
    if (sc->nbodies > 1 && sc->formulation == SPH_FORMULATION_TLSPH) {
        const config_setting_t *method = config_setting_get_member(root, "method");
        return scene_fail_at(
            L, config_setting_get_member(method, "formulation"), NULL,
            "\"tlsph\" runs scenes with one body (the scene has %d): contact between "
            "bodies is implemented for the updated-Lagrangian formulations",
            sc->nbodies);
    }
    if (!g) return SPH_OK;
    /* the bodies of a fluid scene are regions of one fluid: no contact */
    if (SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        return scene_fail_at(L, g, NULL,
                             "is for the solid formulations (contact between bodies and against "
                             "walls); the bodies of formulation \"%s\" are regions of one fluid",
                             sph_formulation_name(sc->formulation));
    if (sc->nbodies < 2 && sc->nwalls == 0)
        return scene_fail_at(
            L, g, NULL,
            "contact acts between bodies or against walls, and the scene has one body "
            "and no wall; remove the group");
    if ((st = scene_check_keys(L, g, SECTIONS("contact"))) ||
        (st = scene_number(L, g, SK_CONTACT_IMPEDANCE, &sc->contact_impedance)) ||
        (st = scene_number(L, g, SK_CONTACT_PENALTY, &sc->contact_penalty)))
        return st;
    return SPH_OK;
}

/* boundary = { periodic = ["x", ...]; far_field = { density; velocity; pressure; };
 *              lower = [...]; upper = [...]; }
 * The fluid wraps around along the periodic axes with the period upper -
 * lower (the seed's Taylor-Green vortex, seed 004 §4.2; the Shu-Osher
 * strip's y).  The period must hold a whole number of spacings, so that the
 * lattice continues across the seam dp apart (particles.c anchors it at
 * lower and checks every particle), and at least two cut-off radii, so that
 * no pair meets through two images at once.  The far field (seed 004 §4.3,
 * the public code's NonReflectiveBoundaryCorrection) acts on the faces of
 * the box [lower, upper] across every axis that is not periodic: the fluid
 * there is blended toward the free stream (density, velocity and, for the
 * ideal gas, pressure). */
static sph_status parse_far_field(loader *L, const config_setting_t *ff) {
    sph_scene *sc = L->scene;
    const bool gas = sc->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE;
    const config_setting_t *velocity_at = NULL;
    sph_status st;
    if ((st = scene_check_keys(L, ff, SECTIONS("boundary.far_field"))) ||
        (st = scene_number_or(L, ff, SK_FAR_FIELD_DENSITY, sc->materials[0].density,
                              &sc->far_field_density)) ||
        (st = scene_vector(L, ff, SK_FAR_FIELD_VELOCITY, sc->dim, sc->far_field_velocity,
                           &velocity_at)))
        return st;
    const config_setting_t *p_at = config_setting_get_member(ff, "pressure");
    if (!gas && p_at)
        return scene_fail_at(L, p_at, NULL,
                             "formulation \"eulerian-wc\" derives the free stream's pressure from "
                             "its density, p = c0^2 (rho - rho0) (seed 004 eq. 11): give density "
                             "only");
    if (gas) {
        if (!p_at)
            return scene_fail_at(L, ff, "pressure",
                                 "missing required key: the ideal gas of formulation "
                                 "\"eulerian-compressible\" needs the free stream's pressure "
                                 "p_inf");
        if ((st = scene_number_or(L, ff, SK_FAR_FIELD_PRESSURE, 0.0, &sc->far_field_pressure)))
            return st;
        if (!sc->background_pressure_given) sc->background_pressure = sc->far_field_pressure;
        /* the blend is the subsonic treatment (the public code's): with
         * |U| >= c every characteristic crosses a face one way, and the
         * blend would hold a state the flow cannot reach */
        double speed2 = 0.0;
        for (int a = 0; a < sc->dim; ++a)
            speed2 += sc->far_field_velocity[a] * sc->far_field_velocity[a];
        const double c_inf =
            sqrt(sc->materials[0].gamma * sc->far_field_pressure / sc->far_field_density);
        if (!(sqrt(speed2) < c_inf))
            return scene_fail_at(L, velocity_at, NULL,
                                 "the far field is a subsonic treatment: the free stream's Mach "
                                 "number |U_inf| / c_inf = %g / %g = %g must be below 1 (c_inf = "
                                 "sqrt(gamma p_inf / rho_inf))",
                                 sqrt(speed2), c_inf, sqrt(speed2) / c_inf);
    }
    sc->has_far_field = true;
    return SPH_OK;
}

sph_status scene_parse_boundary(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g, *upper_at, *ff = NULL;
    sph_status st = scene_group(L, root, SK_BOUNDARY, &g);
    if (st || !g) return st;
    if (!SPH_FORMULATION_IS_EULERIAN(sc->formulation)) {
        if (!config_setting_get_member(g, "periodic") && config_setting_get_member(g, "far_field"))
            return scene_fail_at(L, g, NULL,
                                 "a far field is implemented for the eulerian formulations "
                                 "(\"eulerian-wc\"), got formulation \"%s\"",
                                 sph_formulation_name(sc->formulation));
        return scene_fail_at(L, g, NULL,
                             "periodic boundaries are implemented for the eulerian formulations "
                             "(\"eulerian-wc\", \"eulerian-compressible\"), got formulation \"%s\"",
                             sph_formulation_name(sc->formulation));
    }
    int mask = 0;
    if ((st = scene_check_keys(L, g, SECTIONS("boundary"))) ||
        (st = scene_group(L, g, SK_BOUNDARY_FAR_FIELD, &ff)))
        return st;
    if (ff && sc->dim == 1)
        return scene_fail_at(L, ff, NULL,
                             "a line (dimension 1) has no far field here: end it with fixed-state "
                             "buffers, constraints of type \"fixed\" (the far field's blend is "
                             "built and tested for 2D and 3D)");
    if (ff && (st = parse_far_field(L, ff))) return st;
    /* without a far field the group is there for its periodic axes */
    if (!ff && !config_setting_get_member(g, "periodic"))
        return scene_fail_at(L, g, "periodic",
                             "missing required key: a boundary has periodic axes (periodic), a far "
                             "field (far_field) or both");
    if ((st = scene_axis_list(L, g, SK_BOUNDARY_PERIODIC, false, &mask)) ||
        (st = scene_vector(L, g, SK_BOUNDARY_LOWER, sc->dim, sc->periodic_lower, NULL)) ||
        (st = scene_vector(L, g, SK_BOUNDARY_UPPER, sc->dim, sc->periodic_upper, &upper_at)))
        return st;
    const double dp = sc->dp;
    /* the cut-off radius 2h = 2 smoothing_ratio dp */
    const double cutoff_dp = 2.0 * sc->smoothing_ratio;
    for (int a = 0; a < sc->dim; ++a) {
        const double lo = sc->periodic_lower[a], hi = sc->periodic_upper[a];
        if (!(mask & (1 << a))) {
            if (ff && !(hi > lo))
                return scene_fail_at(
                    L, upper_at, NULL,
                    "must exceed lower along %s (the far field's box [lower, upper]), "
                    "got upper = %g, lower = %g",
                    SCENE_AXES[a], hi, lo);
            continue;
        }
        if (!(hi > lo))
            return scene_fail_at(L, upper_at, NULL,
                                 "must exceed lower along the periodic axis %s, got upper = %g, "
                                 "lower = %g",
                                 SCENE_AXES[a], hi, lo);
        const double period = hi - lo, cells = period / dp, whole = round(cells);
        if (!isfinite(cells) || fabs(cells - whole) > 1e-9 * fmax(1.0, cells))
            return scene_fail_at(
                L, upper_at, NULL,
                "the period along %s, upper - lower = %.10g, must be a whole number "
                "of particle spacings (dp = %g), got %.10g dp",
                SCENE_AXES[a], period, dp, cells);
        if (whole < 2.0 * cutoff_dp - 1e-9)
            return scene_fail_at(
                L, upper_at, NULL,
                "the period along %s (%g) is shorter than two cut-off radii (2 x %g "
                "dp = %g): a particle would meet a neighbour through two images",
                SCENE_AXES[a], period, cutoff_dp, 2.0 * cutoff_dp * dp);
    }
    if (ff && mask == (1 << sc->dim) - 1)
        return scene_fail_at(
            L, ff, NULL,
            "the far field acts on the faces across the axes that are not periodic, "
            "and every axis is periodic: remove one from boundary.periodic or the "
            "far field");
    /* the relaxation (relax.h) knows nothing of the images */
    const config_setting_t *bodies = config_setting_get_member(root, "bodies");
    for (int b = 0; mask && b < sc->nbodies; ++b) {
        if (sc->bodies[b].placement != SPH_PLACEMENT_RELAXED) continue;
        const config_setting_t *e = config_setting_get_elem(bodies, (unsigned)b);
        const config_setting_t *at = e ? config_setting_get_member(e, "placement") : NULL;
        return scene_fail_at(
            L, at ? at : g, at ? NULL : "periodic",
            "a relaxed placement is not supported with a periodic boundary yet: the "
            "relaxation does not see the particles across the seam; place the body "
            "on the lattice");
    }
    sc->periodic_mask = mask;
    /* a group that --set created on the way to a member has no line and no
     * override of its own: name the override of upper */
    const bool located = scene_override_of(g) || config_setting_source_line(g) > 0;
    scene_where_of(L, located ? g : upper_at, sc->periodic_where, sizeof sc->periodic_where);
    return SPH_OK;
}

/* forces = { reference_density; reference_speed; reference_length; window; }:
 * the force on the wall bodies as drag and lift coefficients
 * C = 2 F / (rho_ref U_ref^2 L_ref) (seed 004 §4.3, Table 5), and their
 * mean, amplitude and Strouhal number over the trailing window. */
sph_status scene_parse_forces(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = scene_group(L, root, SK_FORCES, &g);
    if (st || !g) return st;
    if (!SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        return scene_fail_at(
            L, g, NULL,
            "is for the wall bodies of fluid scenes (formulation \"eulerian-wc\"), "
            "got formulation \"%s\"",
            sph_formulation_name(sc->formulation));
    int walls = 0;
    for (int b = 0; b < sc->nbodies; ++b) walls += sc->bodies[b].role == SPH_BODY_WALL;
    if (walls == 0)
        return scene_fail_at(
            L, g, NULL,
            "the forces are those the fluid exerts on the wall bodies, and the scene "
            "has none: give a body role = \"wall\" (the cylinder) or remove the "
            "group");
    const double speed = sqrt(sc->far_field_velocity[0] * sc->far_field_velocity[0] +
                              sc->far_field_velocity[1] * sc->far_field_velocity[1] +
                              sc->far_field_velocity[2] * sc->far_field_velocity[2]);
    const double rho_default = sc->has_far_field ? sc->far_field_density : sc->materials[0].density;
    if ((st = scene_check_keys(L, g, SECTIONS("forces"))) ||
        (st = scene_number_or(L, g, SK_FORCES_REFERENCE_DENSITY, rho_default,
                              &sc->force_reference_density)))
        return st;
    const bool speed_given = config_setting_get_member(g, "reference_speed") != NULL;
    if (!speed_given && !(sc->has_far_field && speed > 0.0))
        return scene_fail_at(L, g, "reference_speed", "missing required key: %s",
                             sc->has_far_field
                                 ? "the far field's velocity is 0, so it cannot be the "
                                   "default reference speed"
                                 : "without a far field there is no free-stream speed "
                                   "to take as the default");
    if ((st =
             scene_number_or(L, g, SK_FORCES_REFERENCE_SPEED, speed, &sc->force_reference_speed)) ||
        (st = scene_number(L, g, SK_FORCES_REFERENCE_LENGTH, &sc->force_reference_length)) ||
        (st = scene_number(L, g, SK_FORCES_WINDOW, &sc->force_window)))
        return st;
    if (!isfinite(sc->force_reference_density * sc->force_reference_speed *
                  sc->force_reference_speed * sc->force_reference_length) ||
        !(sc->force_reference_density * sc->force_reference_speed * sc->force_reference_speed *
              sc->force_reference_length >
          0.0))
        return scene_fail_at(
            L, g, NULL,
            "rho_ref U_ref^2 L_ref = %g x %g^2 x %g, the coefficients' denominator, "
            "is not a finite positive number",
            sc->force_reference_density, sc->force_reference_speed, sc->force_reference_length);
    sc->has_forces = true;
    return SPH_OK;
}
