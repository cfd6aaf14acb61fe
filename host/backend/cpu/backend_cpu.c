/* backend_cpu.c — the native CPU backend (C + OpenMP), the reference platform.
 *
 * Owns the particle arrays in host memory, sorts them by cell at every rebuild
 * (a stable counting sort: the same order as the device's bitonic sort of
 * (cell, index) keys), and calls the physics compiled from device/ for the
 * dimension and precision of the run.
 */
#include "backend.h"
#include "backend_cpu.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SUBSTEP_SUMS_LEN SPH_CARRIED_LEN
#define CPU_GROUP        256 /* = SPH_WG of the C build of device/ */

typedef struct {
    const cpu_kernels *k;
    bool host_clock; /* --step-clock host: one parallel region per substep */
    cpu_buffers b;
    void *spare[FIELD_COUNT]; /* second buffer of each field for the permutation */
    size_t real_size;
    long cells_allocated;
    uint64_t *keys_sorted;
} cpu_impl;

/* Run the loops on the OpenMP team?  The team synchronises on its own
 * spinning barrier (cpu_team.h) and runs an advection step's substeps in one
 * parallel region, so OMP_WAIT_POLICY no longer decides the gain; what
 * remains of the policy is the wake of the team at each rebuild's parallel
 * loops.  The 2D plate, SPH-GNOG-A, to t = 0.3 s on the 2-core CI machine
 * kind (2026-11-27; best of 2-3, one thread against two): 233 particles
 * 0.28 s against 0.36 (passive) and 0.18 (active); 352: 0.56 against 0.59
 * and 0.34; 497: 1.02 against 0.89 and 0.57; 668: 1.64 against 1.27 and
 * 0.93; 1088: 3.65 against 2.46 and 1.99.  So two threads from 400
 * particles up, whatever the policy. */
#define CPU_TEAM_MIN_PARTICLES 400
static bool use_threads(int n) {
    return omp_get_max_threads() >= 2 && n >= CPU_TEAM_MIN_PARTICLES;
}

static size_t field_esize(const sph_backend *be, sph_field f) {
    return sph_field_element_size(be->fields[f].type, &be->features);
}
static size_t field_bytes(const sph_backend *be, sph_field f) {
    return (size_t)be->n * (size_t)be->fields[f].components * field_esize(be, f);
}

/* A float or double element (esize bytes) as double. */
static void set_value(void *buf, size_t esize, size_t index, double value) {
    if (esize == sizeof(double))
        ((double *)buf)[index] = value;
    else
        ((float *)buf)[index] = (float)value;
}
static double get_value(const void *buf, size_t esize, size_t index) {
    return esize == sizeof(double) ? ((const double *)buf)[index]
                                   : (double)((const float *)buf)[index];
}
/* a field's element, or a buffer in the arithmetic precision */
static void set_field(const sph_backend *be, sph_field f, size_t index, double value) {
    const cpu_impl *c = be->impl;
    set_value(c->b.field[f], field_esize(be, f), index, value);
}
static void set_real(const cpu_impl *c, void *buf, size_t index, double value) {
    set_value(buf, c->real_size, index, value);
}
static double get_real(const cpu_impl *c, const void *buf, size_t index) {
    return get_value(buf, c->real_size, index);
}

#define PAIRS_RECORD "neighbour lists and frozen pair geometry"

/* Bytes of one neighbour slot: its index and the frozen pair geometry. */
static size_t pair_slot_bytes(const sph_features *f, size_t real_size) {
    const size_t tlsph = f->formulation == SPH_FORMULATION_TLSPH;
    return sizeof(int32_t) + ((size_t)f->dim + 2 + tlsph) * real_size;
}

/* A fluid's packed rows and the rows of pairs summed once. */
static void free_pair_rows(cpu_buffers *b) {
    int32_t **rows[] = {&b->row_start,  &b->row_j,    &b->row_walls, &b->once_start, &b->once_count,
                        &b->once_walls, &b->once_far, &b->once_j,    &b->far_rows};
    for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k) {
        free(*rows[k]);
        *rows[k] = NULL;
    }
    void **geometry[] = {&b->once_e, &b->once_dwv, &b->once_inv_r, &b->force_sum,
                         &b->far_field_weight};
    for (size_t k = 0; k < sizeof geometry / sizeof geometry[0]; ++k) {
        free(*geometry[k]);
        *geometry[k] = NULL;
    }
    free(b->far_field);
    b->far_field = NULL;
    b->nfar_rows = b->nfar_field = 0;
}

static sph_status alloc_pairs(sph_backend *be, cpu_impl *c, int cap, sph_error *err) {
    const size_t slots = (size_t)be->n * (size_t)cap;
    /* before allocating: the new lists and everything else must fit */
    const double need = (double)slots * (double)pair_slot_bytes(&be->features, c->real_size);
    double others = (double)sph_backend_total_bytes(be);
    for (int k = 0; k < be->nbuffers; ++k)
        if (strcmp(be->buffers[k].name, PAIRS_RECORD) == 0) others -= (double)be->buffers[k].bytes;
    char available[256], need_s[32], others_s[32];
    if (need + others > sph_host_memory_available(available, sizeof available)) {
        sph_format_bytes(need, need_s, sizeof need_s);
        sph_format_bytes(others, others_s, sizeof others_s);
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "the neighbour lists of %d particles with up to %d neighbours each need "
                        "%s besides the %s of the other buffers, but %s",
                        be->n, cap, need_s, others_s, available);
    }
    free(c->b.nbr_j);
    free(c->b.pair_e);
    free(c->b.pair_dwv);
    free(c->b.pair_inv_r);
    free(c->b.pair_w);
    c->b.pair_w = NULL;
    free_pair_rows(&c->b); /* padded rows from here on (pack_pair_rows) */
    c->b.cap = cap;
    c->b.nbr_j = malloc(slots * sizeof(int32_t));
    c->b.pair_e = malloc(slots * (size_t)be->features.dim * c->real_size);
    c->b.pair_dwv = malloc(slots * c->real_size);
    c->b.pair_inv_r = malloc(slots * c->real_size);
    const bool tlsph = be->features.formulation == SPH_FORMULATION_TLSPH;
    if (tlsph) c->b.pair_w = malloc(slots * c->real_size);
    sph_backend_record_buffer(be, PAIRS_RECORD,
                              slots * pair_slot_bytes(&be->features, c->real_size));
    if (!c->b.nbr_j || !c->b.pair_e || !c->b.pair_dwv || !c->b.pair_inv_r ||
        (tlsph && !c->b.pair_w)) {
        sph_format_bytes(need, need_s, sizeof need_s);
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "out of host memory for the neighbour lists (%d particles x %d slots, "
                        "%s); %s",
                        be->n, cap, need_s, available);
    }
    return SPH_OK;
}

static sph_status cpu_upload(sph_backend *be, const sph_particles *p, sph_error *err) {
    cpu_impl *c = be->impl;
    const int n = be->n, d = be->features.dim;
    if (p->n != n || p->dim != d)
        return sph_fail(err, SPH_ERR_RUNTIME, "particle set does not match the backend");
    for (int f = 0; f < FIELD_COUNT; ++f)
        if (c->b.field[f]) memset(c->b.field[f], 0, field_bytes(be, (sph_field)f));
    for (size_t k = 0; k < (size_t)d * n; ++k) {
        set_field(be, FIELD_POS, k, p->pos[k]);
        set_field(be, FIELD_VEL, k, p->vel[k]);
    }
    for (int i = 0; i < n; ++i) {
        set_field(be, FIELD_MASS, (size_t)i, p->mass[i]);
        set_field(be, FIELD_RHO, (size_t)i, p->rho[i]);
        set_field(be, FIELD_VOL, (size_t)i, p->mass[i] / p->rho[i]);
    }
    memcpy(c->b.field[FIELD_ID], p->id, (size_t)n * sizeof(int32_t));
    if (c->b.field[FIELD_BODY]) memcpy(c->b.field[FIELD_BODY], p->body, (size_t)n);
    if (c->b.field[FIELD_MATERIAL]) memcpy(c->b.field[FIELD_MATERIAL], p->material, (size_t)n);
    if (c->b.field[FIELD_FIXED]) memcpy(c->b.field[FIELD_FIXED], p->fixed, (size_t)n);
    /* the compressible initial pressure (the WC one follows from rho by the
     * EOS, and the total energy from the pressure: eulerian_prepare) */
    if (c->b.field[FIELD_PRESSURE] && p->pressure)
        for (int i = 0; i < n; ++i) set_field(be, FIELD_PRESSURE, (size_t)i, p->pressure[i]);
    /* walls and the far field: kinds and normals */
    if (c->b.field[FIELD_KIND] && p->kind) memcpy(c->b.field[FIELD_KIND], p->kind, (size_t)n);
    if (c->b.field[FIELD_NORMAL] && p->normal)
        for (size_t k = 0; k < (size_t)d * n; ++k) set_field(be, FIELD_NORMAL, k, p->normal[k]);
    memset(c->b.substep_sums, 0, SUBSTEP_SUMS_LEN * c->real_size);
    return SPH_OK;
}

/* The keys sorted by cell, and the cell ranges (counting_sort_by_cell,
 * device/neighbour_build.cl, the sort of CPU devices too). */
static void sort_by_cell(cpu_impl *c, long ncells) {
    c->k->sort_by_cell(&c->b, ncells, c->keys_sorted);
    uint64_t *t = c->b.keys;
    c->b.keys = c->keys_sorted;
    c->keys_sorted = t;
}

/* dst[k] = src[keys[k] & 0xFFFFFFFF] for one component of n elements of
 * ESIZE bytes, as an orphaned worksharing loop of the caller's parallel
 * region.  The memcpy of a constant size compiles to one load and store; of
 * the run-time size it was a libc call per element, 5 % of a 2D plate run at
 * H/dp = 10. */
#define DEFINE_GATHER_BY_KEY(name, ESIZE)                                                          \
    static void name(char *dst, const char *src, const uint64_t *keys, int n) {                    \
        _Pragma("omp for schedule(static) nowait") for (int k = 0; k < n; ++k) memcpy(             \
            dst + (size_t)k * (ESIZE), src + (size_t)(keys[k] & 0xFFFFFFFFu) * (ESIZE), (ESIZE));  \
    }
DEFINE_GATHER_BY_KEY(gather_by_key_8, 8)
DEFINE_GATHER_BY_KEY(gather_by_key_4, 4)
DEFINE_GATHER_BY_KEY(gather_by_key_1, 1)

static void permute_fields(sph_backend *be, cpu_impl *c) {
    const int n = be->n;
    const uint64_t *keys = c->b.keys;
#pragma omp parallel if (c->b.parallel)
    for (int f = 0; f < FIELD_COUNT; ++f) {
        if (!c->b.field[f]) continue;
        const sph_field_info *info = &be->fields[f];
        const size_t esize = sph_field_element_size(info->type, &be->features);
        for (int comp = 0; comp < info->components; ++comp) {
            const size_t base = (size_t)comp * (size_t)n * esize;
            const char *src = (const char *)c->b.field[f] + base;
            char *dst = (char *)c->spare[f] + base;
            if (esize == 8)
                gather_by_key_8(dst, src, keys, n);
            else if (esize == 4)
                gather_by_key_4(dst, src, keys, n);
            else
                gather_by_key_1(dst, src, keys, n); /* FIELD_TYPE_U8 */
        }
    }
    for (int f = 0; f < FIELD_COUNT; ++f) {
        if (!c->b.field[f]) continue;
        void *t = c->b.field[f];
        c->b.field[f] = c->spare[f];
        c->spare[f] = t;
    }
}

/* Each packed row's wall pairs moved after its fluid pairs (pack_pair_rows),
 * their count in row_walls. */
static sph_status partition_wall_pairs(sph_backend *be, cpu_impl *c, const uint8_t *kind,
                                       sph_error *err) {
    const size_t n = (size_t)be->n, esize = c->real_size, total = (size_t)c->b.row_start[n];
    const size_t dim = (size_t)be->features.dim;
    int32_t *order = malloc((size_t)c->b.cap * sizeof(int32_t));
    char *scratch = malloc((size_t)c->b.cap * (esize > sizeof(int32_t) ? esize : sizeof(int32_t)));
    if (!order || !scratch) {
        free(order);
        free(scratch);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    /* the arrays of one slot each: j, then the geometry's components */
    char *arrays[3 + 3];
    size_t sizes[3 + 3], narrays = 0;
    arrays[narrays] = (char *)c->b.row_j, sizes[narrays++] = sizeof(int32_t);
    for (size_t a = 0; a < dim; ++a)
        arrays[narrays] = (char *)c->b.pair_e + a * total * esize, sizes[narrays++] = esize;
    arrays[narrays] = c->b.pair_dwv, sizes[narrays++] = esize;
    arrays[narrays] = c->b.pair_inv_r, sizes[narrays++] = esize;
    for (size_t i = 0; i < n; ++i) {
        const size_t first = (size_t)c->b.row_start[i];
        const int count = c->b.row_start[i + 1] - c->b.row_start[i];
        int fluid = 0, walls = 0;
        for (int k = 0; k < count; ++k)
            if (kind[c->b.row_j[first + (size_t)k]] != SPH_PARTICLE_WALL) order[fluid++] = k;
        for (int k = 0; k < count; ++k)
            if (kind[c->b.row_j[first + (size_t)k]] == SPH_PARTICLE_WALL)
                order[fluid + walls++] = k;
        c->b.row_walls[i] = walls;
        if (walls == 0) continue;
        for (size_t g = 0; g < narrays; ++g) {
            char *row = arrays[g] + first * sizes[g];
            for (int k = 0; k < count; ++k)
                memcpy(scratch + (size_t)k * sizes[g], row + (size_t)order[k] * sizes[g], sizes[g]);
            memcpy(row, scratch, (size_t)count * sizes[g]);
        }
    }
    free(order);
    free(scratch);
    return SPH_OK;
}

/* Fluids: the rebuild's padded rows packed (eulerian_step.cl, "the frozen
 * pair rows"), once after the build and before fluid_setup.  row_start is
 * the prefix sum of the counts, row_j a packed copy of nbr_j (which keeps
 * its padded rows for the monitor), and the pair geometry is packed in
 * place: each slot moves to an index no larger than its own (row_start[i]
 * <= i cap, a component's base a total <= a n cap), so an ascending copy
 * never overwrites a slot it has yet to read; then the arrays shrink. */
static sph_status pack_pair_rows(sph_backend *be, cpu_impl *c, sph_error *err) {
    const size_t n = (size_t)be->n, cap = (size_t)c->b.cap, esize = c->real_size;
    sph_status st = SPH_OK;
    /* the rows are unpacked here: alloc_pairs, which the rebuild runs first
     * when they were packed, freed them */
    c->b.row_start = malloc((n + 1) * sizeof(int32_t));
    if (!c->b.row_start) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    size_t total = 0;
    for (size_t i = 0; i < n; ++i) {
        c->b.row_start[i] = (int32_t)total;
        total += (size_t)c->b.nbr_count[i];
    }
    if (total > (size_t)INT32_MAX / 3)
        return sph_fail(err, SPH_ERR_RUNTIME, "%zu particle pairs exceed the 32-bit pair index",
                        total);
    c->b.row_start[n] = (int32_t)total;
    c->b.row_j = malloc((total ? total : 1) * sizeof(int32_t));
    if (!c->b.row_j) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    for (size_t i = 0; i < n; ++i)
        memcpy(c->b.row_j + c->b.row_start[i], c->b.nbr_j + i * cap,
               (size_t)c->b.nbr_count[i] * sizeof(int32_t));

    struct {
        void **array;
        size_t components;
    } geometry[] = {
        {&c->b.pair_e, (size_t)be->features.dim}, {&c->b.pair_dwv, 1}, {&c->b.pair_inv_r, 1}};
    for (size_t g = 0; g < sizeof geometry / sizeof geometry[0]; ++g) {
        char *base = *geometry[g].array;
        for (size_t a = 0; a < geometry[g].components; ++a)
            for (size_t i = 0; i < n; ++i)
                memmove(base + (a * total + (size_t)c->b.row_start[i]) * esize,
                        base + (a * n * cap + i * cap) * esize, (size_t)c->b.nbr_count[i] * esize);
        void *shrunk = realloc(base, (total ? total : 1) * geometry[g].components * esize);
        if (shrunk) *geometry[g].array = shrunk;
    }
    /* the wall pairs last in each row (a stable partition: slot order kept
     * within both parts), the pair geometry moved with them */
    const uint8_t *kind = c->b.field[FIELD_KIND];
    bool walls = false;
    for (size_t i = 0; kind && i < n && !walls; ++i) walls = kind[i] == SPH_PARTICLE_WALL;
    if (walls) {
        c->b.row_walls = malloc(n * sizeof(int32_t));
        if (!c->b.row_walls) return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
        if ((st = partition_wall_pairs(be, c, kind, err))) return st;
    }
    sph_backend_record_buffer(be, PAIRS_RECORD,
                              n * cap * sizeof(int32_t) + (n + 1) * sizeof(int32_t) +
                                  (walls ? n * sizeof(int32_t) : 0) +
                                  total * pair_slot_bytes(&be->features, esize));
    return st;
}

/* The shortest block of the pairs summed once.  The blocks go to the
 * threads one at a time (PAIRS_ONCE_THEN's dynamic schedule), and where the
 * largest j - i is a few particles (a 1D line: 5) that cost more than the
 * pairs: the Shu-Osher line at dp = 1/400 took 8.4 s on two threads and
 * 4.1 s on one with blocks of 5 particles. */
#define ONCE_BLOCK_MIN 256

/* The block length of the pairs summed once (eulerian_step.cl, "sum each
 * fluid pair once"): the largest j - i of a fluid pair with j > i whose
 * particles lie within the cut-off without a periodic image (a pair across
 * a periodic axis may join the first particle and the last), at least
 * ONCE_BLOCK_MIN (a longer block keeps a block's writes within it and the
 * next). */
static int pairs_once_block(const sph_backend *be, const cpu_impl *c, const uint8_t *kind) {
    const size_t n = (size_t)be->n, dim = (size_t)be->features.dim;
    const double *pos = c->b.field[FIELD_POS]; /* fluids run in double */
    const double cutoff = ((const sph_params_f64 *)c->b.prm)->cutoff;
    const double reach2 = cutoff * cutoff * (1.0 + 1e-9);
    int block = 1;
    for (size_t i = 0; i < n; ++i) {
        if (kind && kind[i] == SPH_PARTICLE_WALL) continue;
        for (int32_t s = c->b.row_start[i]; s < c->b.row_start[i + 1]; ++s) {
            const size_t j = (size_t)c->b.row_j[s];
            if (j <= i || (int)(j - i) <= block || (kind && kind[j] == SPH_PARTICLE_WALL)) continue;
            double d2 = 0.0;
            for (size_t a = 0; a < dim; ++a) {
                const double d = pos[a * n + i] - pos[a * n + j];
                d2 += d * d;
            }
            if (d2 <= reach2) block = (int)(j - i);
        }
    }
    return block > ONCE_BLOCK_MIN ? block : ONCE_BLOCK_MIN;
}

/* Whether the steps' rates leave particle i's state alone (HOLDS_STATE,
 * eulerian_step.cl: a wall, far-field or fixed-state particle). */
static bool holds_state(const uint8_t *kind, const uint8_t *fixed, int32_t i) {
    return (kind && kind[i] != SPH_PARTICLE_FLUID) || (fixed && fixed[i]);
}

/* The part of row i's slot k in the rows of pairs summed once: 0 a fluid
 * pair with j > i in this block or the next, 1 one with j past them (far),
 * 2 a wall pair, -1 none (j < i; i a wall particle: the fluid side sums
 * a wall pair; i and j both holding their state, whose rates no step uses:
 * the far field's pairs among themselves, 2 % of the cylinder's). */
static int once_part(const uint8_t *kind, const uint8_t *fixed, int32_t i, int32_t j, int block) {
    if (kind && kind[i] == SPH_PARTICLE_WALL) return -1;
    if (holds_state(kind, fixed, i) && holds_state(kind, fixed, j)) return -1;
    if (kind && kind[j] == SPH_PARTICLE_WALL) return 2;
    if (j < i) return -1;
    return j / block <= i / block + 1 ? 0 : 1;
}

/* Which row sums each fluid pair of once_part's part 0: take[s] for the
 * packed rows' slot s (row i, neighbour j).  A pair is row i's for j > i,
 * but a row's pairs are padded to whole lanes, and by index order the rows
 * hold 0 to 20 pairs each: on the cylinder at dp = 1/10, 9.66 pairs a row
 * in 11.16 slots, 13 % of the lanes empty.  A pair whose particles share
 * a block may be summed in either row (its terms are antisymmetric, and
 * the block's thread writes to both), so walking the rows in order, row i
 * hands its last c mod lanes such pairs (c its pairs, those handed to it
 * included) to their rows j > i, which then hold (j, i): its count becomes
 * whole lanes.  A row with fewer such pairs keeps them and its padding
 * (the cylinder's once rows: 65.6 MB before, 57.6 MB after).  The assignment depends on the rows
 * alone, so every thread count sums the same terms in the same order. */
static void balance_once_rows(const cpu_buffers *b, int n, int lanes, int block, uint8_t *take) {
    for (int i = 0; i < n; ++i) {
        int count = 0, movable = 0;
        for (int32_t s = b->row_start[i]; s < b->row_start[i + 1]; ++s) {
            if (!take[s]) continue;
            ++count;
            movable += b->row_j[s] > i && b->row_j[s] / block == i / block;
        }
        int hand = count % lanes;
        if (hand == 0 || movable < hand) continue;
        for (int32_t s = b->row_start[i + 1] - 1; s >= b->row_start[i] && hand > 0; --s) {
            const int32_t j = b->row_j[s];
            if (!take[s] || j <= i || j / block != i / block) continue;
            for (int32_t t = b->row_start[j]; t < b->row_start[j + 1]; ++t)
                if (b->row_j[t] == i) { /* row j's slot of i: the pair seen from j */
                    take[s] = 0;
                    take[t] = 1;
                    --hand;
                    break;
                }
        }
    }
}

/* Slot s's part in row i of the rows summed once: 0 where row i takes the
 * pair (balance_once_rows), -1 for a fluid pair another row takes, else
 * once_part's. */
static int slot_part(const cpu_buffers *b, const uint8_t *kind, const uint8_t *fixed,
                     const uint8_t *take, int32_t i, int32_t s, int block) {
    if (take[s]) return 0;
    const int part = once_part(kind, fixed, i, b->row_j[s], block);
    return part == 0 ? -1 : part;
}

/* Fluids (the two stages and SSP-RK): the rows of pairs summed once
 * (cpu_buffers, eulerian_step.cl), copied from the packed rows after fluid_setup has
 * corrected their gradients (both directions of a pair: its slot in row
 * i and in row j, g_ji = -g_ij). */
static sph_status build_once_rows(sph_backend *be, cpu_impl *c, sph_error *err) {
    const size_t n = (size_t)be->n, dim = (size_t)be->features.dim, esize = c->real_size;
    const size_t total = (size_t)c->b.row_start[n];
    const int lanes = c->k->pair_lanes;
    const uint8_t *kind = c->b.field[FIELD_KIND], *fixed = c->b.field[FIELD_FIXED];
    const int block = pairs_once_block(be, c, kind);
    cpu_buffers *b = &c->b;
    b->pair_block = block;
    b->once_start = malloc((n + 1) * sizeof(int32_t));
    b->once_count = malloc(n * sizeof(int32_t));
    b->once_walls = malloc(n * sizeof(int32_t));
    b->once_far = malloc(n * sizeof(int32_t));
    uint8_t *take = malloc(total ? total : 1);
    if (!b->once_start || !b->once_count || !b->once_walls || !b->once_far || !take) {
        free(take);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    for (size_t i = 0; i < n; ++i)
        for (int32_t s = b->row_start[i]; s < b->row_start[i + 1]; ++s)
            take[s] = once_part(kind, fixed, (int32_t)i, b->row_j[s], block) == 0;
    balance_once_rows(b, (int)n, lanes, block, take);
    size_t slots = 0;
    int nfar_rows = 0;
    for (size_t i = 0; i < n; ++i) {
        int parts[3] = {0, 0, 0};
        for (int32_t s = b->row_start[i]; s < b->row_start[i + 1]; ++s) {
            const int part = slot_part(b, kind, fixed, take, (int32_t)i, s, block);
            if (part >= 0) ++parts[part];
        }
        b->once_start[i] = (int32_t)slots;
        b->once_count[i] = (parts[0] + lanes - 1) / lanes * lanes;
        b->once_far[i] = (parts[1] + lanes - 1) / lanes * lanes;
        b->once_walls[i] = parts[2];
        nfar_rows += parts[1] > 0;
        slots += (size_t)(b->once_count[i] + b->once_walls[i] + b->once_far[i]);
    }
    if (slots > (size_t)INT32_MAX / 3) {
        free(take);
        return sph_fail(err, SPH_ERR_RUNTIME, "%zu particle pairs exceed the 32-bit pair index",
                        slots);
    }
    b->once_start[n] = (int32_t)slots;
    const size_t alloc = slots ? slots : 1;
    /* zeros: the padding's geometry */
    b->once_j = malloc(alloc * sizeof(int32_t));
    b->once_e = calloc(alloc * dim, esize);
    b->once_dwv = calloc(alloc, esize);
    b->once_inv_r = calloc(alloc, esize);
    b->far_rows = malloc((nfar_rows ? (size_t)nfar_rows : 1) * sizeof(int32_t));
    /* the two stages' momentum sums (SSP-RK sums into its momentum_rate) */
    const bool two_stage = !b->field[FIELD_MOMENTUM_RATE];
    b->force_sum = two_stage ? calloc(n * dim, esize) : NULL;
    if (!b->once_j || !b->once_e || !b->once_dwv || !b->once_inv_r || !b->far_rows ||
        (two_stage && !b->force_sum)) {
        free(take);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    b->nfar_rows = 0;
    for (size_t i = 0; i < n; ++i) {
        const size_t first = (size_t)b->once_start[i];
        /* the next slot of each part (once_part): pairs, far (after the
         * walls), walls (after the pairs) */
        size_t next[3] = {first, first + (size_t)(b->once_count[i] + b->once_walls[i]),
                          first + (size_t)b->once_count[i]};
        for (int32_t s = b->row_start[i]; s < b->row_start[i + 1]; ++s) {
            const int part = slot_part(b, kind, fixed, take, (int32_t)i, s, block);
            if (part < 0) continue;
            const size_t to = next[part]++;
            b->once_j[to] = b->row_j[s];
            for (size_t a = 0; a < dim; ++a)
                memcpy((char *)b->once_e + (a * slots + to) * esize,
                       (const char *)b->pair_e + (a * total + (size_t)s) * esize, esize);
            memcpy((char *)b->once_dwv + to * esize, (const char *)b->pair_dwv + (size_t)s * esize,
                   esize);
            memcpy((char *)b->once_inv_r + to * esize,
                   (const char *)b->pair_inv_r + (size_t)s * esize, esize);
        }
        /* empty pairs (j = i, zero geometry) to whole lanes: after the
         * pairs, and after the far pairs, at the row's end */
        const size_t pads[2][2] = {{next[0], first + (size_t)b->once_count[i]},
                                   {next[1], (size_t)b->once_start[i + 1]}};
        for (int p = 0; p < 2; ++p)
            for (size_t to = pads[p][0]; to < pads[p][1]; ++to) b->once_j[to] = (int32_t)i;
        if (b->once_far[i] > 0) b->far_rows[b->nfar_rows++] = (int32_t)i;
    }
    free(take);
    sph_backend_record_buffer(be, "fluid pairs summed once",
                              (n * 4 + 1 + slots + (size_t)nfar_rows) * sizeof(int32_t) +
                                  slots * (dim + 2) * esize + (two_stage ? n * dim * esize : 0));
    return SPH_OK;
}

/* Phase timing when profiling (wall clock of the calling thread). */
static double phase_start(const sph_backend *be) {
    return be->profiling ? omp_get_wtime() : 0.0;
}
static void phase_end(sph_backend *be, const char *name, double start) {
    if (be->profiling) sph_backend_profile_add(be, name, omp_get_wtime() - start);
}

/* The rebuild's steps (sph_backend_rebuild). */
static sph_status cpu_rebuild_reduce(sph_backend *be, double *out, sph_error *err) {
    (void)err;
    cpu_impl *c = be->impl;
    const double t0 = phase_start(be);
    c->k->rebuild_reduce(&c->b, out);
    phase_end(be, "rebuild_reduce", t0);
    return SPH_OK;
}

static sph_status cpu_rebuild_sort(sph_backend *be, const sph_grid *grid, sph_error *err) {
    cpu_impl *c = be->impl;
    if (grid->ncells > c->cells_allocated) {
        free(c->b.cell_start);
        free(c->b.cell_end);
        c->b.cell_start = malloc((size_t)grid->ncells * sizeof(int32_t));
        c->b.cell_end = malloc((size_t)grid->ncells * sizeof(int32_t));
        if (!c->b.cell_start || !c->b.cell_end)
            return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory for %ld grid cells",
                            grid->ncells);
        c->cells_allocated = grid->ncells;
    }
    const double t0 = phase_start(be);
    c->k->cell_keys(&c->b, grid, be->geometry_shift);
    sort_by_cell(c, grid->ncells);
    permute_fields(be, c);
    phase_end(be, "cell sort and permutation", t0);
    /* packed rows (a fluid's) go back to the padded layout the build writes */
    return c->b.row_start ? alloc_pairs(be, c, c->b.cap, err) : SPH_OK;
}

static sph_status cpu_rebuild_build(sph_backend *be, const sph_grid *grid, int *needed,
                                    sph_error *err) {
    (void)err;
    cpu_impl *c = be->impl;
    const double t0 = phase_start(be);
    *needed = c->k->build_neighbours(&c->b, grid, be->geometry_shift);
    phase_end(be, "build_neighbours", t0);
    return SPH_OK;
}

static sph_status cpu_rebuild_grow(sph_backend *be, int cap, sph_error *err) {
    return alloc_pairs(be, be->impl, cap, err);
}

/* A far-field particle (IS_FAR_FIELD, eulerian_step.cl). */
static bool is_far_field(const uint8_t *kind, int i) {
    return kind[i] == SPH_PARTICLE_INFLOW || kind[i] == SPH_PARTICLE_OUTFLOW;
}

/* The far field's particles, for fluid_setup to weigh and the steps to
 * blend (cpu_buffers.far_field); none without a far field. */
static sph_status list_far_field(sph_backend *be, cpu_impl *c, sph_error *err) {
    cpu_buffers *b = &c->b;
    const uint8_t *kind = b->field[FIELD_KIND];
    if (!kind || ((const sph_params_f64 *)b->prm)->far_field_density <= 0) return SPH_OK;
    const int n = be->n;
    int count = 0;
    for (int i = 0; i < n; ++i) count += is_far_field(kind, i);
    b->far_field = malloc((count ? (size_t)count : 1) * sizeof(int32_t));
    b->far_field_weight = malloc((count ? (size_t)count : 1) * c->real_size);
    if (!b->far_field || !b->far_field_weight)
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    for (int i = 0; i < n; ++i)
        if (is_far_field(kind, i)) b->far_field[b->nfar_field++] = i;
    sph_backend_record_buffer(be, "far field", (size_t)count * (sizeof(int32_t) + c->real_size));
    return SPH_OK;
}

static sph_status cpu_rebuild_finish(sph_backend *be, sph_error *err) {
    cpu_impl *c = be->impl;
    if (!c->k->fluid_setup) return SPH_OK;
    const double t0 = phase_start(be);
    sph_status st = pack_pair_rows(be, c, err);
    if (st || (st = list_far_field(be, c, err))) return st;
    c->k->fluid_setup(&c->b);
    /* the rows of pairs summed once, for the two stages and SSP-RK alike */
    if ((st = build_once_rows(be, c, err))) return st;
    /* SSP-RK's rates are sums of pairs summed once: zeros to start from
     * (eulerian_rates_pairs; each stage's update zeroes them after it) */
    const sph_field rates[] = {FIELD_MASS_RATE, FIELD_MOMENTUM_RATE, FIELD_ENERGY_RATE};
    for (size_t k = 0; k < sizeof rates / sizeof rates[0]; ++k)
        if (c->b.field[rates[k]]) memset(c->b.field[rates[k]], 0, field_bytes(be, rates[k]));
    phase_end(be, "fluid setup", t0);
    return SPH_OK;
}

static int cpu_rebuild_capacity(const sph_backend *be) {
    return ((const cpu_impl *)be->impl)->b.cap;
}

static sph_status cpu_rebuild(sph_backend *be, sph_rebuild_info *info, sph_error *err) {
    cpu_impl *c = be->impl;
    static const sph_rebuild_steps steps = {cpu_rebuild_reduce, cpu_rebuild_sort,
                                            cpu_rebuild_build,  cpu_rebuild_grow,
                                            cpu_rebuild_finish, cpu_rebuild_capacity};
    /* the cut-off in the run precision, as the kernels hold it; periodic
     * axes are the fluids', which run in double */
    const double cutoff = c->real_size == sizeof(float)
                              ? (double)((const sph_params_f32 *)c->b.prm)->cutoff
                              : ((const sph_params_f64 *)c->b.prm)->cutoff;
    const sph_params_f64 *prm64 = c->real_size == sizeof(double) ? c->b.prm : NULL;
    static const double no_period[3] = {0, 0, 0};
    return sph_backend_rebuild(be, &steps, cutoff, prm64 ? prm64->periodic_mask : 0,
                               prm64 ? prm64->period : no_period, info, err);
}

static sph_status cpu_substep(sph_backend *be, double dt, double *max_speed2, sph_error *err) {
    (void)err;
    cpu_impl *c = be->impl;
    const double t0 = phase_start(be);
    c->k->substep(&c->b, dt, max_speed2);
    phase_end(be, "acoustic substep", t0);
    return SPH_OK;
}

static sph_status cpu_advance(sph_backend *be, double *clock, long limit, sph_error *err) {
    cpu_impl *c = be->impl;
    if (c->host_clock) return sph_backend_advance_by_substeps(be, clock, limit, err);
    const double t0 = phase_start(be);
    c->k->advance(&c->b, clock, limit);
    phase_end(be, "acoustic substep", t0);
    return SPH_OK;
}

static sph_status cpu_diagnostics(sph_backend *be, sph_diagnostics *out, sph_error *err) {
    (void)err;
    cpu_impl *c = be->impl;
    const int d = be->features.dim;
    /* fluids: 2 + d + (1 or 3), mass and energy, the wall forces (2d) */
    double red[4 + 3 + 3 + 6] = {0};
    const double t0 = phase_start(be);
    c->k->diagnostics(&c->b, red);
    phase_end(be, "diagnostics_reduce", t0);
    sph_diagnostics_unpack(red, d, out);
    return SPH_OK;
}

static sph_status cpu_monitor(sph_backend *be, double *out, sph_error *err) {
    (void)err;
    cpu_impl *c = be->impl;
    c->k->monitor(&c->b, out);
    return SPH_OK;
}

static sph_status cpu_download(sph_backend *be, sph_field f, void *host, sph_error *err) {
    cpu_impl *c = be->impl;
    if (sph_backend_require_field(be, f, err)) return SPH_ERR_RUNTIME;
    /* a field the steps do not keep is formed from the state first */
    if (f == FIELD_VORTICITY && c->k->fluid_vorticity) c->k->fluid_vorticity(&c->b);
    const sph_field_info *info = &be->fields[f];
    const size_t count = (size_t)be->n * (size_t)info->components;
    if (sph_field_is_real(info->type)) {
        double *out = host;
        const size_t esize = field_esize(be, f);
        for (size_t k = 0; k < count; ++k) out[k] = get_value(c->b.field[f], esize, k);
    } else {
        memcpy(host, c->b.field[f], field_bytes(be, f));
    }
    return SPH_OK;
}

static sph_status cpu_upload_field(sph_backend *be, sph_field f, const void *host, sph_error *err) {
    cpu_impl *c = be->impl;
    if (sph_backend_require_field(be, f, err)) return SPH_ERR_RUNTIME;
    const sph_field_info *info = &be->fields[f];
    const size_t count = (size_t)be->n * (size_t)info->components;
    if (sph_field_is_real(info->type)) {
        const double *in = host;
        for (size_t k = 0; k < count; ++k) set_field(be, f, k, in[k]);
    } else {
        memcpy(c->b.field[f], host, field_bytes(be, f));
    }
    return SPH_OK;
}

static sph_status cpu_download_carried(sph_backend *be, double *out, sph_error *err) {
    (void)err;
    cpu_impl *c = be->impl;
    for (int k = 0; k < SPH_CARRIED_LEN; ++k) out[k] = get_real(c, c->b.substep_sums, (size_t)k);
    return SPH_OK;
}

static sph_status cpu_upload_carried(sph_backend *be, const double *in, sph_error *err) {
    (void)err;
    cpu_impl *c = be->impl;
    for (int k = 0; k < SPH_CARRIED_LEN; ++k) set_real(c, c->b.substep_sums, (size_t)k, in[k]);
    return SPH_OK;
}

static sph_status cpu_download_neighbours(sph_backend *be, sph_neighbour_lists *out,
                                          sph_error *err) {
    cpu_impl *c = be->impl;
    out->n = be->n;
    out->cap = c->b.cap;
    out->count = malloc((size_t)be->n * sizeof(int32_t));
    out->j = malloc((size_t)be->n * (size_t)c->b.cap * sizeof(int32_t));
    if (!out->count || !out->j) {
        sph_neighbour_lists_free(out);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    memcpy(out->count, c->b.nbr_count, (size_t)be->n * sizeof(int32_t));
    memcpy(out->j, c->b.nbr_j, (size_t)be->n * (size_t)c->b.cap * sizeof(int32_t));
    return SPH_OK;
}

static void cpu_destroy(sph_backend *be) {
    cpu_impl *c = be->impl;
    if (c) {
        for (int f = 0; f < FIELD_COUNT; ++f) {
            free(c->b.field[f]);
            free(c->spare[f]);
        }
        free(c->b.nbr_count);
        free(c->b.nbr_j);
        free_pair_rows(&c->b);
        free(c->b.pair_e);
        free(c->b.pair_dwv);
        free(c->b.pair_inv_r);
        free(c->b.pair_w);
        free(c->b.keys);
        free(c->keys_sorted);
        free(c->b.cell_start);
        free(c->b.cell_end);
        free(c->b.prm);
        free(c->b.grid_geom);
        free(c->b.partials);
        free(c->b.substep_sums);
        free(c);
    }
    free(be);
}

static const sph_backend_ops cpu_ops = {
    .upload = cpu_upload,
    .rebuild = cpu_rebuild,
    .substep = cpu_substep,
    .advance = cpu_advance,
    .diagnostics = cpu_diagnostics,
    .monitor = cpu_monitor,
    .download = cpu_download,
    .download_neighbours = cpu_download_neighbours,
    .upload_field = cpu_upload_field,
    .download_carried = cpu_download_carried,
    .upload_carried = cpu_upload_carried,
    .destroy = cpu_destroy,
};

sph_status sph_backend_cpu_create(const sph_backend_request *req, const sph_features *f,
                                  const sph_params_f64 *prm, int n, sph_backend **out,
                                  sph_error *err) {
    *out = NULL;
    const cpu_kernels *kernels = cpu_kernels_for_features(f);
    if (!kernels || kernels->formulation != (int)f->formulation)
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "native backend: no instance compiled for formulation %s",
                        sph_formulation_name(f->formulation));
    sph_backend *be = calloc(1, sizeof *be);
    cpu_impl *c = calloc(1, sizeof *c);
    if (!be || !c) {
        free(be);
        free(c);
        return sph_fail(err, SPH_ERR_RUNTIME, "out of host memory");
    }
    be->impl = c;
    be->ops = &cpu_ops;
    be->kind_name = "cpu";
    be->profiling = req->profile;
    be->features = *f;
    be->n = n;
    sph_fields_layout(f, be->fields);
    c->k = kernels;
    c->host_clock = req->step_clock == SPH_STEP_CLOCK_HOST;
    c->real_size = f->double_precision ? sizeof(double) : sizeof(float);
    c->b.n = n;
    c->b.rk_stages = f->fluid_rk_stages;
    c->b.parallel = use_threads(n);
    snprintf(be->device_name, sizeof be->device_name, "native CPU backend, %d OpenMP thread%s",
             c->b.parallel ? omp_get_max_threads() : 1, c->b.parallel ? "s" : "");
    snprintf(be->build_options, sizeof be->build_options,
             "native: dim=%d precision=%s formulation=%s (compiled in) rotation=%s clamp=%d "
             "bodies=%d%s step_clock=%s",
             f->dim, sph_precision_name(f), sph_formulation_name(f->formulation),
             sph_rotation_name(f->rotation), f->has_clamp ? 1 : 0, f->nbodies,
             f->torque_projection ? " torque_projection=1" : "", c->host_clock ? "host" : "team");

    /* before allocating: what the run needs must fit in the memory */
    const int cap0 = sph_initial_neighbour_capacity(f->dim, prm->cutoff / prm->dp);
    const int ngroups = (n + CPU_GROUP - 1) / CPU_GROUP;
    double fields_bytes = 0.0;
    for (int k = 0; k < FIELD_COUNT; ++k)
        if (be->fields[k].present) fields_bytes += 2.0 * (double)field_bytes(be, (sph_field)k);
    fields_bytes += (double)n * (2.0 * sizeof(uint64_t) + sizeof(int32_t)) +
                    (double)ngroups * sph_partial_ncomp(f) * (double)c->real_size;
    const double pairs_bytes = (double)n * (double)cap0 * (double)pair_slot_bytes(f, c->real_size);
    const double particles_bytes = (double)n * (double)sph_particles_bytes_each(f->dim, true);
    char available[256];
    const double limit = sph_host_memory_available(available, sizeof available);
    if (fields_bytes + pairs_bytes + particles_bytes > limit) {
        char total_s[32], fields_s[32], pairs_s[32], particles_s[32];
        sph_format_bytes(fields_bytes + pairs_bytes + particles_bytes, total_s, sizeof total_s);
        sph_format_bytes(fields_bytes, fields_s, sizeof fields_s);
        sph_format_bytes(pairs_bytes, pairs_s, sizeof pairs_s);
        sph_format_bytes(particles_bytes, particles_s, sizeof particles_s);
        free(be);
        free(c);
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "the native backend needs %s of memory for %d particles (%s of fields, "
                        "%s of neighbour lists, %s of initial particle arrays), but %s; lower "
                        "the resolution",
                        total_s, n, fields_s, pairs_s, particles_s, available);
    }

    bool ok = true;
    for (int k = 0; k < FIELD_COUNT; ++k) {
        if (!be->fields[k].present) continue;
        const size_t bytes = field_bytes(be, (sph_field)k);
        c->b.field[k] = malloc(bytes);
        c->spare[k] = malloc(bytes);
        ok = ok && c->b.field[k] && c->spare[k];
        sph_backend_record_buffer(be, be->fields[k].name, 2 * bytes);
    }
    c->b.ngroups = ngroups;
    c->b.prm =
        malloc(c->real_size == sizeof(float) ? sizeof(sph_params_f32) : sizeof(sph_params_f64));
    c->b.grid_geom = malloc(4 * c->real_size);
    c->b.partials = malloc((size_t)ngroups * (size_t)sph_partial_ncomp(f) * c->real_size);
    c->b.substep_sums = calloc(SUBSTEP_SUMS_LEN, c->real_size);
    c->b.keys = malloc((size_t)n * sizeof(uint64_t));
    c->keys_sorted = malloc((size_t)n * sizeof(uint64_t));
    c->b.nbr_count = malloc((size_t)n * sizeof(int32_t));
    ok = ok && c->b.prm && c->b.grid_geom && c->b.partials && c->b.substep_sums && c->b.keys &&
         c->keys_sorted && c->b.nbr_count;
    if (!ok) {
        cpu_destroy(be);
        char fields_s[32];
        sph_format_bytes(fields_bytes, fields_s, sizeof fields_s);
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "out of host memory for the fields of %d particles (%s); %s", n, fields_s,
                        available);
    }
    /* the block in the run precision (sph_params.h) */
    if (c->real_size == sizeof(float))
        sph_params_to_f32(prm, c->b.prm);
    else
        memcpy(c->b.prm, prm, sizeof *prm);
    sph_status st = alloc_pairs(be, c, cap0, err);
    if (st) {
        cpu_destroy(be);
        return st;
    }
    *out = be;
    return SPH_OK;
}
