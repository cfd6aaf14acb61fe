/* test_particles — the initial particle set (host/setup/particles.c).
 *
 * Counts follow from the lattice rule (cell centres of a dp-grid anchored at
 * the lower corner of all bodies) and the case geometry; energies and
 * momenta from the initial velocity fields: the first cantilever mode of
 * 003 eqs. 50-51 for the oscillating plate (reference value of the initial
 * kinetic energy 4.0647984104106447 J/m) and rigid rotation for the
 * spinning plate, whose sums over the lattice are evaluated in closed form
 * below. */
#include "particles.h"
#include "sph_constants.h"
#include "test_support.h"

#include <float.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static test_scene_dir tmp;

typedef struct {
    double ke, p[3], lz, max_speed[3];
} moments;

static moments compute_moments(const sph_particles *p) {
    moments m = {0};
    const size_t n = (size_t)p->n;
    for (size_t i = 0; i < n; i++) {
        double v2 = 0.0;
        for (int a = 0; a < p->dim; a++) {
            double v = p->vel[(size_t)a * n + i];
            v2 += v * v;
            m.p[a] += p->mass[i] * v;
            if (fabs(v) > m.max_speed[a]) m.max_speed[a] = fabs(v);
        }
        m.ke += 0.5 * p->mass[i] * v2;
        double x = p->pos[i], y = p->pos[n + i], vx = p->vel[i], vy = p->vel[n + i];
        m.lz += p->mass[i] * (x * vy - y * vx);
    }
    return m;
}

/* the particle nearest to (x, y) */
static size_t nearest(const sph_particles *p, double x, double y) {
    size_t best = 0;
    double best_d = INFINITY;
    const size_t n = (size_t)p->n;
    for (size_t i = 0; i < n; i++) {
        double dx = p->pos[i] - x, dy = p->pos[n + i] - y, d = dx * dx + dy * dy;
        if (d < best_d) best_d = d, best = i;
    }
    return best;
}

static void check_bookkeeping(test_counts *c, const sph_particles *p, const sph_scene *s,
                              const char *what) {
    bool ids = true, bodies_sorted = true, masses = true;
    int counts[SPH_MAX_BODIES] = {0};
    for (int i = 0; i < p->n; i++) {
        ids &= p->id[i] == i;
        if (i > 0) bodies_sorted &= p->body[i] >= p->body[i - 1];
        const sph_material *m = &s->materials[s->bodies[p->body[i]].material];
        masses &= p->mass[i] == m->density * pow(s->dp, s->dim) && p->rho[i] == m->density;
        counts[p->body[i]]++;
    }
    CHECK(c, ids, "%s: id = running index", what);
    CHECK(c, bodies_sorted, "%s: particles numbered body by body", what);
    CHECK(c, masses, "%s: m = rho0 dp^d, rho = rho0", what);
    for (int b = 0; b < s->nbodies; b++)
        CHECK(c, counts[b] == p->body_count[b], "%s: body_count[%d] = %d, counted %d", what, b,
              p->body_count[b], counts[b]);
}

static void test_oscillating_plate(test_counts *c) {
    char path[1024];
    test_repo_path("cases/oscillating_plate_2d/scene.cfg", path, sizeof path);
    sph_scene s;
    sph_error err = {0};
    sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "load: %s", err.msg);
    if (st != SPH_OK) return;
    sph_particles p;
    st = sph_particles_generate(&s, &p, &err);
    CHECK(c, st == SPH_OK, "generate: %s", err.msg);
    if (st != SPH_OK) return;
    /* beam 130 x 10 + clamp base 34 x 18 - their overlap 30 x 10 = 1612;
     * fixed: base - beam = 612 - 300 = 312 */
    CHECK(c, p.n == 1612, "n = %d", p.n);
    CHECK(c, p.dim == 2, "dim");
    CHECK(c, p.fixed != NULL && p.fixed_count == 312, "fixed_count = %d", p.fixed_count);
    CHECK(c, p.body_count[0] == 1612, "body_count[0] = %d", p.body_count[0]);
    check_bookkeeping(c, &p, &s, "plate");

    int fixed = 0;
    bool fixed_at_rest = true, fixed_in_clamp = true;
    for (int i = 0; i < p.n; i++) {
        if (!p.fixed[i]) continue;
        fixed++;
        fixed_at_rest &= p.vel[i] == 0.0 && p.vel[(size_t)p.n + (size_t)i] == 0.0;
        double x[3] = {p.pos[i], p.pos[(size_t)p.n + (size_t)i], 0.0};
        fixed_in_clamp &= sph_shape_contains(&s, 3, x);
    }
    CHECK(c, fixed == p.fixed_count, "flags = count");
    CHECK(c, fixed_at_rest, "the clamp starts at rest (s <= 0)");
    CHECK(c, fixed_in_clamp, "fixed particles lie in the clamp region");

    /* first particle: lower-left corner of the lattice, origin + dp/2 */
    CHECK_NEAR(c, p.pos[0], -0.068 + 0.001, 1e-15, "x[0]");
    CHECK_NEAR(c, p.pos[p.n], -0.018 + 0.001, 1e-15, "y[0]");
    CHECK(c, p.pos[1] > p.pos[0] && p.pos[p.n + 1] == p.pos[p.n], "x runs fastest");

    moments m = compute_moments(&p);
    if (getenv("SPH_TEST_VERBOSE")) printf("plate KE0 %.17g, max vy %.17g\n", m.ke, m.max_speed[1]);
    CHECK(c, fabs(m.ke - 4.0647984104106447) <= 1e-6 * 4.0647984104106447,
          "KE0 = %.17g J/m, reference 4.0647984104106447", m.ke);
    /* v_y(L) = 0.05 c0; the last column sits at x = 0.199, just short of L */
    double c0 = sqrt(2e6 / (3 * (1 - 2 * 0.3975) * 1000.0));
    CHECK(c, m.max_speed[1] <= 0.05 * c0 && m.max_speed[1] >= 0.99 * 0.05 * c0,
          "max |v_y| = %.10g, 0.05 c0 = %.10g", m.max_speed[1], 0.05 * c0);
    CHECK(c, m.max_speed[0] == 0.0, "no v_x");
    size_t tip = nearest(&p, 0.199, 0.009);
    CHECK(c, fabs(p.vel[(size_t)p.n + tip]) == m.max_speed[1], "fastest at the tip");
    sph_particles_free(&p);
    CHECK(c, p.pos == NULL && p.n == 0, "free clears");
    sph_particles_free(&p);
    sph_scene_free(&s);

    /* H/dp = 30 (003 Table 1): beam 390 x 30 = 11700; base (90 + 4) x (30 + 8)
     * = 3572; overlap 90 x 30 = 2700; total 11700 + 3572 - 2700 = 12572;
     * fixed 3572 - 2700 = 872 */
    const char *ratio[] = {"resolution.ratio=30"};
    st = sph_scene_load(&s, path, ratio, 1, &err);
    CHECK(c, st == SPH_OK, "load ratio 30: %s", err.msg);
    if (st != SPH_OK) return;
    st = sph_particles_generate(&s, &p, &err);
    CHECK(c, st == SPH_OK, "generate ratio 30: %s", err.msg);
    if (st == SPH_OK) {
        CHECK(c, p.n == 12572, "n = %d", p.n);
        CHECK(c, p.fixed_count == 872, "fixed_count = %d", p.fixed_count);
        CHECK(c, p.body_count[0] == 12572, "body_count[0]");
        check_bookkeeping(c, &p, &s, "plate H/dp = 30");
    }
    sph_particles_free(&p);
    sph_scene_free(&s);
}

static void test_spinning_plate(test_counts *c) {
    char path[1024];
    test_repo_path("cases/spinning_plate_2d/scene.cfg", path, sizeof path);
    sph_scene s;
    sph_error err = {0};
    sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "load: %s", err.msg);
    if (st != SPH_OK) return;
    sph_particles p;
    st = sph_particles_generate(&s, &p, &err);
    CHECK(c, st == SPH_OK, "generate: %s", err.msg);
    if (st != SPH_OK) return;
    CHECK(c, p.n == 400, "20 x 20 = 400, got %d", p.n);
    CHECK(c, p.fixed == NULL && p.fixed_count == 0, "no constraints, no fixed flags");
    check_bookkeeping(c, &p, &s, "square");
    /* m = 1100 * 0.05^2 = 2.75; sum of r^2 over the lattice = 2 * 20 *
     * 2 * 0.05^2 * sum_{k<10} (k + 1/2)^2 = 66.5; KE0 = m w^2 66.5 / 2,
     * Lz = m w 66.5 = 2 KE0 / w */
    moments m = compute_moments(&p);
    CHECK(c, fabs(m.ke - 228593.75) <= 1e-9 * 228593.75, "KE0 = %.17g", m.ke);
    CHECK(c, hypot(m.p[0], m.p[1]) < 1e-9, "|P| = %g", hypot(m.p[0], m.p[1]));
    CHECK(c, fabs(m.lz - 9143.75) <= 1e-9 * 9143.75, "Lz = %.17g", m.lz);
    CHECK(c, fabs(m.lz - 2 * m.ke / 50.0) <= 1e-9 * m.lz, "Lz = 2 KE0 / omega");
    sph_particles_free(&p);
    sph_scene_free(&s);
}

static const char CUBE[] =
    "dimension = 3;\n"
    "resolution = { dp = 0.1; };\n"
    "method = { formulation = \"enog-a\"; };\n"
    "time = { end = 0.1; output_interval = 0.01; };\n"
    "materials = { m = { density = 1000.0; youngs_modulus = 1.0e6; poisson_ratio = 0.3; }; };\n"
    "shapes = { cube = { type = \"box\"; lower = [-0.5, -0.5, -0.5]; upper = [0.5, 0.5, 0.5]; "
    "}; };\n"
    "bodies = ( { name = \"cube\"; material = \"m\"; shape = \"cube\";\n"
    "  initial_velocity = { type = \"rigid_rotation\"; omega = [0.0, 0.0, 50.0]; }; } );\n";

static void test_cube(test_counts *c) {
    char path[1024];
    test_scene_write(&tmp, CUBE, path, sizeof path);
    sph_scene s;
    sph_error err = {0};
    sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "load cube: %s", err.msg);
    if (st != SPH_OK) return;
    sph_particles p;
    st = sph_particles_generate(&s, &p, &err);
    CHECK(c, st == SPH_OK, "generate cube: %s", err.msg);
    if (st != SPH_OK) return;
    CHECK(c, p.n == 1000 && p.dim == 3, "10^3 = 1000, got %d", p.n);
    check_bookkeeping(c, &p, &s, "cube");
    /* m = 1000 * 0.1^3 = 1; sum over the lattice of x^2 + y^2 = 2 * 100 *
     * 2 * 0.1^2 * sum_{k<5} (k + 1/2)^2 = 165: KE0 = 50^2 165 / 2 = 206250,
     * Lz = 50 * 165 = 8250; no motion along the axis */
    moments m = compute_moments(&p);
    CHECK(c, fabs(m.ke - 206250.0) <= 1e-9 * 206250.0, "KE0 = %.17g", m.ke);
    CHECK(c, fabs(m.lz - 8250.0) <= 1e-9 * 8250.0, "Lz = %.17g", m.lz);
    CHECK(c, m.max_speed[2] == 0.0, "v_z = 0");
    CHECK(c, fabs(m.p[0]) < 1e-9 && fabs(m.p[1]) < 1e-9, "P = 0");
    /* z outermost: the first 100 particles form the bottom layer */
    bool layer = true;
    for (int i = 0; i < 100; i++) layer &= p.pos[2 * (size_t)p.n + (size_t)i] == -0.45;
    CHECK(c, layer && p.pos[2 * (size_t)p.n + 100] > -0.45, "z runs slowest");
    sph_particles_free(&p);
    sph_scene_free(&s);
}

/* Two bodies that touch along x = 1 (overlapping bodies are an error). */
static const char TWO[] =
    "dimension = 2;\n"
    "resolution = { dp = 0.1; };\n"
    "method = { formulation = \"enog\"; };\n"
    "time = { end = 0.1; output_interval = 0.01; };\n"
    "materials = { a = { density = 1000.0; youngs_modulus = 1.0e6; poisson_ratio = 0.3; };\n"
    "              b = { density = 2000.0; youngs_modulus = 1.0e6; poisson_ratio = 0.3; }; };\n"
    "shapes = { left = { type = \"box\"; lower = [0.0, 0.0]; upper = [1.0, 1.0]; };\n"
    "           right = { type = \"box\"; lower = [1.0, 0.0]; upper = [1.5, 1.0]; };\n"
    "           edge = { type = \"box\"; lower = [1.4, 0.0]; upper = [1.5, 1.0]; }; };\n"
    "bodies = ( { name = \"l\"; material = \"a\"; shape = \"left\"; },\n"
    "           { name = \"r\"; material = \"b\"; shape = \"right\";\n"
    "             initial_velocity = { type = \"uniform\"; vector = [1.0, -2.0]; };\n"
    "             constraints = ( { type = \"fixed\"; region = \"edge\"; } ); } );\n";

static void test_two_bodies(test_counts *c) {
    char path[1024];
    test_scene_write(&tmp, TWO, path, sizeof path);
    sph_scene s;
    sph_error err = {0};
    sph_status st = sph_scene_load(&s, path, NULL, 0, &err);
    CHECK(c, st == SPH_OK, "load two bodies: %s", err.msg);
    if (st != SPH_OK) return;
    sph_particles p;
    st = sph_particles_generate(&s, &p, &err);
    CHECK(c, st == SPH_OK, "generate two bodies: %s", err.msg);
    if (st == SPH_OK) {
        /* left: 10 x 10; right: 5 x 10 */
        CHECK(c, p.n == 150 && p.body_count[0] == 100 && p.body_count[1] == 50,
              "n %d, counts %d %d", p.n, p.body_count[0], p.body_count[1]);
        /* one column of the right body is fixed; flags exist for every body */
        CHECK(c, p.fixed && p.fixed_count == 10, "fixed_count %d", p.fixed_count);
        check_bookkeeping(c, &p, &s, "two bodies");
        const size_t n = (size_t)p.n;
        bool ok = true;
        for (size_t i = 0; i < n; i++) {
            if (p.body[i] == 1)
                ok &= p.pos[i] > 1.0 && p.vel[i] == 1.0 && p.vel[n + i] == -2.0 &&
                      fabs(p.mass[i] - 20.0) < 1e-12;
            else
                ok &= p.vel[i] == 0.0 && p.fixed[i] == 0;
        }
        CHECK(c, ok, "ownership, uniform velocity, per-body material");
    }
    sph_particles_free(&p);
    sph_scene_free(&s);

    /* a user lattice origin shifts the grid, here by a quarter spacing */
    const char *origin[] = {"lattice_origin=[0.025, 0.0]"};
    st = sph_scene_load(&s, path, origin, 1, &err);
    CHECK(c, st == SPH_OK, "lattice origin: %s", err.msg);
    if (st == SPH_OK && sph_particles_generate(&s, &p, &err) == SPH_OK) {
        /* centres at x = 0.075, 0.175, ...: 10 columns in [0, 1], 5 more in (1, 1.5] */
        CHECK(c, p.n == 150 && fabs(p.pos[0] - 0.075) < 1e-12, "n %d, x0 %g", p.n, p.pos[0]);
        sph_particles_free(&p);
    }
    sph_scene_free(&s);

    /* replacing a list element keeps its place in the list */
    const char *replace[] = {"bodies.[0]={ name = \"l2\"; material = \"a\"; shape = \"left\"; }"};
    st = sph_scene_load(&s, path, replace, 1, &err);
    CHECK(c,
          st == SPH_OK && strcmp(s.bodies[0].name, "l2") == 0 && strcmp(s.bodies[1].name, "r") == 0,
          "replaced body 0: %s", err.msg);
    if (st == SPH_OK && sph_particles_generate(&s, &p, &err) == SPH_OK) {
        CHECK(c, p.body_count[0] == 100 && p.body_count[1] == 50, "same ownership");
        sph_particles_free(&p);
    }
    sph_scene_free(&s);

    /* a body inside an earlier one overlaps it: an error naming both */
    const char *hidden[] = {"bodies.r.shape=\"edge\"", "bodies.l.shape=right"};
    st = sph_scene_load(&s, path, hidden, 2, &err);
    CHECK(c, st == SPH_OK, "hidden: %s", err.msg);
    if (st == SPH_OK) {
        st = sph_particles_generate(&s, &p, &err);
        CHECK(c,
              st == SPH_ERR_INPUT && strstr(err.msg, ":11: bodies.r: overlaps body 'l'") &&
                  strstr(err.msg, ":10: bodies.l"),
              "overlapping bodies: status %d, '%s'", st, err.msg);
        CHECK(c, p.pos == NULL && p.n == 0, "nothing allocated on failure");
    }
    sph_scene_free(&s);

    /* a body thinner than the spacing has no particles */
    const char *thin[] = {"shapes.right.upper=[1.04, 1.0]", "shapes.edge.lower=[1.0, 0.0]"};
    st = sph_scene_load(&s, path, thin, 2, &err);
    CHECK(c, st == SPH_OK, "thin: %s", err.msg);
    if (st == SPH_OK) {
        st = sph_particles_generate(&s, &p, &err);
        CHECK(c,
              st == SPH_ERR_INPUT && strstr(err.msg, "bodies.r") && strstr(err.msg, "no particles"),
              "empty body: status %d, '%s'", st, err.msg);
        CHECK(c, p.pos == NULL && p.n == 0, "nothing allocated on failure");
    }
    sph_scene_free(&s);
}

static void test_velocity_fields(test_counts *c) {
    sph_scene s;
    memset(&s, 0, sizeof s);
    s.dim = 2;
    s.nmaterials = 1;
    s.materials[0].sound_speed = 10.0;
    sph_body b;
    memset(&b, 0, sizeof b);
    b.velocity.type = SPH_VELOCITY_CANTILEVER_MODE;
    b.velocity.amplitude_c0 = 0.1;
    b.velocity.length = 2.0;
    b.velocity.kl = 1.875;
    b.velocity.clamp_x = 1.0;
    b.velocity.axis = 1;
    double v[3], x[3] = {3.0, 0.5, 0.0};
    /* at the free end s = L: v = amplitude c0 exactly */
    sph_velocity_field_eval(&s, &b, x, v);
    CHECK_NEAR(c, v[1], 1.0, 1e-12, "cantilever tip");
    CHECK(c, v[0] == 0.0, "only the chosen axis");
    x[0] = 0.5; /* behind the clamp */
    sph_velocity_field_eval(&s, &b, x, v);
    CHECK(c, v[1] == 0.0, "at rest behind the clamp");
    x[0] = 2.0; /* mid-span: the mode is below the tip value and positive */
    sph_velocity_field_eval(&s, &b, x, v);
    CHECK(c, v[1] > 0.0 && v[1] < 1.0, "mid-span %g", v[1]);

    b.velocity.type = SPH_VELOCITY_RIGID_ROTATION;
    b.velocity.omega[2] = 2.0;
    b.velocity.centre[0] = 1.0;
    x[0] = 1.0;
    x[1] = 3.0;
    sph_velocity_field_eval(&s, &b, x, v);
    CHECK(c, v[0] == -6.0 && v[1] == 0.0, "2D rotation (%g, %g)", v[0], v[1]);
    s.dim = 3;
    b.velocity.omega[0] = 1.0;
    b.velocity.omega[2] = 0.0;
    x[2] = 4.0;
    sph_velocity_field_eval(&s, &b, x, v); /* (1,0,0) x (0,3,4) = (0,-4,3) */
    CHECK(c, v[0] == 0.0 && v[1] == -4.0 && v[2] == 3.0, "3D rotation");
}

/* The colliding rings of 000 §6.3 on the lattice: particle counts close to
 * the rings' area, and the two rings mirror images of each other in x = 0
 * particle by particle, to the round-off of the lattice coordinates, 1e-15
 * m (the lattice spans 0.17 x 0.08 from the lower
 * corner (-0.085, -0.04), a whole number of spacings at dp = 0.001, 0.002,
 * 0.0025), so that the collision is symmetric to round-off. */
static void test_rings(test_counts *c) {
    char path[1024];
    test_case_path("colliding_rings_2d", path, sizeof path);
    const double dps[3] = {0.001, 0.002, 0.0025};
    for (int k = 0; k < 3; ++k) {
        char set[64];
        snprintf(set, sizeof set, "resolution.dp=%g", dps[k]);
        const char *ov[1] = {set};
        sph_scene s;
        sph_particles p;
        sph_error err = {0};
        sph_status st = sph_scene_load(&s, path, ov, 1, &err);
        if (!st) st = sph_particles_generate(&s, &p, &err);
        CHECK(c, st == SPH_OK, "rings at dp %g: %s", dps[k], err.msg);
        if (st) {
            if (s.resolved_text) sph_scene_free(&s);
            continue;
        }
        const int n = p.n;
        const double area = 3.14159265358979323846 * (0.04 * 0.04 - 0.03 * 0.03);
        const double expected = area / (dps[k] * dps[k]);
        long unmatched = 0;
        for (int i = 0; i < n; ++i) {
            if (p.body[i] != 0) continue;
            bool found = false;
            for (int j = 0; j < n && !found; ++j)
                found = p.body[j] == 1 && fabs(p.pos[j] + p.pos[i]) < 1e-15 &&
                        fabs(p.pos[n + j] - p.pos[n + i]) < 1e-15;
            if (!found) ++unmatched;
        }
        printf("rings at dp %g: %d particles per ring (area / dp^2 = %.1f), %ld unmatched\n",
               dps[k], p.body_count[0], expected, unmatched);
        CHECK(c, p.body_count[0] == p.body_count[1] && n == 2 * p.body_count[0],
              "dp %g: ring counts %d, %d", dps[k], p.body_count[0], p.body_count[1]);
        /* measured 2196, 548, 364 against 2199.1, 549.8, 351.9 */
        CHECK(c, fabs(p.body_count[0] - expected) < 0.04 * expected, "dp %g: %d particles", dps[k],
              p.body_count[0]);
        CHECK(c, unmatched == 0, "dp %g: %ld particles of the left ring have no mirror image",
              dps[k], unmatched);
        check_bookkeeping(c, &p, &s, "rings");
        sph_particles_free(&p);
        sph_scene_free(&s);
    }
}

/* Largest |v_expr - v_builtin| over the particles and over the components,
 * and the largest |v_builtin| (both sets place the same particles). */
static void velocity_difference(const sph_particles *a, const sph_particles *b, double *diff,
                                double *scale) {
    *diff = 0.0;
    *scale = 0.0;
    const size_t n = (size_t)a->n;
    for (size_t i = 0; i < (size_t)a->dim * n; i++) {
        *diff = fmax(*diff, fabs(a->vel[i] - b->vel[i]));
        *scale = fmax(*scale, fabs(b->vel[i]));
    }
}

/* The initial velocity as an expression (host/setup/expression.c) against the
 * built-in field it writes out, on the same case: the spinning plate's
 * rigid rotation and the 3D plate's mode (2, 2).  The expressions perform
 * the built-in's operations on the same doubles (`pi` is the double nearest
 * pi in both), but muParser's bytecode may fold or reorder a constant (x / 0.4
 * as x * 2.5): a result or a sine's argument may move by an ulp or two.
 * Tolerance: 4 DBL_EPSILON * `scale`, with scale = max |v| for the rotation
 * (a product of exact-rounded terms) and amplitude * (largest sine argument,
 * m pi = 2 pi) for the mode (an argument's ulp passes through sin with slope
 * at most 1, times the other factor, at most 1). */
static void check_expression_matches(test_counts *c, const char *scene_path, const char *what,
                                     const char *const *overrides, int noverrides,
                                     const char *const *expression_overrides, int nexpr,
                                     double scale_floor) {
    sph_scene builtin, expr;
    sph_error err = {0};
    sph_status st = sph_scene_load(&builtin, scene_path, overrides, noverrides, &err);
    CHECK(c, st == SPH_OK, "%s: load built-in: %s", what, err.msg);
    if (st != SPH_OK) return;
    const char *all[8];
    int nall = 0;
    for (int k = 0; k < noverrides; k++) all[nall++] = overrides[k];
    for (int k = 0; k < nexpr; k++) all[nall++] = expression_overrides[k];
    st = sph_scene_load(&expr, scene_path, all, nall, &err);
    CHECK(c, st == SPH_OK, "%s: load expression: %s", what, err.msg);
    if (st != SPH_OK) {
        sph_scene_free(&builtin);
        return;
    }
    CHECK(c, expr.bodies[0].velocity.type == SPH_VELOCITY_EXPRESSION, "%s: expression type", what);
    sph_particles pb, pe;
    st = sph_particles_generate(&builtin, &pb, &err);
    CHECK(c, st == SPH_OK, "%s: generate built-in: %s", what, err.msg);
    if (st == SPH_OK) {
        st = sph_particles_generate(&expr, &pe, &err);
        CHECK(c, st == SPH_OK, "%s: generate expression: %s", what, err.msg);
        if (st == SPH_OK) {
            CHECK(c, pe.n == pb.n && pe.n > 0, "%s: same particles (%d, %d)", what, pe.n, pb.n);
            if (pe.n == pb.n) {
                double diff, scale;
                velocity_difference(&pe, &pb, &diff, &scale);
                CHECK(c, scale > 0.0 && diff <= 4.0 * DBL_EPSILON * fmax(scale, scale_floor),
                      "%s: max |v_expression - v_built-in| = %.3g, max |v| = %.17g", what, diff,
                      scale);
                printf("%s: %d particles, max |v_expression - v_built-in| = %.3g (max |v| "
                       "%.6g)\n",
                       what, pe.n, diff, scale);
            }
            sph_particles_free(&pe);
        }
        sph_particles_free(&pb);
    }
    sph_scene_free(&expr);
    sph_scene_free(&builtin);
}

static void test_expression_velocity(test_counts *c) {
    char path[1024];
    /* cases/spinning_plate_2d: rigid_rotation, omega = 50, centre (0, 0) */
    test_repo_path("cases/spinning_plate_2d/scene.cfg", path, sizeof path);
    const char *const rotation[] = {
        "constants={ w = 50.0; cx = 0.0; cy = 0.0; }",
        "bodies.plate.initial_velocity={ type = \"expression\"; x = \"-w * (y - cy)\"; "
        "y = \"w * (x - cx)\"; }"};
    check_expression_matches(c, path, "spinning plate, rigid rotation", NULL, 0, rotation, 2, 0.0);
    /* cases/oscillating_plate_3d at dp = 0.02: plate_mode, amplitude 1,
     * lower (0, 0), size (0.4, 0.4), modes (2, 2), axis z */
    test_repo_path("cases/oscillating_plate_3d/scene.cfg", path, sizeof path);
    const char *const coarse[] = {"resolution.dp=0.02"};
    const char *const mode[] = {
        "bodies.plate.initial_velocity={ type = \"expression\"; z = \"1.0 * sin(2 * pi * (x - "
        "0.0) / 0.4) * sin(2 * _pi * (y - 0.0) / 0.4)\"; }"};
    check_expression_matches(c, path, "3D plate, mode (2, 2)", coarse, 1, mode, 1,
                             1.0 * 2.0 * 3.14159265358979323846);

    /* a value that is not finite at a particle names the key and the particle */
    test_repo_path("cases/spinning_plate_2d/scene.cfg", path, sizeof path);
    const char *const pole[] = {"bodies.plate.initial_velocity={ type = \"expression\"; "
                                "x = \"x > 0.4 && y > 0.4 ? 1 / (x - x) : 0\"; }"};
    sph_scene s;
    sph_error err = {0};
    sph_status st = sph_scene_load(&s, path, pole, 1, &err);
    CHECK(c, st == SPH_OK, "pole: load: %s", err.msg);
    if (st != SPH_OK) return;
    sph_particles p;
    st = sph_particles_generate(&s, &p, &err);
    CHECK(c,
          st == SPH_ERR_INPUT &&
              strstr(err.msg, "bodies.plate.initial_velocity.x: the "
                              "expression \"x > 0.4") &&
              strstr(err.msg, "gives inf at the particle at (0.425, 0.425)"),
          "pole: %s", err.msg);
    if (st == SPH_OK) sph_particles_free(&p);
    sph_scene_free(&s);
}

/* The flow around a cylinder in small (seed 004 §4.3; docs/scene-format.md,
 * "Fluids"): the box [0, 6] x [0, 4] at dp = 0.1, a wall disc r = 0.5 at
 * (2, 2) on its own lattice at dp/2, the far field U = (1, 0) on the four
 * faces.  `wall_extra` goes into the wall body's group, `order` puts the
 * wall first (1) or last (0). */
static sph_status load_cylinder(sph_scene *s, const char *wall_extra, int wall_first,
                                const char *boundary, sph_error *err) {
    char text[4096], path[1024];
    char wall[512], fluid[256];
    snprintf(wall, sizeof wall, "{ name = \"cyl\"; role = \"wall\"; shape = \"disc\"; %s }",
             wall_extra);
    snprintf(fluid, sizeof fluid, "{ name = \"fluid\"; material = \"water\"; shape = \"box\"; }");
    snprintf(text, sizeof text,
             "dimension = 2;\n"
             "resolution = { dp = 0.1; };\n"
             "method = { formulation = \"eulerian-wc\"; kernel = \"laguerre-gauss\"; };\n"
             "time = { end = 1.0; output_interval = 0.1; };\n"
             "materials = { water = { density = 1.0; sound_speed = 10.0; viscosity = 0.02; }; };\n"
             "shapes = {\n"
             "  box = { type = \"box\"; lower = [0.0, 0.0]; upper = [6.0, 4.0]; };\n"
             "  disc = { type = \"disc\"; centre = [2.0, 2.0]; radius = 0.5; };\n"
             "};\n"
             "bodies = ( %s, %s );\n"
             "boundary = { %s lower = [0.0, 0.0]; upper = [6.0, 4.0]; };\n"
             "forces = { reference_length = 1.0; reference_speed = 1.0; };\n",
             wall_first ? wall : fluid, wall_first ? fluid : wall, boundary);
    test_scene_write(&tmp, text, path, sizeof path);
    return sph_scene_load(s, path, NULL, 0, err);
}

#define FAR_FIELD "far_field = { density = 1.0; velocity = [1.0, 0.0]; };"

/* Wall particles: kind, mass rho (dp/2)^2, inside the disc (at least
 * `inset` inside), unit radial normals; returns their count. */
static int check_wall(test_counts *c, const sph_particles *p, int wall_body, double inset,
                      const char *what) {
    const size_t n = (size_t)p->n;
    const double cx = 2.0, cy = 2.0, r = 0.5, s = 0.05;
    int count = 0;
    bool kinds = true, masses = true, inside = true, unit = true, radial = true;
    double worst_dot = 1.0, worst_unit = 0.0;
    for (size_t i = 0; i < n; i++) {
        if (p->body[i] != wall_body) continue;
        count++;
        const double x = p->pos[i] - cx, y = p->pos[n + i] - cy, d = sqrt(x * x + y * y);
        const double nx = p->normal[i], ny = p->normal[n + i];
        const double len = sqrt(nx * nx + ny * ny), dot = (nx * x + ny * y) / d;
        kinds &= p->kind[i] == SPH_PARTICLE_WALL;
        masses &= fabs(p->mass[i] - s * s) < 1e-15 && p->rho[i] == 1.0;
        inside &= d <= r - inset + 1e-12;
        unit &= fabs(len - 1.0) < 1e-12;
        radial &= dot > 0.99;
        worst_unit = fmax(worst_unit, fabs(len - 1.0));
        worst_dot = fmin(worst_dot, dot);
    }
    CHECK(c, kinds, "%s: wall particles are SPH_PARTICLE_WALL", what);
    CHECK(c, masses, "%s: wall mass rho (dp/2)^2 = 0.0025, rho rho0", what);
    CHECK(c, inside, "%s: wall particles inside the disc, %g from its surface", what, inset);
    CHECK(c, unit, "%s: unit normals (worst |n| - 1 = %g)", what, worst_unit);
    CHECK(c, radial, "%s: radial normals, out of the wall (worst dot %g)", what, worst_dot);
    /* pi r^2 / (dp/2)^2 = 314.16 */
    const double area = 3.14159265358979323846 * r * r / (s * s);
    CHECK(c, fabs(count - area) <= 0.1 * area, "%s: %d wall particles, pi r^2 / (dp/2)^2 = %.1f",
          what, count, area);
    return count;
}

static void test_cylinder(test_counts *c) {
    sph_scene s;
    sph_error err = {0};
    sph_particles p;
    sph_status st = load_cylinder(&s, "", 0, FAR_FIELD, &err);
    CHECK(c, st == SPH_OK, "cylinder scene: %s", err.msg);
    if (st != SPH_OK) return;
    st = sph_particles_generate(&s, &p, &err);
    CHECK(c, st == SPH_OK, "cylinder particles: %s", err.msg);
    int nwall = 0, nfluid = 0;
    if (st == SPH_OK) {
        const size_t n = (size_t)p.n;
        CHECK(c, p.kind != NULL && p.normal != NULL, "kind and normal allocated");
        if (!p.kind || !p.normal) {
            sph_particles_free(&p);
            sph_scene_free(&s);
            return;
        }
        nwall = check_wall(c, &p, 1, 0.0, "lattice wall");
        /* the wall lattice is anchored at the scene's origin (0, 0):
         * its points are (i + 1/2) dp/2 */
        bool aligned = true;
        for (size_t i = 0; i < n; i++) {
            if (p.body[i] != 1) continue;
            for (int a = 0; a < 2; a++) {
                const double k = p.pos[(size_t)a * n + i] / 0.05 - 0.5;
                aligned &= fabs(k - round(k)) < 1e-9;
            }
        }
        CHECK(c, aligned, "wall lattice (i + 1/2) dp/2 from the origin");
        /* fluid: not inside the disc, on the dp lattice, mass rho0 dp^2;
         * within 2h = 0.26 of a face: inflow or outflow with the nearest
         * face's outward normal, else plain fluid with no normal */
        const double cutoff = 2.0 * 1.3 * 0.1;
        bool outside = true, masses = true, kinds = true;
        int per_face[4] = {0, 0, 0, 0}, plain = 0, inside_lattice = 0;
        for (size_t i = 0; i < n; i++) {
            if (p.body[i] != 0) continue;
            nfluid++;
            const double x = p.pos[i], y = p.pos[n + i];
            outside &= hypot(x - 2.0, y - 2.0) > 0.5;
            masses &= fabs(p.mass[i] - 0.01) < 1e-16 && p.rho[i] == 1.0;
            const double dist[4] = {x, 6.0 - x, y, 4.0 - y}; /* left, right, bottom, top */
            const double normals[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
            /* the nearest face within 2h; rounding-level ties to the first */
            int face = -1;
            double best = INFINITY;
            for (int f = 0; f < 4; f++)
                if (dist[f] < cutoff && dist[f] < best - 1e-10) best = dist[f], face = f;
            if (face < 0) {
                plain++;
                kinds &=
                    p.kind[i] == SPH_PARTICLE_FLUID && p.normal[i] == 0.0 && p.normal[n + i] == 0.0;
                continue;
            }
            per_face[face]++;
            const uint8_t expect = face == 1 ? SPH_PARTICLE_OUTFLOW : SPH_PARTICLE_INFLOW;
            kinds &= p.kind[i] == expect && p.normal[i] == normals[face][0] &&
                     p.normal[n + i] == normals[face][1];
        }
        for (long i = 0; i < 60; i++)
            for (long j = 0; j < 40; j++)
                inside_lattice += hypot(0.05 + 0.1 * i - 2.0, 0.05 + 0.1 * j - 2.0) <= 0.5;
        CHECK(c, outside, "no fluid particle inside the disc");
        CHECK(c, nfluid == 2400 - inside_lattice, "fluid: %d = 60 x 40 - %d in the disc", nfluid,
              inside_lattice);
        CHECK(c, masses, "fluid mass rho0 dp^2");
        CHECK(c, kinds, "far-field kinds and normals (nearest face, ties the first axis)");
        CHECK(c, per_face[0] > 0 && per_face[1] > 0 && per_face[2] > 0 && per_face[3] > 0,
              "far-field particles on all four faces: left %d right %d bottom %d top %d",
              per_face[0], per_face[1], per_face[2], per_face[3]);
        int outflow = 0, inflow = 0;
        for (size_t i = 0; i < n; i++) {
            outflow += p.kind[i] == SPH_PARTICLE_OUTFLOW;
            inflow += p.kind[i] == SPH_PARTICLE_INFLOW;
        }
        CHECK(c, outflow == per_face[1] && inflow == per_face[0] + per_face[2] + per_face[3],
              "outflow %d (right face only, U . n > 0), inflow %d (left, bottom, top)", outflow,
              inflow);
        /* three layers (0.05, 0.15, 0.25 < 2h = 0.26) along each face; of
         * the 3 x 3 points of a corner, the 6 with |x - face| <= |y - face|
         * (ties to x) go to the left or right face: 3 x 40 - 2 x 3 there,
         * 3 x 60 - 2 x 6 on the bottom and top */
        CHECK(c,
              per_face[0] == 114 && per_face[1] == 114 && per_face[2] == 168 &&
                  per_face[3] == 168 && plain == nfluid - 564,
              "layers: left %d right %d (114), bottom %d top %d (168)", per_face[0], per_face[1],
              per_face[2], per_face[3]);
        sph_particles_free(&p);
        CHECK(c, p.kind == NULL && p.normal == NULL, "freed");
    }
    sph_scene_free(&s);

    /* the wall first in scene order: the same particles, the wall's first */
    st = load_cylinder(&s, "", 1, FAR_FIELD, &err);
    CHECK(c, st == SPH_OK, "wall first: %s", err.msg);
    if (st == SPH_OK) {
        st = sph_particles_generate(&s, &p, &err);
        CHECK(c, st == SPH_OK, "wall first: particles: %s", err.msg);
        if (st == SPH_OK) {
            CHECK(c, p.body_count[0] == nwall && p.body_count[1] == nfluid && p.body[0] == 0,
                  "wall first: %d wall, %d fluid", p.body_count[0], p.body_count[1]);
            sph_particles_free(&p);
        }
        sph_scene_free(&s);
    }

    /* a relaxed wall at its own spacing: the same count, dp/4 inside the
     * surface, normals still radial */
    st = load_cylinder(&s, "placement = \"relaxed\"; relaxation = { steps = 100; };", 0, FAR_FIELD,
                       &err);
    CHECK(c, st == SPH_OK, "relaxed wall: %s", err.msg);
    if (st == SPH_OK) {
        st = sph_particles_generate(&s, &p, &err);
        CHECK(c, st == SPH_OK, "relaxed wall: particles: %s", err.msg);
        if (st == SPH_OK) {
            const int count = check_wall(c, &p, 1, 0.025 - 1e-9, "relaxed wall");
            const sph_relax_report *r = &p.relax[1];
            printf("cylinder r = 0.5 at dp = 0.1: %d wall particles at dp/2 (pi r^2 / (dp/2)^2 = "
                   "314.2), %d fluid; relaxed wall: residual mean %.4g (lattice %.4g, start %.4g), "
                   "closest pair %.3f dp/2\n",
                   nwall, nfluid, r->mean, r->lattice_mean, r->start_mean, r->min_distance);
            CHECK(c, count == nwall && r->relaxed && r->steps == 100 && r->particles == nwall,
                  "relaxed wall: %d particles (lattice %d), %d steps", count, nwall, r->steps);
            /* the residual and closest pair are measured at the wall's
             * spacing: the closest pair in units of dp/2 */
            CHECK(c, r->mean < r->start_mean && r->min_distance > 0.5 && r->min_distance < 1.5,
                  "relaxed wall: residual %g (start %g), closest pair %g spacings", r->mean,
                  r->start_mean, r->min_distance);
            sph_particles_free(&p);
        }
        sph_scene_free(&s);
    }

    /* a periodic channel along x with the wall, no far field: kinds
     * allocated, every fluid particle plain fluid; the wall's lattice
     * passes the periodic check */
    st = load_cylinder(&s, "spacing = 0.25;", 0, "periodic = [\"x\", \"y\"];", &err);
    CHECK(c, st == SPH_OK, "periodic with a wall: %s", err.msg);
    if (st == SPH_OK) {
        st = sph_particles_generate(&s, &p, &err);
        CHECK(c, st == SPH_OK, "periodic with a wall: particles: %s", err.msg);
        if (st == SPH_OK) {
            const size_t n = (size_t)p.n;
            bool plain = p.kind != NULL;
            int walls = 0;
            for (size_t i = 0; plain && i < n; i++) {
                walls += p.kind[i] == SPH_PARTICLE_WALL;
                if (p.body[i] == 0)
                    plain &= p.kind[i] == SPH_PARTICLE_FLUID && p.normal[i] == 0.0 &&
                             p.normal[n + i] == 0.0;
                else
                    plain &=
                        p.kind[i] == SPH_PARTICLE_WALL && fabs(p.mass[i] - 0.025 * 0.025) < 1e-16;
            }
            /* pi r^2 / (dp/4)^2 = 1256.6 */
            CHECK(c, plain && fabs(walls - 1256.6) < 0.05 * 1256.6,
                  "periodic: plain fluid, %d wall particles at dp/4", walls);
            sph_particles_free(&p);
        }
        sph_scene_free(&s);
    }
}

int main(void) {
    test_counts c = {0, 0};
    if (test_scene_dir_open(&tmp, "test_particles") != 0) return 2;
    test_oscillating_plate(&c);
    test_spinning_plate(&c);
    test_cube(&c);
    test_two_bodies(&c);
    test_velocity_fields(&c);
    test_rings(&c);
    test_expression_velocity(&c);
    test_cylinder(&c);
    test_scene_dir_close(&tmp);
    return test_summary("test_particles", &c);
}
