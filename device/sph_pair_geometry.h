/* sph_pair_geometry.h — the frozen pair geometry of an advection step, read
 * by the acoustic passes: stored per pair slot, or recomputed per pair.
 *
 * Every acoustic substep of an advection step uses the pair geometry of the
 * configuration rebuild (neighbour_build.cl): e_ij (from j to i), dW/dr V_j
 * and 1/r_ij at the shifted positions x + s v.  Two ways to serve it:
 *
 *   SPH_PAIR_RECOMPUTE 0 (stored): build_neighbours writes e, dW V_j and 1/r
 *     to per-slot arrays and every pass streams them back: (d + 2) reals and
 *     the index per slot and pass.  Cheapest where arithmetic is dear and
 *     bandwidth plentiful relative to it (CPUs: the native backend, pocl).
 *   SPH_PAIR_RECOMPUTE 1 (recomputed): a per-particle copy of the shifted
 *     positions (pair_pos, written once per rebuild by shifted_positions) is
 *     kept instead, and each pass recomputes the geometry from it: only the
 *     index per slot is streamed, the positions of the neighbours come from
 *     the cache.  For GPUs, whose acoustic passes were bound by the slot
 *     arrays' traffic (docs/benchmarks.md, "Stored or recomputed pair
 *     geometry"); it also frees those arrays' memory.
 *
 * Both give the geometry of the same configuration to round-off; with
 * recomputation the rebuild itself takes its distances from pair_pos, so the
 * neighbour sets, B (003 eq. 21) and every pass see the same bits, and the
 * pair terms stay exactly antisymmetric (d_ji = -d_ij, a difference of two
 * stored values).  TLSPH keeps its stored reference geometry.
 *
 * Kernels name their pair inputs with PAIR_DIR_PARAMS (e and dW V_j) or
 * PAIR_GEOMETRY_PARAMS (with 1/r as well) and read a pair with
 * PAIR_DIR(slot, j) / PAIR_GEOMETRY(slot, j), which use the kernel's own
 * n, i, stride, prm and vol. */
#ifndef SPH_PAIR_GEOMETRY_H
#define SPH_PAIR_GEOMETRY_H

#include "sph_vec.h"
#include "sph_smoothing_kernel.h"

#ifndef SPH_PAIR_RECOMPUTE
#    define SPH_PAIR_RECOMPUTE 0
#endif

typedef struct {
    vec e;      /* unit vector from j to i */
    real dwv;   /* dW/dr (r_ij) V_j */
    real inv_r; /* 1 / r_ij (PAIR_GEOMETRY only) */
} pair_geometry;

#if SPH_PAIR_RECOMPUTE
#    define PAIR_DIR_PARAMS        GLOBAL const hreal *restrict pair_pos
#    define PAIR_GEOMETRY_PARAMS   GLOBAL const hreal *restrict pair_pos
#    define PAIR_GEOMETRY_ARGS     pair_pos
#    define PAIR_DIR_ARGS          pair_pos
#    define PAIR_DIR(slot, j)      pair_geometry_recomputed(prm, pair_pos, vol, n, i, (j))
#    define PAIR_GEOMETRY(slot, j) pair_geometry_recomputed(prm, pair_pos, vol, n, i, (j))

/* The same arithmetic as build_neighbours on the same stored positions: the
 * bits it froze for the pair (r > 0 there: coincident pairs are not listed). */
FN pair_geometry pair_geometry_recomputed(CONSTANT sph_params *prm,
                                          GLOBAL const hreal *restrict pair_pos,
                                          GLOBAL const real *restrict vol, const int n, const int i,
                                          const int j) {
    pair_geometry g;
    const vec d = hvec_diff(pair_pos, n, i, j);
    const real r = sqrt(vec_dot(d, d));
    g.inv_r = R(1) / r;
    g.e = vec_scale(d, g.inv_r);
    g.dwv = kernel_dw(prm, r) * vol[j];
    return g;
}
#else
#    define PAIR_DIR_PARAMS      GLOBAL const real *restrict pair_e, GLOBAL const real *restrict pair_dwv
#    define PAIR_GEOMETRY_PARAMS PAIR_DIR_PARAMS, GLOBAL const real *restrict pair_inv_r
#    define PAIR_GEOMETRY_ARGS   pair_e, pair_dwv, pair_inv_r
#    define PAIR_DIR_ARGS        pair_e, pair_dwv
#    define PAIR_DIR(slot, j)    pair_geometry_stored(pair_e, pair_dwv, 0, stride, (slot))
#    define PAIR_GEOMETRY(slot, j)                                                                 \
        pair_geometry_stored(pair_e, pair_dwv, pair_inv_r, stride, (slot))

FN pair_geometry pair_geometry_stored(GLOBAL const real *restrict pair_e,
                                      GLOBAL const real *restrict pair_dwv,
                                      GLOBAL const real *restrict pair_inv_r, const int stride,
                                      const int slot) {
    pair_geometry g;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) g.e.c[a] = pair_e[a * stride + slot];
    g.dwv = pair_dwv[slot];
    g.inv_r = pair_inv_r ? pair_inv_r[slot] : R(0);
    return g;
}
#endif

/* Whole lanes of stored geometry (SPH_PAIR_LANES, sph_prelude.h) load
 * straight from the slot arrays, where the neighbours of a particle are
 * contiguous (row-major); otherwise lane by lane through PAIR_GEOMETRY. */
#if SPH_PAIR_LANES > 1 && !SPH_PAIR_RECOMPUTE && SPH_NBR_ROW_MAJOR
#    define PAIR_LANES_DIRECT 1
FN lanes lanes_load(GLOBAL const real *p) {
    lanes v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}
#else
#    define PAIR_LANES_DIRECT 0
#endif

/* Lanes filled one by one: neighbour k of particle i, or past its last
 * neighbour (k >= count, a padded lane) slot 0 and j = i, so v_ij = 0.
 * Returns the slot, sets j. */
FN_HOT int lane_pair(GLOBAL const int *restrict nbr_j, const int n, const int cap, const int i,
                     const int k, const int count, int *j) {
    (void)n; /* NBR_AT takes n or cap, by layout */
    (void)cap;
    const bool live = k < count;
    const int slot = NBR_AT(i, live ? k : 0);
    *j = live ? nbr_j[slot] : i;
    return slot;
}
/* Lane l of e_ij, dW V_j and, where inv_r is given, 1/r from the pair's
 * geometry g; all 0 for a padded lane (live false), so every term it adds is
 * a zero (1/r too: recomputed geometry gives j = i an infinite 1/r, and
 * 0 * inf is NaN). */
FN_HOT void lane_set_geometry(const pair_geometry g, const bool live, const int l, lanes *e,
                              lanes *dwv, lanes *inv_r) {
    LANE(*dwv, l) = live ? g.dwv : R(0);
    if (inv_r) LANE(*inv_r, l) = live ? g.inv_r : R(0);
    UNROLL for (int a = 0; a < SPH_DIM; ++a) LANE(e[a], l) = live ? g.e.c[a] : R(0);
}

#endif
