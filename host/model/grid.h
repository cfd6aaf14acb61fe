/* grid.h — the cell grid of the neighbour search.
 *
 * Cells of at least the cut-off radius over the particles' current bounding
 * box, recomputed at every rebuild, so each particle's neighbours lie in the
 * 3^d surrounding cells.  If particles spread so far that the grid would have
 * far more cells than particles, the cells are enlarged: the search stays
 * exact, it only visits more candidates.
 */
#ifndef SPH_GRID_H
#define SPH_GRID_H

#include "sph_error.h"

#include <math.h>

typedef struct {
    int dim;
    double origin[3];
    double cell; /* edge length >= cut-off */
    int dims[3]; /* 1 for unused dimensions */
    long ncells;
} sph_grid;

sph_status sph_grid_from_bounds(int dim, const double lower[3], const double upper[3],
                                double cutoff, int nparticles, sph_grid *grid, sph_error *err);

/* Fluids with periodic axes (bit a of mask: axis a wraps around with the
 * length period[a]; device/neighbour_build.cl): along those axes the grid
 * starts where it did (the particles' lower bound, within one dp of the
 * period's start) and has as many whole cells as fit in the period, so
 * that the stencil's neighbour cells wrap around it. */
void sph_grid_make_periodic(sph_grid *grid, int mask, const double period[3]);

/* The cell of coordinate x along axis a, clamped to the grid. */
static inline int sph_grid_coord(const sph_grid *g, int a, double x) {
    const long c = (long)floor((x - g->origin[a]) / g->cell);
    return c < 0 ? 0 : c >= g->dims[a] ? g->dims[a] - 1 : (int)c;
}

/* A host cell list over positions pos[a * n + i] (the relaxation, the
 * kernel study): the grid over their bounding box and the particles sorted
 * by cell, cell c = x + dims[0] (y + dims[1] z) holding order[start[c]] to
 * order[start[c + 1] - 1] in particle order (a counting sort: the
 * neighbour order, and every sum over it, the same on every run).  Rebuilt
 * in place, reusing its arrays; zero-initialise before the first build. */
typedef struct {
    sph_grid grid;
    long ncells_alloc;
    int n_alloc;
    int *start;   /* [ncells + 1] */
    int *order;   /* [n] */
    int *cell_of; /* [n] */
} sph_cell_list;

sph_status sph_cell_list_build(sph_cell_list *c, int dim, const double *pos, int n, double cutoff,
                               sph_error *err);
void sph_cell_list_free(sph_cell_list *c);

#endif
