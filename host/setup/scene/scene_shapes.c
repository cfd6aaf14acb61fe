/* scene_shapes.c — the section `shapes` (boxes, unions, differences, round
 * shapes, meshes) and the geometry queries on the parsed shapes. */
#include "scene_loader.h"

#include "mesh.h"

#include <errno.h>
#include <math.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int scene_find_shape(const loader *L, const char *name) {
    for (int i = 0; i < L->nnamed_shapes; i++)
        if (strcmp(L->scene->shapes[i].name, name) == 0) return i;
    return -1;
}

sph_status scene_unknown_shape(loader *L, const config_setting_t *at, const char *name) {
    const char *names[SPH_SCENE_MAX_SHAPES];
    for (int i = 0; i < L->nnamed_shapes; i++) names[i] = L->scene->shapes[i].name;
    char hint[1024];
    scene_suggest(name, names, L->nnamed_shapes, "defined shapes", hint, sizeof hint);
    return scene_fail_at(L, at, NULL, "unknown shape '%s'%s", name, hint);
}

static sph_status parse_shape(loader *L, const config_setting_t *s, int index);

/* One element of a union/difference `parts`: a shape name or an inline shape. */
static sph_status parse_part(loader *L, const config_setting_t *e, int *out) {
    if (config_setting_type(e) == CONFIG_TYPE_STRING) {
        const char *name = config_setting_get_string(e);
        *out = scene_find_shape(L, name);
        if (*out < 0) return scene_unknown_shape(L, e, name);
        return SPH_OK;
    }
    if (config_setting_is_group(e)) {
        sph_scene *sc = L->scene;
        if (sc->nshapes >= SPH_SCENE_MAX_SHAPES)
            return scene_fail_at(L, e, NULL, "too many shapes (at most %d, inline ones included)",
                                 SPH_SCENE_MAX_SHAPES);
        *out = sc->nshapes++;
        sc->shapes[*out].name[0] = '\0';
        return parse_shape(L, e, *out);
    }
    return scene_fail_at(L, e, NULL,
                         "expected a shape name or an inline shape group { type = ...; }, got %s",
                         scene_type_name(config_setting_type(e)));
}

/* disc, ball, annulus, hollow_sphere (kind 3..6: inner <= |x - centre| <=
 * outer) and cylinder (kind 7); the bounding box goes to lower/upper. */
static sph_status parse_round_shape(loader *L, const config_setting_t *s,
                                    const config_setting_t *type_at, int kind, sph_shape *sh) {
    static const char *const names[] = {"disc", "ball", "annulus", "hollow_sphere", "cylinder"};
    static const char *const other[] = {"ball", "disc", "hollow_sphere", "annulus", ""};
    const int dim = L->scene->dim;
    const int need = kind == 3 || kind == 5 ? 2 : 3;
    if (dim == 1)
        return scene_fail_at(L, type_at, NULL,
                             "\"%s\" is a %dD shape; a line (dimension 1) is made of \"box\"es, "
                             "lower = [x0]; upper = [x1]",
                             names[kind - 3], need);
    if (dim != need) {
        if (kind == 7)
            return scene_fail_at(L, type_at, NULL,
                                 "\"cylinder\" is a 3D shape; in 2D a rectangle is a \"box\"");
        return scene_fail_at(L, type_at, NULL, "\"%s\" is a %dD shape; in %dD use \"%s\"",
                             names[kind - 3], need, dim, other[kind - 3]);
    }
    const bool hollow = kind == 5 || kind == 6;
    sph_status st;
    if (kind == 7)
        st = scene_check_keys(L, s, SECTIONS("shapes", "shapes.cylinder"));
    else if (hollow)
        st = scene_check_keys(L, s, SECTIONS("shapes", "shapes.annulus"));
    else
        st = scene_check_keys(L, s, SECTIONS("shapes", "shapes.disc"));
    const sph_scene_key_id centre = kind == 7 ? SK_CYLINDER_CENTRE
                                    : hollow  ? SK_ANNULUS_CENTRE
                                              : SK_DISC_CENTRE;
    if (st || (st = scene_vector(L, s, centre, dim, sh->centre, NULL))) return st;
    sh->type = kind == 7 ? SPH_SHAPE_CYLINDER : SPH_SHAPE_SPHERE;
    sh->nparts = 0;
    sh->inner_radius = 0.0;
    sh->length = 0.0;
    for (int a = 0; a < 3; a++) sh->axis[a] = 0.0;
    if (hollow) {
        const config_setting_t *outer_at;
        if ((st = scene_number(L, s, SK_ANNULUS_INNER_RADIUS, &sh->inner_radius)) ||
            (st = scene_number(L, s, SK_ANNULUS_OUTER_RADIUS, &sh->outer_radius)) ||
            (st = scene_member(L, s, SK_ANNULUS_OUTER_RADIUS, &outer_at)))
            return st;
        if (!(sh->outer_radius > sh->inner_radius))
            return scene_fail_at(L, outer_at, NULL, "must exceed inner_radius = %g, got %g",
                                 sh->inner_radius, sh->outer_radius);
    } else if ((st = scene_number(L, s, kind == 7 ? SK_CYLINDER_RADIUS : SK_DISC_RADIUS,
                                  &sh->outer_radius))) {
        return st;
    }
    double half[3] = {sh->outer_radius, sh->outer_radius, sh->outer_radius};
    double lo_end[3] = {0, 0, 0}, hi_end[3] = {0, 0, 0};
    if (kind == 7) {
        const config_setting_t *axis_at;
        if ((st = scene_vector(L, s, SK_CYLINDER_AXIS, 3, sh->axis, &axis_at)) ||
            (st = scene_number(L, s, SK_CYLINDER_LENGTH, &sh->length)))
            return st;
        const double norm =
            sqrt(sh->axis[0] * sh->axis[0] + sh->axis[1] * sh->axis[1] + sh->axis[2] * sh->axis[2]);
        if (!(norm > 0.0) || !isfinite(norm))
            return scene_fail_at(L, axis_at, NULL, "must be a non-zero direction, got (%g, %g, %g)",
                                 sh->axis[0], sh->axis[1], sh->axis[2]);
        /* the box of a cylinder: the two end discs of radius R and normal a
         * reach R sqrt(1 - a_k^2) along axis k around their centres */
        for (int a = 0; a < 3; a++) {
            sh->axis[a] /= norm;
            const double end = sh->length * sh->axis[a];
            lo_end[a] = fmin(0.0, end);
            hi_end[a] = fmax(0.0, end);
            half[a] = sh->outer_radius * sqrt(fmax(0.0, 1.0 - sh->axis[a] * sh->axis[a]));
        }
    }
    for (int a = 0; a < 3; a++) {
        sh->lower[a] = a < dim ? sh->centre[a] + lo_end[a] - half[a] : 0.0;
        sh->upper[a] = a < dim ? sh->centre[a] + hi_end[a] + half[a] : 0.0;
        if (a < dim && !(isfinite(sh->lower[a]) && isfinite(sh->upper[a])))
            return scene_fail_at(L, s, NULL, "the shape reaches infinity along %s", SCENE_AXES[a]);
        if (a < dim && !(sh->upper[a] > sh->lower[a]))
            return scene_fail_at(
                L, s, NULL,
                "the shape is too small for the precision of its coordinates along "
                "%s (%g to %g)",
                SCENE_AXES[a], sh->lower[a], sh->upper[a]);
    }
    return SPH_OK;
}

/* `file` as named at `at`, relative to the directory of the scene file
 * (like every path a scene names; an absolute path stays), into out[size]. */
sph_status scene_relative_path(loader *L, const config_setting_t *at, const char *file, char *out,
                               size_t size) {
    const char *slash = strrchr(L->file, '/');
    const int dirlen = file[0] == '/' || !slash ? 0 : (int)(slash - L->file) + 1;
    if ((size_t)dirlen + strlen(file) >= size)
        return scene_fail_at(L, at, NULL, "the path is longer than %d characters", (int)size - 1);
    snprintf(out, size, "%.*s%s", dirlen, L->file, file);
    return SPH_OK;
}

/* Mesh files a scene may name: regular files (not a device or a pipe, which
 * could stream forever) of at most this size. */
#define SPH_MESH_MAX_FILE_BYTES (1L << 30)

/* type = "mesh": file (relative to the scene file's directory), scale,
 * rotate (degrees about x, y, z, in that order), translate; read and
 * checked now (host/setup/mesh.c), so that a bad mesh is an error at its key. */
static sph_status parse_mesh_shape(loader *L, const config_setting_t *s,
                                   const config_setting_t *type_at, sph_shape *sh) {
    if (L->scene->dim != 3)
        return scene_fail_at(
            L, type_at, NULL,
            "\"mesh\" is a 3D shape (a closed triangle surface); in %dD use boxes, "
            "discs and annuli",
            L->scene->dim);
    sph_status st = scene_check_keys(L, s, SECTIONS("shapes", "shapes.mesh"));
    if (st) return st;
    const config_setting_t *file_at;
    const char *file = "";
    if ((st = scene_member(L, s, SK_MESH_FILE, &file_at)) ||
        (st = scene_as_string(L, file_at, &file)))
        return st;
    if (!*file) return scene_fail_at(L, file_at, NULL, "must name a mesh file (STL, OBJ)");
    sph_mesh_transform tf = {1.0, {0, 0, 0}, {0, 0, 0}};
    if ((st = scene_number(L, s, SK_MESH_SCALE, &tf.scale)) ||
        (st = scene_vector(L, s, SK_MESH_ROTATE, 3, tf.rotate_deg, NULL)) ||
        (st = scene_vector(L, s, SK_MESH_TRANSLATE, 3, tf.translate, NULL)))
        return st;
    char path[SPH_SCENE_PATH_LEN];
    if ((st = scene_relative_path(L, file_at, file, path, sizeof path))) return st;
    struct stat info;
    if (stat(path, &info) != 0)
        return scene_fail_at(L, file_at, NULL, "mesh file %s: cannot open it: %s", path,
                             strerror(errno));
    if (!S_ISREG(info.st_mode))
        return scene_fail_at(L, file_at, NULL, "mesh file %s: not a regular file", path);
    if (info.st_size == 0) return scene_fail_at(L, file_at, NULL, "mesh file %s is empty", path);
    if (info.st_size > SPH_MESH_MAX_FILE_BYTES)
        return scene_fail_at(L, file_at, NULL, "mesh file %s: %lld bytes, more than the %ld read",
                             path, (long long)info.st_size, SPH_MESH_MAX_FILE_BYTES);
    char why[512];
    sh->mesh = sph_mesh_load(path, NULL, 0, NULL, &tf, why, sizeof why);
    if (!sh->mesh) return scene_fail_at(L, file_at, NULL, "mesh file %s %s", path, why);
    sh->type = SPH_SHAPE_MESH;
    sh->nparts = 0;
    sph_mesh_bounds(sh->mesh, sh->lower, sh->upper);
    return SPH_OK;
}

static sph_status parse_shape(loader *L, const config_setting_t *s, int index) {
    sph_scene *sc = L->scene;
    sph_shape *sh = &sc->shapes[index];
    L->shape_def[index] = s;
    L->shape_parts[index] = NULL;
    sh->line = (int)config_setting_source_line(s);
    if (!config_setting_is_group(s))
        return scene_fail_at(L, s, NULL, "expected a shape group { type = ...; }, got %s",
                             scene_type_name(config_setting_type(s)));
    int type = 0;
    const config_setting_t *type_at;
    sph_status st = scene_keyword(L, s, SK_SHAPE_TYPE, &type, &type_at);
    if (st) return st;
    const int dim = sc->dim;
    if (type == 8) return parse_mesh_shape(L, s, type_at, sh);
    if (type >= 3) return parse_round_shape(L, s, type_at, type, sh);
    if (type == 0) {
        sh->type = SPH_SHAPE_BOX;
        const config_setting_t *upper_at;
        double lpad[3] = {0, 0, 0}, upad[3] = {0, 0, 0};
        if ((st = scene_check_keys(L, s, SECTIONS("shapes", "shapes.box"))) ||
            (st = scene_vector(L, s, SK_BOX_LOWER, dim, sh->lower, NULL)) ||
            (st = scene_vector(L, s, SK_BOX_UPPER, dim, sh->upper, &upper_at)))
            return st;
        const sph_scene_key_id pad_keys[2] = {SK_BOX_LOWER_PAD_DP, SK_BOX_UPPER_PAD_DP};
        double *pads[2] = {lpad, upad};
        for (int k = 0; k < 2; k++) {
            const config_setting_t *at;
            if ((st = scene_vector(L, s, pad_keys[k], dim, pads[k], &at))) return st;
            for (int a = 0; at && a < dim; a++)
                if (pads[k][a] < 0)
                    return scene_fail_at(L, config_setting_get_elem(at, (unsigned)a), NULL,
                                         "padding must be >= 0, got %g", pads[k][a]);
        }
        /* padding in particle spacings, e.g. the clamp layer of the plate */
        for (int a = 0; a < dim; a++) {
            sh->lower[a] -= lpad[a] * sc->dp;
            sh->upper[a] += upad[a] * sc->dp;
        }
        for (int a = 0; a < dim; a++)
            if (!isfinite(sh->lower[a]) || !isfinite(sh->upper[a]))
                return scene_fail_at(
                    L, s, NULL,
                    "padding by %g and %g spacings (dp = %g) takes the box to infinity "
                    "along %s",
                    lpad[a], upad[a], sc->dp, SCENE_AXES[a]);
        for (int a = 0; a < dim; a++)
            if (!(sh->upper[a] > sh->lower[a]))
                return scene_fail_at(L, upper_at, NULL,
                                     "must exceed lower in every component (padding included), got "
                                     "upper.%s = %g <= lower.%s = %g",
                                     SCENE_AXES[a], sh->upper[a], SCENE_AXES[a], sh->lower[a]);
        sh->nparts = 0;
        return SPH_OK;
    }

    sh->type = type == 1 ? SPH_SHAPE_UNION : SPH_SHAPE_DIFFERENCE;
    const config_setting_t *parts;
    if ((st = scene_check_keys(L, s, SECTIONS("shapes", "shapes.union"))) ||
        (st = scene_member(L, s, SK_SET_PARTS, &parts)))
        return st;
    L->shape_parts[index] = parts;
    if (!config_setting_is_array(parts) && !config_setting_is_list(parts))
        return scene_fail_at(L, parts, NULL,
                             "expected an array of shape names [\"a\", \"b\"] or a list, got %s",
                             scene_type_name(config_setting_type(parts)));
    int n = config_setting_length(parts);
    int min = sh->type == SPH_SHAPE_UNION ? 1 : 2;
    if (n < min)
        return scene_fail_at(L, parts, NULL, "a %s needs at least %d part%s, got %d",
                             type == 1 ? "union" : "difference", min, min == 1 ? "" : "s", n);
    if (n > SPH_SCENE_MAX_SHAPE_PARTS)
        return scene_fail_at(L, parts, NULL, "at most %d parts, got %d", SPH_SCENE_MAX_SHAPE_PARTS,
                             n);
    sh->nparts = n;
    for (int i = 0; i < n; i++) {
        int part = -1;
        if ((st = parse_part(L, config_setting_get_elem(parts, (unsigned)i), &part))) return st;
        sh->parts[i] = part;
    }
    return SPH_OK;
}

/* Depth-first search for a shape that contains itself. */
static sph_status check_cycles(loader *L, int u, int *state, int *stack, int depth) {
    const sph_scene *sc = L->scene;
    state[u] = 1;
    stack[depth] = u;
    const sph_shape *sh = &sc->shapes[u];
    for (int i = 0; i < sh->nparts; i++) {
        int v = sh->parts[i];
        if (state[v] == 1) {
            char chain[1024];
            size_t len = 0;
            int from = depth;
            while (from > 0 && stack[from] != v) from--;
            for (int k = from; k <= depth + 1 && len < sizeof chain; k++) {
                int w = k <= depth ? stack[k] : v;
                const char *name = sc->shapes[w].name;
                if (name[0])
                    len += (size_t)snprintf(chain + len, sizeof chain - len, "%s'%s'",
                                            k > from ? " -> " : "", name);
                else
                    len += (size_t)snprintf(chain + len, sizeof chain - len,
                                            "%s(inline shape, line %d)", k > from ? " -> " : "",
                                            sc->shapes[w].line);
            }
            return scene_fail_at(L, L->shape_parts[u] ? L->shape_parts[u] : L->shape_def[u], NULL,
                                 "shapes refer to each other in a cycle: %s", chain);
        }
        if (state[v] == 0) {
            sph_status st = check_cycles(L, v, state, stack, depth + 1);
            if (st) return st;
        }
    }
    state[u] = 2;
    return SPH_OK;
}

/* Nodes of the shape's tree with shared parts expanded, memoised in
 * nodes[] (0: not yet known); capped just above the limit.  Needs an acyclic
 * shape table. */
#define SPH_SCENE_MAX_SHAPE_NODES 1024
static long shape_tree_size(const sph_scene *sc, int u, long *nodes) {
    if (nodes[u]) return nodes[u];
    long n = 1;
    for (int i = 0; i < sc->shapes[u].nparts && n <= SPH_SCENE_MAX_SHAPE_NODES; i++)
        n += shape_tree_size(sc, sc->shapes[u].parts[i], nodes);
    return nodes[u] = n;
}

sph_status scene_parse_shapes(loader *L, const config_setting_t *root) {
    sph_scene *sc = L->scene;
    const config_setting_t *g;
    sph_status st = scene_group(L, root, SK_SHAPES, &g);
    if (st) return st;
    int n = config_setting_length(g);
    if (n == 0) return scene_fail_at(L, g, NULL, "define at least one shape");
    if (n > SPH_SCENE_MAX_SHAPES)
        return scene_fail_at(L, g, NULL, "at most %d shapes, got %d", SPH_SCENE_MAX_SHAPES, n);
    /* names first, so that a shape may refer to one defined after it */
    for (int i = 0; i < n; i++) {
        const config_setting_t *s = config_setting_get_elem(g, (unsigned)i);
        char why[256];
        if (!sph_name_check(s->name, why, sizeof why)) return scene_fail_at(L, s, NULL, "%s", why);
        snprintf(sc->shapes[i].name, sizeof sc->shapes[i].name, "%s", s->name);
    }
    sc->nshapes = L->nnamed_shapes = n;
    for (int i = 0; i < n; i++)
        if ((st = parse_shape(L, config_setting_get_elem(g, (unsigned)i), i))) return st;
    int state[SPH_SCENE_MAX_SHAPES] = {0}, stack[SPH_SCENE_MAX_SHAPES + 1];
    for (int i = 0; i < sc->nshapes; i++)
        if (state[i] == 0 && (st = check_cycles(L, i, state, stack, 0))) return st;
    /* a shape used more than once is evaluated each time (sph_shape_contains,
     * sph_shape_bounds): bound the expanded tree, which a chain of unions
     * of the previous shape twice would grow as 2^depth */
    long nodes[SPH_SCENE_MAX_SHAPES] = {0};
    for (int i = 0; i < sc->nshapes; i++)
        if (shape_tree_size(sc, i, nodes) > SPH_SCENE_MAX_SHAPE_NODES)
            return scene_fail_at(L, L->shape_parts[i] ? L->shape_parts[i] : L->shape_def[i], NULL,
                                 "the shape expands to more than %d boxes, unions and differences "
                                 "(a shape used in several places counts each time)",
                                 SPH_SCENE_MAX_SHAPE_NODES);
    return SPH_OK;
}

/* ------------------------------------------------------------------------ */
/* geometry                                                                  */
/* ------------------------------------------------------------------------ */

bool sph_shape_contains(const sph_scene *scene, int shape, const double x[3]) {
    const sph_shape *sh = &scene->shapes[shape];
    switch (sh->type) {
    case SPH_SHAPE_BOX:
        for (int a = 0; a < scene->dim; a++)
            if (x[a] < sh->lower[a] || x[a] > sh->upper[a]) return false;
        return true;
    case SPH_SHAPE_UNION:
        for (int i = 0; i < sh->nparts; i++)
            if (sph_shape_contains(scene, sh->parts[i], x)) return true;
        return false;
    case SPH_SHAPE_DIFFERENCE:
        if (!sph_shape_contains(scene, sh->parts[0], x)) return false;
        for (int i = 1; i < sh->nparts; i++)
            if (sph_shape_contains(scene, sh->parts[i], x)) return false;
        return true;
    case SPH_SHAPE_SPHERE: {
        double r2 = 0.0;
        for (int a = 0; a < scene->dim; a++) r2 += (x[a] - sh->centre[a]) * (x[a] - sh->centre[a]);
        return r2 >= sh->inner_radius * sh->inner_radius &&
               r2 <= sh->outer_radius * sh->outer_radius;
    }
    case SPH_SHAPE_MESH:
        return sph_mesh_contains(sh->mesh, x);
    case SPH_SHAPE_CYLINDER: {
        double d[3], s = 0.0;
        for (int a = 0; a < 3; a++) {
            d[a] = x[a] - sh->centre[a];
            s += d[a] * sh->axis[a];
        }
        if (s < 0.0 || s > sh->length) return false;
        double r2 = 0.0;
        for (int a = 0; a < 3; a++) r2 += (d[a] - s * sh->axis[a]) * (d[a] - s * sh->axis[a]);
        return r2 <= sh->outer_radius * sh->outer_radius;
    }
    }
    return false;
}

void sph_shape_bounds(const sph_scene *scene, int shape, double lower[3], double upper[3]) {
    const sph_shape *sh = &scene->shapes[shape];
    switch (sh->type) {
    case SPH_SHAPE_BOX:
    case SPH_SHAPE_SPHERE:
    case SPH_SHAPE_CYLINDER:
    case SPH_SHAPE_MESH:
        /* round shapes and meshes store their bounding box */
        for (int a = 0; a < 3; a++) lower[a] = sh->lower[a], upper[a] = sh->upper[a];
        return;
    case SPH_SHAPE_UNION:
        sph_shape_bounds(scene, sh->parts[0], lower, upper);
        for (int i = 1; i < sh->nparts; i++) {
            double lo[3], hi[3];
            sph_shape_bounds(scene, sh->parts[i], lo, hi);
            for (int a = 0; a < 3; a++) {
                if (lo[a] < lower[a]) lower[a] = lo[a];
                if (hi[a] > upper[a]) upper[a] = hi[a];
            }
        }
        return;
    case SPH_SHAPE_DIFFERENCE:
        /* removing parts never grows the first one */
        sph_shape_bounds(scene, sh->parts[0], lower, upper);
        return;
    }
}
