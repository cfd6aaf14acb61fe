/* plot.h — `sphsolid run ... --plot`: the PNG plots of a run directory.
 *
 * tools/plot_run.py is embedded in the binary (so this works from any
 * directory, like the OpenCL sources) and fed to Debian's Python on stdin:
 * /usr/bin/python3, or $SPHSOLID_PYTHON.
 */
#ifndef SPH_PLOT_H
#define SPH_PLOT_H

#include "sph_error.h"

#include <stdbool.h>

sph_status sph_plot_run(const char *run_dir, bool quiet, sph_error *err);

#endif
