/* neighbour_build.cl — the configuration rebuild of each advection step.
 *
 * Cell sorting: every particle gets the key (cell << 32 | current index);
 * the keys are sorted (bitonic sort on GPUs, a stable counting sort on the
 * CPU and on CPU devices: both give the same order), all particle fields are gathered into
 * the sorted order, cell ranges are found from the sorted keys, and each
 * particle gathers its neighbours from the 3^d surrounding cells.
 *
 * The pair geometry is frozen here for the whole advection step (reference
 * notes §0.5 and §4): e_ij (from j to i), dW/dr V_j and 1/r_ij per pair, and
 * the kernel-gradient correction matrix (003 eq. 21)
 *     B_i = (-sum_j r_ij (x) grad_i W_ij V_j)^-1
 * computed as a Tikhonov-regularised inverse so that a particle with a
 * degenerate support (isolated, or on a line) gets a finite B.
 *
 * The frozen geometry is that of the middle of the interval it serves: the
 * positions x + s v with s = geometry_shift, half the coming advection step
 * (half the coming acoustic step with single-criterion stepping; 0 for TLSPH's
 * reference configuration), set by the host (host/run/solver.c); the cells are
 * those of the shifted positions too, so the pair sets are exactly those
 * within 2h there.  Position Verlet
 * (000 eqs. 27-29) conserves angular momentum exactly for central pair forces
 * evaluated at the half-step positions; forces along directions e_ij frozen
 * at the start of the interval instead lag the body's rotation by omega s,
 * which tilts the centripetal forces of a spinning solid forward by that
 * angle: a spurious torque that spins it up at the relative rate
 * omega^2 s (first order in the step).  On the spinning plate at acoustic
 * CFL 0.1 this lag was the whole of SPH-GNOG-A's angular-momentum error,
 * 1.51 % against 0.036 % with the shift, and 2.54 % against 1.06 % of
 * SPH-ENOG-A's (003 Fig. 13: 0.55 % and 2.58 %).
 */
#include "sph_vec.h"
#include "sph_smoothing_kernel.h"
#include "sph_pair_geometry.h"

#define SPH_TIKHONOV_EPS R(1e-8)
#define SORT_PAD_KEY     ((ulong)0xFFFFFFFFFFFFFFFFUL)

/* Grid geometry buffer: origin (SPH_DIM entries, padded to 3), then 1/cell. */
#define GRID_INV_CELL 3

FN int cell_coordinate(const real x, const real origin, const real inv_cell, const int cells) {
    int c = (int)floor((x - origin) * inv_cell);
    return c < 0 ? 0 : (c >= cells ? cells - 1 : c);
}

FN int cell_index_of(const vec x, GLOBAL const real *grid_geom, const int gx, const int gy,
                     const int gz) {
    const real inv_cell = grid_geom[GRID_INV_CELL];
    const int cx = cell_coordinate(x.c[0], grid_geom[0], inv_cell, gx);
#if SPH_DIM == 1
    (void)gy;
    (void)gz;
    return cx;
#else
    const int cy = cell_coordinate(x.c[1], grid_geom[1], inv_cell, gy);
#endif
#if SPH_DIM == 3
    const int cz = cell_coordinate(x.c[2], grid_geom[2], inv_cell, gz);
    return cx + gx * (cy + gy * cz);
#elif SPH_DIM == 2
    (void)gz;
    return cx + gx * cy;
#endif
}

/* Keys for the sort; items in [n, npad) pad the power-of-two sort. */
/* buffers of cell_keys: reads pos vel grid_geom:small; writes keys:ulong*npad */
KERNEL void cell_keys(ITEM_PARAM const int n, const int npad, GLOBAL const hreal *restrict pos,
                      GLOBAL const real *restrict vel, const real geometry_shift,
                      GLOBAL const real *restrict grid_geom, const int gx, const int gy,
                      const int gz, GLOBAL ulong *restrict keys) {
    const int i = ITEM_ID;
    if (i >= npad) return;
    if (i >= n) {
        keys[i] = SORT_PAD_KEY;
        return;
    }
    /* the cell of the shifted position x + s v, where the pair geometry is
     * taken (see the top): the stencil then holds every pair within 2h */
    const vec x = vec_axpy(hvec_load(pos, n, i), geometry_shift, vec_load(vel, n, i));
    const ulong cell = (ulong)cell_index_of(x, grid_geom, gx, gy, gz);
    keys[i] = (cell << 32) | (ulong)i;
}

FN int key_index(const ulong key) {
    return (int)(key & (ulong)0xFFFFFFFFUL);
}
FN int key_cell(const ulong key) {
    return (int)(key >> 32);
}

/* Gather fields into the sorted order, dst[c][k] = src[c][perm k], up to
 * PERMUTE_BATCH fields of one element type per launch (slots past the last
 * have ncomp = 0): a launch costs 5-8 us on pocl, and the ENOG-A plate has
 * 12 real fields. */
#define PERMUTE_BATCH 8 /* the host fills this many slots (backend_opencl.c) */
#define PERMUTE_SLOT_PARAMS(type, s)                                                               \
    , const int ncomp##s, GLOBAL const type *restrict src##s, GLOBAL type *restrict dst##s
#define PERMUTE_SLOT(s)                                                                            \
    for (int c = 0; c < ncomp##s; ++c) dst##s[c * n + k] = src##s[c * n + from]
#define DEFINE_PERMUTE(name, type)                                                                 \
    KERNEL void name(ITEM_PARAM const int n,                                                       \
                     GLOBAL const ulong *restrict keys PERMUTE_SLOT_PARAMS(type, 0)                \
                         PERMUTE_SLOT_PARAMS(type, 1) PERMUTE_SLOT_PARAMS(type, 2)                 \
                             PERMUTE_SLOT_PARAMS(type, 3) PERMUTE_SLOT_PARAMS(type, 4)             \
                                 PERMUTE_SLOT_PARAMS(type, 5) PERMUTE_SLOT_PARAMS(type, 6)         \
                                     PERMUTE_SLOT_PARAMS(type, 7)) {                               \
        const int k = ITEM_ID;                                                                     \
        if (k >= n) return;                                                                        \
        const int from = key_index(keys[k]);                                                       \
        PERMUTE_SLOT(0);                                                                           \
        PERMUTE_SLOT(1);                                                                           \
        PERMUTE_SLOT(2);                                                                           \
        PERMUTE_SLOT(3);                                                                           \
        PERMUTE_SLOT(4);                                                                           \
        PERMUTE_SLOT(5);                                                                           \
        PERMUTE_SLOT(6);                                                                           \
        PERMUTE_SLOT(7);                                                                           \
    }
/* buffers of permute_real: reads keys:ulong*n src0:host src1:host src2:host src3:host src4:host
 * src5:host src6:host src7:host; writes dst0:host dst1:host dst2:host dst3:host dst4:host
 * dst5:host dst6:host dst7:host */
DEFINE_PERMUTE(permute_real, real)
/* buffers of permute_int: reads keys:ulong*n src0:host src1:host src2:host src3:host src4:host
 * src5:host src6:host src7:host; writes dst0:host dst1:host dst2:host dst3:host dst4:host
 * dst5:host dst6:host dst7:host */
DEFINE_PERMUTE(permute_int, int)
/* buffers of permute_u8: reads keys:ulong*n src0:host src1:host src2:host src3:host src4:host
 * src5:host src6:host src7:host; writes dst0:host dst1:host dst2:host dst3:host dst4:host
 * dst5:host dst6:host dst7:host */
DEFINE_PERMUTE(permute_u8, u8)
#if SPH_MIXED
/* the history fields of mixed precision (double) */
/* buffers of permute_hreal: reads keys:ulong*n src0:host src1:host src2:host src3:host src4:host
 * src5:host src6:host src7:host; writes dst0:host dst1:host dst2:host dst3:host dst4:host
 * dst5:host dst6:host dst7:host */
DEFINE_PERMUTE(permute_hreal, hreal)
#endif

/* Stable counting sort of the keys by cell, which also yields the cell
 * ranges: the same order as the bitonic sort (the key's low half is the
 * current index, so ties stay in index order).  The native backend runs it
 * on the host thread, CPU devices on one work-item (counting_sort): a pass
 * over the particles, one over the cells and one to scatter, where the
 * bitonic network made ~log2(n)^2 / 2 passes and, at n = 1612, seven launches
 * (bitonic sort, fills, cell ranges) against one.  Empty cells get an empty
 * range [offset, offset). */
FN void counting_sort_by_cell(const int n, const int ncells, GLOBAL const ulong *restrict keys,
                              GLOBAL ulong *restrict sorted, GLOBAL int *restrict cell_start,
                              GLOBAL int *restrict cell_end) {
    for (int cell = 0; cell < ncells; ++cell) cell_end[cell] = 0;
    for (int i = 0; i < n; ++i) cell_end[key_cell(keys[i])]++;
    int offset = 0;
    for (int cell = 0; cell < ncells; ++cell) {
        const int count = cell_end[cell];
        cell_start[cell] = offset;
        cell_end[cell] = offset;
        offset += count;
    }
    for (int i = 0; i < n; ++i) {
        const ulong key = keys[i];
        sorted[cell_end[key_cell(key)]++] = key;
    }
}

#if SPH_OPENCL && SPH_COUNTING_SORT
/* buffers of counting_sort: reads keys:ulong*n; writes keys_sorted:ulong*n cell_start:int*cells
 * cell_end:int*cells */
__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void
counting_sort(const int n, const int gx, const int gy, const int gz,
              GLOBAL const ulong *restrict keys, GLOBAL ulong *restrict keys_sorted,
              GLOBAL int *restrict cell_start, GLOBAL int *restrict cell_end) {
    counting_sort_by_cell(n, gx * gy * gz, keys, keys_sorted, cell_start, cell_end);
}
#endif

/* B = (A^T A + eps I)^-1 A^T (the reference's Tikhonov inverse). */
FN mat correction_matrix(const mat a) {
    mat ata = mat_mul(mat_transpose(a), a);
    UNROLL for (int d = 0; d < SPH_DIM; ++d) ata.m[d][d] += SPH_TIKHONOV_EPS;
    return mat_mul(mat_inverse(ata), mat_transpose(a));
}

/* TLSPH keeps B of t = 0 for the whole run, and its deformation gradient must
 * reproduce a uniform deformation to round-off (the patch test of 002 §2.2.1):
 * the Tikhonov term leaves A B = I - O(eps / lambda^2), about 1e-8 here.  One
 * Newton-Schulz step B <- B (2I - A B) squares that error and keeps B bounded
 * (at most twice the Tikhonov value) on a degenerate support. */
FN mat refine_correction(const mat a, const mat b) {
    mat r = mat_scale(mat_mul(a, b), R(-1));
    UNROLL for (int d = 0; d < SPH_DIM; ++d) r.m[d][d] += R(2);
    return mat_mul(b, r);
}

#if SPH_HAS_TLSPH
/* TLSPH's hourglass force weighs each pair by W(X_ij) V0_j / X_ij^2 of the
 * reference configuration (002): stored once, so the kernel's cost does not
 * enter the substeps (Laguerre-Gauss costs the same per step as Wendland);
 * and F starts as the identity */
#    define PAIR_W_PARAMS , GLOBAL real *restrict pair_w, GLOBAL real *restrict defgrad
#else
#    define PAIR_W_PARAMS
#endif

#if SPH_HAS_CONTACT
/* bodies that do not merge (sph_contact.h): the body of every particle, and
 * the number of its contact neighbours */
#    define CONTACT_BUILD_PARAMS                                                                   \
        , GLOBAL const u8 *restrict body, GLOBAL int *restrict contact_count
#else
#    define CONTACT_BUILD_PARAMS
#endif

/* Neighbours of i within the cut-off 2h.  With several bodies
 * (SPH_HAS_CONTACT) only those of i's own body enter the list, the pair
 * geometry and B; the others are contact neighbours, stored from the top of
 * i's row down (slots cap - 1, cap - 2, ...; sph_contact.h), and the row
 * overflows when both together exceed it. */
#if SPH_PAIR_RECOMPUTE
/* The shifted positions x + s v of every particle (s = geometry_shift, see
 * the top), in the precision of the positions, once per rebuild after the
 * fields are sorted: build_neighbours and the acoustic passes take every
 * pair's geometry from these same values (sph_pair_geometry.h). */
/* buffers of shifted_positions: reads pos vel; writes pair_pos:hreal*d*n */
KERNEL void shifted_positions(ITEM_PARAM const int n, GLOBAL const hreal *restrict pos,
                              GLOBAL const real *restrict vel, const real geometry_shift,
                              GLOBAL hreal *restrict pair_pos) {
    const int i = ITEM_ID;
    if (i >= n) return;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) pair_pos[a * n + i] =
        pos[a * n + i] + (hreal)(geometry_shift * vel[a * n + i]);
}
/* the rebuild reads the shifted positions and stores no pair arrays */
#    define BUILD_POSITION_PARAMS GLOBAL const hreal *restrict pair_pos
#    define BUILD_PAIR_OUT_PARAMS
#else
#    define BUILD_POSITION_PARAMS                                                                  \
        GLOBAL const hreal *restrict pos, GLOBAL const real *restrict vel, const real geometry_shift
#    define BUILD_PAIR_OUT_PARAMS                                                                  \
        , GLOBAL real *restrict pair_e, GLOBAL real *restrict pair_dwv,                            \
            GLOBAL real *restrict pair_inv_r
#endif

/* d = x_i - x_j at the shifted positions x + s v (s = geometry_shift, see
 * the top; the cells are those of x) such that d_ji = -d_ij exactly, however
 * the compiler contracts it: the pair terms stay antisymmetric and momentum
 * exact.  Recomputed geometry: the difference of the stored shifted
 * positions, as pair_geometry_recomputed takes it; stored: written as
 * (x_i - x_j) + s (v_i - v_j). */
#if SPH_PAIR_RECOMPUTE
#    define BUILD_PAIR_OFFSET(j) hvec_diff(pair_pos, n, i, (j))
#elif SPH_HAS_EULERIAN
/* fixed particles (eulerian_step.cl): no shift; across a periodic axis the
 * nearest image (unique: a period is at least two cut-offs, host/setup/scene.c) */
#    define BUILD_PAIR_OFFSET(j) periodic_image(prm, hvec_diff(pos, n, i, (j)))
#else
#    define BUILD_PAIR_OFFSET(j)                                                                   \
        vec_axpy(hvec_diff(pos, n, i, (j)), geometry_shift, vec_sub(v_i, vec_load(vel, n, (j))))
#endif

/* The offset d = x_i - x_j of the nearest images along the periodic axes:
 * d - L rint(d / L), odd in d (rint(-x) = -rint(x)), so d_ji = -d_ij exactly. */
FN vec periodic_image(CONSTANT sph_params *prm, vec d) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) if (prm->periodic_mask & (1 << a)) {
        const real period = prm->period[a];
        d.c[a] -= period * rint(d.c[a] / period);
    }
    return d;
}

/* The cells of the stencil along one axis, in increasing order, each once:
 * c - 1 .. c + 1 clipped to the grid, or on a periodic axis wrapped around
 * it (all of its cells when it has fewer than three). */
FN int stencil_cells(const int c, const int cells, const bool periodic, int *out) {
    int m = 0;
    if (!periodic) {
        for (int x = c > 0 ? c - 1 : 0; x <= (c < cells - 1 ? c + 1 : cells - 1); ++x) out[m++] = x;
    } else if (cells < 3) {
        for (int x = 0; x < cells; ++x) out[m++] = x;
    } else if (c == 0) {
        out[0] = 0, out[1] = 1, out[2] = cells - 1, m = 3;
    } else if (c == cells - 1) {
        out[0] = 0, out[1] = cells - 2, out[2] = cells - 1, m = 3;
    } else {
        out[0] = c - 1, out[1] = c, out[2] = c + 1, m = 3;
    }
    return m;
}

/* Candidates tested per batch before their pairs are built: 32 on CPUs
 * (the native backend, and OpenCL CPU devices, which take the row-major
 * neighbour layout), where the test is cheap and its branch mispredicted;
 * 1 (a test and a branch per candidate) on GPUs, where an indexed private
 * array would live in memory.  H/dp = 10 plate to t = 1 s, native: the
 * rebuild 1.12-1.15 s per run with one candidate at a time, 1.04-1.05 s
 * with batches; pocl to t = 0.3 s, 0.46-0.47 s against 0.37-0.40 s
 * (docs/benchmarks.md).  An accepted candidate's offset is computed again
 * rather than stored in the test for every candidate, a third of which are
 * accepted. */
#ifndef SPH_BUILD_BATCH
#    if SPH_OPENCL && !SPH_NBR_ROW_MAJOR
#        define SPH_BUILD_BATCH 1
#    else
#        define SPH_BUILD_BATCH 32
#    endif
#endif

/* buffers of build_neighbours: reads pair_pos:hreal*d*n pos vel vol keys:ulong*n
 * cell_start:int*cells cell_end:int*cells body; writes nbr_count:int*n nbr_j:int*pairs
 * pair_e:real*d*pairs pair_dwv:real*pairs pair_inv_r:real*pairs bmat overflow:small
 * pair_w:real*pairs contact_count; updates defgrad */
KERNEL void build_neighbours(ITEM_PARAM const int n, const int cap, CONSTANT sph_params *prm,
                             BUILD_POSITION_PARAMS, GLOBAL const real *restrict vol, const int gx,
                             const int gy, const int gz, GLOBAL const ulong *restrict keys,
                             GLOBAL const int *restrict cell_start,
                             GLOBAL const int *restrict cell_end, GLOBAL int *restrict nbr_count,
                             GLOBAL int *restrict nbr_j BUILD_PAIR_OUT_PARAMS,
                             GLOBAL real *restrict bmat,
                             GLOBAL int *restrict overflow PAIR_W_PARAMS CONTACT_BUILD_PARAMS) {
    const int i = ITEM_ID;
    if (i >= n) return;
    const int stride = n * cap;
    (void)stride; /* the stored pair arrays */
    const real cutoff = prm->cutoff;
    const real cutoff2 = cutoff * cutoff;
    const kernel_gradient grad_w = kernel_gradient_of(prm);
#if !SPH_PAIR_RECOMPUTE && !SPH_HAS_EULERIAN
    const vec v_i = vec_load(vel, n, i);
#elif !SPH_PAIR_RECOMPUTE
    (void)vel;
    (void)geometry_shift;
#endif
    /* the particle's cell from its sorted key (cell_keys), not recomputed:
     * every particle is searched from the cell it is filed under */
    const int cell = key_cell(keys[i]);
    const int cx = cell % gx;
#if SPH_HAS_EULERIAN
    const int wrap = prm->periodic_mask;
#else
    const int wrap = 0;
#endif
    int xs[3], ys[3], zs[3];
    const int nx = stencil_cells(cx, gx, (wrap & 1) != 0, xs);
#if SPH_DIM == 3
    const int cy = (cell / gx) % gy;
    const int cz = cell / (gx * gy);
    const int nz = stencil_cells(cz, gz, (wrap & 4) != 0, zs);
#else
    const int cy = cell / gx;
    const int nz = 1;
    zs[0] = 0;
    (void)gz;
#endif
#if SPH_DIM == 1
    const int ny = 1;
    ys[0] = 0;
    (void)cy;
#else
    const int ny = stencil_cells(cy, gy, (wrap & 2) != 0, ys);
#endif

    int count = 0, ncontact = 0;
#if SPH_HAS_CONTACT
    const bool separate = PRESENT(contact_count);
    const int body_i = separate ? (int)body[i] : 0;
#endif
    mat moment = mat_zero();
    for (int iz = 0; iz < nz; ++iz)
        for (int iy = 0; iy < ny; ++iy)
            /* runs of consecutive x cells (one run unless a periodic x axis
             * wraps the stencil around), contiguous in the sorted order */
            for (int ix = 0; ix < nx;) {
                const int row = gx * (ys[iy] + gy * zs[iz]);
                int ix_end = ix;
                while (ix_end + 1 < nx && xs[ix_end + 1] == xs[ix_end] + 1) ++ix_end;
                int j_begin = -1, j_end = -1;
                for (int x = xs[ix]; x <= xs[ix_end]; ++x) {
                    const int c = row + x;
                    if (cell_end[c] > cell_start[c]) {
                        if (j_begin < 0) j_begin = cell_start[c];
                        j_end = cell_end[c];
                    }
                }
                ix = ix_end + 1;
                /* the candidates in batches: first which lie within the
                 * cut-off, without a branch (on a CPU a third of them do, in
                 * an order the branch predictor cannot learn), then the pairs */
                for (int j0 = j_begin; j0 < j_end; j0 += SPH_BUILD_BATCH) {
                    const int j1 = j0 + SPH_BUILD_BATCH < j_end ? j0 + SPH_BUILD_BATCH : j_end;
                    int within[SPH_BUILD_BATCH];
                    int m = 0;
                    for (int j = j0; j < j1; ++j) {
                        const vec d = BUILD_PAIR_OFFSET(j);
                        const real r2 = vec_dot(d, d);
                        /* coincident particles (and i itself, d = 0 exactly)
                         * have no direction: left out of the sums (the
                         * instability monitor reports such clustering) */
                        within[m] = j;
                        m += (r2 < cutoff2) & (r2 > R(0));
                    }
                    for (int k = 0; k < m; ++k) {
                        const int j = within[k];
                        const vec d = BUILD_PAIR_OFFSET(j);
                        const real r2 = vec_dot(d, d);
#if SPH_HAS_CONTACT
                        if (separate && (int)body[j] != body_i) {
                            if (count + ncontact < cap) nbr_j[NBR_AT(i, cap - 1 - ncontact)] = j;
                            ++ncontact;
                            continue;
                        }
#endif
                        const real r = sqrt(r2);
                        const vec e = vec_scale(d, R(1) / r);
                        const real dwv = kernel_dw_at(grad_w, r) * vol[j];
                        if (count + ncontact < cap) {
                            const int slot = NBR_AT(i, count);
                            nbr_j[slot] = j;
#if !SPH_PAIR_RECOMPUTE
                            UNROLL for (int a = 0; a < SPH_DIM; ++a) pair_e[a * stride + slot] =
                                e.c[a];
                            pair_dwv[slot] = dwv;
                            pair_inv_r[slot] = R(1) / r;
#endif
#if SPH_HAS_TLSPH
                            if (PRESENT(pair_w)) pair_w[slot] = kernel_w(prm, r) * vol[j] / r2;
#endif
                        }
                        /* A_i = -sum r_ij dW V_j e (x) e, 003 eq. 21 */
                        moment = mat_add_outer(moment, -r * dwv, e, e);
                        ++count;
                    }
                }
            }
    if (count + ncontact > cap) ATOMIC_MAX_INT(overflow, count + ncontact);
    nbr_count[i] = count < cap ? count : cap;
#if SPH_HAS_CONTACT
    if (separate) contact_count[i] = count + ncontact <= cap ? ncontact : 0;
#endif
    mat b = correction_matrix(moment);
    if (RUNTIME_FORMULATION == FORMULATION_TLSPH) b = refine_correction(moment, b);
    sym_store(bmat, n, i, b);
#if SPH_HAS_TLSPH
    /* the reference configuration's F = I, which the strain energy of t = 0
     * reads before the first substep computes F (reduction.cl) */
    if (PRESENT(defgrad)) mat_store(defgrad, n, i, mat_identity());
#endif
}

#if SPH_OPENCL && !SPH_COUNTING_SORT
/* After the bitonic sort: first and one-past-last sorted index of each
 * occupied cell (the ranges of empty cells were zero-filled before; the
 * counting sort writes the ranges itself). */
/* buffers of cell_ranges: reads keys:ulong*n; writes cell_start:int*cells cell_end:int*cells */
KERNEL void cell_ranges(ITEM_PARAM const int n, GLOBAL const ulong *restrict keys,
                        GLOBAL int *restrict cell_start, GLOBAL int *restrict cell_end) {
    const int k = ITEM_ID;
    if (k >= n) return;
    const int cell = key_cell(keys[k]);
    if (k == 0 || key_cell(keys[k - 1]) != cell) cell_start[cell] = k;
    if (k == n - 1 || key_cell(keys[k + 1]) != cell) cell_end[cell] = k + 1;
}

/* Bitonic sort of the padded key array (deterministic, no atomics).
 * bitonic_local_sort sorts every SORT_WG-sized block; for each larger merge
 * size k the host runs bitonic_global for the strides >= SORT_WG and then
 * bitonic_local_merge for the strides inside a block. */
FN void bitonic_compare_local(__local ulong *s, const int lid, const int j, const int up) {
    const int partner = lid ^ j;
    if (partner > lid) {
        const ulong a = s[lid], b = s[partner];
        if ((a > b) == up) {
            s[lid] = b;
            s[partner] = a;
        }
    }
}

/* buffers of bitonic_local_sort: updates keys:ulong*npad */
__kernel __attribute__((reqd_work_group_size(SORT_WG, 1, 1))) void
bitonic_local_sort(GLOBAL ulong *restrict keys) {
    __local ulong s[SORT_WG];
    const int lid = get_local_id(0), gid = get_global_id(0);
    s[lid] = keys[gid];
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int k = 2; k <= SORT_WG; k <<= 1)
        for (int j = k >> 1; j > 0; j >>= 1) {
            bitonic_compare_local(s, lid, j, (gid & k) == 0);
            barrier(CLK_LOCAL_MEM_FENCE);
        }
    keys[gid] = s[lid];
}

/* buffers of bitonic_local_merge: updates keys:ulong*npad */
__kernel __attribute__((reqd_work_group_size(SORT_WG, 1, 1))) void
bitonic_local_merge(GLOBAL ulong *restrict keys, const int k) {
    __local ulong s[SORT_WG];
    const int lid = get_local_id(0), gid = get_global_id(0);
    s[lid] = keys[gid];
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int j = SORT_WG >> 1; j > 0; j >>= 1) {
        bitonic_compare_local(s, lid, j, (gid & k) == 0);
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    keys[gid] = s[lid];
}

/* buffers of bitonic_global: updates keys:ulong*npad */
__kernel void bitonic_global(GLOBAL ulong *restrict keys, const int j, const int k) {
    const int i = get_global_id(0);
    const int partner = i ^ j;
    if (partner > i) {
        const ulong a = keys[i], b = keys[partner];
        if ((a > b) == ((i & k) == 0)) {
            keys[i] = b;
            keys[partner] = a;
        }
    }
}
#endif
