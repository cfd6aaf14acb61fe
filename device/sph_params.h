/* sph_params.h — the run-parameter block, defined once for the host, the
 * native backend and OpenCL C (docs/parameters.md).
 *
 * The block holds what the kernels read besides the particle fields: the
 * run's scalars (smoothing length, coefficients of the formulations), the
 * material table, and the constraint and wall tables.  Each field is listed
 * once below, as an X-macro entry (kind, name, count, comment); the struct
 * declarations, the host's conversion to the run precision and the layout
 * checks are all generated from these lists, so a field cannot exist on one
 * side only.  Real fields are in the run precision (`real`: double, or
 * float in single and mixed precision, whose arithmetic is single); the host
 * fills the double instance (sph_params_f64) and converts.
 *
 * Layout: no implicit padding anywhere (checked by _Static_assert on the
 * host and by the OpenCL compiler in the device program, see
 * SPH_PARAMS_LAYOUT_CHECK), so every offset is the sum of the sizes before
 * it and the host's bytes are the device's struct, whatever compiler builds
 * either side.  Hence the order: reals, tables of reals, then the ints (an
 * even number of them, so the double instance needs no tail padding). */
#ifndef SPH_PARAMS_H
#define SPH_PARAMS_H

#include "sph_constants.h"

/* Every limit of the tables, stated once. */
#define SPH_MAX_BODIES      8  /* bodies of a scene (body ids are u8) */
#define SPH_MAX_CONSTRAINTS 16 /* constraint k holds the particles whose `fixed` is k + 1 */
#define SPH_MAX_WALLS       6  /* rigid walls (device/sph_wall.h) */
/* Materials: every shipped scene has one, entry 0; several materials need a
 * per-particle material id (a later step of issue 32). */
#define SPH_MAX_MATERIALS 8

/* A material's constants (one table row). */
#define SPH_MATERIAL_FIELDS(X, S, T)                                                               \
    X(S, T, REAL, rho0, 1, "reference density")                                                    \
    X(S, T, REAL, c0, 1, "artificial sound speed")                                                 \
    X(S, T, REAL, shear_modulus, 1, "shear modulus G")                                             \
    X(S, T, REAL, bulk_modulus, 1, "K = rho0 c0^2, the stiffness of the equation of state")        \
    X(S, T, REAL, lambda, 1, "Lame's first parameter K - 2G/3 (TLSPH Saint Venant-Kirchhoff)")     \
    X(S, T, REAL, yield, 1, "J2 initial yield stress sigma_Y (003 eq. 11)")                        \
    X(S, T, REAL, hardening, 1, "J2 linear isotropic hardening modulus kappa")                     \
    X(S, T, REAL, viscosity, 1, "fluids: dynamic viscosity mu (004 eq. 13)")                       \
    X(S, T, REAL, gamma, 1, "compressible fluids: ratio of specific heats (004 eq. 11)")           \
    X(S, T, REAL, exponential_b, 1, "TLSPH exponential model: stiffening exponent b")

/* A kinematic constraint (device/sph_constraints.h): along the axes of its
 * mask the velocity is the prescribed one (0 for a clamp or a roller). */
#define SPH_CONSTRAINT_FIELDS(X, S, T)                                                             \
    X(S, T, REALS, velocity, 3, "prescribed velocity along the constrained axes")                  \
    X(S, T, INT, axis_mask, 1, "bit a set: axis a is constrained")                                 \
    X(S, T, INT, reserved, 1, "0; keeps the row free of padding in double")

/* A rigid wall (device/sph_wall.h). */
#define SPH_WALL_FIELDS(X, S, T)                                                                   \
    X(S, T, REALS, point, 3, "a point of the wall's plane")                                        \
    X(S, T, REALS, normal, 3, "unit normal into the solid")

/* The block.  Six ints (smoothing_kernel to elastic_model) select code
 * paths the native backend compiles into each variant and chooses between
 * at run time (one variant serves every kernel, rotation mode, body count,
 * plasticity switch and elastic law;
 * host/backend/cpu/cpu_kernel_tables.c); the OpenCL program has them as -D constants
 * (sph_prelude.h, RUNTIME_*) and never reads these fields. */
#define SPH_PARAMS_FIELDS(X, S, T)                                                                 \
    X(S, T, REAL, h, 1, "smoothing length h")                                                      \
    X(S, T, REAL, cutoff, 1, "support radius 2h, the neighbour cut-off")                           \
    X(S, T, REAL, dp, 1, "initial particle spacing")                                               \
    X(S, T, REALS, gravity, 3, "body acceleration (0 beyond the dimension)")                       \
    X(S, T, REAL, xi_e, 1, "ENOG coefficient xi_E (000 eq. 24)")                                   \
    X(S, T, REAL, xi_g, 1, "GNOG penalty coefficient xi_G (003 eqs. 43, 46)")                      \
    X(S, T, REAL, riemann_limit, 1, ">0: truncated-linear limiter slope; 0: unlimited")            \
    X(S, T, REAL, art_eps, 1, "OAS artificial-stress coefficient epsilon")                         \
    X(S, T, REAL, art_n, 1, "OAS exponent n of f = W(r)/W(dp)")                                    \
    X(S, T, REAL, art_wdp, 1, "W(dp) of the kernel in use")                                        \
    X(S, T, REAL, hourglass, 1, "TLSPH hourglass-control coefficient alpha (002)")                 \
    X(S, T, REAL, pair_damping, 1, "TLSPH pairwise damping coefficient (0: none)")                 \
    X(S, T, REAL, contact_impedance, 1, "contact impedance factor (x 1/2 rho0 c0, sph_contact.h)") \
    X(S, T, REAL, contact_penalty, 1, "contact penalty factor (x rho0 c0^2, sph_contact.h)")       \
    X(S, T, REALS, period, 3, "fluids: length of each periodic axis (0: not periodic)")            \
    X(S, T, REAL, background_pressure, 1, "fluids: p_b of the compressible momentum fluxes")       \
    X(S, T, REAL, far_field_density, 1, "fluids: the far field's free-stream density")             \
    X(S, T, REAL, far_field_pressure, 1, "fluids: the far field's free-stream pressure (gas)")     \
    X(S, T, REALS, far_field_velocity, 3, "fluids: the far field's free-stream velocity")          \
    X(S, T, REAL, viscous_eps_linear, 1, "fluids: eps of 1/(r + eps) in eq. 13, or 0")             \
    X(S, T, REAL, viscous_eps_squared, 1, "fluids: eps^2 of r/(r^2 + eps^2) in eq. 13, or 0")      \
    X(S, T, MATERIALS, materials, SPH_MAX_MATERIALS, "the material table")                         \
    X(S, T, WALLS, walls, SPH_MAX_WALLS, "the wall table, nwalls rows used")                       \
    X(S, T, CONSTRAINTS, constraints, SPH_MAX_CONSTRAINTS, "the constraint table")                 \
    X(S, T, INTS, body_count, SPH_MAX_BODIES, "particles per body")                                \
    X(S, T, INT, nwalls, 1, "rows of the wall table in use")                                       \
    X(S, T, INT, smoothing_kernel, 1,                                                              \
      "native backend: KERNEL_* (not `kernel`, an OpenCL keyword)")                                \
    X(S, T, INT, rotation, 1, "native backend: ROTATION_*")                                        \
    X(S, T, INT, nbodies, 1, "native backend: number of bodies")                                   \
    X(S, T, INT, plastic, 1, "native backend: 1 for J2 plasticity")                                \
    X(S, T, INT, torque_projection, 1, "native backend: 1 for the torque projection")              \
    X(S, T, INT, elastic_model, 1, "native backend: ELASTIC_MODEL_* of TLSPH")                     \
    X(S, T, INT, periodic_mask, 1, "fluids: bit a set: axis a is periodic (neighbour_build.cl)")

/* Declarations: S names the instance (f32, f64), T is its real type. */
#define SPH_DECL_REAL(S, T, name, n)           T name;
#define SPH_DECL_REALS(S, T, name, n)          T name[n];
#define SPH_DECL_INT(S, T, name, n)            int name;
#define SPH_DECL_INTS(S, T, name, n)           int name[n];
#define SPH_DECL_MATERIALS(S, T, name, n)      sph_params_material_##S name[n];
#define SPH_DECL_CONSTRAINTS(S, T, name, n)    sph_params_constraint_##S name[n];
#define SPH_DECL_WALLS(S, T, name, n)          sph_params_wall_##S name[n];
#define SPH_DECL(S, T, kind, name, n, comment) SPH_DECL_##kind(S, T, name, n)

/* The sum of the fields' sizes: equal to the struct's size when it has no
 * padding. */
#define SPH_SIZE_REAL(S, T, n)  +sizeof(T)
#define SPH_SIZE_REALS(S, T, n) +(n) * sizeof(T)
#define SPH_SIZE_INT(S, T, n)   +sizeof(int)
#define SPH_SIZE_INTS(S, T, n)  +(n) * sizeof(int)
/* a table counts its rows' sizes; the rows are checked on their own (a
 * macro cannot expand itself inside its own expansion) */
#define SPH_SIZE_MATERIALS(S, T, n)            +(n) * sizeof(sph_params_material_##S)
#define SPH_SIZE_CONSTRAINTS(S, T, n)          +(n) * sizeof(sph_params_constraint_##S)
#define SPH_SIZE_WALLS(S, T, n)                +(n) * sizeof(sph_params_wall_##S)
#define SPH_SIZE(S, T, kind, name, n, comment) SPH_SIZE_##kind(S, T, n)

#define SPH_PARAMS_DEFINE(S, T)                                                                    \
    typedef struct {                                                                               \
        SPH_MATERIAL_FIELDS(SPH_DECL, S, T)                                                        \
    } sph_params_material_##S;                                                                     \
    typedef struct {                                                                               \
        SPH_CONSTRAINT_FIELDS(SPH_DECL, S, T)                                                      \
    } sph_params_constraint_##S;                                                                   \
    typedef struct {                                                                               \
        SPH_WALL_FIELDS(SPH_DECL, S, T)                                                            \
    } sph_params_wall_##S;                                                                         \
    typedef struct {                                                                               \
        SPH_PARAMS_FIELDS(SPH_DECL, S, T)                                                          \
    } sph_params_##S;

/* The size the block of instance (S, T) has without padding. */
#define SPH_PARAMS_PACKED_SIZE(S, T)     (0 SPH_PARAMS_FIELDS(SPH_SIZE, S, T))
#define SPH_MATERIAL_PACKED_SIZE(S, T)   (0 SPH_MATERIAL_FIELDS(SPH_SIZE, S, T))
#define SPH_CONSTRAINT_PACKED_SIZE(S, T) (0 SPH_CONSTRAINT_FIELDS(SPH_SIZE, S, T))
#define SPH_WALL_PACKED_SIZE(S, T)       (0 SPH_WALL_FIELDS(SPH_SIZE, S, T))

#ifdef __OPENCL_VERSION__
/* The device program has the instance of its precision only (double needs
 * cl_khr_fp64).  OpenCL C 1.2 has no _Static_assert: a negative array size
 * fails the build instead.  SPH_PARAMS_SIZE is the host's sizeof (an option
 * of the build, host/model/feature_set.c), so a layout the two compilers disagree
 * on cannot run. */
#    if SPH_DOUBLE
SPH_PARAMS_DEFINE(f64, double)
typedef sph_params_f64 sph_params;
typedef sph_params_material_f64 sph_params_material;
typedef sph_params_constraint_f64 sph_params_constraint;
typedef sph_params_wall_f64 sph_params_wall;
#        define SPH_PARAMS_INSTANCE f64, double
#    else
SPH_PARAMS_DEFINE(f32, float)
typedef sph_params_f32 sph_params;
typedef sph_params_material_f32 sph_params_material;
typedef sph_params_constraint_f32 sph_params_constraint;
typedef sph_params_wall_f32 sph_params_wall;
#        define SPH_PARAMS_INSTANCE f32, float
#    endif
#    define SPH_PARAMS_CHECK_(name, cond)      typedef char name[(cond) ? 1 : -1]
#    define SPH_PARAMS_CHECK(name, cond)       SPH_PARAMS_CHECK_(name, cond)
#    define SPH_PARAMS_PACKED_SIZE_I(args)     SPH_PARAMS_PACKED_SIZE(args)
#    define SPH_MATERIAL_PACKED_SIZE_I(args)   SPH_MATERIAL_PACKED_SIZE(args)
#    define SPH_CONSTRAINT_PACKED_SIZE_I(args) SPH_CONSTRAINT_PACKED_SIZE(args)
#    define SPH_WALL_PACKED_SIZE_I(args)       SPH_WALL_PACKED_SIZE(args)
SPH_PARAMS_CHECK(sph_params_has_no_padding,
                 sizeof(sph_params) == SPH_PARAMS_PACKED_SIZE_I(SPH_PARAMS_INSTANCE));
SPH_PARAMS_CHECK(sph_material_has_no_padding,
                 sizeof(sph_params_material) == SPH_MATERIAL_PACKED_SIZE_I(SPH_PARAMS_INSTANCE));
SPH_PARAMS_CHECK(sph_constraint_has_no_padding,
                 sizeof(sph_params_constraint) ==
                     SPH_CONSTRAINT_PACKED_SIZE_I(SPH_PARAMS_INSTANCE));
SPH_PARAMS_CHECK(sph_wall_has_no_padding,
                 sizeof(sph_params_wall) == SPH_WALL_PACKED_SIZE_I(SPH_PARAMS_INSTANCE));
#    ifdef SPH_PARAMS_SIZE
SPH_PARAMS_CHECK(sph_params_size_is_the_hosts, sizeof(sph_params) == SPH_PARAMS_SIZE);
#    endif
#else
SPH_PARAMS_DEFINE(f64, double)
SPH_PARAMS_DEFINE(f32, float)
/* no padding in either instance: offsets are prefix sums of the sizes, the
 * same for every compiler */
#    ifdef SPH_DOUBLE
/* the native backend's device code: the instance of its real type */
#        if SPH_DOUBLE
typedef sph_params_f64 sph_params;
typedef sph_params_material_f64 sph_params_material;
typedef sph_params_constraint_f64 sph_params_constraint;
typedef sph_params_wall_f64 sph_params_wall;
#        else
typedef sph_params_f32 sph_params;
typedef sph_params_material_f32 sph_params_material;
typedef sph_params_constraint_f32 sph_params_constraint;
typedef sph_params_wall_f32 sph_params_wall;
#        endif
#    endif
_Static_assert(sizeof(sph_params_f64) == SPH_PARAMS_PACKED_SIZE(f64, double), "padding in f64");
_Static_assert(sizeof(sph_params_f32) == SPH_PARAMS_PACKED_SIZE(f32, float), "padding in f32");
_Static_assert(sizeof(sph_params_material_f64) == SPH_MATERIAL_PACKED_SIZE(f64, double), "padding");
_Static_assert(sizeof(sph_params_constraint_f64) == SPH_CONSTRAINT_PACKED_SIZE(f64, double),
               "padding");
_Static_assert(sizeof(sph_params_wall_f64) == SPH_WALL_PACKED_SIZE(f64, double), "padding");
_Static_assert(sizeof(sph_params_material_f32) == SPH_MATERIAL_PACKED_SIZE(f32, float), "padding");
_Static_assert(sizeof(sph_params_constraint_f32) == SPH_CONSTRAINT_PACKED_SIZE(f32, float),
               "padding");
_Static_assert(sizeof(sph_params_wall_f32) == SPH_WALL_PACKED_SIZE(f32, float), "padding");

/* The host's conversion of the double block to the run precision: each
 * real rounded once, as the old per-entry conversion did. */
#    define SPH_CONV_REAL(S, T, name, n) d->name = (T)s->name;
#    define SPH_CONV_REALS(S, T, name, n)                                                          \
        for (int k_ = 0; k_ < (n); ++k_) d->name[k_] = (T)s->name[k_];
#    define SPH_CONV_INT(S, T, name, n) d->name = s->name;
#    define SPH_CONV_INTS(S, T, name, n)                                                           \
        for (int k_ = 0; k_ < (n); ++k_) d->name[k_] = s->name[k_];
#    define SPH_CONV_MATERIALS(S, T, name, n)                                                      \
        for (int k_ = 0; k_ < (n); ++k_) sph_params_material_to_##S(&s->name[k_], &d->name[k_]);
#    define SPH_CONV_CONSTRAINTS(S, T, name, n)                                                    \
        for (int k_ = 0; k_ < (n); ++k_) sph_params_constraint_to_##S(&s->name[k_], &d->name[k_]);
#    define SPH_CONV_WALLS(S, T, name, n)                                                          \
        for (int k_ = 0; k_ < (n); ++k_) sph_params_wall_to_##S(&s->name[k_], &d->name[k_]);
#    define SPH_CONV(S, T, kind, name, n, comment) SPH_CONV_##kind(S, T, name, n)

static inline void sph_params_material_to_f32(const sph_params_material_f64 *s,
                                              sph_params_material_f32 *d) {
    SPH_MATERIAL_FIELDS(SPH_CONV, f32, float)
}
static inline void sph_params_constraint_to_f32(const sph_params_constraint_f64 *s,
                                                sph_params_constraint_f32 *d) {
    SPH_CONSTRAINT_FIELDS(SPH_CONV, f32, float)
}
static inline void sph_params_wall_to_f32(const sph_params_wall_f64 *s, sph_params_wall_f32 *d) {
    SPH_WALL_FIELDS(SPH_CONV, f32, float)
}
static inline void sph_params_to_f32(const sph_params_f64 *s, sph_params_f32 *d) {
    SPH_PARAMS_FIELDS(SPH_CONV, f32, float)
}
#endif

#endif
