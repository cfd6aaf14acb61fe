/* backend_cpu.h — the native backend's seam between its generic host part
 * (backend_cpu.c: allocation, sort, permutation) and the physics, which is the
 * device/ source compiled as C once per dimension, precision and formulation
 * (backend_cpu_kernels.c; instances cpu_<dim>d_<f64|f32|mixed>_<formulation>,
 * listed in CMakeLists.txt and host/cpu_kernel_tables.c). */
#ifndef SPH_BACKEND_CPU_H
#define SPH_BACKEND_CPU_H

#include "fields.h"
#include "grid.h"

#include <stdbool.h>
#include <stdint.h>

/* Buffers in the variant's precision, passed as untyped pointers. */
typedef struct {
    int n, cap;
    void *field[FIELD_COUNT]; /* NULL when the field is not present */
    int32_t *nbr_count, *nbr_j;
    void *pair_e, *pair_dwv, *pair_inv_r;
    /* fluids (eulerian_step.cl): the rows packed after the rebuild, particle
     * i's pairs at row_start[i] ... row_start[i + 1] - 1 of row_j and of
     * pair_e, pair_dwv, pair_inv_r, which then hold the packed rows;
     * nbr_count and nbr_j keep the padded ones (the monitor).  A row's wall
     * pairs come last, row_walls[i] of them (NULL without walls).  NULL
     * before */
    int32_t *row_start, *row_j, *row_walls;
    /* ... and, for the two-stage passes, each fluid pair once
     * (eulerian_step.cl, "sum each fluid pair once"; build_once_rows): row i
     * from once_start[i] holds once_count[i] pairs with j > i (padded with
     * empty pairs, j = i, to whole lanes), once_walls[i] wall pairs, then
     * once_far[i] far pairs, in once_j and once_e, once_dwv, once_inv_r;
     * far_rows lists the nfar_rows rows with far pairs; pair_block is the
     * block length; force_sum the momentum rates (dim x n).  NULL before,
     * and for SSP-RK2 */
    int32_t *once_start, *once_count, *once_walls, *once_far, *once_j, *far_rows;
    void *once_e, *once_dwv, *once_inv_r, *force_sum;
    int nfar_rows, pair_block;
    void *pair_w; /* TLSPH only: reference hourglass weights (else NULL) */
    uint64_t *keys;
    int32_t *cell_start, *cell_end;
    void *prm;          /* sph_params in the run precision */
    void *grid_geom;    /* real[4]: origin, 1/cell */
    void *partials;     /* real[ngroups * ncomp] */
    void *substep_sums; /* real[1 + SPH_MAX_BODIES * 9] */
    int ngroups;
    bool parallel; /* run the loops on the OpenMP team (else on the calling thread) */
} cpu_buffers;

typedef struct {
    int dim;
    bool double_precision;
    bool mixed_precision; /* single arithmetic, history fields double */
    int formulation;      /* the FORMULATION_* it was compiled for */
    int pair_lanes;       /* SPH_PAIR_LANES: the pair loops' SIMD lanes */
    /* V = m/rho; out: -min x (dim), max x (dim), max |v|^2, max 4h|a| */
    void (*rebuild_reduce)(cpu_buffers *b, double *out);
    /* keys of the cells of x + geometry_shift v (neighbour_build.cl) */
    void (*cell_keys)(cpu_buffers *b, const sph_grid *g, double geometry_shift);
    /* stable counting sort of the keys into sorted, with the cell ranges
     * (neighbour_build.cl: counting_sort_by_cell) */
    void (*sort_by_cell)(const cpu_buffers *b, long ncells, uint64_t *sorted);
    /* returns the largest neighbour count when it exceeds cap, else 0 */
    /* the pair geometry at x + geometry_shift v (neighbour_build.cl) */
    int (*build_neighbours)(cpu_buffers *b, const sph_grid *g, double geometry_shift);
    void (*substep)(cpu_buffers *b, double dt, double *max_speed2);
    /* fluids, once after the rebuild (eulerian_step.cl): the initial EOS
     * state and the corrected pair gradients; NULL for solids */
    void (*fluid_setup)(cpu_buffers *b);
    /* kinetic, strain, momentum (dim), angular (1 or 3) */
    void (*diagnostics)(cpu_buffers *b, double *out);
    /* instability monitor (device/monitor.cl): SPH_MONITOR_NCOMP(dim) values */
    void (*monitor)(cpu_buffers *b, double *out);
    /* the monitor's measures of particle i alone, from host copies of the
     * fields (double, field layout) and row-major neighbour lists: which
     * particle tripped a check (host/instability.c) */
    void (*monitor_particle)(const sph_params_f64 *prm, int n, int cap, const int32_t *nbr_count,
                             const int32_t *nbr_j, const double *pos, const double *vel,
                             const double *vol, const double *bmat, int i, double *out);
    /* physics probes for unit tests and observers */
    double (*kernel_w)(const sph_params_f64 *prm, double r);
    double (*kernel_dw)(const sph_params_f64 *prm, double r);
    /* the kernel integrated over a plane at the distance d (sph_wall.h) */
    double (*wall_plane_kernel)(const sph_params_f64 *prm, double d);
    /* the ideal gas's sound speed sqrt(gamma p / rho) (sph_eulerian.h) */
    double (*ideal_gas_sound_speed)(double p, double rho, double gamma);
    /* Rodrigues matrix (row-major dim x dim) of spin components w over dt */
    void (*rodrigues)(const double *w, double dt, double *rot);
    /* pair terms of sph_riemann.h for states i, j (vectors of length dim) */
    void (*riemann_pair)(const double *v_i, const double *v_j, double p_i, double p_j, double z,
                         double dw, const double *e_ij, double *pressure, double *dissipation,
                         double *continuity);
    /* snapshot fields from rho and tau (host arrays, tau in field layout)
     * and the material rows (NULL: row 0); any output may be NULL:
     * pressure [n], von Mises [n], tau [n][6] */
    void (*stress_output)(const sph_params_f64 *prm, int n, const double *rho, const double *tau,
                          const uint8_t *material, double *pressure, double *von_mises,
                          double *tensor6);
    /* one substep of a material point's shear stress: Jaumann rate and, when
     * alpha is given and prm->plastic is set, the J2 return (row-major) */
    void (*stress_update)(const sph_params_f64 *prm, const double *grad_v, double dt, double *tau,
                          double *alpha);
    /* artificial stress of one particle (OAS), row-major d x d */
    void (*artificial_stress)(const double *tau, double p, double rho, double epsilon, double *r);
    /* TLSPH finite-strain J2 update of a material point (tl_j2_kirchhoff):
     * f row-major d x d; state = C_p^-1 (row-major d x d), (C_p^-1)_zz,
     * alpha, updated in place; tau = Kirchhoff stress (row-major d x d),
     * then tau_zz.  Returns 1 when it yielded. */
    int (*tl_j2_update)(const sph_params_f64 *prm, const double *f, double *state, double *tau);
} cpu_kernels;

/* the double or single instance of the SPH-ENOG build (physics probes: the
 * point functions do not depend on the formulation) */
const cpu_kernels *cpu_kernels_for(int dim, bool double_precision);
/* the instance of a run's dimension, precision mode and formulation */
const cpu_kernels *cpu_kernels_for_features(const sph_features *f);

#endif
