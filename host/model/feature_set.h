/* feature_set.h — what a scene needs, and nothing more.
 *
 * A scene resolves to a feature set: dimension, precision, formulation and
 * rotation mode, kernel, constraints, bodies, time-stepping criteria.  The
 * OpenCL program is built from it (the -D options below: kernels, kernel
 * arguments and buffers of unused features do not exist in that program);
 * the native backend selects its code paths from the same set, and the field
 * registry (fields.h) allocates only the buffers it names.
 */
#ifndef SPH_FEATURE_SET_H
#define SPH_FEATURE_SET_H

#include "particles.h"
#include "scene.h"
#include "sph_params.h"

#include <stdbool.h>
#include <stddef.h>

/* Precision modes (issue 5): double; single; mixed = single arithmetic with
 * the history fields (positions, density, shear stress, accumulated shear
 * acceleration; device/sph_prelude.h, hreal) stored and updated in double. */
typedef enum { SPH_PRECISION_DOUBLE, SPH_PRECISION_SINGLE, SPH_PRECISION_MIXED } sph_precision;

typedef struct {
    int dim;
    bool double_precision; /* the arithmetic and the non-history fields */
    bool mixed_precision;  /* single arithmetic, history fields in double */
    sph_formulation formulation;
    sph_rotation rotation;
    sph_kernel kernel;
    sph_stepping stepping;
    bool has_clamp;
    bool plastic; /* J2 plasticity (003 eqs. 11-14; TLSPH: finite strain, sph_plasticity.h) */
    /* TLSPH: the elastic law (ELASTIC_MODEL_*, materials.X.model) and the
     * pairwise numerical damping (method.pairwise_damping > 0) */
    int elastic_model;
    bool tl_damping;
    int nbodies;
    /* rows of the material table in use (sph_scene_material_rows): with
     * more than one, every particle carries its row (device/sph_materials.h) */
    int materials;
    /* several bodies that do not merge: same-body neighbour lists and the
     * contact force between bodies (device/sph_contact.h); not TLSPH */
    bool contact;
    int walls; /* rigid walls (device/sph_wall.h) */
    /* SPH-ENOG-A's accumulated shear acceleration kept free of net torque
     * per body (method.torque_projection, device/sph_torque_projection.h) */
    bool torque_projection;
    /* fluids (device/eulerian_step.cl): particle kinds and normals (walls
     * or a far field), wall bodies, the far field */
    bool fluid_kinds, fluid_walls, far_field;
    /* fluids in 2D and 3D whose snapshots write the vorticity (output.fields) */
    bool fluid_vorticity;
    /* fluids: SSP Runge-Kutta of fluid_rk_stages (2 or 3) stages in place of
     * the two-stage update (time.integrator) */
    bool fluid_rk;
    int fluid_rk_stages;
} sph_features;

void sph_features_from_scene(const sph_scene *scene, const sph_particles *particles,
                             sph_precision precision, sph_features *out);

/* "double", "single" or "mixed" */
const char *sph_precision_name(const sph_features *f);
/* Parse a precision name; false if it is none of them. */
bool sph_precision_parse(const char *name, sph_precision *out);
/* The history fields are double (double and mixed precision). */
bool sph_history_double(const sph_features *f);

/* OpenCL build options of the feature set plus the device-dependent layout
 * choices (work-group sizes, neighbour-array layout). */
/* The OpenCL program's -D options: the scene's features and the device's
 * layout choices (neighbour slots row- or column-major; pair geometry stored
 * or recomputed, device/sph_pair_geometry.h). */
void sph_features_build_options(const sph_features *f, int reduce_wg, int sort_wg,
                                bool nbr_row_major, bool pair_recompute, char *buf, size_t len);

/* Components of the substep reduction (device/reduction.cl, substep_ncomp)
 * and the most any reduction of the run has: the rows of the partials. */
int sph_substep_ncomp(const sph_features *f);
int sph_partial_ncomp(const sph_features *f);

/* The run-parameter block of the kernels (device/sph_params.h), in double;
 * backends convert it to their precision. */
sph_status sph_params_fill(const sph_scene *scene, const sph_particles *particles,
                           const sph_features *f, sph_params_f64 *prm, sph_error *err);

#endif
