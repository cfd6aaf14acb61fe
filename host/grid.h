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

typedef struct {
    int dim;
    double origin[3];
    double cell; /* edge length >= cut-off */
    int dims[3]; /* 1 for unused dimensions */
    long ncells;
} sph_grid;

sph_status sph_grid_from_bounds(int dim, const double lower[3], const double upper[3],
                                double cutoff, int nparticles, sph_grid *grid, sph_error *err);

#endif
