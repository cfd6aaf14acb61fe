/* cpu_kernel_tables.c — which compiled instance of the physics source
 * (backend_cpu_kernels.c, one per dimension, precision and formulation)
 * serves a run.
 * A file of its own so that what needs only the kernels' point functions
 * (the particle relaxation, the fuzz harness that drives it) links them
 * without the rest of the native backend. */
#include "backend_cpu.h"
#include "sph_constants.h"

/* the instances CMakeLists.txt builds, in FORMULATION_* order */
#define CPU_INSTANCES(dim, prec)                                                                   \
    extern const cpu_kernels cpu_##dim##d_##prec##_enog, cpu_##dim##d_##prec##_enog_a,             \
        cpu_##dim##d_##prec##_og, cpu_##dim##d_##prec##_oas, cpu_##dim##d_##prec##_gnog,           \
        cpu_##dim##d_##prec##_gnog_a, cpu_##dim##d_##prec##_tlsph;
CPU_INSTANCES(2, f64)
CPU_INSTANCES(2, f32)
CPU_INSTANCES(2, mixed)
CPU_INSTANCES(3, f64)
CPU_INSTANCES(3, f32)
CPU_INSTANCES(3, mixed)
/* the fluid formulations: double precision only; dimension 1 has them alone */
extern const cpu_kernels cpu_1d_f64_eulerian_wc, cpu_1d_f64_eulerian_compressible,
    cpu_2d_f64_eulerian_wc, cpu_2d_f64_eulerian_compressible, cpu_3d_f64_eulerian_wc,
    cpu_3d_f64_eulerian_compressible;
#define CPU_ROW(dim, prec, fluid_wc, fluid_compressible)                                           \
    {                                                                                              \
        &cpu_##dim##d_##prec##_enog, &cpu_##dim##d_##prec##_enog_a, &cpu_##dim##d_##prec##_og,     \
            &cpu_##dim##d_##prec##_oas, &cpu_##dim##d_##prec##_gnog,                               \
            &cpu_##dim##d_##prec##_gnog_a, &cpu_##dim##d_##prec##_tlsph, fluid_wc,                 \
            fluid_compressible                                                                     \
    }
#define CPU_FORMULATION_COUNT 9

/* [dimension - 1][f64, f32, mixed][formulation]; NULL: no such instance */
static const cpu_kernels *const cpu_instances[3][3][CPU_FORMULATION_COUNT] = {
    {{NULL, NULL, NULL, NULL, NULL, NULL, NULL, &cpu_1d_f64_eulerian_wc,
      &cpu_1d_f64_eulerian_compressible},
     {NULL},
     {NULL}},
    {CPU_ROW(2, f64, &cpu_2d_f64_eulerian_wc, &cpu_2d_f64_eulerian_compressible),
     CPU_ROW(2, f32, NULL, NULL), CPU_ROW(2, mixed, NULL, NULL)},
    {CPU_ROW(3, f64, &cpu_3d_f64_eulerian_wc, &cpu_3d_f64_eulerian_compressible),
     CPU_ROW(3, f32, NULL, NULL), CPU_ROW(3, mixed, NULL, NULL)},
};

/* The point functions (kernel values, probes) of a dimension: the ENOG
 * instance's; in 1D, where only the fluids exist, the weakly compressible
 * one's (double precision). */
const cpu_kernels *cpu_kernels_for(int dim, bool double_precision) {
    if (dim == 1) return double_precision ? &cpu_1d_f64_eulerian_wc : NULL;
    return cpu_instances[dim == 2 ? 1 : 2][double_precision ? 0 : 1][FORMULATION_ENOG];
}

const cpu_kernels *cpu_kernels_for_features(const sph_features *f) {
    const int prec = f->mixed_precision ? 2 : f->double_precision ? 0 : 1;
    const int form = (int)f->formulation;
    if (form < 0 || form >= CPU_FORMULATION_COUNT) return NULL;
    if (f->dim < 1 || f->dim > 3) return NULL;
    return cpu_instances[f->dim - 1][prec][form];
}

const sph_physics *sph_physics_for(int dim, bool double_precision) {
    const cpu_kernels *k = cpu_kernels_for(dim, double_precision);
    return k ? &k->physics : NULL;
}
