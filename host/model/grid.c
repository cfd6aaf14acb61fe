#include "grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Enough cells for a dense scene, bounded for a scattered one. */
static long max_cells(int nparticles) {
    return 8L * nparticles + 4096L;
}

sph_status sph_grid_from_bounds(int dim, const double lower[3], const double upper[3],
                                double cutoff, int nparticles, sph_grid *grid, sph_error *err) {
    grid->dim = dim;
    for (int a = 0; a < 3; ++a) {
        if (a < dim && !(isfinite(lower[a]) && isfinite(upper[a])))
            return sph_fail(err, SPH_ERR_RUNTIME,
                            "particle positions are not finite (NaN or Inf): the simulation has "
                            "become unstable");
    }
    double cell = cutoff;
    for (;;) {
        long ncells = 1;
        for (int a = 0; a < 3; ++a) {
            if (a < dim) {
                const double extent = upper[a] - lower[a];
                const double count = floor(extent / cell) + 1.0;
                if (count > 1e9) {
                    ncells = -1;
                    break;
                }
                grid->dims[a] = (int)count;
                ncells *= grid->dims[a];
            } else {
                grid->dims[a] = 1;
            }
            if (ncells > max_cells(nparticles)) break;
        }
        if (ncells > 0 && ncells <= max_cells(nparticles)) {
            grid->ncells = ncells;
            break;
        }
        cell *= 2.0;
    }
    grid->cell = cell;
    for (int a = 0; a < 3; ++a) grid->origin[a] = a < dim ? lower[a] : 0.0;
    return SPH_OK;
}

void sph_grid_make_periodic(sph_grid *grid, int mask, const double period[3]) {
    if (!mask) return;
    long ncells = 1;
    for (int a = 0; a < grid->dim; ++a) {
        if (mask & (1 << a)) {
            /* whole cells of at least `cell` over the period: the last one
             * takes the remainder (sph_grid_coord clamps into it) */
            const double count = floor(period[a] / grid->cell);
            grid->dims[a] = count < 1.0 ? 1 : (int)count;
        }
        ncells *= grid->dims[a];
    }
    grid->ncells = ncells;
}

sph_status sph_cell_list_build(sph_cell_list *c, int dim, const double *pos, int n, double cutoff,
                               sph_error *err) {
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int a = 0; a < dim; a++) {
        lo[a] = INFINITY, hi[a] = -INFINITY;
        for (int i = 0; i < n; i++) {
            const double x = pos[(size_t)a * (size_t)n + (size_t)i];
            lo[a] = fmin(lo[a], x), hi[a] = fmax(hi[a], x);
        }
    }
    sph_status st = sph_grid_from_bounds(dim, lo, hi, cutoff, n, &c->grid, err);
    if (st) return st;
    if (c->grid.ncells + 1 > c->ncells_alloc) {
        free(c->start);
        c->ncells_alloc = c->grid.ncells + 1;
        c->start = malloc((size_t)c->ncells_alloc * sizeof *c->start);
        if (!c->start) {
            c->ncells_alloc = 0;
            return sph_fail(err, SPH_ERR_RUNTIME,
                            "out of memory building the cells of %d particles", n);
        }
    }
    if (n > c->n_alloc) {
        free(c->order);
        free(c->cell_of);
        c->order = malloc((size_t)n * sizeof *c->order);
        c->cell_of = malloc((size_t)n * sizeof *c->cell_of);
        c->n_alloc = c->order && c->cell_of ? n : 0;
        if (!c->n_alloc)
            return sph_fail(err, SPH_ERR_RUNTIME,
                            "out of memory building the cells of %d particles", n);
    }
    memset(c->start, 0, (size_t)(c->grid.ncells + 1) * sizeof *c->start);
    for (int i = 0; i < n; i++) {
        long cell = 0;
        for (int a = dim - 1; a >= 0; a--)
            cell = cell * c->grid.dims[a] +
                   sph_grid_coord(&c->grid, a, pos[(size_t)a * (size_t)n + (size_t)i]);
        c->cell_of[i] = (int)cell;
        c->start[cell + 1]++;
    }
    for (long k = 0; k < c->grid.ncells; k++) c->start[k + 1] += c->start[k];
    /* fill each cell in particle order */
    int *cursor = malloc((size_t)c->grid.ncells * sizeof *cursor);
    if (!cursor)
        return sph_fail(err, SPH_ERR_RUNTIME, "out of memory building the cells of %d particles",
                        n);
    memcpy(cursor, c->start, (size_t)c->grid.ncells * sizeof *cursor);
    for (int i = 0; i < n; i++) c->order[cursor[c->cell_of[i]]++] = i;
    free(cursor);
    return SPH_OK;
}

void sph_cell_list_free(sph_cell_list *c) {
    free(c->start);
    free(c->order);
    free(c->cell_of);
    memset(c, 0, sizeof *c);
}
