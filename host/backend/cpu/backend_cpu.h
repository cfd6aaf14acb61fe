/* backend_cpu.h — the native backend's seam between its generic host part
 * (backend_cpu.c: allocation, sort, permutation) and the physics, which is the
 * device/ source compiled as C once per dimension, precision and formulation
 * (backend_cpu_kernels.c; instances cpu_<dim>d_<f64|f32|mixed>_<formulation>,
 * listed in CMakeLists.txt and host/backend/cpu/cpu_kernel_tables.c). */
#ifndef SPH_BACKEND_CPU_H
#define SPH_BACKEND_CPU_H

#include "fields.h"
#include "grid.h"
#include "cpu_team.h"
#include "physics.h"

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
    /* ... and, for the rate passes (the two stages' and SSP-RK's), each
     * fluid pair once (eulerian_step.cl, "sum each fluid pair once";
     * build_once_rows): row i from once_start[i] holds once_count[i] fluid
     * pairs, each in one row only (j > i, or j < i in i's block where
     * balance_once_rows handed it to i; padded with empty pairs, j = i, to
     * whole lanes), once_walls[i] wall pairs, then once_far[i] far pairs, in
     * once_j and once_e, once_dwv, once_inv_r; far_rows lists the nfar_rows
     * rows with far pairs; pair_block is the block length; force_sum the two
     * stages' momentum rates (dim x n; NULL for SSP-RK, which sums into its
     * momentum_rate field).  NULL before */
    int32_t *once_start, *once_count, *once_walls, *once_far, *once_j, *far_rows;
    void *once_e, *once_dwv, *once_inv_r, *force_sum;
    int nfar_rows, pair_block;
    /* the far field's particles (kind inflow or outflow) and their frozen
     * weights S (eulerian_step.cl, far_field_weight), nfar_field of each;
     * NULL without a far field */
    int32_t *far_field;
    void *far_field_weight;
    int nfar_field;
    void *pair_w; /* TLSPH only: reference hourglass weights (else NULL) */
    uint64_t *keys;
    int32_t *cell_start, *cell_end;
    void *prm;          /* sph_params in the run precision */
    void *grid_geom;    /* real[4]: origin, 1/cell */
    void *partials;     /* real[ngroups * ncomp] */
    void *substep_sums; /* real[1 + SPH_MAX_BODIES * 9] */
    int ngroups;
    int rk_stages;         /* fluids: SSP-RK's stages (time.integrator), 0: the two stages */
    bool parallel;         /* run the loops on the OpenMP team (else on the calling thread) */
    cpu_team_barrier team; /* the substeps' barrier (cpu_team.h) */
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
    /* substeps under the step clock (device/sph_step_clock.h) until it
     * halts or clock[CLOCK_COUNT] reaches limit, in one parallel region */
    void (*advance)(cpu_buffers *b, double *clock, long limit);
    /* fluids, once after the rebuild (eulerian_step.cl): the initial EOS
     * state and the corrected pair gradients; NULL for solids */
    void (*fluid_setup)(cpu_buffers *b);
    /* fluids in 2D and 3D: the vorticity of the current state into its field
     * (eulerian_vorticity), when a snapshot downloads it */
    void (*fluid_vorticity)(cpu_buffers *b);
    /* kinetic, strain, momentum (dim), angular (1 or 3) */
    void (*diagnostics)(cpu_buffers *b, double *out);
    /* instability monitor (device/monitor.cl): SPH_MONITOR_NCOMP(dim) values */
    void (*monitor)(cpu_buffers *b, double *out);
    /* the point functions of the same instance (model/physics.h) */
    sph_physics physics;
} cpu_kernels;

/* the double or single instance of the SPH-ENOG build (its point functions
 * do not depend on the formulation: sph_physics_for) */
const cpu_kernels *cpu_kernels_for(int dim, bool double_precision);
/* the instance of a run's dimension, precision mode and formulation */
const cpu_kernels *cpu_kernels_for_features(const sph_features *f);

#endif
