/* scene_observers.c — the sections `observers`, `analysis`, `output` and
 * `monitor`. */
#include "scene_loader.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* observers.X.quantity ("position", the default, or "traction") and, for a
 * traction, its plane's normal. */
static sph_status parse_observed(loader *L, const config_setting_t *o, sph_observer *obs) {
    const sph_scene *sc = L->scene;
    const config_setting_t *at;
    int quantity = SPH_OBSERVE_POSITION;
    sph_status st = scene_keyword(L, o, SK_OBSERVER_QUANTITY, &quantity, &at);
    if (st) return st;
    obs->quantity = (sph_observed)quantity;
    const config_setting_t *normal = config_setting_get_member(o, "normal");
    if (quantity == SPH_OBSERVE_POSITION) {
        if (normal)
            return scene_fail_at(
                L, normal, NULL,
                "is the plane of a traction (quantity = \"traction\"); observer '%s' "
                "reports its position",
                obs->name);
        return SPH_OK;
    }
    if (SPH_FORMULATION_IS_EULERIAN(sc->formulation) || sc->formulation == SPH_FORMULATION_TLSPH)
        return scene_fail_at(L, at, NULL,
                             "a traction observer reads the Cauchy stress -p I + tau of the "
                             "updated-Lagrangian solids; formulation \"%s\" has no such stress",
                             sph_formulation_name(sc->formulation));
    if ((st = scene_require(L, o, SK_OBSERVER_NORMAL, &at)) ||
        (st = scene_vector(L, o, SK_OBSERVER_NORMAL, sc->dim, obs->normal, &at)))
        return st;
    double norm = 0.0;
    for (int a = 0; a < sc->dim; ++a) norm += obs->normal[a] * obs->normal[a];
    norm = sqrt(norm);
    if (!(norm > 0.0) || !isfinite(norm))
        return scene_fail_at(L, at, NULL,
                             "must be a non-zero vector (the normal of the traction's plane)");
    for (int a = 0; a < sc->dim; ++a) obs->normal[a] /= norm;
    return SPH_OK;
}

sph_status scene_parse_observers(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *list;
    sph_status st = scene_list(L, root, SK_OBSERVERS, &list);
    if (st || !list) return st;
    int n = config_setting_length(list);
    if (n > SPH_SCENE_MAX_OBSERVERS)
        return scene_fail_at(L, list, NULL, "at most %d observers, got %d", SPH_SCENE_MAX_OBSERVERS,
                             n);
    for (int i = 0; i < n; i++) {
        const config_setting_t *o = config_setting_get_elem(list, (unsigned)i), *at;
        const char *name = "";
        if ((st = scene_named_element(L, o, i, "an observer group { name; position; }", "observer",
                                      "observers", SK_OBSERVER_NAME, sc->observers[0].name,
                                      sizeof sc->observers[0], &name, &at)))
            return st;
        if (sph_observer_name_reserved(name))
            return scene_fail_at(
                L, at, NULL, "'%s' is reserved: timeseries.csv has %s_x, ... columns of its own",
                name, name);
        snprintf(sc->observers[i].name, sizeof sc->observers[i].name, "%s", name);
        if ((st =
                 scene_vector(L, o, SK_OBSERVER_POSITION, sc->dim, sc->observers[i].position, &at)))
            return st;
        scene_where_of(L, at, sc->observers[i].where, sizeof sc->observers[i].where);
        if ((st = parse_observed(L, o, &sc->observers[i]))) return st;
    }
    sc->nobservers = n;
    return SPH_OK;
}

/* The observer named by key `key` of group g. */
static sph_status get_observer(loader *L, const config_setting_t *g, sph_scene_key_id key,
                               int *out) {
    const sph_scene *sc = L->scene;
    const config_setting_t *at;
    const char *name = "";
    sph_status st = scene_name(L, g, key, &name, &at);
    if (st) return st;
    *out = -1;
    for (int i = 0; i < sc->nobservers; i++)
        if (strcmp(sc->observers[i].name, name) == 0) *out = i;
    if (*out >= 0) return SPH_OK;
    const char *names[SPH_SCENE_MAX_OBSERVERS];
    for (int i = 0; i < sc->nobservers; i++) names[i] = sc->observers[i].name;
    char hint[1024];
    scene_suggest(name, names, sc->nobservers, "defined observers", hint, sizeof hint);
    return scene_fail_at(L, at, NULL, "unknown observer '%s'%s", name, hint);
}

/* analysis.wave = { incident; transmitted; }: two traction observers with
 * the same normal, on either side of an interface (host/run/analysis.h). */
static sph_status parse_wave(loader *L, const config_setting_t *w) {
    sph_scene *sc = L->scene;
    sph_status st;
    if ((st = scene_check_keys(L, w, SECTIONS("analysis.wave"))) ||
        (st = get_observer(L, w, SK_WAVE_INCIDENT, &sc->wave_incident)) ||
        (st = get_observer(L, w, SK_WAVE_TRANSMITTED, &sc->wave_transmitted)))
        return st;
    const sph_observer *in = &sc->observers[sc->wave_incident],
                       *out = &sc->observers[sc->wave_transmitted];
    const char *key = in->quantity != SPH_OBSERVE_TRACTION ? "incident" : "transmitted";
    if (in->quantity != SPH_OBSERVE_TRACTION || out->quantity != SPH_OBSERVE_TRACTION)
        return scene_fail_at(
            L, config_setting_get_member(w, key), NULL,
            "observer '%s' reports a position; the wave analysis reads the traction "
            "of two observers with quantity = \"traction\"",
            (in->quantity != SPH_OBSERVE_TRACTION ? in : out)->name);
    if (sc->wave_incident == sc->wave_transmitted)
        return scene_fail_at(
            L, config_setting_get_member(w, "transmitted"), NULL,
            "is the incident observer too; the transmitted pulse is read on the other "
            "side of the interface");
    double dot = 0.0;
    for (int a = 0; a < sc->dim; ++a) dot += in->normal[a] * out->normal[a];
    if (fabs(dot) < 1.0 - 1e-9)
        return scene_fail_at(L, config_setting_get_member(w, "transmitted"), NULL,
                             "observers '%s' and '%s' have different normals; the wave analysis "
                             "compares the normal traction on parallel planes",
                             in->name, out->name);
    return SPH_OK;
}

sph_status scene_parse_analysis(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g, *p, *w;
    sph_status st = scene_group(L, root, SK_ANALYSIS, &g);
    if (st || !g) return st;
    if ((st = scene_check_keys(L, g, SECTIONS("analysis"))) ||
        (st = scene_group(L, g, SK_ANALYSIS_PERIOD, &p)) ||
        (st = scene_group(L, g, SK_ANALYSIS_WAVE, &w)))
        return st;
    if (w && (st = parse_wave(L, w))) return st;
    if (!p) return SPH_OK;
    if ((st = scene_check_keys(L, p, SECTIONS("analysis.period"))) ||
        (st = get_observer(L, p, SK_PERIOD_OBSERVER, &sc->period_observer)))
        return st;
    if (sc->observers[sc->period_observer].quantity != SPH_OBSERVE_POSITION)
        return scene_fail_at(
            L, config_setting_get_member(p, "observer"), NULL,
            "observer '%s' reports a traction; the period is that of an observer's "
            "position",
            sc->observers[sc->period_observer].name);
    return scene_axis(L, p, SK_PERIOD_AXIS, &sc->period_axis);
}

/* the names of sph_output_field, in its order: the words of output.fields */
#define OUTPUT_FIELD_NAMES (sph_scene_key_at(SK_OUTPUT_FIELDS)->words)

static bool scene_is_plastic(const sph_scene *sc) {
    int row_of[SPH_MAX_MATERIALS];
    sph_scene_material_rows(sc, row_of);
    for (int k = 0; k < sc->nmaterials; ++k)
        if (row_of[k] >= 0 && sc->materials[k].plastic) return true;
    return false;
}

const char *sph_output_field_name(sph_output_field f) {
    return (unsigned)f < SPH_OUT_COUNT ? OUTPUT_FIELD_NAMES[f] : "?";
}

/* output = { snapshot_interval; fields = [...]; } (docs/output-format.md) */
sph_status scene_parse_output(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g, *at = NULL;
    sph_status st = scene_group(L, root, SK_OUTPUT, &g);
    if (st) return st;
    static const sph_output_field defaults[] = {
        SPH_OUT_VELOCITY,  SPH_OUT_DISPLACEMENT, SPH_OUT_DENSITY,    SPH_OUT_PRESSURE,
        SPH_OUT_VON_MISES, SPH_OUT_BODY_ID,      SPH_OUT_PARTICLE_ID};
    /* a fluid's particles do not move and carry no stress deviator: no
     * displacement, von Mises or shear stress; the flow's own fields instead */
    static const sph_output_field fluid_defaults[] = {SPH_OUT_VELOCITY, SPH_OUT_DENSITY,
                                                      SPH_OUT_PRESSURE, SPH_OUT_VORTICITY,
                                                      SPH_OUT_PARTICLE_ID};
    const bool eulerian = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    const bool compressible = sc->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE;
    if (eulerian) {
        for (size_t k = 0; k < sizeof fluid_defaults / sizeof fluid_defaults[0]; ++k)
            sc->output_field[fluid_defaults[k]] = true;
        sc->output_field[SPH_OUT_MACH_NUMBER] = compressible;
        sc->output_field[SPH_OUT_VORTICITY] = sc->dim > 1; /* a line has none */
    } else {
        for (size_t k = 0; k < sizeof defaults / sizeof defaults[0]; ++k)
            sc->output_field[defaults[k]] = true;
    }
    const bool plastic = scene_is_plastic(sc);
    sc->output_field[SPH_OUT_PLASTIC_STRAIN] = plastic;
    int row_of[SPH_MAX_MATERIALS];
    const bool several_materials = sph_scene_material_rows(sc, row_of) > 1;
    sc->output_field[SPH_OUT_MATERIAL_ID] = several_materials;
    sc->snapshot_interval = 10.0 * sc->output_interval;
    if (g) {
        if ((st = scene_check_keys(L, g, SECTIONS("output"))) ||
            (st = scene_number_or(L, g, SK_OUTPUT_SNAPSHOT_INTERVAL, sc->snapshot_interval,
                                  &sc->snapshot_interval)) ||
            (st = scene_member(L, g, SK_OUTPUT_FIELDS, &at)))
            return st;
    }
    if (at) {
        if (!config_setting_is_array(at) && !config_setting_is_list(at))
            return scene_fail_at(L, at, NULL,
                                 "expected an array of field names [\"velocity\", ...], got %s",
                                 scene_type_name(config_setting_type(at)));
        memset(sc->output_field, 0, sizeof sc->output_field);
        const int n = config_setting_length(at);
        for (int i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(at, (unsigned)i);
            const char *name = "";
            if ((st = scene_as_string(L, e, &name))) return st;
            int found = -1;
            for (int k = 0; k < SPH_OUT_COUNT; k++)
                if (strcmp(name, OUTPUT_FIELD_NAMES[k]) == 0) found = k;
            if (found < 0) {
                char hint[512];
                scene_suggest(name, OUTPUT_FIELD_NAMES, SPH_OUT_COUNT, "fields", hint, sizeof hint);
                return scene_fail_at(L, e, NULL, "unknown output field '%s'%s", name, hint);
            }
            const bool solid_field = found == SPH_OUT_DISPLACEMENT || found == SPH_OUT_VON_MISES ||
                                     found == SPH_OUT_SHEAR_STRESS ||
                                     found == SPH_OUT_PLASTIC_STRAIN;
            if (eulerian && solid_field)
                return scene_fail_at(L, e, NULL,
                                     "%s is a field of the solid formulations; formulation \"%s\" "
                                     "keeps its particles fixed and has no stress deviator (fluid "
                                     "fields: velocity, density, pressure, vorticity, body_id, "
                                     "particle_id%s)",
                                     name, sph_formulation_name(sc->formulation),
                                     compressible ? ", mach_number" : "");
            if (!eulerian && (found == SPH_OUT_VORTICITY || found == SPH_OUT_MACH_NUMBER))
                return scene_fail_at(L, e, NULL,
                                     "%s is a fluid field (formulations \"eulerian-wc\" and "
                                     "\"eulerian-compressible\"), and this scene's formulation is "
                                     "\"%s\"",
                                     name, sph_formulation_name(sc->formulation));
            if (found == SPH_OUT_VORTICITY && sc->dim == 1)
                return scene_fail_at(
                    L, e, NULL,
                    "vorticity is a field of 2D and 3D flows; a line (dimension 1) "
                    "has none");
            if (found == SPH_OUT_MACH_NUMBER && !compressible)
                return scene_fail_at(
                    L, e, NULL,
                    "mach_number is a field of formulation \"eulerian-compressible\", "
                    "whose sound speed c = sqrt(gamma p / rho) varies; the weakly "
                    "compressible fluid's Mach number is |v| / c0 (the velocity field "
                    "over sound_speed)");
            if (found == SPH_OUT_PLASTIC_STRAIN && !plastic)
                return scene_fail_at(
                    L, e, NULL,
                    "plastic_strain needs a plastic material (a yield_stress), and "
                    "this scene's materials are elastic");
            if (sc->output_field[found])
                return scene_fail_at(L, e, NULL, "field '%s' is listed twice", name);
            sc->output_field[found] = true;
        }
    }
    /* snapshots fall on output times: the solver lands exactly on those */
    if (sc->snapshot_interval > 0) {
        const double ratio = sc->snapshot_interval / sc->output_interval;
        const double whole = round(ratio);
        const config_setting_t *si = g ? config_setting_get_member(g, "snapshot_interval") : NULL;
        if (whole < 1 || fabs(ratio - whole) > 1e-9 * whole)
            return scene_fail_at(
                L, si ? si : (g ? g : root), si ? NULL : "snapshot_interval",
                "must be a whole multiple of time.output_interval (%g), or 0 for no "
                "snapshots, got %g",
                sc->output_interval, sc->snapshot_interval);
        if (whole > INT_MAX)
            return scene_fail_at(L, si ? si : (g ? g : root), si ? NULL : "snapshot_interval",
                                 "must be at most %d output intervals (%g), got %g", INT_MAX,
                                 sc->output_interval, sc->snapshot_interval);
        sc->snapshot_every = (int)whole;
    }
    return SPH_OK;
}

/* monitor = { zigzag_threshold; min_distance_ratio; energy_growth;
 *             speed_limit; domain_margin; domain = { lower; upper; }; action; } */
sph_status scene_parse_monitor(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = scene_group(L, root, SK_MONITOR, &g);
    /* TLSPH has no Riemann dissipation: its velocity field keeps a steady
     * particle-scale acoustic content (indicator 0.3 to 0.6 on the plate,
     * not growing) that this measure cannot tell from zigzag, so for TLSPH
     * the zigzag check is off unless a threshold is given */
    const double zigzag_default = sc->formulation == SPH_FORMULATION_TLSPH
                                      ? INFINITY
                                      : sph_scene_key_at(SK_MONITOR_ZIGZAG_THRESHOLD)->def;
    sc->monitor_zigzag = zigzag_default;
    sc->monitor_min_distance = sph_scene_key_at(SK_MONITOR_MIN_DISTANCE_RATIO)->def;
    sc->monitor_action = (sph_monitor_action)sph_scene_key_at(SK_MONITOR_ACTION)->def;
    sc->monitor_energy_growth = sph_scene_key_at(SK_MONITOR_ENERGY_GROWTH)->def;
    sc->monitor_speed_limit = sph_scene_key_at(SK_MONITOR_SPEED_LIMIT)->def;
    sc->monitor_domain_margin = sph_scene_key_at(SK_MONITOR_DOMAIN_MARGIN)->def;
    sc->monitor_has_domain = false;
    if (st || !g) return st;
    int action = 0;
    const config_setting_t *dom = NULL;
    if ((st = scene_check_keys(L, g, SECTIONS("monitor"))) ||
        (st = scene_number(L, g, SK_MONITOR_SPEED_LIMIT, &sc->monitor_speed_limit)) ||
        (st = scene_number(L, g, SK_MONITOR_ENERGY_GROWTH, &sc->monitor_energy_growth)) ||
        (st = scene_number(L, g, SK_MONITOR_DOMAIN_MARGIN, &sc->monitor_domain_margin)) ||
        (st = scene_group(L, g, SK_MONITOR_DOMAIN, &dom)))
        return st;
    if (dom) {
        const config_setting_t *upper_at;
        if ((st = scene_check_keys(L, dom, SECTIONS("monitor.domain"))) ||
            (st = scene_vector(L, dom, SK_DOMAIN_LOWER, sc->dim, sc->monitor_domain_lower, NULL)) ||
            (st = scene_vector(L, dom, SK_DOMAIN_UPPER, sc->dim, sc->monitor_domain_upper,
                               &upper_at)))
            return st;
        for (int a = 0; a < sc->dim; a++)
            if (!(sc->monitor_domain_upper[a] > sc->monitor_domain_lower[a]))
                return scene_fail_at(
                    L, upper_at, NULL,
                    "the domain must have upper > lower along every axis; along %s "
                    "upper = %g, lower = %g",
                    SCENE_AXES[a], sc->monitor_domain_upper[a], sc->monitor_domain_lower[a]);
        sc->monitor_has_domain = true;
        /* a group that --set created on the way to lower or upper has no
         * line and no override of its own: name the override of upper */
        const bool dom_located = scene_override_of(dom) || config_setting_source_line(dom) > 0;
        scene_where_of(L, dom_located ? dom : upper_at, sc->monitor_domain_where,
                       sizeof sc->monitor_domain_where);
    }
    if ((st = scene_number_or(L, g, SK_MONITOR_ZIGZAG_THRESHOLD, zigzag_default,
                              &sc->monitor_zigzag)) ||
        (st = scene_number(L, g, SK_MONITOR_MIN_DISTANCE_RATIO, &sc->monitor_min_distance)) ||
        (st = scene_keyword(L, g, SK_MONITOR_ACTION, &action, NULL)))
        return st;
    sc->monitor_action = (sph_monitor_action)action;
    return SPH_OK;
}
