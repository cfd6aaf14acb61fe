/* sph_prelude.h — one dialect for the physics source.
 *
 * Every file in device/ is compiled twice: as OpenCL C 1.2 by the device
 * backend (with the scene's features as -D options) and as C11 by the native
 * CPU backend (once per dimension, precision and formulation, the other
 * features switched at run time).  This header hides the few differences
 * between the two languages so that the physics exists exactly once.
 *
 * Build-time symbols (set by the host, see host/features.c):
 *   SPH_DIM          2 or 3; 1 for the fluid formulations only
 *   SPH_DOUBLE       1 for double precision, 0 for single
 *   SPH_MIXED        1 for mixed precision (with SPH_DOUBLE 0): single
 *                    arithmetic, the history fields in double (hreal below)
 *   SPH_KERNEL       smoothing kernel (KERNEL_* below)
 *   SPH_FORMULATION  FORMULATION_* (sph_constants.h); SPH_CPU_FORMULATION is
 *                    its counterpart in the native backend's C build
 *   SPH_PLASTIC      1 when the material follows J2 plasticity (003 eqs. 11-14)
 *   SPH_ELASTIC_MODEL ELASTIC_MODEL_* (sph_constants.h): TLSPH's elastic law
 *   SPH_TL_DAMPING   1 when TLSPH has the pairwise numerical damping
 *   SPH_ROTATION     ROTATION_* : how the accumulated shear acceleration turns
 *   SPH_TORQUE_PROJECTION 1: the accumulated ENOG shear acceleration is kept
 *                    free of net torque per body (sph_torque_projection.h)
 *   SPH_HAS_CLAMP    1 when the scene has fixed (clamped) particles
 *   SPH_NBODIES      number of bodies (1 when the scene has one body)
 *   SPH_MATERIALS    rows of the material table in use, given only when
 *                    more than one: particles then carry a material id
 *                    (sph_materials.h)
 *   SPH_CONTACT      1 when bodies must not merge: the neighbour lists hold
 *                    same-body pairs, and different bodies interact only by
 *                    the contact force (sph_contact.h); scenes with several
 *                    bodies (updated-Lagrangian formulations)
 *   SPH_WALLS        number of rigid walls (sph_wall.h), 0 without
 *   SPH_NBR_ROW_MAJOR 1: pair slot (i,k) at i*cap+k (CPU caches);
 *                     0: at k*n+i (coalesced on GPUs)
 *   SPH_WG           work-group size of the reduction kernels
 *   SPH_STEP_CLOCK   1 (OpenCL, double-capable devices): the substep kernels
 *                    read dt from the step clock (sph_step_clock.h) that
 *                    the previous substep planned on the device; 0: dt is a
 *                    kernel argument set by the host
 *   SPH_REDUCE_BLOCKS 1 (OpenCL, CPU devices): each work-item of a reduction's
 *                    first stage sums a block of SPH_WG particles, without
 *                    barriers (reduction.cl); 0: a tree over the work-group
 *   SPH_COUNTING_SORT 1 (OpenCL, CPU devices): the cell sort is a counting
 *                    sort on one work-item (neighbour_build.cl); 0: bitonic
 *   SPH_SUBSTEP_LOOP 1 (OpenCL): the program of substep_loop.cl, whose one
 *                    work-group of SPH_LOOP_WG items runs many substeps per
 *                    launch; its per-item kernels are functions (KERNEL)
 */
#ifndef SPH_PRELUDE_H
#define SPH_PRELUDE_H

#include "sph_params.h"

#ifndef SPH_MIXED
#    define SPH_MIXED 0
#endif

#ifdef __OPENCL_VERSION__
#    define SPH_OPENCL 1
#    pragma OPENCL FP_CONTRACT OFF
#    if SPH_DOUBLE || SPH_MIXED || SPH_STEP_CLOCK
#        pragma OPENCL EXTENSION cl_khr_fp64 : enable
#    endif
#    if SPH_DOUBLE
typedef double real;
#    else
typedef float real;
#    endif
#    define GLOBAL   __global
#    define CONSTANT __constant
#    define FN       static inline
#    define FN_HOT   static inline
/* Loops over the components of a vector or matrix (SPH_DIM, NSYM, NSPIN),
 * unrolled in full: pocl 3.1 (LLVM 15) left the 2-trip loops of the 2D
 * helpers rolled, kept their vectors on the stack, and stalled on reading
 * them back (store forwarding), which made acoustic_velocity_terms 4x
 * slower per particle than the same source compiled by GCC or clang for the
 * native backend (docs/benchmarks.md, "pocl"). */
#    define UNROLL       _Pragma("unroll")
#    define UNROLL_LANES UNROLL
/* A per-item kernel is an OpenCL kernel here and a plain function called in
 * an OpenMP loop on the CPU.  ITEM_PARAM/ITEM_ID give it its item index.
 * The substep loop's program (SPH_SUBSTEP_LOOP, substep_loop.cl) makes them
 * functions here too, which its one kernel calls for each particle of its
 * work-items, as the native backend's thread team does. */
#    if SPH_SUBSTEP_LOOP
#        define KERNEL     FN
#        define ITEM_PARAM const int item_,
#        define ITEM_ID    item_
#    else
#        define KERNEL __kernel
#        define ITEM_PARAM
#        define ITEM_ID ((int)get_global_id(0))
#    endif
/* Optional buffers exist only when their feature is compiled in. */
#    define PRESENT(p)          1
#    define RUNTIME_ROTATION    SPH_ROTATION
#    define RUNTIME_KERNEL      SPH_KERNEL
#    define RUNTIME_NBODIES     SPH_NBODIES
#    define RUNTIME_FORMULATION SPH_FORMULATION
#    define RUNTIME_PLASTIC     SPH_PLASTIC
#    ifndef SPH_ELASTIC_MODEL
#        define SPH_ELASTIC_MODEL ELASTIC_MODEL_SVK
#    endif
#    ifndef SPH_TL_DAMPING
#        define SPH_TL_DAMPING 0
#    endif
#    define RUNTIME_ELASTIC_MODEL SPH_ELASTIC_MODEL
#    ifndef SPH_TORQUE_PROJECTION
#        define SPH_TORQUE_PROJECTION 0
#    endif
#    define RUNTIME_TORQUE_PROJECTION SPH_TORQUE_PROJECTION
/* Which optional buffers and code paths this program has. */
#    define SPH_HAS_ROTATION_AVG (SPH_ROTATION == ROTATION_AVERAGED)
#    define SPH_HAS_BODY_IDS     (SPH_NBODIES > 1)
#    define SPH_HAS_ENOG                                                                           \
        (SPH_FORMULATION == FORMULATION_ENOG || SPH_FORMULATION == FORMULATION_ENOG_A)
#    define SPH_HAS_STRESS_DIV                                                                     \
        (SPH_FORMULATION == FORMULATION_OG || SPH_FORMULATION == FORMULATION_OAS ||                \
         SPH_FORMULATION == FORMULATION_GNOG || SPH_FORMULATION == FORMULATION_GNOG_A)
#    define SPH_HAS_PENALTY                                                                        \
        (SPH_FORMULATION == FORMULATION_GNOG || SPH_FORMULATION == FORMULATION_GNOG_A)
#    define SPH_HAS_ART_STRESS        (SPH_FORMULATION == FORMULATION_OAS)
#    define SPH_HAS_TLSPH             (SPH_FORMULATION == FORMULATION_TLSPH)
#    define SPH_HAS_PLASTICITY        SPH_PLASTIC
#    define SPH_HAS_TORQUE_PROJECTION SPH_TORQUE_PROJECTION
/* TLSPH with a J2 material: the finite-strain return map and the 002
 * hourglass switch (sph_plasticity.h, tl_step.cl) */
#    define SPH_HAS_TL_PLASTICITY (SPH_HAS_TLSPH && SPH_PLASTIC)
/* TLSPH with a hyperelastic law (neo-Hookean, exponential) and with the
 * pairwise damping (tl_step.cl) */
#    define SPH_HAS_HYPERELASTIC (SPH_HAS_TLSPH && SPH_ELASTIC_MODEL != ELASTIC_MODEL_SVK)
#    define SPH_HAS_TL_DAMPING   (SPH_HAS_TLSPH && SPH_TL_DAMPING)
/* separate bodies with contact between them (sph_contact.h) */
#    define SPH_HAS_CONTACT SPH_CONTACT
/* rigid walls (sph_wall.h) */
#    define SPH_HAS_WALLS (SPH_WALLS > 0)
/* several materials: the per-particle material id (sph_materials.h) */
#    ifndef SPH_MATERIALS
#        define SPH_MATERIALS 1
#    endif
#    define SPH_HAS_MATERIAL_IDS (SPH_MATERIALS > 1)
typedef uchar u8;
#    define ATOMIC_MAX_INT(p, v) atomic_max((p), (v))
#    define REAL_LOWEST          (-INFINITY)
#else
#    include <tgmath.h>
#    include <stdint.h>
#    define SPH_OPENCL 0
#    if SPH_DOUBLE
typedef double real;
#    else
typedef float real;
#    endif
#    define GLOBAL
#    define CONSTANT const
#    define FN       static inline
/* once per particle and substep, on the path of every scene: inlined into
 * the pass that calls it, whose register values it then reads directly (out
 * of line, the 2D matrices it is passed were stored to the stack as scalars
 * and read back as vectors, a store-forwarding stall that made
 * shear_stress_advance 13 % of the H/dp = 10 plate's run) */
#    define FN_HOT   static inline __attribute__((always_inline))
/* GCC and clang unroll the component loops themselves (see the OpenCL
 * branch) */
#    define UNROLL
/* ... but not a pair loop's lanes (SPH_PAIR_LANES trips, each gathering a
 * neighbour): rolled, the gathered scalars went to the stack and were read
 * back as vectors, stalling on store forwarding (eulerian_step.cl) */
#    if defined(__clang__)
#        define UNROLL_LANES _Pragma("unroll")
#    elif defined(__GNUC__)
#        define UNROLL_LANES _Pragma("GCC unroll 16")
#    else
#        define UNROLL_LANES
#    endif
/* a kernel is the body of one loop of the native backend: inlined there
 * (left to GCC, acoustic_shear_force stayed out of line once the substep's
 * passes became a function of their own, and the plate ran 13 % slower) */
#    define KERNEL           static inline __attribute__((always_inline))
#    define ITEM_PARAM       const int item_,
#    define ITEM_ID          item_
/* The CPU backend compiles every feature in (the formulation aside) and
 * passes NULL for the buffers a scene does not have. */
#    define PRESENT(p)       ((p) != 0)
/* One native variant serves every kernel, rotation mode, body count,
 * plasticity switch and torque projection: their values are run parameters
 * of the block (sph_params.h). */
#    define RUNTIME_ROTATION (prm->rotation)
#    define RUNTIME_KERNEL   (prm->smoothing_kernel)
#    define RUNTIME_NBODIES  (prm->nbodies)
/* each native instance is compiled for one formulation (CMakeLists.txt) */
#    ifndef SPH_CPU_FORMULATION
#        error "the native backend compiles each variant for one SPH_CPU_FORMULATION"
#    endif
#    define RUNTIME_FORMULATION       SPH_CPU_FORMULATION
#    define RUNTIME_PLASTIC           (prm->plastic)
#    define RUNTIME_ELASTIC_MODEL     (prm->elastic_model)
#    define RUNTIME_TORQUE_PROJECTION (prm->torque_projection)
#    define SPH_HAS_ROTATION_AVG      1
#    define SPH_HAS_BODY_IDS          1
#    define SPH_HAS_ENOG              1
#    define SPH_HAS_STRESS_DIV        1
#    define SPH_HAS_PENALTY           1
#    define SPH_HAS_ART_STRESS        1
#    define SPH_HAS_TLSPH             1
#    define SPH_HAS_PLASTICITY        1
#    define SPH_HAS_TORQUE_PROJECTION 1

#    define SPH_HAS_TL_PLASTICITY 1
#    define SPH_HAS_HYPERELASTIC  1
#    define SPH_HAS_TL_DAMPING    1
#    define SPH_HAS_CONTACT       1
#    define SPH_HAS_WALLS         1
#    define SPH_HAS_MATERIAL_IDS  1
#    ifndef SPH_HAS_CLAMP
#        define SPH_HAS_CLAMP 1
#    endif
#    ifndef SPH_NBODIES
#        define SPH_NBODIES SPH_MAX_BODIES
#    endif
#    ifndef SPH_NBR_ROW_MAJOR
#        define SPH_NBR_ROW_MAJOR 1
#    endif
#    ifndef SPH_WG
#        define SPH_WG 256
#    endif
typedef uint8_t u8;
typedef uint64_t ulong;
/* Rare event (neighbour-capacity overflow): a compare-and-swap loop. */
#    define ATOMIC_MAX_INT(p, v)                                                                   \
        do {                                                                                       \
            int seen_ = __atomic_load_n((p), __ATOMIC_RELAXED);                                    \
            while (seen_ < (v) && !__atomic_compare_exchange_n(                                    \
                                      (p), &seen_, (v), 0, __ATOMIC_RELAXED, __ATOMIC_RELAXED))    \
                ;                                                                                  \
        } while (0)
#    define REAL_LOWEST (-INFINITY)
#endif

#define R(x) ((real)(x))

/* The eulerian (fluid) formulations, fixed particles (eulerian_step.cl):
 * compile-time in both dialects (each native instance is compiled for one
 * formulation), so a solid program has none of their buffers or code. */
#define SPH_HAS_EULERIAN     FORM_IS_EULERIAN(RUNTIME_FORMULATION)
#define SPH_HAS_COMPRESSIBLE (RUNTIME_FORMULATION == FORMULATION_EULERIAN_COMPRESSIBLE)
/* Fluid scenes with wall bodies or a far field: the per-particle kind and
 * normal (SPH_FLUID_KINDS), the wall-pair forces (SPH_FLUID_WALLS), the far
 * field's pass (SPH_FAR_FIELD), SSP-RK's passes (SPH_FLUID_RK,
 * time.integrator), the snapshots' vorticity (SPH_FLUID_VORTICITY,
 * output.fields); -D options of the OpenCL program, always
 * compiled into the native fluid instances (PRESENT tests the buffers). */
#if SPH_OPENCL
#    ifndef SPH_FLUID_KINDS
#        define SPH_FLUID_KINDS 0
#    endif
#    ifndef SPH_FLUID_WALLS
#        define SPH_FLUID_WALLS 0
#    endif
#    ifndef SPH_FAR_FIELD
#        define SPH_FAR_FIELD 0
#    endif
#    ifndef SPH_FLUID_RK
#        define SPH_FLUID_RK 0
#    endif
#    ifndef SPH_FLUID_VORTICITY
#        define SPH_FLUID_VORTICITY 0
#    endif
#    define SPH_FLUID_TWO_STAGE (SPH_HAS_EULERIAN && !SPH_FLUID_RK)
#else
#    define SPH_FLUID_KINDS     SPH_HAS_EULERIAN
#    define SPH_FLUID_WALLS     SPH_HAS_EULERIAN
#    define SPH_FAR_FIELD       SPH_HAS_EULERIAN
#    define SPH_FLUID_RK        SPH_HAS_EULERIAN
#    define SPH_FLUID_VORTICITY SPH_HAS_EULERIAN
#    define SPH_FLUID_TWO_STAGE SPH_HAS_EULERIAN
#endif

/* The substep size dt of the substep kernels: an argument, or (SPH_STEP_CLOCK)
 * the size the previous substep's substep_finalize planned in the step
 * clock.  A halted clock turns the substeps the host enqueued past the end of
 * the advection step into no-ops. */
#if SPH_OPENCL && SPH_STEP_CLOCK
#    define CLOCK_MEM GLOBAL
#    include "sph_step_clock.h"
#    define STEP_DT_PARAM GLOBAL const double *restrict step_clock
#    define STEP_DT_BEGIN                                                                          \
        if (step_clock[CLOCK_HALTED] != 0.0) return;                                               \
        const real dt = (real)step_clock[CLOCK_DT]
#else
#    define STEP_DT_PARAM const real dt
#    define STEP_DT_BEGIN (void)0
#endif

/* The history fields: the state a run sums from many small increments over
 * its whole length (positions, density, shear stress, the accumulated shear
 * acceleration).  In mixed precision (SPH_MIXED) they are stored and updated
 * in double while all other arithmetic is single: an acoustic step moves a
 * particle by ~1e-6 of its coordinate and changes the density by ~1e-7 of
 * itself, which a float sum would round away (issue 5, "Precision modes").
 * Otherwise hreal is real.  sph_vec.h has their loads and updates. */
#if SPH_MIXED && !SPH_DOUBLE
typedef double hreal;
#else
typedef real hreal;
#endif

#if SPH_DOUBLE
#    define REAL_EPSILON 2.220446049250313e-16
#else
#    define REAL_EPSILON 1.1920929e-7f
#endif

/* Components of the per-particle quantities for this dimension. */
#define NSYM (SPH_DIM * (SPH_DIM + 1) / 2) /* symmetric tensor */
/* independent spin components: none in 1D (no rotation, no vorticity) */
#define NSPIN (SPH_DIM == 1 ? 0 : SPH_DIM == 2 ? 1 : 3)

/* Lanes of the neighbour sums: lane l sums the neighbours k = l, l + lanes,
 * ..., and the lanes are added in order at the end, a fixed order, so
 * results stay deterministic.  On the CPU a lanes value is a SIMD vector
 * (GCC/clang vector extensions: the compilers did not vectorise the pair
 * loops themselves); in OpenCL one lane, the plain sequential sum, the
 * work-items being the vectors. */
#ifndef SPH_PAIR_LANES
#    if SPH_OPENCL
#        define SPH_PAIR_LANES 1
#    else
#        define SPH_PAIR_LANES 4
#    endif
#endif
#if SPH_PAIR_LANES > 1
typedef real lanes __attribute__((vector_size(SPH_PAIR_LANES * sizeof(real))));
#    define LANE(x, l) ((x)[l])
#else
typedef real lanes;
#    define LANE(x, l) (x)
#endif
FN lanes lanes_zero(void) {
    lanes z;
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) LANE(z, l) = R(0);
    return z;
}
/* Lanes from SPH_PAIR_LANES scalars x[0], x[1], ...: a vector built in
 * registers (writing lanes one by one into a vector in memory and reading
 * it back stalls on store forwarding, which cost more than the lanes saved). */
#if SPH_PAIR_LANES == 1
#    define LANES_FROM(x) ((x)[0])
#elif SPH_PAIR_LANES == 2
#    define LANES_FROM(x) ((lanes){(x)[0], (x)[1]})
#elif SPH_PAIR_LANES == 4
#    define LANES_FROM(x) ((lanes){(x)[0], (x)[1], (x)[2], (x)[3]})
#elif SPH_PAIR_LANES == 8
#    define LANES_FROM(x) ((lanes){(x)[0], (x)[1], (x)[2], (x)[3], (x)[4], (x)[5], (x)[6], (x)[7]})
#endif
FN lanes lanes_broadcast(const real x) {
    lanes z;
    UNROLL for (int l = 0; l < SPH_PAIR_LANES; ++l) LANE(z, l) = x;
    return z;
}
/* max(x, 0) and min(x, 1) lane by lane without branches, as the scalar
 * comparisons x > 0 ? x : 0 and at_most_one (sph_riemann.h) give them, NaN
 * included (0 and 1): on the CPU by the comparison's lane mask (all bits
 * set where true), since C has no ?: on vectors. */
#if SPH_PAIR_LANES > 1
#    if SPH_DOUBLE
typedef long long lanes_bits __attribute__((vector_size(SPH_PAIR_LANES * sizeof(real))));
#    else
typedef int lanes_bits __attribute__((vector_size(SPH_PAIR_LANES * sizeof(real))));
#    endif
FN lanes lanes_positive_part(const lanes x) {
    return (lanes)((lanes_bits)x & (x > lanes_zero()));
}
FN lanes lanes_at_most_one(const lanes x) {
    const lanes one = lanes_broadcast(R(1));
    const lanes_bits below = x < one;
    return (lanes)(((lanes_bits)x & below) | ((lanes_bits)one & ~below));
}
#else
FN lanes lanes_positive_part(const lanes x) {
    return x > R(0) ? x : R(0);
}
FN lanes lanes_at_most_one(const lanes x) {
    return x < R(1) ? x : R(1);
}
#endif

/* Pair slot (i, k) in the frozen neighbour arrays (see SPH_NBR_ROW_MAJOR). */
#if SPH_NBR_ROW_MAJOR
#    define NBR_AT(i, k) ((i)*cap + (k))
#else
#    define NBR_AT(i, k) ((k)*n + (i))
#endif

#endif
