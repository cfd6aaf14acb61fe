/* scene.h — a validated simulation scene.
 *
 * Scenes are libconfig files (docs/scene-format.md): commented, human
 * readable, every setting carries its source line.  sph_scene_load parses
 * the file, applies the CLI overrides (`--set key=value`), checks every key
 * against the schema (unknown keys are rejected with the nearest valid name)
 * and every value against its range, and resolves names (materials, shapes,
 * observers) into indices.  All errors are SPH_ERR_INPUT with a message that
 * names the file, the line and the full key path.
 *
 * The struct is plain data with fixed-size tables; the only heap block is
 * `resolved_text`, released by sph_scene_free.
 */
#ifndef SPH_SCENE_H
#define SPH_SCENE_H

#include "expression.h"
#include "sph_error.h"
/* the limits on bodies, materials and walls (the parameter block's tables) */
#include "sph_params.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define SPH_NAME_LEN              64
#define SPH_SCENE_MAX_SHAPES      64
#define SPH_SCENE_MAX_SHAPE_PARTS 16
#define SPH_SCENE_MAX_CONSTRAINTS 8
#define SPH_SCENE_MAX_REGIONS     8 /* material regions per body */
#define SPH_SCENE_MAX_OBSERVERS   16
#define SPH_SCENE_MAX_CONSTANTS   32 /* named constants of the expressions */
#define SPH_SCENE_PATH_LEN        1024
#define SPH_SCENE_WHERE_LEN       (SPH_SCENE_PATH_LEN + 160)

/* values equal the device's FORMULATION_* */
typedef enum {
    SPH_FORMULATION_ENOG = 0,
    SPH_FORMULATION_ENOG_A = 1,
    SPH_FORMULATION_OG = 2,
    SPH_FORMULATION_OAS = 3,
    SPH_FORMULATION_GNOG = 4,
    SPH_FORMULATION_GNOG_A = 5,
    SPH_FORMULATION_TLSPH = 6,
    /* seed 004 §3.1: fixed particles, conserved variables, Riemann fluxes
     * (device/eulerian_step.cl); weakly compressible p = c0^2 (rho - rho0)
     * with the linearised solver, or an ideal gas with HLLC and energy */
    SPH_FORMULATION_EULERIAN_WC = 7,
    SPH_FORMULATION_EULERIAN_COMPRESSIBLE = 8
} sph_formulation;
#define SPH_FORMULATION_IS_EULERIAN(f)                                                             \
    ((f) == SPH_FORMULATION_EULERIAN_WC || (f) == SPH_FORMULATION_EULERIAN_COMPRESSIBLE)
/* values equal the device's ROTATION_* */
typedef enum {
    SPH_ROTATION_NONE = 0,
    SPH_ROTATION_AVERAGED = 1,
    SPH_ROTATION_PER_PARTICLE = 2
} sph_rotation;
typedef enum { SPH_STEPPING_DUAL = 0, SPH_STEPPING_SINGLE = 1 } sph_stepping;
/* How the viscous term of the fluids (004 eq. 13) keeps 1/r finite for the
 * closest pairs, with eps = 0.01 h: r / (r^2 + eps^2) (Morris et al. 1997;
 * relative change (eps/r)^2 <= 1e-4, so the viscosity converges) or
 * 1 / (r + eps) as the public reference code has it (about 1 % less
 * viscosity at any resolution: the Taylor-Green kinetic energy then stops
 * converging below dp = 1/50, docs/fluids.md) */
typedef enum { SPH_VISCOUS_SQUARED = 0, SPH_VISCOUS_LINEAR = 1 } sph_viscous_regularization;
/* The fluids' update (time.integrator, device/eulerian_step.cl): the public
 * code's two stages (momentum from the state n, then mass and energy with
 * the new velocity), SSP-RK2 or SSP-RK3 (Shu & Osher 1988) */
typedef enum {
    SPH_FLUID_TWO_STAGE = 0,
    SPH_FLUID_SSP_RK2 = 1,
    SPH_FLUID_SSP_RK3 = 2
} sph_fluid_integrator;
/* values equal the device's KERNEL_* */
typedef enum {
    SPH_KERNEL_WENDLAND_C2 = 0,
    SPH_KERNEL_LAGUERRE_GAUSS = 1,
    SPH_KERNEL_LAGUERRE_WENDLAND = 2,
    SPH_KERNEL_CUBIC_BSPLINE = 3
} sph_kernel;

typedef enum {
    SPH_SHAPE_BOX,
    SPH_SHAPE_UNION,
    SPH_SHAPE_DIFFERENCE,
    /* inner_radius <= |x - centre| <= outer_radius: "disc" (2D) and "ball"
     * (3D) with inner_radius 0, "annulus" (2D), "hollow_sphere" (3D) */
    SPH_SHAPE_SPHERE,
    /* 0 <= (x - centre).axis <= length and the distance from the axis <=
     * outer_radius: "cylinder" (3D), centre = the centre of one end */
    SPH_SHAPE_CYLINDER,
    /* a closed triangle mesh read from a file (host/setup/mesh.h), 3D */
    SPH_SHAPE_MESH
} sph_shape_type;
typedef struct {
    sph_shape_type type;
    char name[SPH_NAME_LEN];   /* "" for a shape written inline */
    int line;                  /* source line of its definition */
    double lower[3], upper[3]; /* box corners in metres, padding applied */
    /* round shapes: centre, radii, unit axis and length (cylinder) */
    double centre[3], inner_radius, outer_radius, axis[3], length;
    int nparts;
    int parts[SPH_SCENE_MAX_SHAPE_PARTS]; /* indices into sph_scene.shapes */
    /* "mesh": the transformed, checked mesh (owned; sph_scene_free releases
     * it); lower/upper hold its bounding box */
    struct sph_mesh *mesh;
} sph_shape;

typedef enum {
    SPH_VELOCITY_ZERO,
    SPH_VELOCITY_UNIFORM,         /* v = vector */
    SPH_VELOCITY_RIGID_ROTATION,  /* v = omega x (x - centre) */
    SPH_VELOCITY_CANTILEVER_MODE, /* 003 eqs. 50-51, see below */
    SPH_VELOCITY_PLATE_MODE,      /* 000 eq. 35, see below */
    SPH_VELOCITY_EXPRESSION       /* v_a = expression[a](x, y, z), see below */
} sph_velocity_type;
typedef struct {
    sph_velocity_type type;
    double vector[3];
    double omega[3]; /* 2D: only omega[2] (about z) is used */
    double centre[3];
    /* cantilever mode: v[axis] = amplitude_c0 * c0 * f(s)/f(length) with
     * s = x - clamp_x for s > 0, else 0;  f(s) = (sin kL + sinh kL)(cos ks -
     * cosh ks) - (cos kL + cosh kL)(sin ks - sinh ks),  k = kl / length */
    double amplitude_c0, length, kl, clamp_x;
    int axis;
    /* plate mode (3D): v[axis] = amplitude sin(m pi (x - lower_x) / size_x)
     * sin(n pi (y - lower_y) / size_y), the mode (m, n) of a simply supported
     * rectangular plate (000 eq. 35) */
    double amplitude, lower[2], size[2];
    int modes[2];
    /* expression: component a is expression[a] of x, y (, z) and the
     * scene's constants, "" for 0 (expression.h); compiled and checked at
     * load, evaluated per particle by particles.c, whose messages about a
     * non-finite value name expression_where[a] ("<file>:<line>:
     * bodies.<name>.initial_velocity.y", see sph_body.where) */
    char expression[3][SPH_EXPRESSION_MAX_LEN];
    char expression_where[3][SPH_SCENE_WHERE_LEN];
} sph_velocity_field;

typedef struct {
    char name[SPH_NAME_LEN];
    double density, youngs_modulus, poisson_ratio;
    /* derived: c0 = sqrt(E / (3 (1 - 2 nu) rho0)) (000 eq. 5), G = E/(2(1+nu)),
     * K = rho0 c0^2 = E / (3 (1 - 2 nu)) */
    double sound_speed, shear_modulus, bulk_modulus;
    /* J2 plasticity with linear isotropic hardening (003 eqs. 11-14) when
     * yield_stress is given */
    bool plastic;
    double yield_stress, hardening_modulus;
    /* TLSPH's elastic law (`model`): ELASTIC_MODEL_* of device/sph_constants.h
     * (Saint Venant-Kirchhoff, neo-Hookean, exponential) and the exponential
     * law's stiffening exponent b (device/tl_step.cl) */
    int elastic_model;
    double exponential_b;
    /* fluids (the eulerian formulations): `fluid` when the material has no
     * youngs_modulus; density is rho0 (WC: p = c0^2 (rho - rho0) with
     * c0 = sound_speed), viscosity the dynamic viscosity mu (eq. 13, 0: none),
     * gamma the ideal gas's ratio of specific heats (compressible) */
    bool fluid;
    double viscosity, gamma;
} sph_material;

typedef enum {
    SPH_CONSTRAINT_FIXED,      /* at rest: every axis */
    SPH_CONSTRAINT_FIXED_AXES, /* at rest along the chosen axes (rollers, supports) */
    SPH_CONSTRAINT_VELOCITY    /* moving at a prescribed velocity along the chosen axes */
} sph_constraint_type;
typedef struct {
    sph_constraint_type type;
    int region;         /* shape index */
    int axis_mask;      /* bit a: axis a is constrained */
    double velocity[3]; /* prescribed velocity (0 unless SPH_CONSTRAINT_VELOCITY) */
    /* "<file>:<line>: bodies.<name>.constraints.[k].region" (see sph_body.where),
     * for a region that selects none of the body's particles (particles.c) */
    char where[SPH_SCENE_WHERE_LEN];
} sph_constraint;

/* bodies.X.regions[k]: the particles of the body inside `shape` are of
 * `material` instead of the body's own (the first region that holds a
 * particle decides); the parts are bonded: they share the body's neighbour
 * lists, and every pair across the interface takes the two-material terms
 * of device/sph_materials.h. */
typedef struct {
    int shape;    /* index into shapes */
    int material; /* index into materials */
    /* "<file>:<line>: bodies.<name>.regions.[k]" (see sph_body.where), for
     * a region that selects none of the body's particles (particles.c) */
    char where[SPH_SCENE_WHERE_LEN];
} sph_region;

/* How a body's particles are placed (particles.c, relax.c). */
typedef enum {
    SPH_PLACEMENT_LATTICE = 0, /* cell centres of the dp lattice */
    SPH_PLACEMENT_RELAXED = 1  /* the lattice particles, perturbed and relaxed (relax.h) */
} sph_placement;
/* bodies[i].relaxation.step: how far each relaxation step moves the
 * particles (relax.h) */
typedef enum {
    SPH_RELAX_STEP_NORMALISED = 0, /* the largest move h/32 (the reference code's) */
    SPH_RELAX_STEP_FIXED = 1       /* x += alpha h^2 a, alpha below the lattice's limit */
} sph_relax_step;
/* bodies[i].relaxation (docs/scene-format.md) */
typedef struct {
    int steps;           /* at most this many relaxation steps */
    sph_relax_step step; /* the step's rule */
    double tolerance;    /* stop once the mean residual is at most this (0: run all steps) */
    double perturbation; /* amplitude of the initial random offset per axis, in dp */
    uint64_t seed;       /* of the offset's pseudo-random sequence, the full unsigned range */
    /* where the relaxed positions are saved and reused ("": nowhere),
     * resolved against the scene file's directory */
    char file[SPH_SCENE_PATH_LEN];
} sph_relaxation;

/* What a body is in a fluid scene (the eulerian formulations). */
typedef enum {
    SPH_BODY_MATTER = 0, /* the body's material moves (a solid, or the fluid) */
    /* a rigid wall at rest: its particles (spacing_ratio dp apart, the public
     * code's cylinder at dp/2) bound the fluid by the mirrored Riemann
     * state and the no-slip viscous term (device/eulerian_step.cl) */
    SPH_BODY_WALL = 1
} sph_body_role;

typedef struct {
    char name[SPH_NAME_LEN];
    int material;         /* index into materials */
    sph_body_role role;   /* bodies.X.role: "matter" (default) or "wall" (fluid scenes) */
    double spacing_ratio; /* bodies.X.spacing: its particle spacing / dp (1; walls 0.5) */
    int shape;            /* index into shapes */
    sph_velocity_field velocity;
    sph_placement placement;
    sph_relaxation relaxation; /* placement == SPH_PLACEMENT_RELAXED */
    int nconstraints;
    sph_constraint constraints[SPH_SCENE_MAX_CONSTRAINTS];
    int nregions;
    sph_region regions[SPH_SCENE_MAX_REGIONS];
    /* fluid bodies: initial density and pressure as expressions of x, y, z
     * and the scene's constants ("": not given; the material's density, the
     * pressure of the EOS); *_where as expression_where of the velocity */
    char initial_density[SPH_EXPRESSION_MAX_LEN];
    char initial_density_where[SPH_SCENE_WHERE_LEN];
    char initial_pressure[SPH_EXPRESSION_MAX_LEN];
    char initial_pressure_where[SPH_SCENE_WHERE_LEN];
    /* where it is defined, for messages about it after loading (overlaps,
     * no particles): "<file>:<line>: bodies.<name>" or "--set ...: ..." */
    char where[SPH_SCENE_WHERE_LEN];
} sph_body;

/* What an observer reports (observers.<name>.quantity). */
typedef enum {
    SPH_OBSERVE_POSITION = 0, /* its material point's position: <name>_x, ... */
    /* the traction sigma . n on the plane of unit normal n through it,
     * sigma = -p I + tau of the solid: <name>_traction_x, ... */
    SPH_OBSERVE_TRACTION = 1
} sph_observed;

typedef struct {
    char name[SPH_NAME_LEN];
    double position[3];
    sph_observed quantity;
    double normal[3]; /* unit; SPH_OBSERVE_TRACTION */
    /* "<file>:<line>: observers.<name>.position" (see sph_body.where) */
    char where[SPH_SCENE_WHERE_LEN];
} sph_observer;

typedef enum {
    SPH_MONITOR_STOP = 0,   /* stop, keep the results, exit status 4 */
    SPH_MONITOR_REPORT = 1, /* report once and go on */
    SPH_MONITOR_OFF = 2
} sph_monitor_action;

/* Point data of the snapshots (docs/output-format.md); order = file order. */
typedef enum {
    SPH_OUT_VELOCITY,
    SPH_OUT_DISPLACEMENT,
    SPH_OUT_DENSITY,
    SPH_OUT_PRESSURE,
    SPH_OUT_VON_MISES,
    SPH_OUT_SHEAR_STRESS,
    SPH_OUT_BODY_ID,
    SPH_OUT_PARTICLE_ID,
    SPH_OUT_PLASTIC_STRAIN, /* plastic materials only */
    SPH_OUT_VORTICITY,      /* fluids: curl v (2D: the z component) */
    SPH_OUT_MACH_NUMBER,    /* fluids, compressible: |v| / c */
    SPH_OUT_MATERIAL_ID,    /* the material's index in the scene (several materials) */
    SPH_OUT_COUNT
} sph_output_field;

/* A rigid frictionless wall (device/sph_wall.h): the half-space behind the
 * plane through `point`, `normal` (unit) pointing into the solid. */
typedef struct {
    char name[SPH_NAME_LEN];
    double point[3];
    double normal[3];
    char where[SPH_SCENE_WHERE_LEN]; /* "file:line: walls.[k]" for messages */
} sph_wall;

typedef struct {
    char path[SPH_SCENE_PATH_LEN]; /* the scene file as given */
    char *resolved_text;           /* the scene after overrides, libconfig syntax (owned) */
    char title[256];
    int dim;

    /* discretisation */
    double dp;              /* initial particle spacing */
    double smoothing_ratio; /* h / dp (1.3) */
    sph_kernel kernel;
    bool has_lattice_origin;
    double lattice_origin[3]; /* default: lower corner of all bodies */

    /* method */
    sph_formulation formulation;
    sph_rotation rotation;
    bool torque_projection;           /* ENOG-A: a^s kept torque-free per body */
    double xi_e;                      /* default 0.7 d + 2.1 */
    double xi_g;                      /* GNOG: 4.0 elastic, 0.2 plastic; GNOG-A: 2.0 */
    double art_epsilon, art_exponent; /* OAS artificial stress: 0.3, 4 */
    double hourglass_alpha;           /* TLSPH hourglass control (002) */
    double pairwise_damping;          /* TLSPH pairwise numerical damping c_d (0: none) */
    double riemann_limiter_slope;     /* 0: unlimited dissipation */
    /* compressible: p_b subtracted from p* in the momentum fluxes (the far
     * field's p_inf unless method.background_pressure is given) */
    double background_pressure;
    bool background_pressure_given;
    sph_viscous_regularization viscous_regularization; /* fluids */
    sph_fluid_integrator fluid_integrator;             /* fluids: time.integrator */
    /* contact between bodies (scenes with several bodies, device/sph_contact.h)
     * and with walls (device/sph_wall.h): factors of the impedance term
     * (1/2 rho0 c0 u between bodies, rho0 c0 u at a wall) and of the penalty
     * (rho0 c0^2) */
    double contact_impedance, contact_penalty;
    double gravity[3];

    /* `constants`: names and values usable in the expressions of initial
     * fields, in file order */
    int nconstants;
    char constant_name[SPH_SCENE_MAX_CONSTANTS][SPH_NAME_LEN];
    double constant_value[SPH_SCENE_MAX_CONSTANTS];

    /* time */
    double end_time, output_interval;
    sph_stepping stepping;
    double cfl_advection, cfl_acoustic;
    bool has_reference_speed;
    double reference_speed; /* U_ref; default: max initial speed */
    bool acceleration_criterion;
    /* freeze the pair geometry at the start of the interval it serves (the
     * public reference code) instead of its midpoint (neighbour_build.cl) */
    bool geometry_at_start;

    int nmaterials;
    sph_material materials[SPH_MAX_MATERIALS];
    int nshapes;
    sph_shape shapes[SPH_SCENE_MAX_SHAPES];
    int nbodies;
    sph_body bodies[SPH_MAX_BODIES];
    int nobservers;
    sph_observer observers[SPH_SCENE_MAX_OBSERVERS];
    int nwalls;
    sph_wall walls[SPH_MAX_WALLS];

    /* fluids: `boundary.periodic` (bit a: axis a wraps around with the
     * period periodic_upper[a] - periodic_lower[a]) */
    int periodic_mask;
    double periodic_lower[3], periodic_upper[3];
    char periodic_where[SPH_SCENE_WHERE_LEN]; /* "<file>:<line>: boundary" */
    /* `boundary.far_field`: on the faces of [periodic_lower, periodic_upper]
     * (boundary.lower/upper) across the non-periodic axes, the fluid is
     * blended toward the free stream (rho_inf, U_inf and, for the ideal
     * gas, p_inf) after every step (004's far field;
     * eulerian-sph-reference.md §4) */
    bool has_far_field;
    double far_field_density, far_field_velocity[3], far_field_pressure;
    /* `forces`: the force on the wall bodies as drag and lift coefficients,
     * C = 2 F / (rho_ref U_ref^2 L_ref) (004 §4.3), and the summary's
     * mean drag, lift amplitude and Strouhal number over the trailing
     * `window` of the run (0: the whole run after its first half) */
    bool has_forces;
    double force_reference_density, force_reference_speed, force_reference_length;
    double force_window;

    /* snapshots: every `snapshot_every` output times (0: none) and at the end */
    double snapshot_interval;
    int snapshot_every;
    bool output_field[SPH_OUT_COUNT];

    /* instability monitor (device/monitor.cl), checked at output times */
    double monitor_zigzag;        /* zigzag indicator threshold */
    double monitor_min_distance;  /* pair distance / dp threshold */
    double monitor_energy_growth; /* trip when E(t) > (1 + this) E(0) */
    double monitor_speed_limit;   /* trip when max |v| > this (c0 + initial max |v|) */
    /* particles must stay inside [lower, upper]: given, or the initial
     * bounding box grown by domain_margin times its largest extent */
    double monitor_domain_margin;
    bool monitor_has_domain;
    double monitor_domain_lower[3], monitor_domain_upper[3];
    /* "<file>:<line>: monitor.domain" (see sph_body.where): the initial
     * particles must lie inside it (particles.c) */
    char monitor_domain_where[SPH_SCENE_WHERE_LEN];
    sph_monitor_action monitor_action;

    /* analysis.wave: a stress pulse's transmission through an interface,
     * from two traction observers (host/run/analysis.h, sph_wave_metrics):
     * the incident (and reflected) pulse at one, the transmitted at the
     * other; -1: none */
    int wave_incident, wave_transmitted;
    /* analysis: first oscillation period of an observer's coordinate */
    int period_observer; /* -1: none */
    int period_axis;
} sph_scene;

/* Parse, override, validate.  `overrides` are "key=value" strings. */
sph_status sph_scene_load(sph_scene *scene, const char *path, const char *const *overrides,
                          int noverrides, sph_error *err);
/* The same from scene text (a checkpoint's resolved scene); `origin` names
 * it in messages. */
sph_status sph_scene_load_text(sph_scene *scene, const char *origin, const char *text,
                               const char *const *overrides, int noverrides, sph_error *err);
/* Where `key` (a full path, "time.end") got its value, in the scene-error
 * prefix: "--set KEY=VALUE: KEY" when an override made it, else
 * "FILE:LINE: KEY" with its line (or that of the nearest group holding it,
 * where the key is left at its default), else "FILE: KEY" (a restart's
 * stored scene has no file).  True when the file or an override gives the
 * key, false when it is defaulted.  For messages after loading (the
 * pre-run work estimate); it reads the scene file again. */
bool sph_scene_key_where(const sph_scene *scene, const char *const *overrides, int noverrides,
                         const char *key, char *buf, size_t size);
void sph_scene_free(sph_scene *scene);

/* The rule for the names of materials, shapes, bodies, observers and walls
 * (docs/scene-format.md, "Names"): a letter, then letters, digits, '_' or
 * '-', at most SPH_NAME_LEN - 1 characters.  Names become timeseries.csv
 * column names, JSON strings, HDF5 attributes and `--set` key components;
 * under this rule none of them needs quoting or escaping.  False with the
 * reason in `why` (one line: bytes outside printable ASCII appear as \xHH). */
bool sph_name_check(const char *name, char *why, size_t size);
/* Observer names whose timeseries.csv columns <name>_x, _y, _z would repeat
 * built-in columns (momentum_x, angular_momentum_x, ...). */
bool sph_observer_name_reserved(const char *name);

/* Geometry queries on the scene's shape table. */
bool sph_shape_contains(const sph_scene *scene, int shape, const double x[3]);
void sph_shape_bounds(const sph_scene *scene, int shape, double lower[3], double upper[3]);

/* The scene's constraints in one table, body by body: the index of body b's
 * constraint c (at most SPH_MAX_CONSTRAINTS in all), and the entry itself. */
int sph_constraint_index(const sph_scene *scene, int body, int constraint);
int sph_constraint_count(const sph_scene *scene);
const sph_constraint *sph_constraint_at(const sph_scene *scene, int index);
/* true when a constraint prescribes a non-zero velocity (external work) */
bool sph_scene_has_driven_constraint(const sph_scene *scene);

/* The rows of a run's material table: the scene's materials that a body
 * or a region uses, in order of first use (body by body, its own material
 * before its regions'); row_of[m] is material m's row, -1 when unused.
 * Returns the number of rows (1 for every scene of one material). */
int sph_scene_material_rows(const sph_scene *scene, int row_of[SPH_MAX_MATERIALS]);
/* The material (an index into scene->materials) of body b's particle at x:
 * that of its first region holding x, else the body's. */
int sph_body_material_at(const sph_scene *scene, int body, const double x[3]);

const char *sph_formulation_name(sph_formulation f);

/* Independent components of a spin (rotation rate, vorticity, angular
 * momentum) in `dim` dimensions: none on a line, 1 in the plane, 3 in space
 * (NSPIN of device/sph_prelude.h). */
static inline int sph_spin_components(int dim) {
    return dim == 1 ? 0 : dim == 2 ? 1 : 3;
}
const char *sph_rotation_name(sph_rotation r);
const char *sph_kernel_name(sph_kernel k);
const char *sph_stepping_name(sph_stepping s);
const char *sph_output_field_name(sph_output_field f);
const char *sph_placement_name(sph_placement p);

/* The variables of the expressions of initial fields in a scene of
 * dimension `dim`: "x", "y" (, "z"); returns their number. */
int sph_scene_expression_variables(int dim, const char *vars[3]);
/* The scene's constants in the form expression.h takes; `names` must hold
 * SPH_SCENE_MAX_CONSTANTS pointers and live as long as the result. */
sph_expression_constants sph_scene_expression_constants(const sph_scene *scene,
                                                        const char *names[SPH_SCENE_MAX_CONSTANTS]);

#endif
