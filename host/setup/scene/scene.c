/* scene.c — load, override and validate a scene file (docs/scene-format.md).
 *
 * Three stages, all on one libconfig tree:
 *   1. parse the file (libconfig gives every setting its source line);
 *   2. apply the `--set key=value` overrides to the tree, marking every
 *      setting they create through its libconfig hook so that later messages
 *      can name the override instead of a file line;
 *   3. walk the tree against the schema (scene_keys.def), one section per
 *      file (scene_loader.h lists them), filling sph_scene.  Every group's
 *      members are checked against the keys valid there, so a typo is an
 *      error (with the nearest valid name) rather than a silently ignored
 *      setting that leaves a default in force.
 * The first problem found is reported; nothing is printed.
 */
#include "scene.h"

#include "scene_loader.h"

#include "mesh.h"

#include "sph_constants.h"

#include <libconfig.h>

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
static sph_status parse_scene(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    sph_status st;
    if ((st = scene_check_keys(L, root, SECTIONS("")))) return st;

    const config_setting_t *at;
    if ((st = scene_member(L, root, SK_TITLE, &at))) return st;
    if (at) {
        const char *title = "";
        if ((st = scene_as_string(L, at, &title))) return st;
        if (strlen(title) >= sizeof sc->title)
            return scene_fail_at(L, at, NULL, "titles are limited to %zu characters",
                                 sizeof sc->title - 1);
        snprintf(sc->title, sizeof sc->title, "%s", title);
    }
    scene_wide_int dim = {false, 0};
    bool present = false;
    char text[24];
    if ((st = scene_wide_integer(L, root, SK_DIMENSION, &dim, &present, &at))) return st;
    if (!scene_wide_in(dim, 1, 3))
        return scene_fail_at(L, at, NULL, "must be 1, 2 or 3, got %s", scene_wide_text(dim, text));
    sc->dim = (int)dim.magnitude;
    const config_setting_t *dim_at = at;

    if ((st = scene_parse_resolution(L, root)) || (st = scene_parse_method(L, root))) return st;
    /* 1D: the shock tubes of the fluid formulations (seed 004 §4.1); a solid
     * line has no shear, so none of the solid methods means anything there */
    if (sc->dim == 1 && !SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        return scene_fail_at(L, dim_at, NULL,
                             "dimension 1 is for the fluid formulations (\"eulerian-wc\", "
                             "\"eulerian-compressible\"), got formulation \"%s\"",
                             sph_formulation_name(sc->formulation));
    if ((st = scene_parse_time(L, root)) || (st = scene_parse_materials(L, root)) ||
        (st = scene_parse_shapes(L, root)) || (st = scene_parse_constants(L, root)) ||
        (st = scene_parse_bodies(L, root)) || (st = scene_parse_observers(L, root)) ||
        (st = scene_parse_analysis(L, root)) || (st = scene_parse_output(L, root)) ||
        (st = scene_parse_monitor(L, root)))
        return st;
    if ((st = scene_check_material_model(L, root)) || (st = scene_parse_walls(L, root)) ||
        (st = scene_parse_contact(L, root)) || (st = scene_parse_boundary(L, root)) ||
        (st = scene_parse_forces(L, root)))
        return st;
    /* A gas bounded by wall bodies: the wall pairs complete each truncated
     * support's pressure sum only approximately (the walls are relaxed at
     * dp/2), and the momentum fluxes err by p - p_b (device/eulerian_step.cl,
     * SOLVER_BACKGROUND), and below p_b they pull the gas toward themselves;
     * without a far field (whose p_inf is the default) the lowest pressure
     * a wall sees is the scene's to say. */
    if (sc->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE && !sc->has_far_field &&
        !sc->background_pressure_given)
        for (int b = 0; b < sc->nbodies; ++b)
            if (sc->bodies[b].role == SPH_BODY_WALL) {
                const config_setting_t *method = config_setting_get_member(root, "method");
                return scene_fail_at(L, method ? method : root, "background_pressure",
                                     "missing required key: a gas bounded by wall body '%s' "
                                     "without a far field needs the pressure p_b its momentum "
                                     "fluxes are taken relative to: a wall errs by a fraction "
                                     "of p - p_b and pulls the gas below p_b toward itself, so "
                                     "give the lowest pressure a wall sees (docs/fluids.md)",
                                     sc->bodies[b].name);
            }
    if ((st = scene_vector(L, root, SK_GRAVITY, sc->dim, sc->gravity, NULL)) ||
        (st = scene_vector(L, root, SK_LATTICE_ORIGIN, sc->dim, sc->lattice_origin, &at)))
        return st;
    sc->has_lattice_origin = at != NULL;
    return SPH_OK;
}

/* ------------------------------------------------------------------------ */
/* public API                                                                */
/* ------------------------------------------------------------------------ */

static sph_status read_scene_file(loader *L, config_t *cfg, const char *path) {
    FILE *fp = fopen(path, "r");
    if (!fp)
        return sph_fail(L->err, SPH_ERR_INPUT, "%s: cannot read scene file: %s", path,
                        strerror(errno));
    struct stat stbuf;
    if (fstat(fileno(fp), &stbuf) == 0 && S_ISDIR(stbuf.st_mode)) {
        fclose(fp);
        return sph_fail(L->err, SPH_ERR_INPUT, "%s: cannot read scene file: %s", path,
                        strerror(EISDIR));
    }
    /* @include "x" is resolved next to the scene file */
    char dir[SPH_SCENE_PATH_LEN];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash) {
        *slash = '\0';
        config_set_include_dir(cfg, dir[0] ? dir : "/");
    }
    /* read whole, for widen_integers */
    scene_text raw = {NULL, 0, 0};
    char chunk[4096];
    bool mem_ok = scene_text_put(&raw, "", 0);
    size_t got;
    while (mem_ok && (got = fread(chunk, 1, sizeof chunk, fp)) > 0)
        mem_ok = scene_text_put(&raw, chunk, got);
    int read_errno = ferror(fp) ? errno : 0;
    fclose(fp);
    if (read_errno || !mem_ok) {
        free(raw.buf);
        return sph_fail(L->err, read_errno ? SPH_ERR_INPUT : SPH_ERR_RUNTIME,
                        "%s: cannot read scene file: %s", path,
                        read_errno ? strerror(read_errno) : "out of memory");
    }
    /* libconfig reads text up to a NUL; from a file it took one for a
     * character it does not know: keep that a syntax error */
    const char *nul = memchr(raw.buf, '\0', raw.len);
    if (nul) {
        int line = 1;
        for (const char *c = raw.buf; c < nul; c++) line += *c == '\n';
        free(raw.buf);
        return sph_fail(L->err, SPH_ERR_INPUT, "%s:%d: syntax error: a NUL byte", path, line);
    }
    char *wide = scene_widen_integers(raw.buf);
    free(raw.buf);
    if (!wide) return sph_fail(L->err, SPH_ERR_RUNTIME, "%s: out of memory reading it", path);
    int ok = config_read_string(cfg, wide);
    free(wide);
    if (ok == CONFIG_TRUE) return SPH_OK;
    if (config_error_type(cfg) == CONFIG_ERR_FILE_IO)
        return sph_fail(L->err, SPH_ERR_INPUT, "%s: cannot read scene file: %s", path,
                        config_error_text(cfg));
    const char *text = config_error_text(cfg) ? config_error_text(cfg) : "syntax error";
    const char *file = config_error_file(cfg) ? config_error_file(cfg) : path;
    const char *hint = strstr(text, "mismatched element type")
                           ? " (write every number of an array as a decimal (0.0, not 0), or use "
                             "a list ( ... ))"
                           : "";
    if (strcmp(text, "syntax error") == 0)
        return sph_fail(L->err, SPH_ERR_INPUT, "%s:%d: syntax error", file, config_error_line(cfg));
    return sph_fail(L->err, SPH_ERR_INPUT, "%s:%d: syntax error: %s%s", file,
                    config_error_line(cfg), text, hint);
}

static sph_status write_resolved(sph_scene *scene, const config_t *cfg, sph_error *err) {
    char *buf = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&buf, &len);
    if (!mem)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot record the resolved scene: %s",
                        strerror(errno));
    config_write(cfg, mem);
    if (fclose(mem) != 0 || !buf) {
        free(buf);
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot record the resolved scene: out of memory");
    }
    scene->resolved_text = buf;
    return SPH_OK;
}

/* The first setting of tree `a` whose value the resolved text `b` (the same
 * tree written by libconfig and read back) does not reproduce, else NULL:
 * libconfig writes numbers with 15 significant digits. */
static const config_setting_t *first_changed(const config_setting_t *a, const config_setting_t *b) {
    if (!b || a->type != b->type) return a;
    switch (a->type) {
    case CONFIG_TYPE_GROUP:
    case CONFIG_TYPE_LIST:
    case CONFIG_TYPE_ARRAY: {
        int n = config_setting_length(a);
        if (config_setting_length(b) != n) return a;
        for (int i = 0; i < n; i++) {
            const config_setting_t *d = first_changed(config_setting_get_elem(a, (unsigned)i),
                                                      config_setting_get_elem(b, (unsigned)i));
            if (d) return d;
        }
        return NULL;
    }
    case CONFIG_TYPE_FLOAT:
        return a->value.fval == b->value.fval ? NULL : a;
    case CONFIG_TYPE_STRING:
        return strcmp(a->value.sval, b->value.sval) == 0 ? NULL : a;
    case CONFIG_TYPE_INT64:
        return a->value.llval == b->value.llval ? NULL : a;
    default: /* int, bool */
        return a->value.ival == b->value.ival ? NULL : a;
    }
}

/* A checkpoint stores the resolved text and a restart reloads it: it must
 * give back the same values. */
static sph_status check_resolved(loader *L, const config_t *cfg) {
    config_t again;
    config_init(&again);
    sph_status st = SPH_OK;
    if (config_read_string(&again, L->scene->resolved_text) != CONFIG_TRUE) {
        st = sph_fail(L->err, SPH_ERR_INPUT,
                      "%s: the scene cannot be stored for a restart: its resolved text does not "
                      "parse (line %d: %s)",
                      L->file, config_error_line(&again),
                      config_error_text(&again) ? config_error_text(&again) : "syntax error");
    } else {
        const config_setting_t *d =
            first_changed(config_root_setting(cfg), config_root_setting(&again));
        if (d && d->type == CONFIG_TYPE_FLOAT)
            st = scene_fail_at(
                L, d, NULL,
                "%.17g has more significant digits than a stored scene keeps (15), so "
                "a restart would differ; round it",
                d->value.fval);
        else if (d)
            st = scene_fail_at(L, d, NULL,
                               "the value does not survive storing the scene for a restart");
    }
    config_destroy(&again);
    return st;
}

/* Load from a file (`text` NULL) or from scene text (restarts: the text
 * stored in a checkpoint, `path` naming where it came from). */
static sph_status load(sph_scene *scene, const char *path, const char *text,
                       const char *const *overrides, int noverrides, sph_error *err) {
    memset(scene, 0, sizeof *scene);
    scene->period_observer = -1;
    scene->wave_incident = scene->wave_transmitted = -1;
    scene->acceleration_criterion = true;
    if (!path) return sph_fail(err, SPH_ERR_INPUT, "no scene file given");
    if (strlen(path) >= sizeof scene->path)
        return sph_fail(err, SPH_ERR_INPUT, "%s: cannot read scene file: path too long", path);
    snprintf(scene->path, sizeof scene->path, "%s", path);

    loader L = {.file = path, .err = err, .scene = scene};
    config_t cfg;
    config_init(&cfg);
    sph_status st = SPH_OK;
    char *wide = text ? scene_widen_integers(text) : NULL;
    if (!text) {
        st = read_scene_file(&L, &cfg, path);
    } else if (!wide) {
        st = sph_fail(err, SPH_ERR_RUNTIME, "%s: out of memory reading the scene", path);
    } else if (config_read_string(&cfg, wide) != CONFIG_TRUE) {
        st = sph_fail(err, SPH_ERR_INPUT, "%s:%d: the stored scene does not parse: %s", path,
                      config_error_line(&cfg),
                      config_error_text(&cfg) ? config_error_text(&cfg) : "syntax error");
    }
    free(wide);
    for (int i = 0; st == SPH_OK && i < noverrides; i++)
        st = scene_apply_override(&L, &cfg, overrides[i]);
    if (st == SPH_OK) st = write_resolved(scene, &cfg, err);
    if (st == SPH_OK) st = parse_scene(&L, config_root_setting(&cfg));
    if (st == SPH_OK) st = check_resolved(&L, &cfg);
    config_destroy(&cfg);
    if (st != SPH_OK) sph_scene_free(scene);
    return st;
}

sph_status sph_scene_load(sph_scene *scene, const char *path, const char *const *overrides,
                          int noverrides, sph_error *err) {
    return load(scene, path, NULL, overrides, noverrides, err);
}

sph_status sph_scene_load_text(sph_scene *scene, const char *origin, const char *text,
                               const char *const *overrides, int noverrides, sph_error *err) {
    return load(scene, origin, text, overrides, noverrides, err);
}

bool sph_scene_key_where(const sph_scene *scene, const char *const *overrides, int noverrides,
                         const char *key, char *buf, size_t size) {
    /* the scene keeps no source lines after loading: read its file again
     * as load() does (the same text preparation and overrides, so that
     * override_of names the --set that made a setting) */
    sph_error ignored;
    loader L = {.file = scene->path, .err = &ignored, .scene = NULL};
    config_t cfg;
    config_init(&cfg);
    sph_status st = read_scene_file(&L, &cfg, scene->path);
    for (int i = 0; st == SPH_OK && i < noverrides; i++)
        st = scene_apply_override(&L, &cfg, overrides[i]);
    const config_setting_t *s = NULL;
    bool given = false;
    if (st == SPH_OK) {
        char path[SPH_SCENE_PATH_LEN];
        snprintf(path, sizeof path, "%s", key);
        for (;;) {
            s = config_lookup(&cfg, path);
            if (s) {
                given = strcmp(path, key) == 0;
                break;
            }
            char *dot = strrchr(path, '.');
            if (!dot) break;
            *dot = '\0';
        }
    }
    const char *ov = s ? scene_override_of(s) : NULL;
    const unsigned line = s ? config_setting_source_line(s) : 0;
    if (ov)
        sph_format(buf, size, "--set %s: %s", ov, key);
    else if (line > 0)
        sph_format(buf, size, "%s:%u: %s", scene->path, line, key);
    else
        sph_format(buf, size, "%s: %s", scene->path, key);
    config_destroy(&cfg);
    return given || ov != NULL;
}

void sph_scene_free(sph_scene *scene) {
    if (!scene) return;
    free(scene->resolved_text);
    scene->resolved_text = NULL;
    /* every shape slot: a load that failed may have read meshes past nshapes' count */
    for (int i = 0; i < SPH_SCENE_MAX_SHAPES; i++) {
        sph_mesh_free(scene->shapes[i].mesh);
        scene->shapes[i].mesh = NULL;
    }
}

/* ------------------------------------------------------------------------ */
/* names                                                                     */
/* ------------------------------------------------------------------------ */

const char *sph_placement_name(sph_placement p) {
    return p == SPH_PLACEMENT_RELAXED ? "relaxed" : "lattice";
}

const char *sph_formulation_name(sph_formulation f) {
    switch (f) {
    case SPH_FORMULATION_ENOG:
    case SPH_FORMULATION_ENOG_A:
    case SPH_FORMULATION_OG:
    case SPH_FORMULATION_OAS:
    case SPH_FORMULATION_GNOG:
    case SPH_FORMULATION_GNOG_A:
    case SPH_FORMULATION_TLSPH:
    case SPH_FORMULATION_EULERIAN_WC:
    case SPH_FORMULATION_EULERIAN_COMPRESSIBLE:
        return scene_word(SK_METHOD_FORMULATION, (int)f);
    }
    return "?";
}

const char *sph_rotation_name(sph_rotation r) {
    switch (r) {
    case SPH_ROTATION_NONE:
        return "none";
    case SPH_ROTATION_AVERAGED:
        return "averaged";
    case SPH_ROTATION_PER_PARTICLE:
        return "per-particle";
    }
    return "?";
}

const char *sph_kernel_name(sph_kernel k) {
    switch (k) {
    case SPH_KERNEL_WENDLAND_C2:
    case SPH_KERNEL_LAGUERRE_GAUSS:
    case SPH_KERNEL_LAGUERRE_WENDLAND:
    case SPH_KERNEL_CUBIC_BSPLINE:
        return scene_word(SK_METHOD_KERNEL, (int)k);
    }
    return "?";
}

const char *sph_stepping_name(sph_stepping s) {
    switch (s) {
    case SPH_STEPPING_DUAL:
        return "dual";
    case SPH_STEPPING_SINGLE:
        return "single";
    }
    return "?";
}

/* ------------------------------------------------------------------------ */
/* the constraint table                                                      */
/* ------------------------------------------------------------------------ */

int sph_constraint_index(const sph_scene *scene, int body, int constraint) {
    int k = 0;
    for (int b = 0; b < body; b++) k += scene->bodies[b].nconstraints;
    return k + constraint;
}

int sph_scene_material_rows(const sph_scene *scene, int row_of[SPH_MAX_MATERIALS]) {
    for (int m = 0; m < SPH_MAX_MATERIALS; m++) row_of[m] = -1;
    int rows = 0;
    for (int b = 0; b < scene->nbodies; b++) {
        const sph_body *body = &scene->bodies[b];
        for (int k = -1; k < body->nregions; k++) {
            const int m = k < 0 ? body->material : body->regions[k].material;
            if (m >= 0 && m < SPH_MAX_MATERIALS && row_of[m] < 0) row_of[m] = rows++;
        }
    }
    return rows;
}

int sph_body_material_at(const sph_scene *scene, int body, const double x[3]) {
    const sph_body *b = &scene->bodies[body];
    for (int k = 0; k < b->nregions; k++)
        if (sph_shape_contains(scene, b->regions[k].shape, x)) return b->regions[k].material;
    return b->material;
}

int sph_constraint_count(const sph_scene *scene) {
    return sph_constraint_index(scene, scene->nbodies, 0);
}

const sph_constraint *sph_constraint_at(const sph_scene *scene, int index) {
    for (int b = 0; b < scene->nbodies; b++) {
        if (index < scene->bodies[b].nconstraints) return &scene->bodies[b].constraints[index];
        index -= scene->bodies[b].nconstraints;
    }
    return NULL;
}

bool sph_scene_has_driven_constraint(const sph_scene *scene) {
    for (int k = 0; k < sph_constraint_count(scene); k++) {
        const sph_constraint *c = sph_constraint_at(scene, k);
        for (int a = 0; a < scene->dim; a++)
            if (c->type == SPH_CONSTRAINT_VELOCITY && c->velocity[a] != 0.0) return true;
    }
    return false;
}

int sph_scene_expression_variables(int dim, const char *vars[3]) {
    for (int a = 0; a < 3; a++) vars[a] = SCENE_AXES[a];
    return dim;
}

sph_expression_constants
sph_scene_expression_constants(const sph_scene *scene, const char *names[SPH_SCENE_MAX_CONSTANTS]) {
    for (int k = 0; k < scene->nconstants; k++) names[k] = scene->constant_name[k];
    return (sph_expression_constants){scene->nconstants, names, scene->constant_value};
}
