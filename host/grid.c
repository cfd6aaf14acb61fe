#include "grid.h"

#include <math.h>

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
