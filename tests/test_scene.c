/* test_scene — scene loading, overrides and error reporting (host/setup/scene/).
 *
 * The two shipped cases must load with the values their files state; the
 * derived material constants follow 000 eq. 5 (c0 = sqrt(E / (3 (1 - 2 nu)
 * rho0))); every kind of bad input is rejected with SPH_ERR_INPUT and a
 * message that names the file, the line and the key path (or the override). */
#include "particles.h"
#include "scene.h"
#include "test_support.h"

#include <stdbool.h>
#include <stdlib.h>
#include <unistd.h>

static test_scene_dir tmp;

static bool near_rel(double a, double b, double rel) {
    return fabs(a - b) <= rel * fabs(b);
}

/* Load cases/<name>/scene.cfg without overrides; false (and a failed
 * check) when it does not load. */
static bool load_case_scene(test_counts *c, const char *case_name, sph_scene *s) {
    char path[1024];
    test_case_path(case_name, path, sizeof path);
    sph_error err = {0};
    const sph_status st = sph_scene_load(s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "load %s: %s", path, err.msg);
    return st == SPH_OK;
}

static void test_oscillating_plate(test_counts *c) {
    sph_scene s;
    if (!load_case_scene(c, "oscillating_plate_2d", &s)) return;
    CHECK(c, s.dim == 2, "dim %d", s.dim);
    CHECK(c, strcmp(s.title, "2D oscillating plate") == 0, "title '%s'", s.title);
    /* dp = H / ratio = 0.02 / 10 */
    CHECK(c, near_rel(s.dp, 0.002, 1e-15), "dp %.17g", s.dp);
    CHECK_NEAR(c, s.smoothing_ratio, 1.3, 0.0, "smoothing_ratio");
    CHECK(c, s.kernel == SPH_KERNEL_WENDLAND_C2, "kernel");
    CHECK(c, s.formulation == SPH_FORMULATION_ENOG_A, "formulation %d", s.formulation);
    CHECK(c, s.rotation == SPH_ROTATION_AVERAGED, "rotation %d", s.rotation);
    CHECK(c, s.stepping == SPH_STEPPING_DUAL, "stepping %d", s.stepping);
    CHECK_NEAR(c, s.end_time, 1.0, 0.0, "end");
    CHECK_NEAR(c, s.output_interval, 0.01, 0.0, "output_interval");
    CHECK_NEAR(c, s.cfl_advection, 0.2, 0.0, "cfl_advection");
    CHECK_NEAR(c, s.cfl_acoustic, 0.4, 0.0, "cfl_acoustic");
    /* defaults: xi_e = 0.7 d + 2.1, unlimited Riemann dissipation */
    CHECK_NEAR(c, s.xi_e, 3.5, 1e-15, "xi_e default");
    CHECK_NEAR(c, s.riemann_limiter_slope, 0.0, 0.0, "riemann_limiter default");
    CHECK(c, !s.has_reference_speed, "has_reference_speed");
    CHECK(c, s.acceleration_criterion, "acceleration_criterion default");
    CHECK(c, !s.has_lattice_origin, "has_lattice_origin");
    CHECK(c, s.gravity[0] == 0.0 && s.gravity[1] == 0.0, "gravity default");

    CHECK(c, s.nmaterials == 1, "nmaterials %d", s.nmaterials);
    const sph_material *m = &s.materials[0];
    CHECK(c, strcmp(m->name, "plate") == 0, "material name '%s'", m->name);
    /* c0 = sqrt(2e6 / (3 (1 - 2 * 0.3975) 1000)) = 57.0266 */
    CHECK(c, near_rel(m->sound_speed, 57.0266, 1e-4), "c0 %.10g", m->sound_speed);
    CHECK(c, near_rel(m->shear_modulus, 2e6 / (2 * 1.3975), 1e-14), "G %.10g", m->shear_modulus);
    CHECK(c, near_rel(m->bulk_modulus, m->density * m->sound_speed * m->sound_speed, 1e-14),
          "K = rho0 c0^2: %.10g", m->bulk_modulus);

    CHECK(c, s.nshapes == 4, "nshapes %d", s.nshapes);
    CHECK(c, strcmp(s.shapes[1].name, "base") == 0 && s.shapes[1].type == SPH_SHAPE_BOX, "shape 1");
    /* the base grown by 4 dp left, down and up */
    CHECK(c, near_rel(s.shapes[1].lower[0], -0.068, 1e-14), "base lower x %.17g",
          s.shapes[1].lower[0]);
    CHECK(c, near_rel(s.shapes[1].lower[1], -0.018, 1e-14), "base lower y");
    CHECK(c, near_rel(s.shapes[1].upper[1], 0.018, 1e-14), "base upper y");
    CHECK(c, s.shapes[1].upper[0] == 0.0, "base upper x");
    CHECK(c,
          s.shapes[2].type == SPH_SHAPE_UNION && s.shapes[2].nparts == 2 &&
              s.shapes[2].parts[0] == 0 && s.shapes[2].parts[1] == 1,
          "plate = union(beam, base)");
    CHECK(c,
          s.shapes[3].type == SPH_SHAPE_DIFFERENCE && s.shapes[3].parts[0] == 1 &&
              s.shapes[3].parts[1] == 0,
          "clamp = base - beam");

    CHECK(c, s.nbodies == 1, "nbodies %d", s.nbodies);
    const sph_body *b = &s.bodies[0];
    CHECK(c, strcmp(b->name, "plate") == 0 && b->material == 0 && b->shape == 2, "body");
    CHECK(c, b->velocity.type == SPH_VELOCITY_CANTILEVER_MODE, "velocity type");
    CHECK_NEAR(c, b->velocity.amplitude_c0, 0.05, 0.0, "amplitude_c0");
    CHECK_NEAR(c, b->velocity.length, 0.2, 0.0, "length");
    CHECK_NEAR(c, b->velocity.kl, 1.875, 0.0, "kl");
    CHECK(c, b->velocity.axis == 1, "axis %d", b->velocity.axis);
    CHECK(c,
          b->nconstraints == 1 && b->constraints[0].type == SPH_CONSTRAINT_FIXED &&
              b->constraints[0].region == 3,
          "clamp constraint");
    CHECK(c, s.nobservers == 1 && strcmp(s.observers[0].name, "tip") == 0, "observer");
    CHECK(c, s.observers[0].position[0] == 0.2 && s.observers[0].position[1] == 0.0,
          "observer position");
    CHECK(c, s.period_observer == 0 && s.period_axis == 1, "period observer %d axis %d",
          s.period_observer, s.period_axis);

    /* geometry: the plate is beam + base, the clamp is base - beam */
    double mid[3] = {0.1, 0.0, 0.0}, root[3] = {-0.03, 0.0, 0.0}, pad[3] = {-0.065, 0.0, 0.0},
           above[3] = {0.1, 0.015, 0.0}, cap[3] = {-0.03, 0.015, 0.0};
    CHECK(c, sph_shape_contains(&s, 2, mid) && !sph_shape_contains(&s, 3, mid), "mid-span");
    CHECK(c, sph_shape_contains(&s, 2, root) && !sph_shape_contains(&s, 3, root), "inserted part");
    CHECK(c, sph_shape_contains(&s, 2, pad) && sph_shape_contains(&s, 3, pad), "clamp pad");
    CHECK(c, !sph_shape_contains(&s, 2, above), "above the free span");
    CHECK(c, sph_shape_contains(&s, 3, cap), "clamp layer above the inserted part");
    double lo[3], hi[3];
    sph_shape_bounds(&s, 2, lo, hi);
    CHECK(c, near_rel(lo[0], -0.068, 1e-14) && hi[0] == 0.2 && near_rel(hi[1], 0.018, 1e-14),
          "union bounds [%g %g] x [%g %g]", lo[0], hi[0], lo[1], hi[1]);
    sph_shape_bounds(&s, 3, lo, hi);
    CHECK(c, hi[0] == 0.0, "difference bounds = bounds of the first part");

    CHECK(c, s.resolved_text && strstr(s.resolved_text, "youngs_modulus"), "resolved_text");
    sph_scene_free(&s);
    CHECK(c, s.resolved_text == NULL, "free clears resolved_text");
    sph_scene_free(&s); /* twice is harmless */
}

static void test_spinning_plate(test_counts *c) {
    sph_scene s;
    if (!load_case_scene(c, "spinning_plate_2d", &s)) return;
    CHECK(c, s.dim == 2 && s.dp == 0.05, "dim %d dp %g", s.dim, s.dp);
    CHECK(c, s.formulation == SPH_FORMULATION_ENOG_A && s.rotation == SPH_ROTATION_AVERAGED,
          "method");
    CHECK(c, s.stepping == SPH_STEPPING_SINGLE, "stepping");
    CHECK_NEAR(c, s.cfl_acoustic, 0.1, 0.0, "cfl_acoustic");
    CHECK_NEAR(c, s.cfl_advection, 0.2, 0.0, "cfl_advection default");
    CHECK_NEAR(c, s.end_time, 0.5, 0.0, "end");
    CHECK(c, s.nshapes == 1 && s.nbodies == 1, "tables");
    /* rubber: c0 = sqrt(1.7e7 / (3 (1 - 0.9) 1100)) */
    CHECK(c, near_rel(s.materials[0].sound_speed, sqrt(1.7e7 / (0.3 * 1100.0)), 1e-14), "c0");
    const sph_velocity_field *v = &s.bodies[0].velocity;
    CHECK(c, v->type == SPH_VELOCITY_RIGID_ROTATION && v->omega[2] == 50.0 && v->omega[0] == 0.0,
          "rigid rotation at 50 rad/s about z");
    CHECK(c, s.nobservers == 1 && s.period_observer == -1, "no period analysis");
    sph_scene_free(&s);
}

/* A material with its own sound speed (003 §5.2.3): K = rho0 c0^2, G from E, nu. */
/* The acoustic CFL defaults to 0.4 (000, 003) and to 0.2 with the
 * Laguerre-Wendland kernel, whose plate blows up at 0.3-0.4 (docs/method.md,
 * kernels); a scene's own value always wins.  The square Taylor bar states
 * no CFL, the plate states 0.4. */
static void test_kernel_cfl(test_counts *c) {
    char bar[1024], plate[1024];
    test_case_path("taylor_bar_square", bar, sizeof bar);
    test_case_path("oscillating_plate_2d", plate, sizeof plate);
    const char *lw[] = {"method.kernel=\"laguerre-wendland\""};
    struct {
        const char *path;
        int noverrides;
        double cfl;
    } rows[] = {{bar, 0, 0.4}, {bar, 1, 0.2}, {plate, 1, 0.4}};
    for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k) {
        sph_scene s;
        sph_error err = {0};
        const sph_status st = sph_scene_load(&s, rows[k].path, lw, rows[k].noverrides, &err);
        CHECK(c, st == SPH_OK, "load %s: %s", rows[k].path, err.msg);
        if (st == SPH_OK)
            CHECK(c, s.cfl_acoustic == rows[k].cfl, "row %zu: cfl_acoustic %g, expected %g", k,
                  s.cfl_acoustic, rows[k].cfl);
        sph_scene_free(&s);
    }
}

static void test_sound_speed(test_counts *c) {
    sph_scene s;
    if (!load_case_scene(c, "high_velocity_impact", &s)) return;
    const sph_material *m = &s.materials[0];
    CHECK(c, m->sound_speed == 5328.0, "c0 %.10g as given", m->sound_speed);
    CHECK(c, near_rel(m->bulk_modulus, 8930.0 * 5328.0 * 5328.0, 1e-14), "K %.10g",
          m->bulk_modulus);
    CHECK(c, near_rel(m->shear_modulus, 7.417e10 / (2.0 * 1.344), 1e-14), "G %.10g",
          m->shear_modulus);
    CHECK(c, m->plastic && m->yield_stress == 3.0e8 && m->hardening_modulus == 0.0,
          "perfectly plastic");
    CHECK(c, s.nbodies == 2 && s.bodies[0].velocity.vector[0] == 3100.0, "projectile at 3100");
    sph_scene_free(&s);
}

static void test_overrides(test_counts *c) {
    char path[1024];
    test_repo_path("cases/oscillating_plate_2d/scene.cfg", path, sizeof path);
    sph_scene s;
    sph_error err = {0};

    const char *ratio[] = {"resolution.ratio=30"};
    sph_status st = sph_scene_load(&s, path, ratio, 1, &err);
    CHECK(c, st == SPH_OK, "ratio=30: %s", err.msg);
    if (st == SPH_OK) {
        CHECK(c, s.dp == 0.02 / 30.0, "dp %.17g", s.dp);
        CHECK(c, strstr(s.resolved_text, "ratio = 30;") != NULL, "resolved text records it");
        /* padding follows dp: base lower x = -0.06 - 4 dp */
        CHECK(c, near_rel(s.shapes[1].lower[0], -0.06 - 4 * 0.02 / 30.0, 1e-14), "padding");
    }
    sph_scene_free(&s);

    const char *enog[] = {"method.formulation=enog", "method.rotation=none"};
    st = sph_scene_load(&s, path, enog, 2, &err);
    CHECK(c, st == SPH_OK, "enog: %s", err.msg);
    CHECK(c, s.formulation == SPH_FORMULATION_ENOG && s.rotation == SPH_ROTATION_NONE,
          "enog, none");
    sph_scene_free(&s);

    /* element of a list addressed by its name, and by its index */
    const char *amp[] = {"bodies.plate.initial_velocity.amplitude_c0=0.01", "time.end=0.5"};
    st = sph_scene_load(&s, path, amp, 2, &err);
    CHECK(c, st == SPH_OK, "amplitude: %s", err.msg);
    CHECK_NEAR(c, s.bodies[0].velocity.amplitude_c0, 0.01, 0.0, "amplitude_c0 override");
    CHECK_NEAR(c, s.end_time, 0.5, 0.0, "end override");
    sph_scene_free(&s);
    const char *amp_idx[] = {"bodies.[0].initial_velocity.amplitude_c0=0.02"};
    st = sph_scene_load(&s, path, amp_idx, 1, &err);
    CHECK(c, st == SPH_OK && s.bodies[0].velocity.amplitude_c0 == 0.02, "by index: %s", err.msg);
    sph_scene_free(&s);

    /* one element of an array; an integer joins an array of decimals */
    const char *elem[] = {"shapes.base.lower_pad_dp.[1]=5"};
    st = sph_scene_load(&s, path, elem, 1, &err);
    CHECK(c, st == SPH_OK && near_rel(s.shapes[1].lower[1], -0.01 - 5 * 0.002, 1e-14),
          "array element replaced, int promoted: %s", err.msg);
    CHECK(c, st != SPH_OK || strstr(s.resolved_text, "lower_pad_dp = [ 4.0, 5.0 ]"),
          "promoted to a decimal in the resolved text");
    sph_scene_free(&s);

    /* later overrides win; aggregates replace and create; strings in quotes */
    const char *more[] = {"time.end=0.7",
                          "time.end=0.8",
                          "gravity=[0.0, -9.81]",
                          "shapes.beam.upper=(0.3, 0.01)",
                          "title=\"sweep run\"",
                          "bodies.plate.initial_velocity={ type = \"zero\"; }",
                          "method.xi_e=4",
                          "shapes.base.lower_pad_dp.[1]=5",
                          "time.acceleration_criterion=false",
                          ("shapes.base={ type = \"box\"; lower = [-0.06, -0.01]; "
                           "upper = [0.0, 0.01]; lower_pad_dp = [4.0, 6.0]; }")};
    st = sph_scene_load(&s, path, more, (int)(sizeof more / sizeof more[0]), &err);
    CHECK(c, st == SPH_OK, "more: %s", err.msg);
    if (st == SPH_OK) {
        CHECK_NEAR(c, s.end_time, 0.8, 0.0, "last override wins");
        CHECK(c, s.gravity[0] == 0.0 && s.gravity[1] == -9.81, "gravity created");
        CHECK(c, s.shapes[0].upper[0] == 0.3, "list replaces array");
        CHECK(c, strcmp(s.title, "sweep run") == 0, "title '%s'", s.title);
        CHECK(c, s.bodies[0].velocity.type == SPH_VELOCITY_ZERO, "group replaced");
        CHECK_NEAR(c, s.xi_e, 4.0, 0.0, "int accepted for a float");
        CHECK(c, near_rel(s.shapes[1].lower[1], -0.01 - 6 * 0.002, 1e-14),
              "the later group replacement wins over the element override: %.17g",
              s.shapes[1].lower[1]);
        CHECK(c, !s.acceleration_criterion, "bool");
        CHECK(c, strcmp(s.shapes[1].name, "base") == 0 && s.shapes[1].upper[1] == 0.01,
              "a replaced group keeps its place: shapes[1] = '%s'", s.shapes[1].name);
        /* the order of the group is kept when a member is replaced */
        const char *beam = strstr(s.resolved_text, "beam");
        const char *base = strstr(s.resolved_text, "base");
        CHECK(c, beam && base && beam < base, "shape order kept");
    }

    /* the resolved text is a loadable scene with the same content */
    if (st == SPH_OK) {
        char copy[1024];
        test_scene_write(&tmp, s.resolved_text, copy, sizeof copy);
        sph_scene r;
        sph_status rst = sph_scene_load(&r, copy, NULL, 0, &err);
        CHECK(c, rst == SPH_OK, "reload resolved text: %s", err.msg);
        if (rst == SPH_OK) {
            CHECK(c,
                  r.end_time == 0.8 && r.gravity[1] == -9.81 && r.dp == s.dp &&
                      r.nshapes == s.nshapes,
                  "round trip");
            sph_scene_free(&r);
        }
    }
    sph_scene_free(&s);
}

/* A small valid scene; each bad-input row edits one part of it. */
static const char BASE[] =
    "# test scene\n"                                                                   /*  1 */
    "dimension = 2;\n"                                                                 /*  2 */
    "resolution = { dp = 0.1; };\n"                                                    /*  3 */
    "method = { formulation = \"enog-a\"; rotation = \"averaged\"; };\n"               /*  4 */
    "time = { end = 1.0; output_interval = 0.1; };\n"                                  /*  5 */
    "materials = {\n"                                                                  /*  6 */
    "  steel = { density = 7800.0; youngs_modulus = 2.0e11; poisson_ratio = 0.3; };\n" /*  7 */
    "};\n"                                                                             /*  8 */
    "shapes = {\n"                                                                     /*  9 */
    "  block = { type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0]; };\n"         /* 10 */
    "};\n"                                                                             /* 11 */
    "bodies = (\n"                                                                     /* 12 */
    "  { name = \"a\"; material = \"steel\"; shape = \"block\"; }\n"                   /* 13 */
    ");\n";                                                                            /* 14 */

typedef struct {
    const char *what;
    const char *find, *replace; /* edit of BASE; find NULL: BASE as is */
    const char *set;            /* one override, or NULL */
    const char *expect;         /* must appear in err.msg; %F stands for the file */
} bad_row;

static const bad_row BAD[] = {
    {"syntax error", "dp = 0.1;", "dp = = 0.1;", NULL, "%F:3: syntax error"},
    {"mixed int/float array", "lower = [0.0, 0.0]", "lower = [0, 0.0]", NULL,
     "%F:10: syntax error: mismatched element type in array"},
    {"mixed array hint", "lower = [0.0, 0.0]", "lower = [0, 0.0]", NULL, "0.0, not 0"},
    {"unknown key, suggestion", "youngs_modulus", "youngs_modulous", NULL,
     "%F:7: materials.steel.youngs_modulous: unknown key 'youngs_modulous' (did you mean "
     "'youngs_modulus'?)"},
    {"unknown top-level key", "dimension = 2;", "dimension = 2; gravty = [0.0, 1.0];", NULL,
     "%F:2: gravty: unknown key 'gravty' (did you mean 'gravity'?)"},
    {"unknown key far from any", "end = 1.0;", "end = 1.0; qqqqqqqq = 1;", NULL,
     "%F:5: time.qqqqqqqq: unknown key 'qqqqqqqq' (valid keys here: end, output_interval"},
    {"E = 0", "youngs_modulus = 2.0e11", "youngs_modulus = 0.0", NULL,
     "%F:7: materials.steel.youngs_modulus: must be > 0, got 0"},
    {"E < 0", "youngs_modulus = 2.0e11", "youngs_modulus = -2.0e11", NULL,
     "%F:7: materials.steel.youngs_modulus: must be > 0, got -2e+11"},
    {"nu = 0.5", "poisson_ratio = 0.3", "poisson_ratio = 0.5", NULL,
     "%F:7: materials.steel.poisson_ratio: must be in [0, 0.5), got 0.5"},
    {"nu < 0", "poisson_ratio = 0.3", "poisson_ratio = -0.1", NULL,
     "%F:7: materials.steel.poisson_ratio: must be in [0, 0.5), got -0.1"},
    {"sound speed 0", "poisson_ratio = 0.3", "poisson_ratio = 0.3; sound_speed = 0.0", NULL,
     "%F:7: materials.steel.sound_speed: must be > 0, got 0"},
    {"density = 0", "density = 7800.0", "density = 0", NULL,
     "%F:7: materials.steel.density: must be > 0, got 0"},
    {"dp = 0", "dp = 0.1", "dp = 0.0", NULL, "%F:3: resolution.dp: must be > 0, got 0"},
    {"dp < 0", "dp = 0.1", "dp = -0.1", NULL, "%F:3: resolution.dp: must be > 0, got -0.1"},
    {"ratio = 0", "dp = 0.1", "reference_length = 1.0; ratio = 0", NULL,
     "%F:3: resolution.ratio: must be > 0, got 0"},
    {"reference_length without ratio", "dp = 0.1", "reference_length = 1.0", NULL,
     "%F:3: resolution.ratio: missing required key"},
    {"both resolution forms", "dp = 0.1;", "dp = 0.1; ratio = 10.0;", NULL,
     "%F:3: resolution: give either dp or reference_length and ratio"},
    {"no resolution", "dp = 0.1;", "", NULL, "%F:3: resolution: missing required key"},
    {"end = 0", "end = 1.0", "end = 0.0", NULL, "%F:5: time.end: must be > 0, got 0"},
    {"end < 0", "end = 1.0", "end = -1", NULL, "%F:5: time.end: must be > 0, got -1"},
    {"output_interval > end", "output_interval = 0.1", "output_interval = 2.0", NULL,
     "%F:5: time.output_interval: must not exceed time.end (1), got 2"},
    {"cfl out of range", "end = 1.0;", "end = 1.0; cfl_acoustic = 1.5;", NULL,
     "%F:5: time.cfl_acoustic: must be in (0, 1], got 1.5"},
    {"integrator on a solid", "end = 1.0;", "end = 1.0; integrator = \"ssp-rk2\";", NULL,
     "%F:5: time.integrator: is for the fluid formulations (\"eulerian-wc\", "
     "\"eulerian-compressible\"); formulation \"enog-a\" steps by time.stepping"},
    {"bad stepping", "end = 1.0;", "end = 1.0; stepping = \"triple\";", NULL,
     "%F:5: time.stepping: must be one of \"dual\", \"single\", got \"triple\""},
    {"missing material key", "density = 7800.0; ", "", NULL,
     "%F:7: materials.steel.density: missing required key"},
    {"missing top-level key", "dimension = 2;\n", "\n", NULL,
     "%F: dimension: missing required key"},
    {"missing end", "end = 1.0; ", "", NULL, "%F:5: time.end: missing required key"},
    {"dimension 4", "dimension = 2;", "dimension = 4;", NULL,
     "%F:2: dimension: must be 1, 2 or 3, got 4"},
    {"a solid line", "dimension = 2;", "dimension = 1;", NULL,
     "%F:2: dimension: dimension 1 is for the fluid formulations (\"eulerian-wc\", "
     "\"eulerian-compressible\"), got formulation \"enog-a\""},
    {"dimension as float", "dimension = 2;", "dimension = 2.0;", NULL,
     "%F:2: dimension: expected an integer, got a number"},
    /* particle placement and relaxation (bodies[i].placement, .relaxation) */
    {"bad placement", "shape = \"block\";", "shape = \"block\"; placement = \"random\";", NULL,
     "%F:13: bodies.a.placement: must be one of \"lattice\", \"relaxed\", got \"random\""},
    {"relaxation on a lattice body", "shape = \"block\";",
     "shape = \"block\"; relaxation = { steps = 10; };", NULL,
     "%F:13: bodies.a.relaxation: a relaxation group needs placement = \"relaxed\""},
    {"relaxation created by --set on a lattice body", NULL, NULL, "bodies.a.relaxation.steps=10",
     "--set bodies.a.relaxation.steps=10: bodies.a.relaxation: a relaxation group needs "
     "placement = \"relaxed\""},
    {"relaxation steps < 0", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { steps = -5; };", NULL,
     "%F:13: bodies.a.relaxation.steps: must be in [0, 1000000], got -5"},
    {"relaxation steps not an integer", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { steps = 10.5; };", NULL,
     "%F:13: bodies.a.relaxation.steps: expected an integer, got a number"},
    {"relaxation perturbation > 0.5", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { perturbation = 0.7; };", NULL,
     "%F:13: bodies.a.relaxation.perturbation: must be in [0, 0.5], got 0.7"},
    {"relaxation tolerance < 0", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { tolerance = -0.01; };", NULL,
     "%F:13: bodies.a.relaxation.tolerance: must be >= 0, got -0.01"},
    {"relaxation seed < 0", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { seed = -1; };", NULL,
     "%F:13: bodies.a.relaxation.seed: must be >= 0, got -1"},
    {"relaxation step rule", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { step = \"half\"; };", NULL,
     "%F:13: bodies.a.relaxation.step: must be one of \"normalised\", \"fixed\", got \"half\""},
    {"relaxation unknown key", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { stepz = 10; };", NULL,
     "%F:13: bodies.a.relaxation.stepz: unknown key 'stepz' (did you mean 'steps'?)"},
    {"relaxation empty file", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { file = \"\"; };", NULL,
     "%F:13: bodies.a.relaxation.file: must not be empty"},
    {"relaxation file not a string", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { file = 3; };", NULL,
     "%F:13: bodies.a.relaxation.file: expected a string, got an integer"},
    {"relaxation not a group", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = 5;", NULL,
     "%F:13: bodies.a.relaxation: expected a group { ... }, got an integer"},
    {"unknown shape in body", "shape = \"block\"", "shape = \"blok\"", NULL,
     "%F:13: bodies.a.shape: unknown shape 'blok' (did you mean 'block'?)"},
    {"unknown material", "material = \"steel\"", "material = \"iron\"", NULL,
     "%F:13: bodies.a.material: unknown material 'iron'"},
    {"box upper <= lower", "upper = [1.0, 1.0]", "upper = [1.0, 0.0]", NULL,
     "%F:10: shapes.block.upper: must exceed lower in every component"},
    {"box negative padding", "upper = [1.0, 1.0];",
     "upper = [1.0, 1.0]; lower_pad_dp = [0.0, -1.0];", NULL,
     "%F:10: shapes.block.lower_pad_dp.[1]: padding must be >= 0, got -1"},
    {"negative upper padding", "upper = [1.0, 1.0];",
     "upper = [1.0, 1.0]; upper_pad_dp = [-20.0, 0.0];", NULL,
     "%F:10: shapes.block.upper_pad_dp.[0]: padding must be >= 0"},
    {"vector of wrong length", "upper = [1.0, 1.0]", "upper = [1.0, 1.0, 1.0]", NULL,
     "%F:10: shapes.block.upper: expected a vector of 2 numbers, got 3 elements"},
    {"vector not a vector", "upper = [1.0, 1.0]", "upper = 1.0", NULL,
     "%F:10: shapes.block.upper: expected a vector of 2 numbers"},
    {"vector with a string", "upper = [1.0, 1.0]", "upper = (1.0, \"1\")", NULL,
     "%F:10: shapes.block.upper.[1]: expected a number, got a string"},
    {"string for a number", "dp = 0.1", "dp = \"small\"", NULL,
     "%F:3: resolution.dp: expected a number, got a string"},
    {"number for a string", "formulation = \"enog-a\"", "formulation = 1", NULL,
     "%F:4: method.formulation: expected a string, got an integer"},
    {"bad formulation", "\"enog-a\"", "\"enogx\"", NULL,
     "%F:4: method.formulation: must be one of \"enog\", \"enog-a\", \"og\", \"oas\", \"gnog\", "
     "\"gnog-a\", \"tlsph\", \"eulerian-wc\", \"eulerian-compressible\", got \"enogx\""},
    {"enog with rotation averaged", "formulation = \"enog-a\"", "formulation = \"enog\"", NULL,
     "%F:4: method.rotation: formulation \"enog\" has no rotation correction"},
    {"enog-a with rotation none", "rotation = \"averaged\"", "rotation = \"none\"", NULL,
     "%F:4: method.rotation: formulation \"enog-a\" needs a rotation correction"},
    {"smoothing ratio out of range", "rotation = \"averaged\";",
     "rotation = \"averaged\"; smoothing_ratio = 2.5;", NULL,
     "%F:4: method.smoothing_ratio: must be in [1, 2], got 2.5"},
    {"viscous regularization on a solid", "rotation = \"averaged\";",
     "rotation = \"averaged\"; viscous_regularization = \"linear\";", NULL,
     "%F:4: method.viscous_regularization: is for the fluid formulations (\"eulerian-wc\" and "
     "\"eulerian-compressible\"), got formulation \"enog-a\""},
    {"duplicate body name", "shape = \"block\"; }\n",
     "shape = \"block\"; },\n  { name = \"a\"; material = \"steel\"; shape = \"block\"; }\n", NULL,
     "%F:14: bodies.[1].name: duplicate body name 'a'"},
    {"bodies not a list",
     "bodies = (\n  { name = \"a\"; material = \"steel\"; shape = \"block\"; }\n);",
     "bodies = {\n  a = { name = \"a\"; material = \"steel\"; shape = \"block\"; };\n};", NULL,
     "%F:12: bodies: expected a list ( { ... }, ... ), got a group { ... }"},
    {"no bodies", "  { name = \"a\"; material = \"steel\"; shape = \"block\"; }\n", "", NULL,
     "%F:12: bodies: expected 1 to 8 bodies, got 0"},
    {"shape cycle", "};\nbodies",
     "  u = { type = \"union\"; parts = [\"v\"]; };\n"
     "  v = { type = \"union\"; parts = [\"u\"]; };\n};\nbodies",
     NULL, "shapes refer to each other in a cycle: 'u' -> 'v' -> 'u'"},
    {"unknown part", "};\nbodies",
     "  u = { type = \"union\"; parts = [\"block\", \"blox\"]; };\n};\nbodies", NULL,
     "%F:11: shapes.u.parts.[1]: unknown shape 'blox'"},
    {"difference of one part", "};\nbodies",
     "  d = { type = \"difference\"; parts = [\"block\"]; };\n};\nbodies", NULL,
     "%F:11: shapes.d.parts: a difference needs at least 2 parts, got 1"},
    {"bad shape type", "type = \"box\"", "type = \"sphere\"", NULL,
     "%F:10: shapes.block.type: must be one of \"box\", \"union\", \"difference\", \"disc\", "
     "\"ball\", \"annulus\", \"hollow_sphere\", \"cylinder\", \"mesh\", got \"sphere\""},
    {"box key on a union", "};\nbodies",
     "  u = { type = \"union\"; parts = [\"block\"]; lower = [0.0, 0.0]; };\n};\nbodies", NULL,
     "%F:11: shapes.u.lower: unknown key 'lower' (valid keys here: type, parts)"},
    {"2D omega as vector", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"rigid_rotation\"; omega = [0.0, 1.0]; };",
     NULL, "%F:13: bodies.a.initial_velocity.omega: expected a number (the rotation rate about z"},
    {"axis z in 2D", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"cantilever_mode\"; amplitude_c0 = 0.1; "
     "length = 1.0; axis = \"z\"; };",
     NULL, "%F:13: bodies.a.initial_velocity.axis: must be \"x\" or \"y\" in 2D, got \"z\""},
    {"cantilever without length", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"cantilever_mode\"; amplitude_c0 = 0.1; };",
     NULL, "%F:13: bodies.a.initial_velocity.length: missing required key"},
    {"constraint region unknown", "shape = \"block\";",
     "shape = \"block\"; constraints = ( { type = \"fixed\"; region = \"clampp\"; } );", NULL,
     "%F:13: bodies.a.constraints.[0].region: unknown shape 'clampp'"},
    {"period observer unknown", ");\n",
     ");\nobservers = ( { name = \"tip\"; position = [1.0, 0.5]; } );\n"
     "analysis = { period = { observer = \"top\"; axis = \"y\"; }; };\n",
     NULL, "%F:16: analysis.period.observer: unknown observer 'top' (did you mean 'tip'?)"},
    {"duplicate observer", ");\n",
     ");\nobservers = ( { name = \"p\"; position = [1.0, 0.5]; },\n"
     "  { name = \"p\"; position = [0.0, 0.5]; } );\n",
     NULL, "%F:16: observers.[1].name: duplicate observer name 'p'"},
    /* round shapes and contact */
    {"annulus inner >= outer", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"annulus\"; centre = [0.5, 0.5]; inner_radius = 0.4; outer_radius = 0.3;", NULL,
     "%F:10: shapes.block.outer_radius: must exceed inner_radius = 0.4, got 0.3"},
    {"annulus inner = 0", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"annulus\"; centre = [0.5, 0.5]; inner_radius = 0; outer_radius = 0.3;", NULL,
     "%F:10: shapes.block.inner_radius: must be > 0, got 0"},
    {"disc radius 0", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"disc\"; centre = [0.5, 0.5]; radius = 0.0;", NULL,
     "%F:10: shapes.block.radius: must be > 0, got 0"},
    {"disc radius < 0", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"disc\"; centre = [0.5, 0.5]; radius = -1;", NULL,
     "%F:10: shapes.block.radius: must be > 0, got -1"},
    {"disc without radius", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"disc\"; centre = [0.5, 0.5];", NULL,
     "%F:10: shapes.block.radius: missing required key"},
    {"disc centre of 3 numbers", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"disc\"; centre = [0.5, 0.5, 0.0]; radius = 0.5;", NULL,
     "%F:10: shapes.block.centre: expected a vector of 2 numbers, got 3 elements"},
    {"annulus with radius", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"annulus\"; centre = [0.5, 0.5]; radius = 0.5;", NULL,
     "%F:10: shapes.block.radius: unknown key 'radius'"},
    {"ball in 2D", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"ball\"; centre = [0.5, 0.5]; radius = 0.5;", NULL,
     "%F:10: shapes.block.type: \"ball\" is a 3D shape; in 2D use \"disc\""},
    {"hollow sphere in 2D", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"hollow_sphere\"; centre = [0.5, 0.5]; inner_radius = 0.1; outer_radius = 0.5;", NULL,
     "%F:10: shapes.block.type: \"hollow_sphere\" is a 3D shape; in 2D use \"annulus\""},
    {"cylinder in 2D", "type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
     "type = \"cylinder\"; centre = [0.5, 0.5]; axis = [1.0, 0.0, 0.0]; radius = 0.5; length = "
     "1.0;",
     NULL, "%F:10: shapes.block.type: \"cylinder\" is a 3D shape"},
    {"contact with one body", "shape = \"block\"; }\n);\n",
     "shape = \"block\"; }\n);\ncontact = { penalty = 2.0; };\n", NULL,
     "%F:15: contact: contact acts between bodies or against walls, and the scene has one body and "
     "no wall"},
    {"contact penalty < 0",
     "};\nbodies = (\n  { name = \"a\"; material = \"steel\"; shape = \"block\"; }\n);\n",
     "  far = { type = \"disc\"; centre = [3.0, 0.5]; radius = 0.5; };\n};\nbodies = (\n"
     "  { name = \"a\"; material = \"steel\"; shape = \"block\"; },\n"
     "  { name = \"b\"; material = \"steel\"; shape = \"far\"; }\n);\n"
     "contact = { penalty = -1.0; };\n",
     NULL, "%F:17: contact.penalty: must be in [0, 100], got -1"},
    {"contact unknown key",
     "};\nbodies = (\n  { name = \"a\"; material = \"steel\"; shape = \"block\"; }\n);\n",
     "  far = { type = \"disc\"; centre = [3.0, 0.5]; radius = 0.5; };\n};\nbodies = (\n"
     "  { name = \"a\"; material = \"steel\"; shape = \"block\"; },\n"
     "  { name = \"b\"; material = \"steel\"; shape = \"far\"; }\n);\n"
     "contact = { friction = 0.3; };\n",
     NULL, "%F:17: contact.friction: unknown key 'friction' (valid keys here: impedance, penalty)"},
    {"tlsph with two bodies",
     "};\nbodies = (\n  { name = \"a\"; material = \"steel\"; shape = \"block\"; }\n);\n",
     "  far = { type = \"disc\"; centre = [3.0, 0.5]; radius = 0.5; };\n};\nbodies = (\n"
     "  { name = \"a\"; material = \"steel\"; shape = \"block\"; },\n"
     "  { name = \"b\"; material = \"steel\"; shape = \"far\"; }\n);\n",
     "method={ formulation = \"tlsph\"; }",
     "method.formulation: \"tlsph\" runs scenes with one body (the scene has 2)"},
    /* overrides */
    {"--set without '='", NULL, NULL, "time.end", "--set time.end: expected key=value"},
    {"--set with an empty key", NULL, NULL, "=5", "--set =5: expected key=value"},
    {"--set to a missing parent", NULL, NULL, "solver.threads=4",
     "--set solver.threads=4: solver: no such setting"},
    {"--set through a missing list element", NULL, NULL, "bodies.nobody.material=steel",
     "--set bodies.nobody.material=steel: bodies.nobody: no such setting"},
    {"--set through a scalar", NULL, NULL, "dimension.x=1",
     "--set dimension.x=1: dimension: is an integer, not a group or list"},
    {"--set invalid value", NULL, NULL, "materials.steel.poisson_ratio=0.5",
     "--set materials.steel.poisson_ratio=0.5: materials.steel.poisson_ratio: must be in [0, "
     "0.5), got 0.5"},
    {"--set unknown key", NULL, NULL, "time.endd=2.0",
     "--set time.endd=2.0: time.endd: unknown key 'endd' (did you mean 'end'?)"},
    {"--set bare-word value", NULL, NULL, "method.formulation=bogus",
     "--set method.formulation=bogus: method.formulation: must be one of"},
    {"--set formulation without rotation", NULL, NULL, "method.formulation=enog",
     "--set method.formulation=enog: method.formulation: formulation \"enog\" conflicts with "
     "method.rotation = \"averaged\" (%F:4); add --set method.rotation=none"},
    {"--set an aggregate with a bad member", NULL, NULL,
     "bodies.a.initial_velocity={ type = \"uniform\"; vector = [1.0]; }",
     "--set bodies.a.initial_velocity={ type = \"uniform\"; vector = [1.0]; }: "
     "bodies.a.initial_velocity.vector: expected a vector of 2 numbers, got 1 element"},
    {"--set with an empty key component", NULL, NULL, "time..end=1.0",
     "--set time..end=1.0: the key has an empty component"},
    {"--set a mixed array", NULL, NULL, "shapes.block.upper=[1, 1.0]",
     "--set shapes.block.upper=[1, 1.0]: cannot parse the value: mismatched element type in "
     "array (write every number of an array as a decimal (0.0, not 0))"},
    {"--set the other resolution form", NULL, NULL, "resolution.ratio=10",
     "--set resolution.ratio=10: resolution.ratio: give either dp or reference_length and ratio"},
    {"--set a string into a float array", NULL, NULL, "shapes.block.upper.[0]=wide",
     "--set shapes.block.upper.[0]=wide: shapes.block.upper.[0]: every element of this array"},
    /* integers beyond 32 bits are read whole, not as their low 32 bits
     * (libconfig 1.5 would read 4294967298 as 2) */
    {"dimension beyond 32 bits", "dimension = 2;", "dimension = 4294967298;", NULL,
     "%F:2: dimension: must be 1, 2 or 3, got 4294967298"},
    {"dimension below -2^31", "dimension = 2;", "dimension = -4294967294;", NULL,
     "%F:2: dimension: must be 1, 2 or 3, got -4294967294"},
    {"dimension in hexadecimal beyond 32 bits", "dimension = 2;", "dimension = 0x100000002;", NULL,
     "%F:2: dimension: must be 1, 2 or 3, got 4294967298"},
    {"dimension with the 64-bit suffix", "dimension = 2;", "dimension = 4294967298L;", NULL,
     "%F:2: dimension: must be 1, 2 or 3, got 4294967298"},
    {"--set dimension beyond 32 bits", NULL, NULL, "dimension=4294967298",
     "--set dimension=4294967298: dimension: must be 1, 2 or 3, got 4294967298"},
    {"relaxation steps beyond 32 bits", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { steps = 4294967297; };", NULL,
     "%F:13: bodies.a.relaxation.steps: must be in [0, 1000000], got 4294967297"},
    {"relaxation seed below -2^31", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { seed = -2147483649; };", NULL,
     "%F:13: bodies.a.relaxation.seed: must be >= 0, got -2147483649"},
    {"relaxation seed -2^63", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { seed = -9223372036854775808; "
     "};",
     NULL, "%F:13: bodies.a.relaxation.seed: must be >= 0, got -9223372036854775808"},
    {"relaxation seed 2^64", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { seed = 18446744073709551616; "
     "};",
     NULL,
     "%F:13: bodies.a.relaxation.seed: expected a 64-bit integer (-9223372036854775808 to "
     "18446744073709551615), got 1.8446744073709552e+19"},
    {"relaxation seed beyond 64 bits in hexadecimal", "shape = \"block\";",
     "shape = \"block\"; placement = \"relaxed\"; relaxation = { seed = 0x10000000000000000; "
     "};",
     NULL, "%F:13: bodies.a.relaxation.seed: expected a 64-bit integer"},
    {"a number key given an integer beyond 32 bits", "poisson_ratio = 0.3",
     "poisson_ratio = 4294967296", NULL,
     "%F:7: materials.steel.poisson_ratio: must be in [0, 0.5), got 4.29497e+09"},
    {"--set a list index beyond 32 bits", NULL, NULL, "bodies.[4294967296].material=steel",
     "--set bodies.[4294967296].material=steel: bodies.[4294967296]: no such setting"},
    /* initial fields as expressions (host/setup/expression.c) */
    {"expression: syntax error", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"expression\"; x = \"sin(\"; };", NULL,
     "%F:13: bodies.a.initial_velocity.x: the expression \"sin(\": Unexpected end of "
     "expression"},
    {"expression: unknown variable", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"expression\"; y = \"2 * q\"; };", NULL,
     "%F:13: bodies.a.initial_velocity.y: the expression \"2 * q\": unknown variable 'q' "
     "(variables: x, y)"},
    {"expression: z in 2D", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"expression\"; x = \"z\"; };", NULL,
     "%F:13: bodies.a.initial_velocity.x: the expression \"z\": unknown variable 'z'"},
    {"expression: a z component in 2D", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"expression\"; z = \"1\"; };", NULL,
     "%F:13: bodies.a.initial_velocity.z: unknown key 'z' (valid keys here: type, x, y)"},
    {"expression: assignment", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"expression\"; x = \"x = 3\"; };", NULL,
     "%F:13: bodies.a.initial_velocity.x: the expression \"x = 3\": '=' at position 2: "
     "assignments are not allowed"},
    {"expression: two results", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"expression\"; x = \"x, y\"; };", NULL,
     "the expression \"x, y\": the expression has 2 comma-separated results"},
    {"expression: empty", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"expression\"; x = \"\"; };", NULL,
     "%F:13: bodies.a.initial_velocity.x: the expression \"\": the expression is empty"},
    {"expression: a control character", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"expression\"; x = \"1\\t+ x\"; };", NULL,
     "%F:13: bodies.a.initial_velocity.x: the expression \"1\\x09+ x\": byte \\x09 at position 1"},
    {"expression: a number", "shape = \"block\";",
     "shape = \"block\"; initial_velocity = { type = \"expression\"; x = 1.0; };", NULL,
     "%F:13: bodies.a.initial_velocity.x: expected a string, got a number"},
    {"constants: a variable's name", "dimension = 2;", "dimension = 2; constants = { y = 1.0; };",
     NULL, "%F:2: constants.y: 'y' is a variable of the expressions, not a constant"},
    {"constants: a function's name", "dimension = 2;", "dimension = 2; constants = { sin = 1.0; };",
     NULL, "%F:2: constants.sin: 'sin' is a function or constant of the expressions already"},
    {"constants: pi", "dimension = 2;", "dimension = 2; constants = { pi = 3.0; };", NULL,
     "%F:2: constants.pi: 'pi' is a function or constant of the expressions already"},
    {"constants: a '-' in the name", "dimension = 2;",
     "dimension = 2; constants = { u-max = 1.0; };", NULL,
     "%F:2: constants.u-max: a constant's name is a letter, then letters, digits or '_'"},
    {"constants: a string", "dimension = 2;", "dimension = 2; constants = { U = \"1\"; };", NULL,
     "%F:2: constants.U: expected a number, got a string"},
    /* fluid keys in a solid scene (seed 004 §3.1 is the eulerian formulations') */
    {"a fluid material with a solid formulation", "youngs_modulus = 2.0e11; poisson_ratio = 0.3;",
     "sound_speed = 1500.0;", NULL,
     "%F:7: materials.steel: a material without youngs_modulus is a fluid, which needs "
     "method.formulation \"eulerian-wc\" or \"eulerian-compressible\", got \"enog-a\""},
    {"viscosity in a solid material", "poisson_ratio = 0.3;",
     "poisson_ratio = 0.3; viscosity = 0.001;", NULL,
     "%F:7: materials.steel.viscosity: is for fluid materials"},
    {"gamma in a solid material", "poisson_ratio = 0.3;", "poisson_ratio = 0.3; gamma = 1.4;", NULL,
     "%F:7: materials.steel.gamma: is for fluid materials"},
    {"initial_density of a solid body", "shape = \"block\";",
     "shape = \"block\"; initial_density = 7800.0;", NULL,
     "%F:13: bodies.a.initial_density: is for fluid bodies (formulations \"eulerian-wc\" and "
     "\"eulerian-compressible\"); formulation \"enog-a\""},
    {"initial_pressure of a solid body", "shape = \"block\";",
     "shape = \"block\"; initial_pressure = \"1e5\";", NULL,
     "%F:13: bodies.a.initial_pressure: is for fluid bodies"},
    {"a periodic boundary in a solid scene", ");\n",
     ");\nboundary = { periodic = [\"x\"]; lower = [0.0, 0.0]; upper = [1.0, 1.0]; };\n", NULL,
     "%F:15: boundary: periodic boundaries are implemented for the eulerian formulations "
     "(\"eulerian-wc\", \"eulerian-compressible\"), got formulation \"enog-a\""},
    {"vorticity of a solid", ");\n", ");\noutput = { fields = [\"velocity\", \"vorticity\"]; };\n",
     NULL,
     "%F:15: output.fields.[1]: vorticity is a fluid field (formulations \"eulerian-wc\" and "
     "\"eulerian-compressible\"), and this scene's formulation is \"enog-a\""},
    {"mach_number of a solid", ");\n", ");\noutput = { fields = [\"mach_number\"]; };\n", NULL,
     "%F:15: output.fields.[0]: mach_number is a fluid field"},
    /* the flow around a cylinder's keys (seed 004 §4.3) are the fluids' */
    {"role wall in a solid scene", "shape = \"block\";", "shape = \"block\"; role = \"wall\";",
     NULL,
     "%F:13: bodies.a.role: is for the bodies of fluid scenes (formulations \"eulerian-wc\" and "
     "\"eulerian-compressible\"): a body there is matter or a wall; formulation \"enog-a\""},
    {"role matter in a solid scene", "shape = \"block\";", "shape = \"block\"; role = \"matter\";",
     NULL, "%F:13: bodies.a.role: is for the bodies of fluid scenes"},
    {"spacing in a solid scene", "shape = \"block\";", "shape = \"block\"; spacing = 1.0;", NULL,
     "%F:13: bodies.a.spacing: is for the bodies of fluid scenes"},
    {"a far field in a solid scene", ");\n",
     ");\nboundary = { far_field = { velocity = [1.0, 0.0]; }; lower = [0.0, 0.0]; upper = [1.0, "
     "1.0]; };\n",
     NULL,
     "%F:15: boundary: a far field is implemented for the eulerian formulations "
     "(\"eulerian-wc\"), got formulation \"enog-a\""},
    {"forces in a solid scene", ");\n", ");\nforces = { reference_length = 1.0; };\n", NULL,
     "%F:15: forces: is for the wall bodies of fluid scenes (formulation \"eulerian-wc\"), got "
     "formulation \"enog-a\""},
};

/* A small valid fluid scene (seed 004 §3.1, the weakly compressible
 * formulation, periodic along x and y); FLUID_BAD edits it. */
static const char FLUID_BASE[] =
    "# fluid test scene\n"                                                                  /*  1 */
    "dimension = 2;\n"                                                                      /*  2 */
    "resolution = { dp = 0.1; };\n"                                                         /*  3 */
    "method = { formulation = \"eulerian-wc\"; };\n"                                        /*  4 */
    "time = { end = 1.0; output_interval = 0.1; };\n"                                       /*  5 */
    "materials = {\n"                                                                       /*  6 */
    "  water = { density = 1.0; sound_speed = 10.0; viscosity = 0.01; };\n"                 /*  7 */
    "};\n"                                                                                  /*  8 */
    "shapes = {\n"                                                                          /*  9 */
    "  box = { type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0]; };\n"                /* 10 */
    "};\n"                                                                                  /* 11 */
    "bodies = (\n"                                                                          /* 12 */
    "  { name = \"f\"; material = \"water\"; shape = \"box\"; }\n"                          /* 13 */
    ");\n"                                                                                  /* 14 */
    "boundary = { periodic = [\"x\", \"y\"]; lower = [0.0, 0.0]; upper = [1.0, 1.0]; };\n"; /* 15 */

/* A fluid on a line (dimension 1: the fluid formulations only), periodic
 * along x; LINE_BAD edits it. */
static const char LINE_BASE[] =
    "# fluid line test scene\n"                                                /*  1 */
    "dimension = 1;\n"                                                         /*  2 */
    "resolution = { dp = 0.1; };\n"                                            /*  3 */
    "method = { formulation = \"eulerian-wc\"; };\n"                           /*  4 */
    "time = { end = 1.0; output_interval = 0.1; };\n"                          /*  5 */
    "materials = { water = { density = 1.0; sound_speed = 10.0; }; };\n"       /*  6 */
    "shapes = { box = { type = \"box\"; lower = [0.0]; upper = [1.0]; }; };\n" /*  7 */
    "bodies = ( { name = \"f\"; material = \"water\"; shape = \"box\";\n"      /*  8 */
    "             initial_density = \"1 + 0.01 * x\"; } );\n"                  /*  9 */
    "boundary = { periodic = [\"x\"]; lower = [0.0]; upper = [1.0]; };\n";     /* 10 */

static const bad_row LINE_BAD[] = {
    {"line: a disc", "type = \"box\"; lower = [0.0]; upper = [1.0];",
     "type = \"disc\"; centre = [0.5]; radius = 0.5;", NULL,
     "%F:7: shapes.box.type: \"disc\" is a 2D shape; a line (dimension 1) is made of \"box\"es"},
    {"line: a y axis", "periodic = [\"x\"];", "periodic = [\"y\"];", NULL,
     "%F:10: boundary.periodic.[0]: expected \"x\", got y"},
    {"line: a 2D vector", "upper = [1.0]; };\n", "upper = [1.0, 1.0]; };\n", NULL,
     "%F:10: boundary.upper: expected a vector of 1 numbers, got 2 elements"},
    {"line: vorticity", "output_interval = 0.1; };",
     "output_interval = 0.1; };\noutput = { fields = [\"vorticity\"]; };", NULL,
     "%F:6: output.fields.[0]: vorticity is a field of 2D and 3D flows; a line (dimension 1) has "
     "none"},
    {"line: relaxed", "shape = \"box\";", "shape = \"box\"; placement = \"relaxed\";", NULL,
     "%F:8: bodies.f.placement: a line (dimension 1) is its lattice: there is nothing to relax"},
    {"line: a wall body", "shape = \"box\";", "shape = \"box\"; role = \"wall\";", NULL,
     "%F:8: bodies.f.role: a line (dimension 1) has no wall bodies"},
    {"line: a far field", "periodic = [\"x\"];",
     "far_field = { density = 1.0; velocity = [1.0]; };", NULL,
     "%F:10: boundary.far_field: a line (dimension 1) has no far field here"},
    {"line: a rotation", "initial_density = \"1 + 0.01 * x\";",
     "initial_velocity = { type = \"rigid_rotation\"; omega = 1.0; };", NULL,
     "%F:9: bodies.f.initial_velocity.type: a line (dimension 1) does not turn or bend"},
    {"line: a y velocity", "initial_density = \"1 + 0.01 * x\";",
     "initial_velocity = { type = \"expression\"; x = \"1\"; y = \"1\"; };", NULL,
     "%F:9: bodies.f.initial_velocity.y: unknown key"},
};

/* the ideal gas of eulerian-compressible in FLUID_BASE: formulation, material, body */
#define GAS_FORMULATION "formulation = \"eulerian-compressible\";"
#define GAS_MATERIAL    "water = { density = 1.0; gamma = 1.4; };"
#define GAS_BODY        "shape = \"box\"; initial_pressure = 71.43;"

static const bad_row FLUID_BAD[] = {
    /* method */
    {"eulerian with a rotation", "formulation = \"eulerian-wc\";",
     "formulation = \"eulerian-wc\"; rotation = \"averaged\";", NULL,
     "%F:4: method.rotation: formulation \"eulerian-wc\" has no rotation correction, so rotation "
     "must be \"none\""},
    {"eulerian with xi_e", "formulation = \"eulerian-wc\";",
     "formulation = \"eulerian-wc\"; xi_e = 3.5;", NULL,
     "%F:4: method.xi_e: is for the solid formulations; formulation \"eulerian-wc\" simulates a "
     "fluid"},
    {"eulerian with xi_g", "formulation = \"eulerian-wc\";",
     "formulation = \"eulerian-wc\"; xi_g = 2.0;", NULL, "%F:4: method.xi_g: is for the solid"},
    {"eulerian with hourglass_alpha", "formulation = \"eulerian-wc\";",
     "formulation = \"eulerian-wc\"; hourglass_alpha = 0.1;", NULL,
     "%F:4: method.hourglass_alpha: is for the solid formulations"},
    {"eulerian with artificial_stress", "formulation = \"eulerian-wc\";",
     "formulation = \"eulerian-wc\"; artificial_stress = { epsilon = 0.3; };", NULL,
     "%F:4: method.artificial_stress: is for the solid formulations"},
    {"eulerian with torque_projection", "formulation = \"eulerian-wc\";",
     "formulation = \"eulerian-wc\"; torque_projection = false;", NULL,
     "%F:4: method.torque_projection: is for the solid formulations"},
    {"eulerian: a negative limiter", "formulation = \"eulerian-wc\";",
     "formulation = \"eulerian-wc\"; riemann_limiter = -1.0;", NULL,
     "%F:4: method.riemann_limiter: must be >= 0, got -1"},
    {"eulerian: an unknown viscous regularization", "formulation = \"eulerian-wc\";",
     "formulation = \"eulerian-wc\"; viscous_regularization = \"cubic\";", NULL,
     "%F:4: method.viscous_regularization: must be one of \"squared\", \"linear\", got "
     "\"cubic\""},
    /* time */
    {"eulerian with dual stepping", "end = 1.0;", "end = 1.0; stepping = \"dual\";", NULL,
     "%F:5: time.stepping: formulation \"eulerian-wc\" keeps its particles fixed: there is no "
     "advection step"},
    {"eulerian with cfl_advection", "end = 1.0;", "end = 1.0; cfl_advection = 0.2;", NULL,
     "%F:5: time.cfl_advection: is for the formulations whose particles move"},
    {"eulerian: an unknown integrator", "end = 1.0;", "end = 1.0; integrator = \"rk4\";", NULL,
     "%F:5: time.integrator: must be one of \"two-stage\", \"ssp-rk2\", \"ssp-rk3\", got "
     "\"rk4\""},
    {"eulerian with frozen_geometry", "end = 1.0;", "end = 1.0; frozen_geometry = \"start\";", NULL,
     "%F:5: time.frozen_geometry: is for the formulations whose particles move"},
    {"eulerian with acceleration_criterion", "end = 1.0;",
     "end = 1.0; acceleration_criterion = true;", NULL,
     "%F:5: time.acceleration_criterion: is for the formulations whose particles move"},
    /* materials */
    {"a solid material with eulerian-wc", "sound_speed = 10.0;",
     "youngs_modulus = 1.0e6; poisson_ratio = 0.3;", NULL,
     "%F:7: materials.water.youngs_modulus: material 'water' is a solid (it has a youngs_modulus), "
     "and formulation \"eulerian-wc\" simulates a fluid"},
    {"several materials", "};\nshapes",
     "  oil = { density = 0.9; sound_speed = 10.0; };\n};\nshapes", NULL,
     "%F:6: materials: several materials (2) are not supported for the eulerian formulations yet"},
    {"fluid without density", "density = 1.0; ", "", NULL,
     "%F:7: materials.water.density: missing required key"},
    {"fluid density 0", "density = 1.0;", "density = 0.0;", NULL,
     "%F:7: materials.water.density: must be > 0, got 0"},
    {"weakly compressible fluid without sound_speed", "sound_speed = 10.0; ", "", NULL,
     "%F:7: materials.water.sound_speed: missing required key"},
    {"weakly compressible fluid with sound_speed 0", "sound_speed = 10.0;", "sound_speed = 0.0;",
     NULL, "%F:7: materials.water.sound_speed: must be > 0, got 0"},
    {"negative viscosity", "viscosity = 0.01;", "viscosity = -0.01;", NULL,
     "%F:7: materials.water.viscosity: must be >= 0, got -0.01"},
    {"poisson_ratio of a fluid", "viscosity = 0.01;", "viscosity = 0.01; poisson_ratio = 0.3;",
     NULL,
     "%F:7: materials.water.poisson_ratio: is for solid materials; material 'water' is a fluid "
     "(it has no youngs_modulus), as formulation \"eulerian-wc\" needs"},
    {"yield_stress of a fluid", "viscosity = 0.01;", "viscosity = 0.01; yield_stress = 1.0;", NULL,
     "%F:7: materials.water.yield_stress: is for solid materials"},
    {"gamma with eulerian-wc", "viscosity = 0.01;", "viscosity = 0.01; gamma = 1.4;", NULL,
     "%F:7: materials.water.gamma: is the ideal gas's ratio of specific heats (formulation "
     "\"eulerian-compressible\")"},
    /* bodies */
    {"initial_pressure with eulerian-wc", "shape = \"box\";",
     "shape = \"box\"; initial_pressure = 1.0;", NULL,
     "%F:13: bodies.f.initial_pressure: formulation \"eulerian-wc\" derives the pressure from the "
     "density, p = c0^2 (rho - rho0)"},
    {"initial_density 0", "shape = \"box\";", "shape = \"box\"; initial_density = 0;", NULL,
     "%F:13: bodies.f.initial_density: an initial density must be > 0, got 0"},
    {"initial_density < 0", "shape = \"box\";", "shape = \"box\"; initial_density = -1.5;", NULL,
     "%F:13: bodies.f.initial_density: an initial density must be > 0, got -1.5"},
    {"initial_density a boolean", "shape = \"box\";", "shape = \"box\"; initial_density = true;",
     NULL,
     "%F:13: bodies.f.initial_density: expected a number or an expression string of x, y and the "
     "constants, got a boolean"},
    {"initial_density: syntax error", "shape = \"box\";",
     "shape = \"box\"; initial_density = \"1 +\";", NULL,
     "%F:13: bodies.f.initial_density: the expression \"1 +\": "},
    {"initial_density: unknown variable", "shape = \"box\";",
     "shape = \"box\"; initial_density = \"1 + q\";", NULL,
     "%F:13: bodies.f.initial_density: the expression \"1 + q\": unknown variable 'q'"},
    {"a velocity constraint on a fluid body", "shape = \"box\";",
     "shape = \"box\"; constraints = ( { type = \"velocity\"; region = \"box\"; } );", NULL,
     "%F:13: bodies.f.constraints.[0].type: a fluid body takes constraints of type \"fixed\" "
     "only"},
    /* walls, contact, output */
    {"walls in a fluid scene", ");\nboundary",
     ");\nwalls = ( { name = \"w\"; point = [0.0, 0.0]; normal = [0.0, 1.0]; } );\nboundary", NULL,
     "%F:15: walls: walls are not supported for the eulerian formulations yet"},
    {"contact in a fluid scene", ");\nboundary", ");\ncontact = { impedance = 1.0; };\nboundary",
     NULL, "%F:15: contact: is for the solid formulations"},
    {"displacement of a fluid", ");\nboundary",
     ");\noutput = { fields = [\"velocity\", \"displacement\"]; };\nboundary", NULL,
     "%F:15: output.fields.[1]: displacement is a field of the solid formulations; formulation "
     "\"eulerian-wc\" keeps its particles fixed"},
    {"von_mises of a fluid", ");\nboundary",
     ");\noutput = { fields = [\"von_mises\"]; };\nboundary", NULL,
     "%F:15: output.fields.[0]: von_mises is a field of the solid formulations"},
    {"mach_number with eulerian-wc", ");\nboundary",
     ");\noutput = { fields = [\"mach_number\"]; };\nboundary", NULL,
     "%F:15: output.fields.[0]: mach_number is a field of formulation \"eulerian-compressible\""},
    /* the periodic boundary */
    {"period not a whole number of dp", "\"y\"]; lower = [0.0, 0.0]; upper = [1.0, 1.0]",
     "\"y\"]; lower = [0.0, 0.0]; upper = [1.05, 1.0]", NULL,
     "%F:15: boundary.upper: the period along x, upper - lower = 1.05, must be a whole number of "
     "particle spacings (dp = 0.1), got 10.5 dp"},
    {"period shorter than two cut-offs", "\"y\"]; lower = [0.0, 0.0]; upper = [1.0, 1.0]",
     "\"y\"]; lower = [0.0, 0.0]; upper = [1.0, 0.5]", NULL,
     "%F:15: boundary.upper: the period along y (0.5) is shorter than two cut-off radii (2 x 2.6 "
     "dp = 0.52): a particle would meet a neighbour through two images"},
    {"period upper <= lower", "\"y\"]; lower = [0.0, 0.0]; upper = [1.0, 1.0]",
     "\"y\"]; lower = [0.0, 0.0]; upper = [0.0, 1.0]", NULL,
     "%F:15: boundary.upper: must exceed lower along the periodic axis x, got upper = 0, lower = "
     "0"},
    {"periodic axis z in 2D", "periodic = [\"x\", \"y\"]", "periodic = [\"z\"]", NULL,
     "%F:15: boundary.periodic.[0]: expected \"x\" or \"y\", got z"},
    {"periodic axis twice", "periodic = [\"x\", \"y\"]", "periodic = [\"x\", \"x\"]", NULL,
     "%F:15: boundary.periodic.[1]: axis \"x\" named twice"},
    {"periodic without lower", "\"y\"]; lower = [0.0, 0.0];", "\"y\"];", NULL,
     "%F:15: boundary.lower: missing required key"},
    {"boundary with an unknown key", "periodic = [", "periods = [", NULL,
     "%F:15: boundary.periods: unknown key 'periods' (did you mean 'periodic'?)"},
    {"periodic with a relaxed body", "shape = \"box\";",
     "shape = \"box\"; placement = \"relaxed\";", NULL,
     "%F:13: bodies.f.placement: a relaxed placement is not supported with a periodic boundary"},
    /* the ideal gas (eulerian-compressible) */
    {"gas with sound_speed", "formulation = \"eulerian-wc\";", GAS_FORMULATION, NULL,
     "%F:7: materials.water.sound_speed: an ideal gas's sound speed follows from its state, "
     "c = sqrt(gamma p / rho)"},
};

/* The flow around a cylinder (seed 004 §4.3) in small: a far field on
 * the four faces of the box, a wall body (a disc at dp/2), the forces on
 * it; CYL_BAD edits it. */
static const char CYL_BASE[] =
    "# cylinder test scene\n"                                                /*  1 */
    "dimension = 2;\n"                                                       /*  2 */
    "resolution = { dp = 0.1; };\n"                                          /*  3 */
    "method = { formulation = \"eulerian-wc\"; };\n"                         /*  4 */
    "time = { end = 1.0; output_interval = 0.1; };\n"                        /*  5 */
    "materials = {\n"                                                        /*  6 */
    "  water = { density = 1.0; sound_speed = 10.0; viscosity = 0.02; };\n"  /*  7 */
    "};\n"                                                                   /*  8 */
    "shapes = {\n"                                                           /*  9 */
    "  box = { type = \"box\"; lower = [0.0, 0.0]; upper = [6.0, 4.0]; };\n" /* 10 */
    "  disc = { type = \"disc\"; centre = [2.0, 2.0]; radius = 0.5; };\n"    /* 11 */
    "};\n"                                                                   /* 12 */
    "bodies = (\n"                                                           /* 13 */
    "  { name = \"f\"; material = \"water\"; shape = \"box\"; },\n"          /* 14 */
    "  { name = \"cyl\"; role = \"wall\"; shape = \"disc\"; }\n"             /* 15 */
    ");\n"                                                                   /* 16 */
    "boundary = { far_field = { density = 1.0; velocity = [1.0, 0.0]; };\n"  /* 17 */
    "             lower = [0.0, 0.0]; upper = [6.0, 4.0]; };\n"              /* 18 */
    "forces = { reference_length = 1.0; };\n";                               /* 19 */

static const bad_row CYL_BAD[] = {
    /* role */
    {"role: an unknown word", "role = \"wall\";", "role = \"solid\";", NULL,
     "%F:15: bodies.cyl.role: must be one of \"matter\", \"wall\", got \"solid\""},
    {"role: not a string", "role = \"wall\";", "role = 1;", NULL,
     "%F:15: bodies.cyl.role: expected a string, got an integer"},
    {"only walls", "name = \"f\"; material", "name = \"f\"; role = \"wall\"; material", NULL,
     "%F:13: bodies: every body is a wall (role = \"wall\"): a fluid scene needs at least one "
     "matter body"},
    {"a wall with an unknown material", "role = \"wall\";",
     "role = \"wall\"; material = \"steel\";", NULL,
     "%F:15: bodies.cyl.material: unknown material 'steel'"},
    {"a matter body without material", "material = \"water\"; shape = \"box\";", "shape = \"box\";",
     NULL, "%F:14: bodies.f.material: missing required key"},
    {"a moving wall", "shape = \"disc\";",
     "shape = \"disc\"; initial_velocity = { type = \"uniform\"; vector = [1.0, 0.0]; };", NULL,
     "%F:15: bodies.cyl.initial_velocity: body 'cyl' is a wall (role = \"wall\"): a wall is at "
     "rest in the fluid's reference state"},
    {"a wall's initial_density", "shape = \"disc\";", "shape = \"disc\"; initial_density = 1.1;",
     NULL, "%F:15: bodies.cyl.initial_density: body 'cyl' is a wall"},
    {"a wall's initial_pressure", "shape = \"disc\";", "shape = \"disc\"; initial_pressure = 1.0;",
     NULL, "%F:15: bodies.cyl.initial_pressure: body 'cyl' is a wall"},
    {"a wall's constraints", "shape = \"disc\";",
     "shape = \"disc\"; constraints = ( { type = \"fixed\"; region = \"disc\"; } );", NULL,
     "%F:15: bodies.cyl.constraints: body 'cyl' is a wall"},
    /* spacing */
    {"spacing 0", "shape = \"disc\";", "shape = \"disc\"; spacing = 0.0;", NULL,
     "%F:15: bodies.cyl.spacing: the body's particle spacing over dp must be in (0, 1], got 0"},
    {"spacing above 1", "shape = \"disc\";", "shape = \"disc\"; spacing = 1.5;", NULL,
     "%F:15: bodies.cyl.spacing: the body's particle spacing over dp must be in (0, 1], got 1.5"},
    {"spacing negative", "shape = \"disc\";", "shape = \"disc\"; spacing = -0.5;", NULL,
     "%F:15: bodies.cyl.spacing: the body's particle spacing over dp must be in (0, 1], got -0.5"},
    {"spacing a string", "shape = \"disc\";", "shape = \"disc\"; spacing = \"half\";", NULL,
     "%F:15: bodies.cyl.spacing: expected a number, got a string"},
    {"a matter body's spacing", "shape = \"box\";", "shape = \"box\"; spacing = 0.5;", NULL,
     "%F:14: bodies.f.spacing: a matter body is placed on the scene's lattice (spacing 1, dp "
     "apart); other spacings are for wall bodies (role = \"wall\") for now, got 0.5"},
    /* the far field */
    {"far field without velocity", "density = 1.0; velocity = [1.0, 0.0]; }", "density = 1.0; }",
     NULL, "%F:17: boundary.far_field.velocity: missing required key"},
    {"far field velocity of the wrong dimension", "velocity = [1.0, 0.0]",
     "velocity = [1.0, 0.0, 0.0]", NULL,
     "%F:17: boundary.far_field.velocity: expected a vector of 2 numbers, got 3 elements"},
    {"far field density 0", "far_field = { density = 1.0;", "far_field = { density = 0.0;", NULL,
     "%F:17: boundary.far_field.density: must be > 0, got 0"},
    {"far field with an unknown key", "far_field = { density",
     "far_field = { temperature = 1.0; density", NULL,
     "%F:17: boundary.far_field.temperature: unknown key 'temperature' (valid keys here: "
     "density, velocity, pressure)"},
    {"far field pressure in the WC formulation", "far_field = { density",
     "far_field = { pressure = 1.0; density", NULL,
     "%F:17: boundary.far_field.pressure: formulation \"eulerian-wc\" derives the free stream's "
     "pressure from its density"},
    {"background_pressure in the WC formulation", "formulation = \"eulerian-wc\";",
     "formulation = \"eulerian-wc\"; background_pressure = 1.0;", NULL,
     "%F:4: method.background_pressure: is for the ideal gas (formulation "
     "\"eulerian-compressible\"); formulation \"eulerian-wc\" has p = c0^2 (rho - rho0), "
     "already 0 at rest"},
    {"far field not a group", "far_field = { density = 1.0; velocity = [1.0, 0.0]; };",
     "far_field = 1.0;", NULL, "%F:17: boundary.far_field: expected a group { ... }, got a number"},
    {"far field without lower", "lower = [0.0, 0.0]; upper = [6.0, 4.0]; };\nforces",
     "upper = [6.0, 4.0]; };\nforces", NULL, "%F:17: boundary.lower: missing required key"},
    {"far field box upper <= lower", "upper = [6.0, 4.0]; };\nforces",
     "upper = [6.0, 0.0]; };\nforces", NULL,
     "%F:18: boundary.upper: must exceed lower along y (the far field's box [lower, upper]), got "
     "upper = 0, lower = 0"},
    {"far field with every axis periodic", "boundary = { far_field",
     "boundary = { periodic = [\"x\", \"y\"]; far_field", NULL,
     "%F:17: boundary.far_field: the far field acts on the faces across the axes that are not "
     "periodic, and every axis is periodic"},
    {"boundary with neither periodic nor far_field",
     "far_field = { density = 1.0; velocity = [1.0, 0.0]; };", "", NULL,
     "%F:17: boundary.periodic: missing required key: a boundary has periodic axes (periodic), a "
     "far field (far_field) or both"},
    /* forces */
    {"forces without reference_length", "forces = { reference_length = 1.0; };",
     "forces = { window = 1.0; };", NULL, "%F:19: forces.reference_length: missing required key"},
    {"forces: reference_length 0", "reference_length = 1.0;", "reference_length = 0.0;", NULL,
     "%F:19: forces.reference_length: must be > 0, got 0"},
    {"forces: reference_density < 0", "reference_length = 1.0;",
     "reference_length = 1.0; reference_density = -1.0;", NULL,
     "%F:19: forces.reference_density: must be > 0, got -1"},
    {"forces: reference_speed 0", "reference_length = 1.0;",
     "reference_length = 1.0; reference_speed = 0.0;", NULL,
     "%F:19: forces.reference_speed: must be > 0, got 0"},
    {"forces: a negative window", "reference_length = 1.0;",
     "reference_length = 1.0; window = -1.0;", NULL, "%F:19: forces.window: must be >= 0, got -1"},
    {"forces: an unknown key", "reference_length = 1.0;", "reference_lenght = 1.0;", NULL,
     "%F:19: forces.reference_lenght: unknown key 'reference_lenght' (did you mean "
     "'reference_length'?)"},
    {"forces without a wall body", "role = \"wall\"; shape = \"disc\";",
     "material = \"water\"; shape = \"disc\";", NULL,
     "%F:19: forces: the forces are those the fluid exerts on the wall bodies, and the scene has "
     "none"},
    {"forces: no default reference speed (a still far field)", "velocity = [1.0, 0.0]",
     "velocity = [0.0, 0.0]", NULL,
     "%F:19: forces.reference_speed: missing required key: the far field's velocity is 0"},
    {"walls (planes) in a fluid scene", ");\nboundary",
     ");\nwalls = ( { name = \"w\"; point = [0.0, 0.0]; normal = [0.0, 1.0]; } );\nboundary", NULL,
     "%F:17: walls: walls are not supported for the eulerian formulations yet (formulation "
     "\"eulerian-wc\"); a fluid scene is bounded by its periodic boundary, a far field "
     "(boundary.far_field) or wall bodies (bodies.X.role = \"wall\")"},
};

/* edits applied in order before a FLUID_GAS row's own (the compressible
 * scene): formulation, material, body */
static const char *const GAS_EDITS[3][2] = {
    {"formulation = \"eulerian-wc\";", GAS_FORMULATION},
    {"water = { density = 1.0; sound_speed = 10.0; viscosity = 0.01; };", GAS_MATERIAL},
    {"shape = \"box\";", GAS_BODY},
};

static const bad_row GAS_BAD[] = {
    {"gamma 0.9", "gamma = 1.4;", "gamma = 0.9;", NULL,
     "%F:7: materials.water.gamma: an ideal gas has 1 < gamma <= 5/3 (5/3: monatomic, 7/5: "
     "diatomic such as air), got 0.9"},
    {"gamma 1", "gamma = 1.4;", "gamma = 1.0;", NULL,
     "%F:7: materials.water.gamma: an ideal gas has 1 < gamma <= 5/3"},
    {"gamma 2", "gamma = 1.4;", "gamma = 2.0;", NULL,
     "%F:7: materials.water.gamma: an ideal gas has 1 < gamma <= 5/3 (5/3: monatomic, 7/5: "
     "diatomic such as air), got 2"},
    {"gamma a string", "gamma = 1.4;", "gamma = \"air\";", NULL,
     "%F:7: materials.water.gamma: expected a number, got a string"},
    {"gas with sound_speed", "gamma = 1.4;", "gamma = 1.4; sound_speed = 340.0;", NULL,
     "%F:7: materials.water.sound_speed: an ideal gas's sound speed follows from its state"},
    {"gas without initial_pressure", " initial_pressure = 71.43;", "", NULL,
     "%F:13: bodies.f.initial_pressure: missing required key: the ideal gas of formulation "
     "\"eulerian-compressible\" starts from a pressure"},
    {"initial_pressure 0", "initial_pressure = 71.43;", "initial_pressure = 0.0;", NULL,
     "%F:13: bodies.f.initial_pressure: an initial pressure must be > 0, got 0"},
    {"initial_pressure: unknown variable", "initial_pressure = 71.43;",
     "initial_pressure = \"p0 * x\";", NULL,
     "%F:13: bodies.f.initial_pressure: the expression \"p0 * x\": unknown variable 'p0'"},
    {"far field: a gas without p_inf", "boundary = { periodic = [\"x\", \"y\"];",
     "boundary = { periodic = [\"x\"]; far_field = { velocity = [1.0, 0.0]; };", NULL,
     "%F:15: boundary.far_field.pressure: missing required key: the ideal gas of formulation "
     "\"eulerian-compressible\" needs the free stream's pressure p_inf"},
    {"far field: p_inf 0", "boundary = { periodic = [\"x\", \"y\"];",
     "boundary = { periodic = [\"x\"]; far_field = { velocity = [1.0, 0.0]; pressure = 0.0; };",
     NULL, "%F:15: boundary.far_field.pressure: must be > 0, got 0"},
    {"far field: a supersonic free stream", "boundary = { periodic = [\"x\", \"y\"];",
     "boundary = { periodic = [\"x\"]; far_field = { velocity = [12.0, 0.0]; pressure = 71.43; "
     "};",
     NULL,
     "%F:15: boundary.far_field.velocity: the far field is a subsonic treatment: the free "
     "stream's Mach number |U_inf| / c_inf = 12 / 10.0001 = 1.19999 must be below 1"},
    {"a gas bounded by a wall without p_b", "shape = \"box\"; initial_pressure = 71.43; }",
     "shape = \"box\"; initial_pressure = 71.43; },\n  { name = \"w\"; role = \"wall\"; shape "
     "= \"box\"; }",
     NULL,
     "%F:4: method.background_pressure: missing required key: a gas bounded by wall body 'w' "
     "without a far field needs the pressure p_b its momentum fluxes are taken relative to"},
    {"background_pressure negative", GAS_FORMULATION,
     "formulation = \"eulerian-compressible\"; background_pressure = -1.0;", NULL,
     "%F:4: method.background_pressure: must be >= 0, got -1"},
    {"mach_number is fine, displacement is not", ");\nboundary",
     ");\noutput = { fields = [\"mach_number\", \"displacement\"]; };\nboundary", NULL,
     "%F:15: output.fields.[1]: displacement is a field of the solid formulations; formulation "
     "\"eulerian-compressible\" keeps its particles fixed and has no stress deviator (fluid "
     "fields: velocity, density, pressure, vorticity, body_id, particle_id, mach_number)"},
};

/* Replace the first `find` in `text` by `replace`. */
static void edit(const char *text, const char *find, const char *replace, char *out, size_t size) {
    const char *at = strstr(text, find);
    if (!at) {
        fprintf(stderr, "test table: '%s' not in BASE\n", find);
        exit(2);
    }
    snprintf(out, size, "%.*s%s%s", (int)(at - text), text, replace, at + strlen(find));
}

/* Expand %F to the file name. */
static void expand(const char *pattern, const char *file, char *out, size_t size) {
    size_t len = 0;
    for (const char *p = pattern; *p && len + 1 < size; p++) {
        if (p[0] == '%' && p[1] == 'F') {
            len += (size_t)snprintf(out + len, size - len, "%s", file);
            p++;
        } else {
            out[len++] = *p;
        }
    }
    out[len < size ? len : size - 1] = '\0';
}

/* Every row of `rows`, an edit of `base`: SPH_ERR_INPUT with the expected
 * text in a one-line message. */
static void run_bad_rows(test_counts *c, const char *base, const bad_row *rows, size_t nrows) {
    char base_path[1024];
    test_scene_write(&tmp, base, base_path, sizeof base_path);
    sph_scene s;
    sph_error err = {0};
    sph_status st = sph_scene_load(&s, base_path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "the base scene must load: %s", err.msg);
    sph_scene_free(&s);

    for (size_t i = 0; i < nrows; i++) {
        const bad_row *row = &rows[i];
        char path[1024], text[4096], expect[2048];
        if (row->find) {
            edit(base, row->find, row->replace, text, sizeof text);
            test_scene_write(&tmp, text, path, sizeof path);
        } else {
            snprintf(path, sizeof path, "%s", base_path);
        }
        const char *ov[1] = {row->set};
        memset(&err, 0, sizeof err);
        st = sph_scene_load(&s, path, ov, row->set ? 1 : 0, &err);
        expand(row->expect, path, expect, sizeof expect);
        if (getenv("SPH_TEST_VERBOSE")) printf("%-40s %s\n", row->what, err.msg);
        CHECK(c, st == SPH_ERR_INPUT, "%s: status %d (message '%s')", row->what, st, err.msg);
        CHECK(c, err.code == SPH_ERR_INPUT, "%s: err.code %d", row->what, err.code);
        CHECK(c, strstr(err.msg, expect) != NULL, "%s:\n  got      '%s'\n  expected '%s'",
              row->what, err.msg, expect);
        /* a value from an override is reported as the override */
        if (row->set && strncmp(row->expect, "--set", 5) == 0)
            CHECK(c, strncmp(err.msg, "--set ", 6) == 0, "%s: '%s' must start with --set",
                  row->what, err.msg);
        CHECK(c, s.resolved_text == NULL, "%s: nothing to free after a failure", row->what);
        CHECK(c, strchr(err.msg, '\n') == NULL, "%s: one line", row->what);
    }
}

static void test_bad_inputs(test_counts *c) {
    run_bad_rows(c, BASE, BAD, sizeof BAD / sizeof BAD[0]);
    run_bad_rows(c, FLUID_BASE, FLUID_BAD, sizeof FLUID_BAD / sizeof FLUID_BAD[0]);
    run_bad_rows(c, LINE_BASE, LINE_BAD, sizeof LINE_BAD / sizeof LINE_BAD[0]);
    run_bad_rows(c, CYL_BASE, CYL_BAD, sizeof CYL_BAD / sizeof CYL_BAD[0]);
    char gas[4096], step[4096];
    snprintf(gas, sizeof gas, "%s", FLUID_BASE);
    for (int k = 0; k < 3; ++k) {
        edit(gas, GAS_EDITS[k][0], GAS_EDITS[k][1], step, sizeof step);
        snprintf(gas, sizeof gas, "%s", step);
    }
    run_bad_rows(c, gas, GAS_BAD, sizeof GAS_BAD / sizeof GAS_BAD[0]);

    sph_scene s;
    sph_error err = {0};
    sph_status st;
    /* a missing file */
    char missing[1024];
    snprintf(missing, sizeof missing, "%s/no-such.cfg", tmp.dir);
    st = sph_scene_load(&s, missing, NULL, 0, &err);
    char expect[1100];
    snprintf(expect, sizeof expect, "%s: cannot read scene file: No such file or directory",
             missing);
    CHECK(c, st == SPH_ERR_INPUT && strcmp(err.msg, expect) == 0, "missing file: '%s'", err.msg);
    st = sph_scene_load(&s, tmp.dir, NULL, 0, &err);
    CHECK(c, st == SPH_ERR_INPUT && strstr(err.msg, "cannot read scene file"), "directory: '%s'",
          err.msg);
}

/* Inline shapes, forward references, 3D and optional keys. */
static void test_features(test_counts *c) {
    static const char text[] =
        "dimension = 3;\n"
        "resolution = { reference_length = 1.0; ratio = 10; };\n"
        "method = { formulation = \"enog-a\"; rotation = \"per-particle\"; xi_e = 3;\n"
        "           riemann_limiter = 1.5; smoothing_ratio = 1.5; };\n"
        "time = { end = 1; output_interval = 1; reference_speed = 2.0;\n"
        "         acceleration_criterion = false; };\n"
        "materials = { m = { density = 1000; youngs_modulus = 1e6; poisson_ratio = 0; }; };\n"
        "shapes = {\n"
        "  holed = { type = \"difference\";\n"
        "            parts = ( \"cube\", { type = \"box\"; lower = (0, 0, 0); upper = (0.2, 0.2, "
        "0.2); } ); };\n"
        "  cube = { type = \"box\"; lower = [-0.5, -0.5, -0.5]; upper = [0.5, 0.5, 0.5]; };\n"
        "};\n"
        "bodies = ( { name = \"b\"; material = \"m\"; shape = \"holed\";\n"
        "             initial_velocity = { type = \"rigid_rotation\"; omega = [0, 0, 50]; centre = "
        "[0, 0, 1]; }; } );\n"
        "gravity = [0.0, 0.0, -9.81];\n"
        "lattice_origin = [-0.5, -0.5, -0.5];\n";
    char path[1024];
    test_scene_write(&tmp, text, path, sizeof path);
    sph_scene s;
    sph_error err = {0};
    sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "3D scene: %s", err.msg);
    if (st != SPH_OK) return;
    CHECK(c, s.dim == 3 && s.dp == 0.1, "dim, dp = 1/10");
    CHECK(c, s.rotation == SPH_ROTATION_PER_PARTICLE, "per-particle");
    CHECK(c, s.xi_e == 3.0 && s.riemann_limiter_slope == 1.5 && s.smoothing_ratio == 1.5,
          "method values");
    CHECK(c, s.has_reference_speed && s.reference_speed == 2.0 && !s.acceleration_criterion,
          "time values");
    CHECK(c, s.has_lattice_origin && s.lattice_origin[2] == -0.5, "lattice origin");
    CHECK(c, s.gravity[2] == -9.81, "gravity");
    CHECK(c, s.materials[0].poisson_ratio == 0.0, "nu = 0 allowed");
    /* named shapes first, the inline box after them */
    CHECK(c,
          s.nshapes == 3 && s.shapes[2].name[0] == '\0' && s.shapes[0].parts[0] == 1 &&
              s.shapes[0].parts[1] == 2,
          "inline part appended, forward reference resolved");
    double in[3] = {-0.25, 0.0, 0.0}, hole[3] = {0.1, 0.1, 0.1};
    CHECK(c, sph_shape_contains(&s, 0, in) && !sph_shape_contains(&s, 0, hole), "difference");
    const sph_velocity_field *v = &s.bodies[0].velocity;
    CHECK(c, v->omega[2] == 50.0 && v->centre[2] == 1.0, "3D rotation");
    sph_scene_free(&s);
}

/* disc, annulus (2D), ball, hollow_sphere, cylinder (3D): containment and
 * bounding boxes, in unions and differences; the contact group. */
static void test_round_shapes(test_counts *c) {
    static const char text2[] =
        "dimension = 2;\n"
        "resolution = { dp = 0.001; };\n"
        "method = { formulation = \"enog-a\"; };\n"
        "time = { end = 0.01; output_interval = 0.001; };\n"
        "materials = { r = { density = 1200; youngs_modulus = 1e7; poisson_ratio = 0.4; }; };\n"
        "shapes = {\n"
        "  ring = { type = \"annulus\"; centre = [-0.045, 0.0]; inner_radius = 0.03; "
        "outer_radius = 0.04; };\n"
        "  notched = { type = \"difference\"; parts = ( { type = \"disc\"; centre = [0.045, 0.0]; "
        "radius = 0.04; }, { type = \"box\"; lower = [0.04, -0.005]; upper = [0.09, 0.005]; } ); "
        "};\n"
        "};\n"
        "bodies = ( { name = \"a\"; material = \"r\"; shape = \"ring\"; },\n"
        "           { name = \"b\"; material = \"r\"; shape = \"notched\"; } );\n"
        "contact = { impedance = 0.5; penalty = 2; };\n";
    char path[1024];
    test_scene_write(&tmp, text2, path, sizeof path);
    sph_scene s;
    sph_error err = {0};
    sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "2D round shapes: %s", err.msg);
    if (st == SPH_OK) {
        const double ring_in[3] = {-0.045 + 0.035, 0.0, 0}, hole[3] = {-0.045, 0.0, 0},
                     outside[3] = {-0.045, 0.0405, 0}, rim[3] = {-0.045, 0.04, 0},
                     disc_in[3] = {0.045, 0.02, 0}, notch[3] = {0.07, 0.0, 0};
        CHECK(c, s.shapes[0].type == SPH_SHAPE_SPHERE && s.shapes[0].inner_radius == 0.03,
              "annulus");
        CHECK(c,
              sph_shape_contains(&s, 0, ring_in) && !sph_shape_contains(&s, 0, hole) &&
                  !sph_shape_contains(&s, 0, outside) && sph_shape_contains(&s, 0, rim),
              "annulus containment (the rim belongs to it)");
        CHECK(c, sph_shape_contains(&s, 1, disc_in) && !sph_shape_contains(&s, 1, notch),
              "disc minus box");
        double lo[3], hi[3];
        sph_shape_bounds(&s, 0, lo, hi);
        CHECK(c, near_rel(lo[0], -0.085, 1e-14) && near_rel(hi[1], 0.04, 1e-14),
              "annulus bounds (%g, %g)", lo[0], hi[1]);
        CHECK(c, s.contact_impedance == 0.5 && s.contact_penalty == 2.0, "contact factors");
        sph_scene_free(&s);
    }
    static const char text3[] =
        "dimension = 3;\n"
        "resolution = { dp = 0.01; };\n"
        "method = { formulation = \"gnog-a\"; };\n"
        "time = { end = 0.01; output_interval = 0.001; };\n"
        "materials = { r = { density = 1200; youngs_modulus = 1e7; poisson_ratio = 0.4; }; };\n"
        "shapes = {\n"
        "  shell = { type = \"hollow_sphere\"; centre = [0.0, 0.0, 0.0]; inner_radius = 0.3; "
        "outer_radius = 0.4; };\n"
        "  bar = { type = \"cylinder\"; centre = [1.0, 0.0, 0.0]; axis = [0.0, 3.0, 4.0]; "
        "radius = 0.1; length = 1.0; };\n"
        "  solid = { type = \"union\"; parts = ( { type = \"ball\"; centre = [0.0, 2.0, 0.0]; "
        "radius = 0.2; }, \"bar\" ); };\n"
        "};\n"
        "bodies = ( { name = \"a\"; material = \"r\"; shape = \"shell\"; },\n"
        "           { name = \"b\"; material = \"r\"; shape = \"solid\"; } );\n";
    test_scene_write(&tmp, text3, path, sizeof path);
    st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "3D round shapes: %s", err.msg);
    if (st == SPH_OK) {
        const double in_shell[3] = {0.0, 0.35, 0.0}, centre[3] = {0, 0, 0},
                     on_axis[3] = {1.0, 0.3, 0.4}, off_axis[3] = {1.0 + 0.11, 0.3, 0.4},
                     past_end[3] = {1.0, 0.6 + 0.06, 0.8 + 0.08}, ball[3] = {0.1, 2.1, 0.1};
        CHECK(c, sph_shape_contains(&s, 0, in_shell) && !sph_shape_contains(&s, 0, centre),
              "hollow sphere");
        CHECK(c,
              sph_shape_contains(&s, 1, on_axis) && !sph_shape_contains(&s, 1, off_axis) &&
                  !sph_shape_contains(&s, 1, past_end),
              "cylinder (axis normalised to (0, 0.6, 0.8))");
        CHECK(c, sph_shape_contains(&s, 2, ball) && sph_shape_contains(&s, 2, on_axis),
              "union of a ball and the cylinder");
        double lo[3], hi[3];
        sph_shape_bounds(&s, 1, lo, hi);
        /* ends (1, 0, 0) and (1, 0.6, 0.8), radius 0.1: half-widths 0.1 sqrt(1 - a_k^2) */
        CHECK(c,
              near_rel(lo[0], 0.9, 1e-14) && near_rel(hi[0], 1.1, 1e-14) &&
                  near_rel(lo[1], -0.08, 1e-12) && near_rel(hi[1], 0.68, 1e-14) &&
                  near_rel(lo[2], -0.06, 1e-12) && near_rel(hi[2], 0.86, 1e-14),
              "cylinder bounds (%g %g %g) (%g %g %g)", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
        sph_scene_free(&s);
    }
}

/* Integers are read as 64 bits: a seed takes the whole unsigned range
 * (docs/scene-format.md), and a number key takes an integer of any size;
 * comments, strings and decimals are left as they are; the values survive
 * the resolved text a checkpoint stores. */
static void test_wide_integers(test_counts *c) {
    static const struct {
        const char *seed;
        uint64_t expect;
    } seeds[] = {{"2147483648", 2147483648ULL},
                 {"4294967296", 4294967296ULL},
                 {"4294967296L", 4294967296ULL},
                 {"9223372036854775807", 9223372036854775807ULL},
                 {"9223372036854775808", 9223372036854775808ULL},
                 {"18446744073709551615", 18446744073709551615ULL},
                 {"0xFFFFFFFFFFFFFFFF", 18446744073709551615ULL},
                 {"0xFFFFFFFFFFFFFFFFL", 18446744073709551615ULL},
                 {"0x80000000", 2147483648ULL},
                 {"0", 0},
                 {"7", 7}};
    for (size_t k = 0; k < sizeof seeds / sizeof seeds[0]; k++) {
        char find[160], text[4096], path[1024];
        snprintf(find, sizeof find,
                 "shape = \"block\"; placement = \"relaxed\"; relaxation = { seed = %s; };",
                 seeds[k].seed);
        edit(BASE, "shape = \"block\";", find, text, sizeof text);
        test_scene_write(&tmp, text, path, sizeof path);
        sph_scene s;
        sph_error err = {0};
        sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
        CHECK(c, st == SPH_OK && s.bodies[0].relaxation.seed == seeds[k].expect,
              "seed = %s: status %d, seed %llu (%s)", seeds[k].seed, st,
              (unsigned long long)s.bodies[0].relaxation.seed, err.msg);
        if (st != SPH_OK) continue;
        /* a restart reloads the resolved text */
        sph_scene r;
        st = sph_scene_load_text(&r, "resolved", s.resolved_text, NULL, 0, &err);
        CHECK(c, st == SPH_OK && r.bodies[0].relaxation.seed == seeds[k].expect,
              "seed = %s after the resolved text: %s", seeds[k].seed, err.msg);
        if (st == SPH_OK) sph_scene_free(&r);
        /* and an override sets the same */
        char ov[128];
        snprintf(ov, sizeof ov, "bodies.a.relaxation.seed=%s", seeds[k].seed);
        const char *ovs[1] = {ov};
        sph_scene_free(&s);
        edit(BASE, "shape = \"block\";", "shape = \"block\"; placement = \"relaxed\";", text,
             sizeof text);
        test_scene_write(&tmp, text, path, sizeof path);
        st = sph_scene_load(&s, path, ovs, 1, &err);
        CHECK(c, st == SPH_OK && s.bodies[0].relaxation.seed == seeds[k].expect,
              "--set %s: status %d, seed %llu (%s)", ov, st,
              (unsigned long long)s.bodies[0].relaxation.seed, err.msg);
        if (st == SPH_OK) sph_scene_free(&s);
    }

    /* numbers: an integer of any size; the text around them untouched */
    char text[4096], path[1024];
    edit(BASE, "# test scene\n",
         "# test scene 4294967296\ntitle = \"run 99999999999999999999 /* 4294967296 */\";\n", text,
         sizeof text);
    char text2[4096];
    edit(text, "youngs_modulus = 2.0e11", "youngs_modulus = 200000000000", text2, sizeof text2);
    edit(text2, "density = 7800.0", "density = 7800000000000000000000", text, sizeof text);
    edit(text, "end = 1.0", "end = 4294967296.5", text2, sizeof text2);
    test_scene_write(&tmp, text2, path, sizeof path);
    sph_scene s;
    sph_error err = {0};
    sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "large integers as numbers: %s", err.msg);
    if (st != SPH_OK) return;
    CHECK(c, s.materials[0].youngs_modulus == 2e11, "E %.17g", s.materials[0].youngs_modulus);
    CHECK(c, s.materials[0].density == 7.8e21, "rho beyond 64 bits %.17g", s.materials[0].density);
    CHECK(c, s.end_time == 4294967296.5, "decimal untouched %.17g", s.end_time);
    CHECK(c, strcmp(s.title, "run 99999999999999999999 /* 4294967296 */") == 0, "title '%s'",
          s.title);
    sph_scene_free(&s);
}

static void test_names(test_counts *c) {
    CHECK(c, strcmp(sph_formulation_name(SPH_FORMULATION_ENOG), "enog") == 0, "enog");
    CHECK(c, strcmp(sph_formulation_name(SPH_FORMULATION_ENOG_A), "enog-a") == 0, "enog-a");
    CHECK(c, strcmp(sph_rotation_name(SPH_ROTATION_PER_PARTICLE), "per-particle") == 0, "rot");
    CHECK(c, strcmp(sph_kernel_name(SPH_KERNEL_WENDLAND_C2), "wendland-c2") == 0, "kernel");
    CHECK(c, strcmp(sph_stepping_name(SPH_STEPPING_SINGLE), "single") == 0, "stepping");
}

/* Initial velocities as expressions and the scene's constants: parsed,
 * kept as text for particles.c, constants overridable with --set. */
static void test_expressions(test_counts *c) {
    char path[1024];
    test_scene_write(&tmp,
                     "dimension = 3;\n"
                     "resolution = { dp = 0.1; };\n"
                     "method = { formulation = \"enog-a\"; };\n"
                     "time = { end = 1.0; output_interval = 0.1; };\n"
                     "constants = { U = 2.0; k_1 = 3; };\n"
                     "materials = { m = { density = 1000.0; youngs_modulus = 1.0e6; "
                     "poisson_ratio = 0.3; }; };\n"
                     "shapes = { b = { type = \"box\"; lower = [0.0, 0.0, 0.0]; "
                     "upper = [1.0, 1.0, 1.0]; }; };\n"
                     "bodies = ( { name = \"a\"; material = \"m\"; shape = \"b\";\n"
                     "  initial_velocity = { type = \"expression\";\n"
                     "    x = \"x <= 0.5 ? U : U * cos(k_1 * pi * z)\"; z = \"x * y * z\"; }; "
                     "} );\n",
                     path, sizeof path);
    sph_scene s;
    sph_error err = {0};
    const char *const ov[] = {"constants.U=5.0"};
    sph_status st = sph_scene_load(&s, path, ov, 1, &err);
    CHECK(c, st == SPH_OK, "expression scene: %s", err.msg);
    if (st != SPH_OK) return;
    const sph_velocity_field *v = &s.bodies[0].velocity;
    CHECK(c, v->type == SPH_VELOCITY_EXPRESSION, "type expression");
    CHECK(c,
          strcmp(v->expression[0], "x <= 0.5 ? U : U * cos(k_1 * pi * z)") == 0 &&
              v->expression[1][0] == '\0' && strcmp(v->expression[2], "x * y * z") == 0,
          "texts '%s' '%s' '%s'", v->expression[0], v->expression[1], v->expression[2]);
    CHECK(c, strstr(v->expression_where[2], ":10: bodies.a.initial_velocity.z") != NULL,
          "where '%s'", v->expression_where[2]);
    CHECK(c,
          s.nconstants == 2 && strcmp(s.constant_name[0], "U") == 0 && s.constant_value[0] == 5.0 &&
              strcmp(s.constant_name[1], "k_1") == 0 && s.constant_value[1] == 3.0,
          "constants (override applied)");
    /* the module evaluates them: U cos(3 pi z) at (0.75, 0, 1/3) = 5 cos(pi) */
    const char *vars[3], *names[SPH_SCENE_MAX_CONSTANTS];
    const int nvars = sph_scene_expression_variables(3, vars);
    const sph_expression_constants k = sph_scene_expression_constants(&s, names);
    sph_expression *e = NULL;
    char why[256];
    CHECK(c, sph_expression_compile(v->expression[0], vars, nvars, &k, &e, why, sizeof why),
          "compile: %s", why);
    double r = 0.0;
    const double at[3] = {0.75, 0.0, 1.0 / 3.0}, before[3] = {0.5, 0.0, 0.0};
    if (e) {
        CHECK(c, sph_expression_eval(e, at, &r, why, sizeof why) && fabs(r + 5.0) < 1e-14,
              "U cos(k_1 pi z) = %.17g", r);
        CHECK(c, sph_expression_eval(e, before, &r, why, sizeof why) && r == 5.0,
              "x <= 0.5 branch: %.17g", r);
    }
    sph_expression_free(e);
    sph_scene_free(&s);
}

/* FLUID_BASE with `nedits` (find, replace) pairs applied in order, written
 * to a fresh scene file whose path goes to `path`. */
static void write_fluid(const char *const (*edits)[2], int nedits, char *path, size_t size) {
    char text[4096], step[4096];
    snprintf(text, sizeof text, "%s", FLUID_BASE);
    for (int k = 0; k < nedits; ++k) {
        edit(text, edits[k][0], edits[k][1], step, sizeof step);
        snprintf(text, sizeof text, "%s", step);
    }
    test_scene_write(&tmp, text, path, size);
}

/* The fluid scenes of the eulerian formulations (seed 004 §3.1): keys,
 * defaults (limiter slope 15 and 1, CFL 0.6 / d, gamma 1.4, single
 * stepping, the fluid output fields) and the initial particles (density
 * and pressure fields, masses rho dp^d, the lattice anchored on the
 * periodic boundary). */
static void test_fluids(test_counts *c) {
    char path[1024];
    sph_scene s;
    sph_error err = {0};
    sph_particles p;

    /* a line: the 1D defaults (CFL 0.4, no vorticity field) and its lattice,
     * masses rho dp */
    test_scene_write(&tmp, LINE_BASE, path, sizeof path);
    sph_status line_st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, line_st == SPH_OK, "line scene: %s", err.msg);
    if (line_st == SPH_OK) {
        CHECK(c, s.dim == 1 && s.cfl_acoustic == 0.4, "dimension 1, CFL 0.4: %d %g", s.dim,
              s.cfl_acoustic);
        CHECK(c, !s.output_field[SPH_OUT_VORTICITY] && s.output_field[SPH_OUT_DENSITY],
              "a line's output fields: density, no vorticity");
        line_st = sph_particles_generate(&s, &p, &err);
        CHECK(c, line_st == SPH_OK, "line particles: %s", err.msg);
        if (line_st == SPH_OK) {
            bool ok = p.n == 10;
            for (int i = 0; ok && i < p.n; ++i) {
                const double x = 0.05 + 0.1 * i, rho = 1 + 0.01 * x;
                ok = fabs(p.pos[i] - x) < 1e-12 && fabs(p.mass[i] - rho * 0.1) < 1e-15;
            }
            CHECK(c, ok, "10 particles at 0.05 + 0.1 i with mass rho(x) dp (n = %d)", p.n);
            sph_particles_free(&p);
        }
        sph_scene_free(&s);
    }

    /* weakly compressible, everything defaulted */
    write_fluid(NULL, 0, path, sizeof path);
    sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "WC scene: %s", err.msg);
    if (st == SPH_OK) {
        CHECK(c, s.formulation == SPH_FORMULATION_EULERIAN_WC && s.rotation == SPH_ROTATION_NONE,
              "eulerian-wc, rotation none");
        CHECK(c, strcmp(sph_formulation_name(s.formulation), "eulerian-wc") == 0, "name");
        CHECK(c, s.riemann_limiter_slope == 15.0, "limiter default 15 (seed 004 eq. 22): %g",
              s.riemann_limiter_slope);
        CHECK(c, s.viscous_regularization == SPH_VISCOUS_SQUARED,
              "viscous regularization default r / (r^2 + eps^2)");
        CHECK(c, s.fluid_integrator == SPH_FLUID_TWO_STAGE, "integrator default two-stage");
        CHECK(c, s.cfl_acoustic == 0.3, "cfl 0.6 / 2: %.17g", s.cfl_acoustic);
        CHECK(c, s.stepping == SPH_STEPPING_SINGLE, "single stepping");
        const sph_material *m = &s.materials[0];
        CHECK(c, m->fluid && m->density == 1.0 && m->sound_speed == 10.0 && m->viscosity == 0.01,
              "fluid material: rho0 %g c0 %g mu %g", m->density, m->sound_speed, m->viscosity);
        CHECK(c, m->bulk_modulus == 100.0 && m->shear_modulus == 0.0 && !m->plastic,
              "K = rho0 c0^2 = %g, G = %g", m->bulk_modulus, m->shear_modulus);
        CHECK(c, s.bodies[0].initial_density[0] == '\0' && s.bodies[0].initial_pressure[0] == '\0',
              "no initial fields");
        CHECK(c, s.periodic_mask == 3, "periodic x and y: mask %d", s.periodic_mask);
        CHECK(c,
              s.periodic_lower[0] == 0.0 && s.periodic_lower[1] == 0.0 &&
                  s.periodic_upper[0] == 1.0 && s.periodic_upper[1] == 1.0,
              "period [0, 1)^2");
        char where[1100];
        snprintf(where, sizeof where, "%s:15: boundary", path);
        CHECK(c, strcmp(s.periodic_where, where) == 0, "periodic_where '%s'", s.periodic_where);
        const bool *f = s.output_field;
        CHECK(c,
              f[SPH_OUT_VELOCITY] && f[SPH_OUT_DENSITY] && f[SPH_OUT_PRESSURE] &&
                  f[SPH_OUT_VORTICITY] && f[SPH_OUT_PARTICLE_ID] && !f[SPH_OUT_DISPLACEMENT] &&
                  !f[SPH_OUT_VON_MISES] && !f[SPH_OUT_SHEAR_STRESS] && !f[SPH_OUT_BODY_ID] &&
                  !f[SPH_OUT_PLASTIC_STRAIN] && !f[SPH_OUT_MACH_NUMBER],
              "fluid output fields");
        CHECK(c,
              strcmp(sph_output_field_name(SPH_OUT_VORTICITY), "vorticity") == 0 &&
                  strcmp(sph_output_field_name(SPH_OUT_MACH_NUMBER), "mach_number") == 0,
              "field names");
        /* the lattice anchored at boundary.lower fills the period: 10 x 10 */
        st = sph_particles_generate(&s, &p, &err);
        CHECK(c, st == SPH_OK, "WC particles: %s", err.msg);
        if (st == SPH_OK) {
            CHECK(c, p.n == 100 && p.pressure == NULL, "n %d, no pressure array", p.n);
            bool ok = true;
            for (int i = 0; i < p.n; ++i) ok &= p.rho[i] == 1.0 && fabs(p.mass[i] - 0.01) < 1e-17;
            CHECK(c, ok, "rho = rho0, m = rho0 dp^2");
            CHECK(c, fabs(p.pos[0] - 0.05) < 1e-15 && fabs(p.pos[p.n - 1] - 0.95) < 1e-15,
                  "x from 0.05 to 0.95: %.17g %.17g", p.pos[0], p.pos[p.n - 1]);
            sph_particles_free(&p);
        }
        sph_scene_free(&s);
    }

    /* an initial density field, an explicit limiter and CFL, a body
     * smaller than the period (the lattice still starts at lower) */
    {
        const char *const e[][2] = {
            {"formulation = \"eulerian-wc\";",
             "formulation = \"eulerian-wc\"; riemann_limiter = 5.0; "
             "viscous_regularization = \"linear\";"},
            {"end = 1.0;", "end = 1.0; cfl_acoustic = 0.25; reference_speed = 1.0; "
                           "integrator = \"ssp-rk3\";"},
            {"shape = \"box\";", "shape = \"box\"; initial_density = \"1 + 0.1 * x * y\";"},
            {"lower = [0.0, 0.0]; upper = [1.0, 1.0]; };\n};", "lower = [0.0, 0.0]; upper = [1.0, "
                                                               "0.5]; };\n};"},
            {"};\nbodies", "};\nconstants = { U = 1.0; };\nbodies"},
        };
        write_fluid(e, 5, path, sizeof path);
        st = sph_scene_load(&s, path, NULL, 0, &err);
        CHECK(c, st == SPH_OK, "WC scene with a density field: %s", err.msg);
        if (st == SPH_OK) {
            CHECK(c,
                  s.riemann_limiter_slope == 5.0 && s.cfl_acoustic == 0.25 &&
                      s.viscous_regularization == SPH_VISCOUS_LINEAR &&
                      s.fluid_integrator == SPH_FLUID_SSP_RK3,
                  "given values");
            CHECK(c, strcmp(s.bodies[0].initial_density, "1 + 0.1 * x * y") == 0, "text '%s'",
                  s.bodies[0].initial_density);
            CHECK(c, strstr(s.bodies[0].initial_density_where, ":14: bodies.f.initial_density"),
                  "where '%s'", s.bodies[0].initial_density_where);
            st = sph_particles_generate(&s, &p, &err);
            CHECK(c, st == SPH_OK, "particles: %s", err.msg);
            if (st == SPH_OK) {
                bool ok = p.n == 50;
                for (int i = 0; i < p.n; ++i) {
                    const double x = p.pos[i], y = p.pos[p.n + i], rho = 1.0 + 0.1 * x * y;
                    ok &= fabs(p.rho[i] - rho) < 1e-15 && fabs(p.mass[i] - rho * 0.01) < 1e-16;
                }
                CHECK(c, ok, "rho = 1 + 0.1 x y, m = rho dp^2 (n %d)", p.n);
                sph_particles_free(&p);
            }
            sph_scene_free(&s);
        }
    }

    /* the ideal gas: gamma default 1.4, limiter 1 (eq. 20), Mach number out,
     * a pressure field; a number for the density */
    {
        const char *const e[][2] = {
            {GAS_EDITS[0][0], GAS_EDITS[0][1]},
            {GAS_EDITS[1][0], GAS_EDITS[1][1]},
            {"shape = \"box\";", "shape = \"box\"; initial_density = 2;\n"
                                 "    initial_pressure = \"71.43 * (1 + x)\";"},
        };
        write_fluid(e, 3, path, sizeof path);
        st = sph_scene_load(&s, path, NULL, 0, &err);
        CHECK(c, st == SPH_OK, "compressible scene: %s", err.msg);
        if (st == SPH_OK) {
            CHECK(c, s.formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE, "compressible");
            CHECK(c, s.riemann_limiter_slope == 1.0, "limiter default 1 (seed 004 eq. 20): %g",
                  s.riemann_limiter_slope);
            CHECK(c, s.cfl_acoustic == 0.3 && s.stepping == SPH_STEPPING_SINGLE, "cfl %g",
                  s.cfl_acoustic);
            const sph_material *m = &s.materials[0];
            CHECK(c, m->fluid && m->gamma == 1.4 && m->sound_speed == 0.0 && m->viscosity == 0.0,
                  "gas: gamma %g c0 %g mu %g", m->gamma, m->sound_speed, m->viscosity);
            CHECK(c, strcmp(s.bodies[0].initial_density, "2") == 0, "a number kept as text '%s'",
                  s.bodies[0].initial_density);
            CHECK(c, strcmp(s.bodies[0].initial_pressure, "71.43 * (1 + x)") == 0, "p text");
            CHECK(c, strstr(s.bodies[0].initial_pressure_where, ":14: bodies.f.initial_pressure"),
                  "where '%s'", s.bodies[0].initial_pressure_where);
            CHECK(c, s.output_field[SPH_OUT_MACH_NUMBER] && s.output_field[SPH_OUT_VORTICITY],
                  "mach_number by default");
            st = sph_particles_generate(&s, &p, &err);
            CHECK(c, st == SPH_OK, "gas particles: %s", err.msg);
            if (st == SPH_OK) {
                bool ok = p.n == 100 && p.pressure != NULL;
                for (int i = 0; ok && i < p.n; ++i)
                    ok &= p.rho[i] == 2.0 && fabs(p.mass[i] - 0.02) < 1e-17 &&
                          fabs(p.pressure[i] - 71.43 * (1.0 + p.pos[i])) < 1e-12;
                CHECK(c, ok, "rho 2, m = 2 dp^2, p = 71.43 (1 + x)");
                sph_particles_free(&p);
                CHECK(c, p.pressure == NULL, "freed");
            }
            sph_scene_free(&s);
        }
    }

    /* gamma = 5/3 in the 15 digits a stored scene keeps; 3D: CFL 0.6 / 3 */
    {
        const char *const e[][2] = {
            {"dimension = 2;", "dimension = 3;"},
            {GAS_EDITS[0][0], GAS_EDITS[0][1]},
            {"water = { density = 1.0; sound_speed = 10.0; viscosity = 0.01; };",
             "water = { density = 1.0; gamma = 1.66666666666667; };"},
            {"shape = \"box\";", "shape = \"box\"; initial_pressure = 1.0;"},
            {"lower = [0.0, 0.0]; upper = [1.0, 1.0]; };\n};",
             "lower = [0.0, 0.0, 0.0]; upper = [1.0, 1.0, 0.6]; };\n};"},
            {"periodic = [\"x\", \"y\"]; lower = [0.0, 0.0]; upper = [1.0, 1.0];",
             "periodic = [\"z\"]; lower = [0.0, 0.0, 0.0]; upper = [1.0, 1.0, 0.6];"},
        };
        write_fluid(e, 6, path, sizeof path);
        st = sph_scene_load(&s, path, NULL, 0, &err);
        CHECK(c, st == SPH_OK, "3D gas: %s", err.msg);
        if (st == SPH_OK) {
            CHECK(c, fabs(s.cfl_acoustic - 0.2) < 1e-15 && s.periodic_mask == 4,
                  "cfl %.17g, mask %d", s.cfl_acoustic, s.periodic_mask);
            CHECK(c, s.materials[0].gamma == 1.66666666666667, "gamma 5/3");
            sph_scene_free(&s);
        }
    }

    /* errors found when the particles are placed: SPH_ERR_INPUT naming the
     * key (and its line) and the particle */
    static const struct {
        const char *what;
        int nedits;
        const char *edits[4][2];
        const char *expect;
    } rows[] = {
        {"a negative density expression",
         1,
         {{"shape = \"box\";", "shape = \"box\"; initial_density = \"x - 0.5\";"}},
         ":13: bodies.f.initial_density: the expression \"x - 0.5\" gives -0.45 at the particle "
         "at (0.05, 0.05) of body 'f': initial densities must be finite and > 0"},
        {"a density that is not a number",
         1,
         {{"shape = \"box\";", "shape = \"box\"; initial_density = \"sqrt(x - 2)\";"}},
         ":13: bodies.f.initial_density: the expression \"sqrt(x - 2)\" gives nan at the "
         "particle at (0.05, 0.05)"},
        {"a negative pressure expression",
         3,
         {{GAS_EDITS[0][0], GAS_EDITS[0][1]},
          {GAS_EDITS[1][0], GAS_EDITS[1][1]},
          {"shape = \"box\";", "shape = \"box\"; initial_pressure = \"y < 0.5 ? 1 : -1\";"}},
         ":13: bodies.f.initial_pressure: the expression \"y < 0.5 ? 1 : -1\" gives -1 at the "
         "particle at (0.05, 0.55) of body 'f': initial pressures must be finite and > 0"},
        {"a lattice origin off the periodic lattice",
         1,
         {{"};\nbodies", "};\nlattice_origin = [0.03, 0.0];\nbodies"}},
         ":16: boundary: the lattice does not fit the periodic axis x: the particle at (0.08, "
         "0.05) "
         "of body 'f'"},
        {"a body beyond the period",
         1,
         {{"upper = [1.0, 1.0]; };\n};", "upper = [1.0, 1.2]; };\n};"}},
         ":15: boundary: the lattice does not fit the periodic axis y: the particle at (0.05, "
         "1.05) "
         "of body 'f'"},
    };
    for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k) {
        write_fluid(rows[k].edits, rows[k].nedits, path, sizeof path);
        memset(&err, 0, sizeof err);
        st = sph_scene_load(&s, path, NULL, 0, &err);
        CHECK(c, st == SPH_OK, "%s: the scene loads: %s", rows[k].what, err.msg);
        if (st != SPH_OK) continue;
        st = sph_particles_generate(&s, &p, &err);
        if (getenv("SPH_TEST_VERBOSE")) printf("%-40s %s\n", rows[k].what, err.msg);
        char expect[1400];
        snprintf(expect, sizeof expect, "%s%s", path, rows[k].expect);
        CHECK(c, st == SPH_ERR_INPUT && strstr(err.msg, expect) != NULL,
              "%s: status %d\n  got      '%s'\n  expected '%s'", rows[k].what, st, err.msg, expect);
        if (st == SPH_OK) sph_particles_free(&p);
        sph_scene_free(&s);
    }
}

/* CYL_BASE with `nedits` (find, replace) pairs applied in order, written
 * to a fresh scene file whose path goes to `path`. */
static void write_cylinder(const char *const (*edits)[2], int nedits, char *path, size_t size) {
    char text[4096], step[4096];
    snprintf(text, sizeof text, "%s", CYL_BASE);
    for (int k = 0; k < nedits; ++k) {
        edit(text, edits[k][0], edits[k][1], step, sizeof step);
        snprintf(text, sizeof text, "%s", step);
    }
    test_scene_write(&tmp, text, path, size);
}

/* The flow around a cylinder's keys (seed 004 §4.3): bodies.X.role and
 * .spacing, boundary.far_field, forces, with their defaults; the far
 * field's box checked when the particles are placed. */
static void test_walls(test_counts *c) {
    char path[1024];
    sph_scene s;
    sph_error err = {0};

    /* solid scenes: every body matter on the scene's lattice */
    if (load_case_scene(c, "oscillating_plate_2d", &s)) {
        CHECK(c, s.bodies[0].role == SPH_BODY_MATTER && s.bodies[0].spacing_ratio == 1.0,
              "solid body: matter, spacing 1 (%d, %g)", s.bodies[0].role,
              s.bodies[0].spacing_ratio);
        CHECK(c, !s.has_far_field && !s.has_forces, "no far field, no forces");
        sph_scene_free(&s);
    }

    /* the base: defaults everywhere */
    write_cylinder(NULL, 0, path, sizeof path);
    sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "cylinder scene: %s", err.msg);
    if (st == SPH_OK) {
        const sph_body *f = &s.bodies[0], *w = &s.bodies[1];
        CHECK(c, f->role == SPH_BODY_MATTER && f->spacing_ratio == 1.0, "fluid: matter, 1");
        CHECK(c, w->role == SPH_BODY_WALL && w->spacing_ratio == 0.5 && w->material == 0,
              "wall: role %d, spacing %g (default dp/2), material %d (the fluid's)", w->role,
              w->spacing_ratio, w->material);
        CHECK(c,
              w->velocity.type == SPH_VELOCITY_ZERO && w->nconstraints == 0 &&
                  w->initial_density[0] == '\0',
              "a wall at rest");
        CHECK(c,
              s.has_far_field && s.far_field_density == 1.0 && s.far_field_velocity[0] == 1.0 &&
                  s.far_field_velocity[1] == 0.0,
              "far field rho %g U (%g, %g)", s.far_field_density, s.far_field_velocity[0],
              s.far_field_velocity[1]);
        CHECK(c, s.periodic_mask == 0, "no periodic axis: mask %d", s.periodic_mask);
        CHECK(c,
              s.periodic_lower[0] == 0.0 && s.periodic_upper[0] == 6.0 &&
                  s.periodic_lower[1] == 0.0 && s.periodic_upper[1] == 4.0,
              "box [0, 6] x [0, 4]");
        char where[1100];
        snprintf(where, sizeof where, "%s:17: boundary", path);
        CHECK(c, strcmp(s.periodic_where, where) == 0, "where '%s'", s.periodic_where);
        CHECK(c,
              s.has_forces && s.force_reference_density == 1.0 && s.force_reference_speed == 1.0 &&
                  s.force_reference_length == 1.0 && s.force_window == 0.0,
              "forces: rho_ref %g U_ref %g L_ref %g window %g", s.force_reference_density,
              s.force_reference_speed, s.force_reference_length, s.force_window);
        sph_scene_free(&s);
    }

    /* given values; the far field's density defaults to rho0, the
     * reference speed to |U_inf|; a wall naming the material, relaxed, at
     * dp/4; a periodic axis beside the far field */
    {
        const char *const e[][2] = {
            {"density = 1.0; sound_speed", "density = 2.0; sound_speed"},
            {"far_field = { density = 1.0; velocity = [1.0, 0.0]; };",
             "periodic = [\"y\"]; far_field = { velocity = [3.0, 4.0]; };"},
            {"role = \"wall\"; shape = \"disc\";",
             "role = \"wall\"; material = \"water\"; shape = \"disc\"; spacing = 0.25; "
             "placement = \"lattice\";"},
            {"forces = { reference_length = 1.0; };",
             "forces = { reference_length = 2.0; window = 50.0; };"},
        };
        write_cylinder(e, 4, path, sizeof path);
        st = sph_scene_load(&s, path, NULL, 0, &err);
        CHECK(c, st == SPH_OK, "cylinder scene, given values: %s", err.msg);
        if (st == SPH_OK) {
            CHECK(c, s.bodies[1].spacing_ratio == 0.25 && s.bodies[1].material == 0,
                  "spacing 0.25");
            CHECK(c, s.far_field_density == 2.0 && s.periodic_mask == 2,
                  "far field rho = rho0 = %g, mask %d", s.far_field_density, s.periodic_mask);
            CHECK(c,
                  s.force_reference_density == 2.0 && s.force_reference_speed == 5.0 &&
                      s.force_reference_length == 2.0 && s.force_window == 50.0,
                  "rho_ref %g (the far field's), U_ref %g (|(3, 4)|), L_ref %g, window %g",
                  s.force_reference_density, s.force_reference_speed, s.force_reference_length,
                  s.force_window);
            sph_scene_free(&s);
        }
    }

    /* no far field: a wall in a periodic channel; rho_ref is the fluid's,
     * U_ref must be given; a relaxed wall body */
    {
        const char *const e[][2] = {
            {"density = 1.0; sound_speed", "density = 3.0; sound_speed"},
            {"far_field = { density = 1.0; velocity = [1.0, 0.0]; };", "periodic = [\"x\"];"},
            {"shape = \"disc\";", "shape = \"disc\"; placement = \"relaxed\";"},
            {"forces = { reference_length = 1.0; };",
             "forces = { reference_length = 1.0; reference_speed = 0.5; };"},
        };
        write_cylinder(e, 4, path, sizeof path);
        memset(&err, 0, sizeof err);
        st = sph_scene_load(&s, path, NULL, 0, &err);
        /* a periodic boundary refuses relaxed bodies, walls included */
        CHECK(c,
              st == SPH_ERR_INPUT && strstr(err.msg, "bodies.cyl.placement: a relaxed placement "
                                                     "is not supported with a periodic"),
              "relaxed wall, periodic: %s", err.msg);
        if (st == SPH_OK) sph_scene_free(&s);
        const char *const e2[][2] = {{e[0][0], e[0][1]}, {e[1][0], e[1][1]}, {e[3][0], e[3][1]}};
        write_cylinder(e2, 3, path, sizeof path);
        st = sph_scene_load(&s, path, NULL, 0, &err);
        CHECK(c, st == SPH_OK, "periodic channel with a wall: %s", err.msg);
        if (st == SPH_OK) {
            CHECK(c,
                  !s.has_far_field && s.periodic_mask == 1 && s.has_forces &&
                      s.force_reference_density == 3.0 && s.force_reference_speed == 0.5,
                  "rho_ref %g (rho0), U_ref %g", s.force_reference_density,
                  s.force_reference_speed);
            sph_scene_free(&s);
        }
        const char *const e3[][2] = {{e[0][0], e[0][1]}, {e[1][0], e[1][1]}};
        write_cylinder(e3, 2, path, sizeof path);
        memset(&err, 0, sizeof err);
        st = sph_scene_load(&s, path, NULL, 0, &err);
        char expect[1200];
        snprintf(expect, sizeof expect,
                 "%s:19: forces.reference_speed: missing required key: without a far field there "
                 "is no free-stream speed",
                 path);
        CHECK(c, st == SPH_ERR_INPUT && strstr(err.msg, expect), "no U_ref: %s", err.msg);
        if (st == SPH_OK) sph_scene_free(&s);
    }

    /* overrides create boundary.far_field and forces */
    {
        const char *const e[][2] = {
            {"\nforces = { reference_length = 1.0; };\n", "\n"},
            {"boundary = { far_field = { density = 1.0; velocity = [1.0, 0.0]; };\n"
             "             lower = [0.0, 0.0]; upper = [6.0, 4.0]; };",
             "boundary = { periodic = [\"x\", \"y\"]; lower = [0.0, 0.0]; upper = [6.0, 4.0]; };"},
        };
        write_cylinder(e, 2, path, sizeof path);
        const char *ov[] = {"boundary.periodic=[\"y\"]", "boundary.far_field.velocity=[2.0, 0.0]",
                            "forces.reference_length=1.0"};
        st = sph_scene_load(&s, path, ov, 3, &err);
        CHECK(c, st == SPH_OK, "far field and forces by --set: %s", err.msg);
        if (st == SPH_OK) {
            CHECK(c,
                  s.has_far_field && s.far_field_velocity[0] == 2.0 && s.periodic_mask == 2 &&
                      s.has_forces && s.force_reference_speed == 2.0,
                  "--set: U %g, mask %d, U_ref %g", s.far_field_velocity[0], s.periodic_mask,
                  s.force_reference_speed);
            sph_scene_free(&s);
        }
        const char *bad[] = {"boundary.periodic=[\"y\"]", "boundary.far_field.velocity=[2.0, 0.0]",
                             "forces.reference_length=-1.0"};
        st = sph_scene_load(&s, path, bad, 3, &err);
        CHECK(c,
              st == SPH_ERR_INPUT &&
                  strstr(err.msg, "--set forces.reference_length=-1.0: "
                                  "forces.reference_length: must be > 0, got -1"),
              "--set forces: %s", err.msg);
        if (st == SPH_OK) sph_scene_free(&s);
    }

    /* a matter particle outside the far field's box: refused when the
     * particles are placed, naming boundary */
    {
        const char *const e[][2] = {
            {"upper = [6.0, 4.0]; };\nforces", "upper = [5.0, 4.0]; };\nforces"}};
        write_cylinder(e, 1, path, sizeof path);
        st = sph_scene_load(&s, path, NULL, 0, &err);
        CHECK(c, st == SPH_OK, "box smaller than the fluid: loads: %s", err.msg);
        if (st == SPH_OK) {
            sph_particles p;
            memset(&err, 0, sizeof err);
            st = sph_particles_generate(&s, &p, &err);
            char expect[2600];
            snprintf(expect, sizeof expect,
                     "%s:17: boundary: the particle at (5.05, 0.05) of body 'f' (%s:14: bodies.f) "
                     "lies outside the far field's box boundary.lower to boundary.upper, (0, 0) "
                     "to (5, 4); every matter body must lie within it",
                     path, path);
            CHECK(c, st == SPH_ERR_INPUT && strstr(err.msg, expect),
                  "outside the box:\n  got      '%s'\n  expected '%s'", err.msg, expect);
            if (st == SPH_OK) sph_particles_free(&p);
            sph_scene_free(&s);
        }
    }
}

int main(void) {
    test_counts c = {0, 0};
    if (test_scene_dir_open(&tmp, "test_scene") != 0) return 2;
    test_oscillating_plate(&c);
    test_spinning_plate(&c);
    test_sound_speed(&c);
    test_kernel_cfl(&c);
    test_overrides(&c);
    test_bad_inputs(&c);
    test_features(&c);
    test_round_shapes(&c);
    test_wide_integers(&c);
    test_names(&c);
    test_expressions(&c);
    test_fluids(&c);
    test_walls(&c);
    test_scene_dir_close(&tmp);
    return test_summary("test_scene", &c);
}
