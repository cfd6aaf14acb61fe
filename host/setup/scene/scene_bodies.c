/* scene_bodies.c — the sections `bodies` and `constants`: shape, material
 * and regions, initial velocity and fluid state, placement and relaxation,
 * constraints. */
#include "scene_loader.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* An expression as a message shows it: quoted, bytes outside printable
 * ASCII as \xHH (the message stays one line), cut after 160 characters. */
static const char *shown_expression(const char *text, char *buf, size_t size) {
    size_t len = 0;
    len += (size_t)snprintf(buf, size, "\"");
    for (size_t i = 0; text[i] && len + 8 < size; i++) {
        const unsigned char c = (unsigned char)text[i];
        if (i == 160) {
            len += (size_t)snprintf(buf + len, size - len, "...");
            break;
        }
        if (c >= ' ' && c <= '~')
            buf[len++] = (char)c;
        else
            len += (size_t)snprintf(buf + len, size - len, "\\x%02X", c);
        buf[len] = '\0';
    }
    if (len + 2 <= size) snprintf(buf + len, size - len, "\"");
    return buf;
}

/* Compile and drop an expression of an initial field: a syntax error, an
 * unknown variable or an over-long text is an input error at its line now,
 * not when the particles are placed.  The text is kept for particles.c. */
static sph_status parse_expression(loader *L, const config_setting_t *s, char *text_out,
                                   size_t text_size) {
    const char *text = "";
    sph_status st = scene_as_string(L, s, &text);
    if (st) return st;
    const char *vars[3], *names[SPH_SCENE_MAX_CONSTANTS];
    const int nvars = sph_scene_expression_variables(L->scene->dim, vars);
    const sph_expression_constants constants = sph_scene_expression_constants(L->scene, names);
    sph_expression *e = NULL;
    char why[768], shown[200];
    if (!sph_expression_compile(text, vars, nvars, &constants, &e, why, sizeof why))
        return scene_fail_at(L, s, NULL, "the expression %s: %s",
                             shown_expression(text, shown, sizeof shown), why);
    sph_expression_free(e);
    /* sph_expression_compile refuses texts that do not fit */
    snprintf(text_out, text_size, "%s", text);
    return SPH_OK;
}

/* `constants = { U = 1.0; Re = 100.0; }`: named numbers for the expressions. */
sph_status scene_parse_constants(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = scene_group(L, root, SK_CONSTANTS, &g);
    if (st || !g) return st;
    const int n = config_setting_length(g);
    if (n > SPH_SCENE_MAX_CONSTANTS)
        return scene_fail_at(L, g, NULL, "at most %d constants, got %d", SPH_SCENE_MAX_CONSTANTS,
                             n);
    /* every variable name is reserved, in 2D too: a scene keeps its meaning
     * when it gains a dimension */
    static const char *const reserved[] = {"x", "y", "z", "t"};
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(g, (unsigned)i);
        char why[256];
        if (!sph_expression_name_check(m->name, reserved, 4, why, sizeof why))
            return scene_fail_at(L, m, NULL, "%s", why);
        if (!config_setting_is_number(m))
            return scene_fail_at(L, m, NULL, "expected a number, got %s",
                                 scene_type_name(config_setting_type(m)));
        if ((st = scene_as_float(L, m, &sc->constant_value[i]))) return st;
        snprintf(sc->constant_name[i], sizeof sc->constant_name[i], "%s", m->name);
        sc->nconstants = i + 1;
    }
    return SPH_OK;
}

static sph_status parse_velocity(loader *L, const config_setting_t *g, sph_velocity_field *v) {
    const int dim = L->scene->dim;
    int type = 0;
    sph_status st = scene_keyword(L, g, SK_VELOCITY_TYPE, &type, NULL);
    if (st) return st;
    v->type = (sph_velocity_type)type;
    if (dim == 1 && v->type != SPH_VELOCITY_EXPRESSION && v->type != SPH_VELOCITY_ZERO &&
        v->type != SPH_VELOCITY_UNIFORM)
        return scene_fail_at(L, config_setting_get_member(g, "type"), NULL,
                             "a line (dimension 1) does not turn or bend: its initial velocity is "
                             "\"zero\", \"uniform\" or an \"expression\"");
    switch (v->type) {
    case SPH_VELOCITY_EXPRESSION: {
        /* v_a = the expression of key SCENE_AXES[a]; a missing key is 0 */
        if ((st = scene_check_keys(L, g,
                                   SECTIONS("initial_velocity", "initial_velocity.expression"))))
            return st;
        for (int a = 0; a < dim; a++) {
            const config_setting_t *s = config_setting_get_member(g, SCENE_AXES[a]);
            if (!s) continue;
            if ((st = parse_expression(L, s, v->expression[a], sizeof v->expression[a]))) return st;
            scene_where_of(L, s, v->expression_where[a], sizeof v->expression_where[a]);
        }
        return SPH_OK;
    }
    case SPH_VELOCITY_ZERO:
        return scene_check_keys(L, g, SECTIONS("initial_velocity"));
    case SPH_VELOCITY_UNIFORM:
        if ((st = scene_check_keys(L, g, SECTIONS("initial_velocity", "initial_velocity.uniform"))))
            return st;
        return scene_vector(L, g, SK_UNIFORM_VECTOR, dim, v->vector, NULL);
    case SPH_VELOCITY_RIGID_ROTATION: {
        const config_setting_t *w;
        if ((st = scene_check_keys(
                 L, g, SECTIONS("initial_velocity", "initial_velocity.rigid_rotation"))) ||
            (st = scene_member(L, g, SK_ROTATION_OMEGA, &w)))
            return st;
        if (dim == 2) {
            /* in the plane the rotation is about z */
            if (!config_setting_is_number(w))
                return scene_fail_at(L, w, NULL,
                                     "expected a number (the rotation rate about z in 2D), got %s",
                                     scene_type_name(config_setting_type(w)));
            if ((st = scene_as_float(L, w, &v->omega[2]))) return st;
        } else if ((st = scene_as_vector(L, w, 3, v->omega))) {
            return st;
        }
        return scene_vector(L, g, SK_ROTATION_CENTRE, dim, v->centre, NULL);
    }
    case SPH_VELOCITY_CANTILEVER_MODE:
        /* 003 eqs. 50-51: the first bending mode of a clamped plate */
        if ((st = scene_check_keys(
                 L, g, SECTIONS("initial_velocity", "initial_velocity.cantilever_mode"))) ||
            (st = scene_number(L, g, SK_CANTILEVER_AMPLITUDE_C0, &v->amplitude_c0)) ||
            (st = scene_number(L, g, SK_CANTILEVER_LENGTH, &v->length)) ||
            (st = scene_number(L, g, SK_CANTILEVER_KL, &v->kl)) ||
            (st = scene_number(L, g, SK_CANTILEVER_CLAMP_X, &v->clamp_x)))
            return st;
        return scene_axis(L, g, SK_CANTILEVER_AXIS, &v->axis);
    case SPH_VELOCITY_PLATE_MODE: {
        /* 000 eq. 35: a mode of the simply supported plate (3D) */
        const config_setting_t *at = config_setting_get_member(g, "type");
        if (dim != 3)
            return scene_fail_at(L, at, NULL,
                                 "\"plate_mode\" is a 3D velocity field (a plate "
                                 "in the x-y plane moving along z)");
        double lower[3] = {0, 0, 0}, size[3] = {0, 0, 0}, modes[3] = {0, 0, 0};
        const config_setting_t *ls, *ss, *ms;
        if ((st = scene_check_keys(L, g,
                                   SECTIONS("initial_velocity", "initial_velocity.plate_mode"))) ||
            (st = scene_number(L, g, SK_PLATE_MODE_AMPLITUDE, &v->amplitude)) ||
            (st = scene_member(L, g, SK_PLATE_MODE_LOWER, &ls)) ||
            (st = scene_as_vector(L, ls, 2, lower)) ||
            (st = scene_member(L, g, SK_PLATE_MODE_SIZE, &ss)) ||
            (st = scene_as_vector(L, ss, 2, size)) ||
            (st = scene_member(L, g, SK_PLATE_MODE_MODES, &ms)) ||
            (st = scene_as_vector(L, ms, 2, modes)))
            return st;
        for (int a = 0; a < 2; ++a) {
            if (!(size[a] > 0.0))
                return scene_fail_at(L, ss, NULL, "the plate's sides must be > 0, got %g", size[a]);
            if (!(modes[a] >= 1.0 && modes[a] <= 1000.0 && modes[a] == floor(modes[a])))
                return scene_fail_at(L, ms, NULL,
                                     "mode numbers are integers from 1 to 1000, got %g", modes[a]);
            v->lower[a] = lower[a];
            v->size[a] = size[a];
            v->modes[a] = (int)modes[a];
        }
        return scene_axis(L, g, SK_PLATE_MODE_AXIS, &v->axis);
    }
    }
    return SPH_OK;
}

static int find_material(const sph_scene *sc, const char *name) {
    for (int i = 0; i < sc->nmaterials; i++)
        if (strcmp(sc->materials[i].name, name) == 0) return i;
    return -1;
}

/* `axes = ["x", "y"]`: the constrained axes of a constraint, as a bit mask;
 * all axes when absent and not required. */
sph_status scene_axis_list(loader *L, const config_setting_t *c, sph_scene_key_id key,
                           bool required, int *mask) {
    const config_setting_t *s;
    sph_status st = required ? scene_require(L, c, key, &s) : scene_member(L, c, key, &s);
    if (st || !s) return st;
    if (!config_setting_is_array(s) && !config_setting_is_list(s))
        return scene_fail_at(L, s, NULL, "expected an array of axes such as [\"x\"], got %s",
                             scene_type_name(config_setting_type(s)));
    const int n = config_setting_length(s);
    if (n == 0) return scene_fail_at(L, s, NULL, "name at least one axis");
    *mask = 0;
    for (int k = 0; k < n; k++) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)k);
        const char *v = config_setting_get_string(e);
        int a = -1;
        for (int d = 0; v && d < L->scene->dim; d++)
            if (strcmp(v, SCENE_AXES[d]) == 0) a = d;
        if (a < 0)
            return scene_fail_at(L, e, NULL, "expected %s, got %s", scene_axes_text(L->scene->dim),
                                 v ? v : scene_type_name(config_setting_type(e)));
        if (*mask & (1 << a)) return scene_fail_at(L, e, NULL, "axis \"%s\" named twice", v);
        *mask |= 1 << a;
    }
    return SPH_OK;
}

static sph_status parse_axes(loader *L, const config_setting_t *c, bool required, int *mask) {
    return scene_axis_list(L, c, SK_CONSTRAINT_AXES, required, mask);
}

/* Element `index` of a list of named groups (bodies, observers, walls): a
 * group of only the keys of name_key's section, whose name differs from those of the elements
 * before it, names + k * stride (the name member of an array of structs).
 * `expected` describes the group for the message, `kind` and `list` name
 * the element and its list. */
sph_status scene_named_element(loader *L, const config_setting_t *g, int index,
                               const char *expected, const char *kind, const char *list,
                               sph_scene_key_id name_key, const char *names, size_t stride,
                               const char **name, const config_setting_t **at) {
    if (!config_setting_is_group(g))
        return scene_fail_at(L, g, NULL, "expected %s, got %s", expected,
                             scene_type_name(config_setting_type(g)));
    sph_status st;
    if ((st = scene_check_keys(L, g, SECTIONS(sph_scene_key_at(name_key)->section))) ||
        (st = scene_name(L, g, name_key, name, at)))
        return st;
    char why[256];
    if (!sph_name_check(*name, why, sizeof why)) return scene_fail_at(L, *at, NULL, "%s", why);
    for (int k = 0; k < index; k++)
        if (strcmp(names + (size_t)k * stride, *name) == 0)
            return scene_fail_at(L, *at, NULL, "duplicate %s name '%s' (%s.[%d] has it too)", kind,
                                 *name, list, k);
    return SPH_OK;
}

/* bodies[i].placement and bodies[i].relaxation (relax.h). */
static sph_status parse_placement(loader *L, const config_setting_t *b, sph_body *body) {
    int placement = 0;
    const config_setting_t *g, *at;
    sph_status st = scene_keyword(L, b, SK_BODY_PLACEMENT, &placement, NULL);
    if (st || (st = scene_group(L, b, SK_BODY_RELAXATION, &g))) return st;
    body->placement = (sph_placement)placement;
    if (placement == SPH_PLACEMENT_RELAXED && L->scene->dim == 1)
        return scene_fail_at(L, b, "placement",
                             "a line (dimension 1) is its lattice: there is nothing to relax");
    sph_relaxation *r = &body->relaxation;
    memset(r, 0, sizeof *r);
    /* the schema's defaults, also for a body without a relaxation group */
    r->steps = (int)sph_scene_key_at(SK_RELAXATION_STEPS)->def;
    r->step = (sph_relax_step)sph_scene_key_at(SK_RELAXATION_STEP)->def;
    r->tolerance = sph_scene_key_at(SK_RELAXATION_TOLERANCE)->def;
    r->perturbation = sph_scene_key_at(SK_RELAXATION_PERTURBATION)->def;
    r->seed = (unsigned long long)sph_scene_key_at(SK_RELAXATION_SEED)->def;
    if (!g) return SPH_OK;
    if (body->placement != SPH_PLACEMENT_RELAXED)
        return scene_fail_at(
            L, g, NULL,
            "a relaxation group needs placement = \"relaxed\" in the same body (the "
            "body is placed on the lattice)");
    scene_wide_int seed = {false, r->seed};
    bool has_seed = false;
    int step = (int)r->step;
    char text[24];
    if ((st = scene_check_keys(L, g, SECTIONS("bodies.relaxation"))) ||
        (st = scene_integer(L, g, SK_RELAXATION_STEPS, &r->steps, &at)) ||
        (st = scene_keyword(L, g, SK_RELAXATION_STEP, &step, NULL)) ||
        (st = scene_number(L, g, SK_RELAXATION_TOLERANCE, &r->tolerance)) ||
        (st = scene_number(L, g, SK_RELAXATION_PERTURBATION, &r->perturbation)) ||
        (st = scene_wide_integer(L, g, SK_RELAXATION_SEED, &seed, &has_seed, &at)))
        return st;
    r->step = (sph_relax_step)step;
    /* any 64-bit pattern seeds splitmix64 (docs/scene-format.md) */
    if (seed.negative)
        return scene_fail_at(L, at, NULL, "must be >= 0, got %s", scene_wide_text(seed, text));
    r->seed = seed.magnitude;
    if ((st = scene_member(L, g, SK_RELAXATION_FILE, &at))) return st;
    if (!at) return SPH_OK;
    const char *file = "";
    if ((st = scene_as_string(L, at, &file))) return st;
    if (!*file)
        return scene_fail_at(L, at, NULL, "must not be empty (leave the key out for no file)");
    return scene_relative_path(L, at, file, r->file, sizeof r->file);
}

/* An initial scalar field of a fluid body: a number (kept as its %.17g
 * text, and then checked > 0 here) or an expression of x, y (, z) and the
 * constants, compiled now and evaluated per particle by particles.c. */
static sph_status parse_initial_scalar(loader *L, const config_setting_t *s, const char *what,
                                       char *text, size_t size, char *where, size_t wsize) {
    scene_where_of(L, s, where, wsize);
    if (config_setting_is_number(s)) {
        double v = 0.0;
        sph_status st = scene_as_float(L, s, &v);
        if (st) return st;
        if (!(v > 0.0))
            return scene_fail_at(L, s, NULL, "an initial %s must be > 0, got %g", what, v);
        snprintf(text, size, "%.17g", v);
        return SPH_OK;
    }
    if (config_setting_type(s) != CONFIG_TYPE_STRING)
        return scene_fail_at(L, s, NULL,
                             "expected a number or an expression string of %s and the constants, "
                             "got %s",
                             scene_variables_text(L->scene->dim),
                             scene_type_name(config_setting_type(s)));
    return parse_expression(L, s, text, size);
}

/* bodies[i].initial_density and .initial_pressure: the initial state of a
 * fluid body.  The weakly compressible fluid's pressure follows from its
 * density (p = c0^2 (rho - rho0), seed 004 eq. 11), so only the density is
 * given (default rho0); the ideal gas needs its pressure (its energy
 * E = p / (gamma - 1) + rho |v|^2 / 2 follows), the density defaulting to
 * the material's. */
static sph_status parse_fluid_state(loader *L, const config_setting_t *b, sph_body *body) {
    const sph_formulation f = L->scene->formulation;
    const config_setting_t *rho_at = config_setting_get_member(b, "initial_density");
    const config_setting_t *p_at = config_setting_get_member(b, "initial_pressure");
    body->initial_density[0] = body->initial_density_where[0] = '\0';
    body->initial_pressure[0] = body->initial_pressure_where[0] = '\0';
    if (!SPH_FORMULATION_IS_EULERIAN(f)) {
        if (rho_at || p_at)
            return scene_fail_at(
                L, rho_at ? rho_at : p_at, NULL,
                "is for fluid bodies (formulations \"eulerian-wc\" and "
                "\"eulerian-compressible\"); formulation \"%s\" starts a solid at its "
                "material's density and zero stress",
                sph_formulation_name(f));
        return SPH_OK;
    }
    if (f == SPH_FORMULATION_EULERIAN_WC && p_at)
        return scene_fail_at(
            L, p_at, NULL,
            "formulation \"eulerian-wc\" derives the pressure from the density, "
            "p = c0^2 (rho - rho0) (seed 004 eq. 11): give initial_density instead");
    if (f == SPH_FORMULATION_EULERIAN_COMPRESSIBLE && !p_at)
        return scene_fail_at(L, b, "initial_pressure",
                             "missing required key: the ideal gas of formulation "
                             "\"eulerian-compressible\" starts from a pressure (a number or an "
                             "expression of %s), from which its energy follows",
                             scene_variables_text(L->scene->dim));
    sph_status st;
    if (rho_at && (st = parse_initial_scalar(
                       L, rho_at, "density", body->initial_density, sizeof body->initial_density,
                       body->initial_density_where, sizeof body->initial_density_where)))
        return st;
    if (p_at && (st = parse_initial_scalar(
                     L, p_at, "pressure", body->initial_pressure, sizeof body->initial_pressure,
                     body->initial_pressure_where, sizeof body->initial_pressure_where)))
        return st;
    return SPH_OK;
}

/* bodies[i].role and bodies[i].spacing (fluid scenes): a body is matter
 * (the fluid, placed on the scene's lattice) or a rigid wall at rest, the
 * public code's cylinder, whose particles sit spacing * dp apart (default
 * dp/2, its adaptation ratio 2; seed 004 section 4.3). */
static sph_status parse_role(loader *L, const config_setting_t *b, sph_body *body) {
    const sph_scene *sc = L->scene;
    const sph_formulation f = sc->formulation;
    const config_setting_t *role_at = NULL, *spacing_at = config_setting_get_member(b, "spacing");
    int role = SPH_BODY_MATTER;
    sph_status st = scene_keyword(L, b, SK_BODY_ROLE, &role, &role_at);
    if (st) return st;
    body->role = (sph_body_role)role;
    body->spacing_ratio = 1.0;
    if (role == SPH_BODY_WALL && L->scene->dim == 1)
        return scene_fail_at(
            L, role_at, NULL,
            "a line (dimension 1) has no wall bodies (their normals and relaxation "
            "need a plane or space): end a line with fixed-state buffers, "
            "constraints of type \"fixed\"");
    if (!SPH_FORMULATION_IS_EULERIAN(f)) {
        const config_setting_t *at = role_at ? role_at : spacing_at;
        if (at)
            return scene_fail_at(
                L, at, NULL,
                "is for the bodies of fluid scenes (formulations \"eulerian-wc\" and "
                "\"eulerian-compressible\"): a body there is matter or a wall; "
                "formulation \"%s\" places every body on the scene's lattice, and "
                "its rigid walls are the `walls` planes",
                sph_formulation_name(f));
        return SPH_OK;
    }
    const bool wall = body->role == SPH_BODY_WALL;
    body->spacing_ratio = wall ? 0.5 : 1.0;
    if (!spacing_at) return SPH_OK;
    double ratio = 0.0;
    if ((st = scene_as_float(L, spacing_at, &ratio))) return st;
    if (!(ratio > 0.0 && ratio <= 1.0))
        return scene_fail_at(L, spacing_at, NULL,
                             "the body's particle spacing over dp must be in (0, 1], got %g",
                             ratio);
    if (!wall && ratio != 1.0)
        return scene_fail_at(
            L, spacing_at, NULL,
            "a matter body is placed on the scene's lattice (spacing 1, dp apart); "
            "other spacings are for wall bodies (role = \"wall\") for now, got %g",
            ratio);
    body->spacing_ratio = ratio;
    return SPH_OK;
}

/* The material named by key k of group g. */
sph_status scene_material(loader *L, const config_setting_t *g, sph_scene_key_id k, int *out) {
    const sph_scene *sc = L->scene;
    const config_setting_t *at;
    const char *material = "";
    sph_status st = scene_name(L, g, k, &material, &at);
    if (st) return st;
    *out = find_material(sc, material);
    if (*out >= 0) return SPH_OK;
    const char *names[SPH_MAX_MATERIALS];
    for (int i = 0; i < sc->nmaterials; i++) names[i] = sc->materials[i].name;
    char hint[1024];
    scene_suggest(material, names, sc->nmaterials, "defined materials", hint, sizeof hint);
    return scene_fail_at(L, at, NULL, "unknown material '%s'%s", material, hint);
}

/* bodies.X.regions = ( { shape; material; }, ... ): parts of the body's
 * shape made of other materials (scene.h, sph_region).  Solids of the
 * updated-Lagrangian formulations only (checked with the materials in
 * check_material_count). */
static sph_status parse_regions(loader *L, const config_setting_t *b, sph_body *body) {
    const config_setting_t *list, *at;
    body->nregions = 0;
    sph_status st = scene_list(L, b, SK_BODY_REGIONS, &list);
    if (st || !list) return st;
    if (body->role == SPH_BODY_WALL)
        return scene_fail_at(L, list, NULL,
                             "body '%s' is a wall (role = \"wall\"): a wall has no material of its "
                             "own, so it takes no regions",
                             body->name);
    const int n = config_setting_length(list);
    if (n < 1 || n > SPH_SCENE_MAX_REGIONS)
        return scene_fail_at(L, list, NULL, "expected 1 to %d regions per body, got %d",
                             SPH_SCENE_MAX_REGIONS, n);
    for (int k = 0; k < n; k++) {
        const config_setting_t *r = config_setting_get_elem(list, (unsigned)k);
        if (!config_setting_is_group(r))
            return scene_fail_at(L, r, NULL, "expected a region group { shape; material; }, got %s",
                                 scene_type_name(config_setting_type(r)));
        sph_region *region = &body->regions[k];
        const char *shape = "";
        if ((st = scene_check_keys(L, r, SECTIONS("bodies.regions"))) ||
            (st = scene_name(L, r, SK_REGION_SHAPE, &shape, &at)))
            return st;
        region->shape = scene_find_shape(L, shape);
        if (region->shape < 0) return scene_unknown_shape(L, at, shape);
        scene_where_of(L, r, region->where, sizeof region->where);
        if ((st = scene_member(L, r, SK_REGION_MATERIAL, &at)) ||
            (st = scene_material(L, r, SK_REGION_MATERIAL, &region->material)))
            return st;
    }
    body->nregions = n;
    return SPH_OK;
}

static sph_status parse_body(loader *L, const config_setting_t *b, int index) {
    sph_scene *sc = L->scene;
    sph_body *body = &sc->bodies[index];
    const config_setting_t *at, *vel, *cons;
    const char *name = "", *shape = "";
    sph_status st = scene_named_element(L, b, index, "a body group { name; material; shape; }",
                                        "body", "bodies", SK_BODY_NAME, sc->bodies[0].name,
                                        sizeof sc->bodies[0], &name, &at);
    if (st) return st;
    snprintf(body->name, sizeof body->name, "%s", name);
    scene_where_of(L, b, body->where, sizeof body->where);
    if ((st = parse_role(L, b, body))) return st;
    const bool wall = body->role == SPH_BODY_WALL;

    /* a wall body takes the scene's one fluid material when it names none */
    if ((st = wall ? scene_member(L, b, SK_BODY_MATERIAL, &at)
                   : scene_require(L, b, SK_BODY_MATERIAL, &at)))
        return st;
    if (at) {
        if ((st = scene_material(L, b, SK_BODY_MATERIAL, &body->material))) return st;
    } else {
        body->material = 0;
    }

    if ((st = scene_name(L, b, SK_BODY_SHAPE, &shape, &at))) return st;
    body->shape = scene_find_shape(L, shape);
    if (body->shape < 0) return scene_unknown_shape(L, at, shape);

    memset(&body->velocity, 0, sizeof body->velocity);
    body->velocity.type = SPH_VELOCITY_ZERO;
    /* a wall is at rest, in the fluid's reference state */
    const config_setting_t *moving =
        wall ? scene_first_member(b, KEY_NAMES("initial_velocity", "initial_density",
                                               "initial_pressure", "constraints"))
             : NULL;
    if (moving)
        return scene_fail_at(L, moving, NULL,
                             "body '%s' is a wall (role = \"wall\"): a wall is at rest in the "
                             "fluid's reference state (the material's density), so it takes no "
                             "initial state or constraints",
                             name);
    if ((st = scene_group(L, b, SK_BODY_INITIAL_VELOCITY, &vel))) return st;
    if (vel && (st = parse_velocity(L, vel, &body->velocity))) return st;

    if ((st = parse_placement(L, b, body))) return st;
    if (!wall && (st = parse_fluid_state(L, b, body))) return st;
    if (wall) {
        body->initial_density[0] = body->initial_density_where[0] = '\0';
        body->initial_pressure[0] = body->initial_pressure_where[0] = '\0';
    }

    body->nconstraints = 0;
    if ((st = scene_list(L, b, SK_BODY_CONSTRAINTS, &cons))) return st;
    int nc = cons ? config_setting_length(cons) : 0;
    /* fluids: type "fixed" holds the state of the region's particles at its
     * initial value, a Dirichlet buffer (device/eulerian_step.cl); the
     * other types move a solid's particles and mean nothing here */
    const bool fluid_body = SPH_FORMULATION_IS_EULERIAN(sc->formulation);
    if (nc > SPH_SCENE_MAX_CONSTRAINTS)
        return scene_fail_at(L, cons, NULL, "at most %d constraints per body, got %d",
                             SPH_SCENE_MAX_CONSTRAINTS, nc);
    for (int i = 0; i < nc; i++) {
        const config_setting_t *c = config_setting_get_elem(cons, (unsigned)i);
        if (!config_setting_is_group(c))
            return scene_fail_at(L, c, NULL,
                                 "expected a constraint group { type; region; }, got %s",
                                 scene_type_name(config_setting_type(c)));
        int type = 0;
        const char *region = "";
        sph_constraint *con = &body->constraints[i];
        memset(con, 0, sizeof *con);
        if ((st = scene_keyword(L, c, SK_CONSTRAINT_TYPE, &type, NULL))) return st;
        if (fluid_body && type != 0)
            return scene_fail_at(
                L, c, "type",
                "a fluid body takes constraints of type \"fixed\" only (its region's "
                "state held at the initial one, a Dirichlet buffer); formulation "
                "\"%s\" keeps every particle in place",
                sph_formulation_name(sc->formulation));
        if (type == SPH_CONSTRAINT_FIXED)
            st = scene_check_keys(L, c, SECTIONS("constraints"));
        else if (type == SPH_CONSTRAINT_FIXED_AXES)
            st = scene_check_keys(L, c, SECTIONS("constraints", "constraints.fixed_axes"));
        else
            st = scene_check_keys(
                L, c, SECTIONS("constraints", "constraints.fixed_axes", "constraints.velocity"));
        if (st || (st = scene_name(L, c, SK_CONSTRAINT_REGION, &region, &at))) return st;
        con->type = (sph_constraint_type)type;
        con->region = scene_find_shape(L, region);
        if (con->region < 0) return scene_unknown_shape(L, at, region);
        scene_where_of(L, at, con->where, sizeof con->where);
        con->axis_mask = (1 << L->scene->dim) - 1;
        if (type != SPH_CONSTRAINT_FIXED &&
            (st = parse_axes(L, c, type == SPH_CONSTRAINT_FIXED_AXES, &con->axis_mask)))
            return st;
        if (type == SPH_CONSTRAINT_VELOCITY &&
            (st = scene_vector(L, c, SK_CONSTRAINT_VELOCITY, L->scene->dim, con->velocity, NULL)))
            return st;
        if (++L->nconstraints_total > SPH_MAX_CONSTRAINTS)
            return scene_fail_at(L, c, NULL,
                                 "at most %d constraints in a scene (all bodies together)",
                                 SPH_MAX_CONSTRAINTS);
    }
    body->nconstraints = nc;
    return parse_regions(L, b, body);
}

sph_status scene_parse_bodies(loader *L, const config_setting_t *root) {
    const config_setting_t *list;
    sph_status st = scene_list(L, root, SK_BODIES, &list);
    if (st) return st;
    int n = config_setting_length(list);
    if (n < 1 || n > SPH_MAX_BODIES)
        return scene_fail_at(L, list, NULL, "expected 1 to %d bodies, got %d", SPH_MAX_BODIES, n);
    for (int i = 0; i < n; i++)
        if ((st = parse_body(L, config_setting_get_elem(list, (unsigned)i), i))) return st;
    sph_scene *sc = L->scene;
    sc->nbodies = n;
    int matter = 0, walls = 0;
    for (int i = 0; i < n; i++) {
        matter += sc->bodies[i].role == SPH_BODY_MATTER;
        walls += sc->bodies[i].role == SPH_BODY_WALL;
    }
    if (matter == 0)
        return scene_fail_at(L, list, NULL,
                             "every body is a wall (role = \"wall\"): a fluid scene needs at least "
                             "one matter body (role = \"matter\", the default), the fluid");
    /* a relaxed fluid keeps off the walls through its own shape (the box
     * minus the cylinder: the relaxation's surface term holds it dp/2 from
     * the wall's surface, as the public code relaxes its fluid against the
     * cylinder) */
    (void)walls;
    return SPH_OK;
}
