/* kernel_study.c — the kernel study of 004 §2.2-2.3 (see kernel_study.h):
 * relax a disc with each kernel and kappa, measure the truncation error of
 * df/dx (004 eq. 6) without and with the correction matrix (eq. 5) and the
 * relaxation residue (eq. 4), write JSON and per-particle CSV. */
#include "kernel_study.h"

#include "physics.h"
#include "grid.h"
#include "output.h"
#include "particles.h"
#include "scene.h"
#include "shape_sdf.h"
#include "sph_constants.h"
#include "wall_clock.h"

#include <errno.h>
#include <json-c/json.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_CASES       64
#define MAX_LIST        16
#define DEFAULT_DP      (1.0 / 60.0)
#define DEFAULT_OUT     "runs/kernel-study"
#define REFERENCE_KAPPA 1.3 /* h = 1.3 dp_ref for every kappa (004 §2.2) */
#define DISC_RADIUS     1.0 /* D = 2 (004 §2.2) */
#define TWO_PI          6.28318530717958647692

/* the functions of 004 §2.2, in the JSON's order */
enum { F_ONE = 0, F_SIN = 1, NFUNC = 2 };
static const char *const FUNCTION_NAMES[NFUNC] = {"one", "sin"};

typedef struct {
    sph_kernel kernel;
    double kappa;
} ks_case;

typedef struct {
    const char *out;
    double dp_ref; /* the spacing at kappa = 1.3: h = 1.3 dp_ref */
    int steps;     /* relaxation steps */
    /* relaxation.step: "fixed" (the default: the relaxation tutorial's step,
     * under each kernel's stability limit) or "normalised" (relax.h) */
    const char *step;
    long long seed;
    double exclude; /* boundary band excluded from the statistics, in h */
    int ncases;
    ks_case cases[MAX_CASES];
} ks_options;

/* One case's result; pos, residue and interior are owned (ks_result_free). */
typedef struct {
    ks_case c;
    double dp, h;
    int n, interior_count, steps;
    double step_alpha; /* the fixed step's alpha (0: normalised) */
    double relax_seconds, eval_seconds;
    double *pos;     /* [2 n], component-major as in sph_particles */
    double *residue; /* [n] |2 sum_j V_j grad_i W_ij| (no boundary term) */
    bool *interior;  /* [n] at least exclude h from the surface: in the statistics */
    int singular;    /* interior particles whose moment matrix could not be inverted */
    /* [corrected][function]: L1 and Linf of |e_i| and of its x component */
    double l1[2][NFUNC], linf[2][NFUNC], l1x[2][NFUNC], linfx[2][NFUNC];
    double res_mean, res_min, res_max;
    /* the relaxation's own report (|sum grad W V + boundary| h, all particles) */
    double project_mean, project_max, min_distance;
} ks_result;

static void ks_result_free(ks_result *r) {
    free(r->pos);
    free(r->residue);
    free(r->interior);
    memset(r, 0, sizeof *r);
}

/* ------------------------------------------------------------------------ */
/* flags                                                                      */
/* ------------------------------------------------------------------------ */

static int flag_error(const char *fmt, const char *arg) {
    fprintf(stderr, "sphsolid kernel-study: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(run `sphsolid --help` for usage)\n");
    return SPH_ERR_INPUT;
}

static bool parse_double(const char *s, double *v) {
    char *end = NULL;
    errno = 0;
    const double x = strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !isfinite(x)) return false;
    *v = x;
    return true;
}

static bool kernel_from_name(const char *name, sph_kernel *k) {
    static const sph_kernel studied[] = {SPH_KERNEL_WENDLAND_C2, SPH_KERNEL_LAGUERRE_WENDLAND,
                                         SPH_KERNEL_LAGUERRE_GAUSS};
    for (size_t i = 0; i < sizeof studied / sizeof studied[0]; i++)
        if (strcmp(name, sph_kernel_name(studied[i])) == 0) {
            *k = studied[i];
            return true;
        }
    return false;
}

/* Split a comma-separated list in place (at most MAX_LIST items). */
static int split_list(char *s, char **items) {
    int n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(s, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (n == MAX_LIST) return -1;
        items[n++] = tok;
    }
    return n;
}

/* The tables' kappas of each kernel (004 Tables 1-4). */
static int table_kappas(sph_kernel k, double *kappas) {
    if (k == SPH_KERNEL_LAGUERRE_GAUSS) {
        kappas[0] = 1.1, kappas[1] = 1.3, kappas[2] = 1.6;
    } else {
        kappas[0] = 1.3, kappas[1] = 2.0, kappas[2] = 2.5;
    }
    return 3;
}

static int parse_flags(int argc, char **argv, ks_options *o) {
    memset(o, 0, sizeof *o);
    o->out = DEFAULT_OUT;
    o->dp_ref = DEFAULT_DP;
    o->steps = 1000;
    o->step = "fixed";
    o->seed = 1;
    o->exclude = 2.0;
    const char *kappa_arg = NULL, *kernel_arg = NULL;
    for (int k = 0; k < argc; k++) {
        const char *a = argv[k];
        const bool valued = strcmp(a, "--out") == 0 || strcmp(a, "--dp") == 0 ||
                            strcmp(a, "--kappas") == 0 || strcmp(a, "--kernels") == 0 ||
                            strcmp(a, "--steps") == 0 || strcmp(a, "--seed") == 0 ||
                            strcmp(a, "--exclude") == 0 || strcmp(a, "--step") == 0;
        if (!valued)
            return flag_error(a[0] == '-' ? "unknown option %s" : "unexpected argument %s", a);
        if (k + 1 >= argc) return flag_error("%s needs a value", a);
        const char *v = argv[++k];
        double x = 0.0;
        if (strcmp(a, "--out") == 0) {
            if (!v[0]) return flag_error("%s", "--out needs a directory");
            o->out = v;
        } else if (strcmp(a, "--dp") == 0) {
            if (!parse_double(v, &x) || !(x > 0.0) || x > 0.25)
                return flag_error("--dp %s: expected a spacing in (0, 0.25] (the disc's D is 2)",
                                  v);
            o->dp_ref = x;
        } else if (strcmp(a, "--steps") == 0) {
            if (!parse_double(v, &x) || x != floor(x) || x < 0 || x > 1000000)
                return flag_error("--steps %s: expected a whole number in [0, 1000000]", v);
            o->steps = (int)x;
        } else if (strcmp(a, "--step") == 0) {
            if (strcmp(v, "fixed") != 0 && strcmp(v, "normalised") != 0)
                return flag_error("--step %s: expected fixed or normalised", v);
            o->step = v;
        } else if (strcmp(a, "--seed") == 0) {
            if (!parse_double(v, &x) || x != floor(x) || x < 0 || x > 1e15)
                return flag_error("--seed %s: expected a whole number >= 0", v);
            o->seed = (long long)x;
        } else if (strcmp(a, "--exclude") == 0) {
            /* below 2h the support of a counted particle would reach
             * beyond the surface, where eq. 6's sums miss the kernel */
            if (!parse_double(v, &x) || x < 2.0 || x > 20.0)
                return flag_error("--exclude %s: expected a depth in [2, 20] (units of h)", v);
            o->exclude = x;
        } else if (strcmp(a, "--kappas") == 0) {
            kappa_arg = v;
        } else {
            kernel_arg = v;
        }
    }
    sph_kernel kernels[MAX_LIST] = {SPH_KERNEL_WENDLAND_C2, SPH_KERNEL_LAGUERRE_WENDLAND,
                                    SPH_KERNEL_LAGUERRE_GAUSS};
    int nkernels = 3;
    char buf[1024];
    char *items[MAX_LIST];
    if (kernel_arg) {
        if (strlen(kernel_arg) >= sizeof buf) return flag_error("%s", "--kernels: list too long");
        snprintf(buf, sizeof buf, "%s", kernel_arg);
        nkernels = split_list(buf, items);
        if (nkernels <= 0)
            return flag_error("--kernels %s: expected 1 to 16 names separated by commas",
                              kernel_arg);
        for (int i = 0; i < nkernels; i++)
            if (!kernel_from_name(items[i], &kernels[i]))
                return flag_error("--kernels: unknown kernel '%s' (wendland-c2, "
                                  "laguerre-wendland, laguerre-gauss)",
                                  items[i]);
    }
    double kappas[MAX_LIST];
    int nkappas = 0;
    if (kappa_arg) {
        if (strlen(kappa_arg) >= sizeof buf) return flag_error("%s", "--kappas: list too long");
        snprintf(buf, sizeof buf, "%s", kappa_arg);
        nkappas = split_list(buf, items);
        if (nkappas <= 0)
            return flag_error("--kappas %s: expected 1 to 16 numbers separated by commas",
                              kappa_arg);
        for (int i = 0; i < nkappas; i++)
            if (!parse_double(items[i], &kappas[i]) || kappas[i] < 0.8 || kappas[i] > 4.0)
                return flag_error("--kappas: '%s' is not a number in [0.8, 4] (kappa = h/dp)",
                                  items[i]);
    }
    for (int i = 0; i < nkernels; i++) {
        double own[MAX_LIST];
        const int m = nkappas ? nkappas : table_kappas(kernels[i], own);
        for (int j = 0; j < m; j++) {
            if (o->ncases == MAX_CASES) return flag_error("%s", "more than 64 cases");
            const double kappa = nkappas ? kappas[j] : own[j];
            for (int q = 0; q < o->ncases; q++)
                if (o->cases[q].kernel == kernels[i] && o->cases[q].kappa == kappa)
                    return flag_error("%s: a kernel or kappa is listed twice",
                                      sph_kernel_name(kernels[i]));
            o->cases[o->ncases].kernel = kernels[i];
            o->cases[o->ncases].kappa = kappa;
            o->ncases++;
        }
    }
    return 0;
}

/* ------------------------------------------------------------------------ */
/* one case: relax, then measure                                              */
/* ------------------------------------------------------------------------ */

/* The disc as a scene, relaxed by the project's relaxation (relax.h).  The
 * material is irrelevant to the relaxation.  kappa and dp are set after
 * loading: the scene's smoothing_ratio range [1, 2] is a run's (2.5 is a
 * table's), and a scene keeps dp to 15 digits, h / kappa needs 17. */
static sph_status relax_disc(const ks_options *o, const ks_case *c, ks_result *r, sph_error *err) {
    char text[2048];
    sph_format(text, sizeof text,
               "dimension = 2;\n"
               "resolution = { dp = %.15g; };\n"
               "method = { formulation = \"enog-a\"; kernel = \"%s\"; smoothing_ratio = 1.3; };\n"
               "time = { end = 1.0; output_interval = 0.1; };\n"
               "materials = { m = { density = 1.0; youngs_modulus = 1.0; poisson_ratio = 0.3; "
               "}; };\n"
               "shapes = { disc = { type = \"disc\"; centre = [0.0, 0.0]; radius = %.17g; }; };\n"
               "bodies = ( { name = \"disc\"; material = \"m\"; shape = \"disc\"; placement = "
               "\"relaxed\"; relaxation = { steps = %d; step = \"%s\"; seed = %lld; }; } );\n",
               r->dp, sph_kernel_name(c->kernel), DISC_RADIUS, o->steps, o->step, o->seed);
    sph_scene *scene = malloc(sizeof *scene);
    if (!scene) return sph_fail(err, SPH_ERR_RUNTIME, "out of memory for the study's scene");
    sph_status st = sph_scene_load_text(scene, "kernel-study disc", text, NULL, 0, err);
    if (st) {
        free(scene);
        return st;
    }
    /* the exact spacing (a scene keeps 15 digits) and kappa */
    scene->dp = r->dp;
    scene->smoothing_ratio = c->kappa;
    sph_particles p;
    st = sph_particles_generate_ex(scene, &p, true, err);
    if (!st) {
        r->n = p.n;
        r->steps = p.relax[0].steps;
        r->relax_seconds = p.relax[0].seconds;
        r->step_alpha = p.relax[0].step_alpha;
        r->project_mean = p.relax[0].mean;
        r->project_max = p.relax[0].max;
        r->min_distance = p.relax[0].min_distance;
        r->pos = malloc((size_t)2 * (size_t)p.n * sizeof *r->pos);
        r->interior = calloc((size_t)p.n, sizeof *r->interior);
        if (!r->pos || !r->interior)
            st = sph_fail(err, SPH_ERR_RUNTIME, "out of memory for %d particles", p.n);
        else {
            memcpy(r->pos, p.pos, (size_t)2 * (size_t)p.n * sizeof *r->pos);
            /* "boundary particles are not considered" (004 §2.2, Fig. 2):
             * by default those whose support 2h reaches beyond the surface,
             * where the particle sums miss part of the kernel (the
             * relaxation adds the level-set term there, eq. 6 has none);
             * --exclude widens the band */
            for (int i = 0; i < p.n; i++) {
                const double x[3] = {p.pos[i], p.pos[p.n + i], 0.0};
                r->interior[i] = sph_shape_sdf(scene, 0, x, NULL) <= -o->exclude * r->h;
            }
        }
        sph_particles_free(&p);
    }
    sph_scene_free(scene);
    free(scene);
    return st;
}

/* Per-particle errors: e[corrected][function] and its x component. */
typedef struct {
    double e[2][NFUNC], ex[2][NFUNC];
    double residue;
    bool singular;
} ks_particle;

/* The sums of particle i (004 eqs. 4-6, with grad_i W_ij = W'(r) r_ij / r,
 * r_ij = x_i - x_j, the convention of eqs. 4-6 and of the reference code,
 * under which grad f_i ~ sum_j (f_i + f_j) grad_i W_ij V_j, the weak form
 * eq. 3 written with 2 fbar_ij = f_i + f_j):
 *   g0 = sum_j grad_i W_ij V_j                 (residue |2 g0|, eq. 4)
 *   M  = sum_j r_ij (x) grad_i W_ij V_j,  B_i = -M^-1   (eq. 5; ~ I)
 *   A_f = sum_j (f_i + f_j) grad_i W_ij V_j     (eq. 6's approximation)
 * and the errors |grad f_i - A_f| and, corrected, |grad f_i - B_i A_f|
 * (grad_i W_ij replaced by B_i grad_i W_ij). */
static void particle_errors(const sph_cell_list *cl, const double *pos, int n, int i, double volume,
                            const sph_physics *k, const sph_params_f64 *prm, ks_particle *out) {
    const double cutoff = 2.0 * prm->h;
    const double xi = pos[i], yi = pos[n + i];
    const double fi[NFUNC] = {1.0, sin(TWO_PI * xi)};
    double g0[2] = {0, 0}, m[2][2] = {{0, 0}, {0, 0}}, af[NFUNC][2] = {{0, 0}, {0, 0}};
    const sph_grid *g = &cl->grid;
    const int cx = sph_grid_coord(g, 0, xi), cy = sph_grid_coord(g, 1, yi);
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            const int ax = cx + dx, ay = cy + dy;
            if (ax < 0 || ay < 0 || ax >= g->dims[0] || ay >= g->dims[1]) continue;
            const size_t c = (size_t)ax + (size_t)g->dims[0] * (size_t)ay;
            for (int q = cl->start[c]; q < cl->start[c + 1]; q++) {
                const int j = cl->order[q];
                if (j == i) continue;
                const double rx = xi - pos[j], ry = yi - pos[n + j];
                const double r2 = rx * rx + ry * ry;
                if (r2 >= cutoff * cutoff || !(r2 > 0.0)) continue;
                const double r = sqrt(r2);
                const double f = k->kernel_dw(prm, r) / r * volume;
                const double gx = f * rx, gy = f * ry;
                g0[0] += gx, g0[1] += gy;
                m[0][0] += rx * gx, m[0][1] += rx * gy;
                m[1][0] += ry * gx, m[1][1] += ry * gy;
                const double fj[NFUNC] = {1.0, sin(TWO_PI * pos[j])};
                for (int fn = 0; fn < NFUNC; fn++) {
                    af[fn][0] += (fi[fn] + fj[fn]) * gx;
                    af[fn][1] += (fi[fn] + fj[fn]) * gy;
                }
            }
        }
    out->residue = 2.0 * hypot(g0[0], g0[1]);
    /* B = -M^-1 */
    const double det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    double b[2][2] = {{1, 0}, {0, 1}};
    out->singular = !(fabs(det) > 0.0);
    if (!out->singular) {
        b[0][0] = -m[1][1] / det, b[0][1] = m[0][1] / det;
        b[1][0] = m[1][0] / det, b[1][1] = -m[0][0] / det;
    }
    const double exact[NFUNC][2] = {{0.0, 0.0}, {TWO_PI * cos(TWO_PI * xi), 0.0}};
    for (int fn = 0; fn < NFUNC; fn++) {
        const double corr[2] = {b[0][0] * af[fn][0] + b[0][1] * af[fn][1],
                                b[1][0] * af[fn][0] + b[1][1] * af[fn][1]};
        const double *approx[2] = {af[fn], corr};
        for (int cr = 0; cr < 2; cr++) {
            const double ex = exact[fn][0] - approx[cr][0], ey = exact[fn][1] - approx[cr][1];
            out->e[cr][fn] = hypot(ex, ey);
            out->ex[cr][fn] = fabs(ex);
        }
    }
}

static sph_status measure(ks_result *r, double exclude, sph_error *err) {
    const double t0 = sph_wall_seconds();
    const int n = r->n;
    sph_params_f64 prm[1];
    memset(prm, 0, sizeof *prm);
    prm->h = r->h;
    prm->cutoff = 2.0 * r->h;
    prm->smoothing_kernel = (int)r->c.kernel;
    prm->dp = r->dp;
    /* the kernel of the physics source (device/sph_smoothing_kernel.h) */
    const sph_physics *k = sph_physics_for(2, true);
    sph_cell_list g = {0};
    sph_status st = sph_cell_list_build(&g, 2, r->pos, n, 2.0 * r->h, err);
    if (st) {
        sph_cell_list_free(&g);
        return st;
    }
    ks_particle *pe = malloc((size_t)(n > 0 ? n : 1) * sizeof *pe);
    r->residue = malloc((size_t)(n > 0 ? n : 1) * sizeof *r->residue);
    if (!pe || !r->residue) {
        free(pe);
        sph_cell_list_free(&g);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of memory measuring %d particles", n);
    }
    const double volume = r->dp * r->dp;
#pragma omp parallel for schedule(static)
    for (int i = 0; i < n; i++) particle_errors(&g, r->pos, n, i, volume, k, prm, &pe[i]);
    /* in-order reductions over the interior particles: the same bits for
     * any thread count */
    memset(r->l1, 0, sizeof r->l1), memset(r->linf, 0, sizeof r->linf);
    memset(r->l1x, 0, sizeof r->l1x), memset(r->linfx, 0, sizeof r->linfx);
    double rsum = 0.0, rmin = INFINITY, rmax = 0.0;
    int count = 0;
    for (int i = 0; i < n; i++) {
        r->residue[i] = pe[i].residue;
        if (!r->interior[i]) continue;
        count++;
        r->singular += pe[i].singular;
        rsum += pe[i].residue;
        rmin = fmin(rmin, pe[i].residue), rmax = fmax(rmax, pe[i].residue);
        for (int cr = 0; cr < 2; cr++)
            for (int fn = 0; fn < NFUNC; fn++) {
                r->l1[cr][fn] += pe[i].e[cr][fn];
                r->linf[cr][fn] = fmax(r->linf[cr][fn], pe[i].e[cr][fn]);
                r->l1x[cr][fn] += pe[i].ex[cr][fn];
                r->linfx[cr][fn] = fmax(r->linfx[cr][fn], pe[i].ex[cr][fn]);
            }
    }
    free(pe);
    sph_cell_list_free(&g);
    if (count == 0)
        return sph_fail(err, SPH_ERR_INPUT,
                        "%s at kappa = %g: no particle lies %g h = %g from the disc's surface; "
                        "use a finer --dp",
                        sph_kernel_name(r->c.kernel), r->c.kappa, exclude, exclude * r->h);
    r->interior_count = count;
    for (int cr = 0; cr < 2; cr++)
        for (int fn = 0; fn < NFUNC; fn++) {
            r->l1[cr][fn] /= count;
            r->l1x[cr][fn] /= count;
        }
    r->res_mean = rsum / count;
    r->res_min = rmin;
    r->res_max = rmax;
    r->eval_seconds = sph_wall_seconds() - t0;
    return SPH_OK;
}

static sph_status run_case(const ks_options *o, const ks_case *c, ks_result *r, sph_error *err) {
    memset(r, 0, sizeof *r);
    r->c = *c;
    r->h = REFERENCE_KAPPA * o->dp_ref;
    r->dp = r->h / c->kappa; /* h constant over kappa (004 §2.2) */
    sph_status st = relax_disc(o, c, r, err);
    if (!st) st = measure(r, o->exclude, err);
    if (st) {
        sph_error_prefix(err, "%s at kappa = %g: ", sph_kernel_name(c->kernel), c->kappa);
        ks_result_free(r);
    }
    return st;
}

/* ------------------------------------------------------------------------ */
/* output                                                                     */
/* ------------------------------------------------------------------------ */

static void csv_name(const ks_result *r, char *buf, size_t len) {
    sph_format(buf, len, "residues_%s_%g.csv", sph_kernel_name(r->c.kernel), r->c.kappa);
}

static sph_status write_csv(const char *path, const ks_result *r, sph_error *err) {
    FILE *f = fopen(path, "w");
    if (!f) return sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", path, strerror(errno));
    fprintf(f, "x,y,residue,interior\n");
    for (int i = 0; i < r->n; i++)
        fprintf(f, "%.10g,%.10g,%.6e,%d\n", r->pos[i], r->pos[r->n + i], r->residue[i],
                r->interior[i] ? 1 : 0);
    const bool bad = ferror(f) != 0;
    if (fclose(f) != 0 || bad)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", path, strerror(errno));
    return SPH_OK;
}

/* kappa as written ("1.3", not 1.3000000000000000444) */
static json_object *kappa_json(double kappa) {
    char buf[32];
    sph_format(buf, sizeof buf, "%.10g", kappa);
    return json_object_new_double_s(kappa, buf);
}

static json_object *build_json(const ks_options *o, const ks_result *res, int nres) {
    json_object *root = json_object_new_object();
    json_object *settings = json_object_new_object();
    json_object_object_add(settings, "disc_diameter", json_object_new_double(2.0 * DISC_RADIUS));
    json_object_object_add(settings, "dp_reference", json_object_new_double(o->dp_ref));
    json_object_object_add(settings, "h", json_object_new_double(REFERENCE_KAPPA * o->dp_ref));
    json_object_object_add(settings, "relaxation_steps", json_object_new_int(o->steps));
    json_object_object_add(settings, "relaxation_step", json_object_new_string(o->step));
    json_object_object_add(settings, "seed", json_object_new_int64(o->seed));
    json_object_object_add(
        settings, "interior",
        json_object_new_string("particles at least exclude_h h inside the surface (signed "
                               "distance <= -exclude_h h); the others are the boundary "
                               "particles, excluded"));
    json_object_object_add(settings, "exclude_h", json_object_new_double(o->exclude));
    json_object_object_add(
        settings, "error",
        json_object_new_string("|grad f_i - sum_j (f_i + f_j) G_ij V_j| (004 eq. 6, vector "
                               "norm), G_ij = grad_i W_ij or, corrected, B_i grad_i W_ij with "
                               "B_i = -(sum_j r_ij (x) grad_i W_ij V_j)^-1 (eq. 5); l1_x, "
                               "linf_x: the x component alone"));
    json_object_object_add(
        settings, "residue",
        json_object_new_string("|2 sum_j V_j grad_i W_ij| (004 eq. 4, Fig. 2), unscaled (1/m), "
                               "equal to the f = 1 error without B; `sphsolid relax` prints "
                               "|sum_j grad_i W_ij V_j + boundary term| h instead"));
    json_object_object_add(root, "settings", settings);
    json_object *errors = json_object_new_array();
    json_object *residues = json_object_new_array();
    json_object *cases = json_object_new_array();
    for (int c = 0; c < nres; c++) {
        const ks_result *r = &res[c];
        const char *kname = sph_kernel_name(r->c.kernel);
        for (int cr = 0; cr < 2; cr++)
            for (int fn = 0; fn < NFUNC; fn++) {
                json_object *e = json_object_new_object();
                json_object_object_add(e, "kernel", json_object_new_string(kname));
                json_object_object_add(e, "kappa", kappa_json(r->c.kappa));
                json_object_object_add(e, "corrected", json_object_new_boolean(cr == 1));
                json_object_object_add(e, "function", json_object_new_string(FUNCTION_NAMES[fn]));
                json_object_object_add(e, "l1", json_object_new_double(r->l1[cr][fn]));
                json_object_object_add(e, "linf", json_object_new_double(r->linf[cr][fn]));
                json_object_object_add(e, "l1_x", json_object_new_double(r->l1x[cr][fn]));
                json_object_object_add(e, "linf_x", json_object_new_double(r->linfx[cr][fn]));
                json_object_array_add(errors, e);
            }
        json_object *s = json_object_new_object();
        json_object_object_add(s, "kernel", json_object_new_string(kname));
        json_object_object_add(s, "kappa", kappa_json(r->c.kappa));
        json_object_object_add(s, "mean", json_object_new_double(r->res_mean));
        json_object_object_add(s, "spread", json_object_new_double(r->res_max - r->res_min));
        json_object_object_add(s, "min", json_object_new_double(r->res_min));
        json_object_object_add(s, "max", json_object_new_double(r->res_max));
        json_object_array_add(residues, s);
        json_object *k = json_object_new_object();
        char name[256];
        csv_name(r, name, sizeof name);
        json_object_object_add(k, "kernel", json_object_new_string(kname));
        json_object_object_add(k, "kappa", kappa_json(r->c.kappa));
        json_object_object_add(k, "dp", json_object_new_double(r->dp));
        json_object_object_add(k, "particles", json_object_new_int(r->n));
        json_object_object_add(k, "interior_particles", json_object_new_int(r->interior_count));
        json_object_object_add(k, "relaxation_steps", json_object_new_int(r->steps));
        if (r->step_alpha > 0.0)
            json_object_object_add(k, "relaxation_step_alpha",
                                   json_object_new_double(r->step_alpha));
        json_object_object_add(k, "relaxation_residual_mean",
                               json_object_new_double(r->project_mean));
        json_object_object_add(k, "relaxation_residual_max",
                               json_object_new_double(r->project_max));
        json_object_object_add(k, "closest_pair_dp", json_object_new_double(r->min_distance));
        json_object_object_add(k, "singular_moment_matrices", json_object_new_int(r->singular));
        json_object_object_add(k, "relax_seconds", json_object_new_double(r->relax_seconds));
        json_object_object_add(k, "measure_seconds", json_object_new_double(r->eval_seconds));
        json_object_object_add(k, "particles_file", json_object_new_string(name));
        json_object_array_add(cases, k);
    }
    json_object_object_add(root, "errors", errors);
    json_object_object_add(root, "residues", residues);
    json_object_object_add(root, "cases", cases);
    return root;
}

/* Write every file as FILE.partial, then rename them all: a failure leaves
 * no file that looks complete (the partials are removed). */
static sph_status write_outputs(const ks_options *o, const ks_result *res, int nres,
                                sph_error *err) {
    sph_status st = sph_output_make_dirs(o->out, err);
    if (st) return st;
    const int nfiles = nres + 1; /* the CSVs, then the JSON last */
    char(*final)[4200] = calloc((size_t)nfiles, sizeof *final);
    char(*partial)[4300] = calloc((size_t)nfiles, sizeof *partial);
    if (!final || !partial) {
        free(final);
        free(partial);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of memory");
    }
    int written = 0;
    for (int c = 0; c < nres && !st; c++) {
        char name[256];
        csv_name(&res[c], name, sizeof name);
        sph_format(final[c], sizeof final[c], "%s/%s", o->out, name);
        sph_format(partial[c], sizeof partial[c], "%s.partial", final[c]);
        st = write_csv(partial[c], &res[c], err);
        written = c + 1;
    }
    if (!st) {
        sph_format(final[nres], sizeof final[nres], "%s/kernel_study.json", o->out);
        sph_format(partial[nres], sizeof partial[nres], "%s.partial", final[nres]);
        json_object *root = build_json(o, res, nres);
        written = nfiles;
        if (json_object_to_file_ext(partial[nres], root,
                                    JSON_C_TO_STRING_PRETTY | JSON_C_TO_STRING_NOSLASHESCAPE) != 0)
            st = sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", partial[nres],
                          json_util_get_last_err());
        json_object_put(root);
    }
    for (int f = 0; f < nfiles && !st; f++)
        if (rename(partial[f], final[f]) != 0)
            st = sph_fail(err, SPH_ERR_RUNTIME, "cannot rename %s to %s: %s", partial[f], final[f],
                          strerror(errno));
    if (st)
        for (int f = 0; f < written; f++) remove(partial[f]);
    free(final);
    free(partial);
    return st;
}

/* ------------------------------------------------------------------------ */

int sph_kernel_study_main(int argc, char **argv) {
    ks_options *o = malloc(sizeof *o);
    if (!o) return SPH_ERR_RUNTIME;
    const int bad = parse_flags(argc, argv, o);
    if (bad) {
        free(o);
        return bad;
    }
    ks_result *res = calloc((size_t)o->ncases, sizeof *res);
    sph_error err = {0};
    sph_status st = res ? SPH_OK : sph_fail(&err, SPH_ERR_RUNTIME, "out of memory");
    int done = 0;
    const double t0 = sph_wall_seconds();
    for (int c = 0; c < o->ncases && !st; c++) {
        st = run_case(o, &o->cases[c], &res[c], &err);
        if (st) break;
        done = c + 1;
        const ks_result *r = &res[c];
        char rule[48];
        if (r->step_alpha > 0.0)
            snprintf(rule, sizeof rule, "%s, alpha %.4g", o->step, r->step_alpha);
        else
            snprintf(rule, sizeof rule, "%s", o->step);
        fprintf(stderr,
                "%s kappa = %g: dp = %.6g, %d particles (%d interior), %d steps (%s), relax %.1f "
                "s; residue mean %.4g, max - min %.4g\n",
                sph_kernel_name(r->c.kernel), r->c.kappa, r->dp, r->n, r->interior_count, r->steps,
                rule, r->relax_seconds, r->res_mean, r->res_max - r->res_min);
    }
    if (!st) st = write_outputs(o, res, done, &err);
    if (st)
        fprintf(stderr, "sphsolid kernel-study: %s\n", err.msg);
    else
        printf("kernel study: %d cases in %.1f s; %s/kernel_study.json\n", done,
               sph_wall_seconds() - t0, o->out);
    for (int c = 0; c < done; c++) ks_result_free(&res[c]);
    free(res);
    free(o);
    return (int)st;
}
