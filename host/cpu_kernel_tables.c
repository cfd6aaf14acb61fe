/* cpu_kernel_tables.c — which compiled instance of the physics source
 * (backend_cpu_kernels.c, one per dimension and precision) serves a run.
 * A file of its own so that what needs only the kernels' point functions
 * (the particle relaxation, the fuzz harness that drives it) links them
 * without the rest of the native backend. */
#include "backend_cpu.h"

const cpu_kernels *cpu_kernels_for(int dim, bool double_precision) {
    if (dim == 2) return double_precision ? &cpu_2d_f64 : &cpu_2d_f32;
    return double_precision ? &cpu_3d_f64 : &cpu_3d_f32;
}

const cpu_kernels *cpu_kernels_for_features(const sph_features *f) {
    if (f->mixed_precision) return f->dim == 2 ? &cpu_2d_mixed : &cpu_3d_mixed;
    return cpu_kernels_for(f->dim, f->double_precision);
}
