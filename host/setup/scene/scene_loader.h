/* scene_loader.h — what the parts of the scene loader share (not an API:
 * scene.h is).  The loader walks one libconfig tree against the schema
 * (scene_schema.h), one section per file:
 *   scene.c            reading the file, the top level, the public API
 *   scene_values.c     typed access through the schema, messages
 *   scene_overrides.c  `--set key=value` and 64-bit integer literals
 *   scene_method.c     resolution, method, time
 *   scene_materials.c  materials and the formulation's material model
 *   scene_shapes.c     shapes, and the geometry queries on them
 *   scene_bodies.c     bodies: velocity, placement, fluid state, regions,
 *                      constraints; the constants of the expressions
 *   scene_observers.c  observers, analysis, output, monitor
 *   scene_boundaries.c walls, contact, the fluids' boundary and forces */
#ifndef SPH_SCENE_LOADER_H
#define SPH_SCENE_LOADER_H

#include "scene.h"
#include "scene_schema.h"

#include <libconfig.h>

#include <stdbool.h>
#include <stddef.h>

typedef struct {
    const char *file; /* the scene path, as given */
    sph_error *err;
    sph_scene *scene;
    int nnamed_shapes; /* shapes [0, nnamed_shapes) are the named members of `shapes` */
    /* the definition of every shape and its `parts` setting, for messages */
    const config_setting_t *shape_def[SPH_SCENE_MAX_SHAPES];
    const config_setting_t *shape_parts[SPH_SCENE_MAX_SHAPES];
    int nconstraints_total; /* constraints of the bodies parsed so far */
} loader;

/* The schema sections whose keys a group may hold, in order:
 * SECTIONS("shapes", "shapes.box"). */
#define SECTIONS(...) ((const char *const[]){__VA_ARGS__, NULL})
/* Key names, for scene_first_member: KEY_NAMES("xi_e", "xi_g"). */
#define KEY_NAMES(...) ((const char *const[]){__VA_ARGS__, NULL})

extern const char *const SCENE_AXES[3];

/* messages (scene_values.c) */
const char *scene_type_name(int type);
const char *scene_override_of(const config_setting_t *s);
__attribute__((format(printf, 4, 5))) sph_status
scene_fail_at(loader *L, const config_setting_t *s, const char *key, const char *fmt, ...);
void scene_where_of(const loader *L, const config_setting_t *s, char *buf, size_t size);
void scene_suggest(const char *given, const char *const *names, int n, const char *what, char *buf,
                   size_t size);
const char *scene_axes_text(int dim);
const char *scene_variables_text(int dim);

/* typed access through the schema (scene_values.c): the key's name, whether
 * it is required, its range and its default come from its table entry */
sph_status scene_check_keys(loader *L, const config_setting_t *g, const char *const *sections);
sph_status scene_member(loader *L, const config_setting_t *g, sph_scene_key_id k,
                        const config_setting_t **out);
sph_status scene_require(loader *L, const config_setting_t *g, sph_scene_key_id k,
                         const config_setting_t **out);
/* The first of the NULL-terminated `names` that g holds, else NULL: the key
 * a refusal names when a group holds keys of another kind of scene. */
const config_setting_t *scene_first_member(const config_setting_t *g, const char *const *names);
sph_status scene_as_float(loader *L, const config_setting_t *s, double *out);
sph_status scene_as_string(loader *L, const config_setting_t *s, const char **out);
sph_status scene_as_vector(loader *L, const config_setting_t *s, int len, double out[3]);
sph_status scene_number(loader *L, const config_setting_t *g, sph_scene_key_id k, double *out);
sph_status scene_number_or(loader *L, const config_setting_t *g, sph_scene_key_id k, double def,
                           double *out);
sph_status scene_integer(loader *L, const config_setting_t *g, sph_scene_key_id k, int *out,
                         const config_setting_t **where);
sph_status scene_boolean(loader *L, const config_setting_t *g, sph_scene_key_id k, bool *out);
sph_status scene_keyword(loader *L, const config_setting_t *g, sph_scene_key_id k, int *out,
                         const config_setting_t **where);
sph_status scene_keyword_or(loader *L, const config_setting_t *g, sph_scene_key_id k, int def,
                            int *out, const config_setting_t **where);
sph_status scene_name(loader *L, const config_setting_t *g, sph_scene_key_id k, const char **out,
                      const config_setting_t **where);
sph_status scene_vector(loader *L, const config_setting_t *g, sph_scene_key_id k, int len,
                        double out[3], const config_setting_t **where);
sph_status scene_group(loader *L, const config_setting_t *g, sph_scene_key_id k,
                       const config_setting_t **out);
sph_status scene_list(loader *L, const config_setting_t *g, sph_scene_key_id k,
                      const config_setting_t **out);
sph_status scene_axis(loader *L, const config_setting_t *g, sph_scene_key_id k, int *out);
sph_status scene_axis_list(loader *L, const config_setting_t *g, sph_scene_key_id k, bool required,
                           int *mask);
const char *scene_word(sph_scene_key_id k, int index);

/* An integer of 64 bits whatever its sign, over [-2^63, 2^64). */
typedef struct {
    bool negative;
    unsigned long long magnitude;
} scene_wide_int;
sph_status scene_wide_integer(loader *L, const config_setting_t *g, sph_scene_key_id k,
                              scene_wide_int *out, bool *present, const config_setting_t **where);
double scene_integer_value(const config_setting_t *s);
bool scene_wide_in(scene_wide_int v, long long lo, unsigned long long hi);
const char *scene_wide_text(scene_wide_int v, char buf[24]);

sph_status scene_relative_path(loader *L, const config_setting_t *at, const char *file, char *out,
                               size_t size);
sph_status scene_named_element(loader *L, const config_setting_t *g, int index,
                               const char *expected, const char *kind, const char *list,
                               sph_scene_key_id name_key, const char *names, size_t stride,
                               const char **name, const config_setting_t **at);

/* the tables parsed so far */
int scene_find_shape(const loader *L, const char *name);
sph_status scene_unknown_shape(loader *L, const config_setting_t *at, const char *name);
sph_status scene_material(loader *L, const config_setting_t *g, sph_scene_key_id k, int *out);

/* text before libconfig (scene_overrides.c) */
typedef struct {
    char *buf;
    size_t len, cap;
} scene_text;
bool scene_text_put(scene_text *t, const char *s, size_t n);
char *scene_widen_integers(const char *text);
sph_status scene_apply_override(loader *L, config_t *cfg, const char *ov);

/* the sections, in the order parse_scene calls them */
sph_status scene_parse_resolution(loader *L, const config_setting_t *root);
sph_status scene_parse_method(loader *L, const config_setting_t *root);
sph_status scene_parse_time(loader *L, const config_setting_t *root);
sph_status scene_parse_materials(loader *L, const config_setting_t *root);
sph_status scene_parse_shapes(loader *L, const config_setting_t *root);
sph_status scene_parse_constants(loader *L, const config_setting_t *root);
sph_status scene_parse_bodies(loader *L, const config_setting_t *root);
sph_status scene_parse_observers(loader *L, const config_setting_t *root);
sph_status scene_parse_analysis(loader *L, const config_setting_t *root);
sph_status scene_parse_output(loader *L, const config_setting_t *root);
sph_status scene_parse_monitor(loader *L, const config_setting_t *root);
sph_status scene_check_material_model(loader *L, const config_setting_t *root);
sph_status scene_parse_walls(loader *L, const config_setting_t *root);
sph_status scene_parse_contact(loader *L, const config_setting_t *root);
sph_status scene_parse_boundary(loader *L, const config_setting_t *root);
sph_status scene_parse_forces(loader *L, const config_setting_t *root);

#endif
