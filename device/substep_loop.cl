/* substep_loop.cl — many acoustic substeps in one launch, for scenes small
 * enough that launches, not bytes, bound their substeps (issue 33, "small
 * scenes").
 *
 * One work-group of SPH_LOOP_WG items runs up to `substeps` substeps: each
 * pass of a substep (the kernels of acoustic_step.cl, tl_step.cl or
 * eulerian_step.cl, which this program, SPH_SUBSTEP_LOOP, compiles as
 * functions of the item index) goes over the particles in strides of the
 * group (never larger than the particle count, backend_opencl.c), a barrier on
 * global memory stands where one launch ended and the next began, and the
 * substep ends in the reduction and the step clock's advance that
 * substep_reduce and substep_finalize (substep_reduce_finish on CPU devices)
 * make in their launches.  The grouping of the reduction is theirs, so the
 * substeps are bit for bit those of the per-substep launches
 * (tests/test_substep_loop.py).  The loop stops where the clock halts (the
 * advection step's end, a non-finite or too fast velocity), as the
 * per-substep kernels turn into no-ops there.
 *
 * The passes need the barriers of one work-group, so one group does all the
 * work: a GPU runs it on one of its compute units, which pays where a
 * substep's work is smaller than the cost of its launches
 * (backend_opencl.c chooses it by the particle count). */
/* the programs' files (backend_opencl.c), whose per-item kernels are
 * functions here: the fluids' far field takes its periodic images from
 * neighbour_build.cl, and reduction.cl brings eulerian_step.cl (the
 * embedded sources are assembled with each file once, so no #include may
 * sit in a conditional block) */
#include "neighbour_build.cl"
#include "acoustic_step.cl"
#include "tl_step.cl"
#include "reduction.cl"

/* The substep reduction of the particles' contributions CONTRIB (as
 * substep_contrib writes particle i's into c) and the clock's advance:
 * CPU devices: blocks of SPH_WG particles, a block per work-item, the rows
 * combined in order by item 0 (substep_reduce_finish); GPUs: the group in
 * segments of SPH_WG items, a segment per block, each a tree as one group of
 * substep_reduce, then finalize_rows as substep_finalize. */
#if SPH_REDUCE_BLOCKS
#    define LOOP_SCRATCH
#    define LOOP_SUBSTEP_REDUCE(NCOMP, CONTRIB)                                                    \
        do {                                                                                       \
            const real dt = (real)step_clock[CLOCK_DT];                                            \
            for (int g = lid; g < ngroups; g += SPH_LOOP_WG)                                       \
                REDUCE_BLOCK(g, n, 1, (NCOMP), SUBSTEP_NCOMP_MAX, partials, CONTRIB);              \
            barrier(CLK_GLOBAL_MEM_FENCE);                                                         \
            if (lid == 0) {                                                                        \
                combine_rows(ngroups, 1, (NCOMP), partials, substep_sums);                         \
                step_clock_finish(step_clock, (double)substep_sums[0]);                            \
            }                                                                                      \
            barrier(CLK_GLOBAL_MEM_FENCE);                                                         \
        } while (0)
#else
#    define LOOP_SCRATCH __local real scratch[SPH_LOOP_WG]
#    define LOOP_SUBSTEP_REDUCE(NCOMP, CONTRIB)                                                    \
        do {                                                                                       \
            const real dt = (real)step_clock[CLOCK_DT];                                            \
            const int segment = lid / SPH_WG, lane = lid % SPH_WG;                                 \
            for (int g0 = 0; g0 < ngroups; g0 += SPH_LOOP_WG / SPH_WG) {                           \
                const int g = g0 + segment, i = g * SPH_WG + lane;                                 \
                real c[SUBSTEP_NCOMP_MAX];                                                         \
                reduce_identity(c, 1, (NCOMP));                                                    \
                if (i < n) CONTRIB;                                                                \
                segment_reduce_store(scratch + segment * SPH_WG, lane, g < ngroups ? g : -1, c, 1, \
                                     (NCOMP), partials);                                           \
            }                                                                                      \
            barrier(CLK_GLOBAL_MEM_FENCE);                                                         \
            finalize_rows(scratch, ngroups, 1, (NCOMP), partials, substep_sums);                   \
            if (lid == 0) step_clock_finish(step_clock, (double)substep_sums[0]);                  \
            barrier(CLK_GLOBAL_MEM_FENCE);                                                         \
        } while (0)
#endif

/* the reduction's body ids (several bodies) */
#if SPH_HAS_BODY_IDS
#    define LOOP_BODY_PARAMS , GLOBAL const u8 *restrict body
#else
#    define LOOP_BODY_PARAMS
#endif

/* Each particle of this work-item: i = lid, lid + SPH_LOOP_WG, ... */
#define FOR_MY_PARTICLES(i) for (int i = lid; i < n; i += SPH_LOOP_WG)
#define PASS_END            barrier(CLK_GLOBAL_MEM_FENCE)

#if SPH_HAS_TLSPH
/* TLSPH (tl_step.cl): deformation, acceleration, update */
/* buffers of tl_substep_loop: reads nbr_count:int*n nbr_j:int*pairs pair_e:real*d*pairs
 * pair_dwv:real*pairs pair_inv_r:real*pairs pair_w:real*pairs mass vol bmat fixed body; writes
 * partials:small defgrad pk1 rho tau acc_shear; updates step_clock:small substep_sums:small pos
 * vel plastic_strain plastic_cinv */
__kernel __attribute__((reqd_work_group_size(SPH_LOOP_WG, 1, 1))) void tl_substep_loop(
    const int substeps, const int n, const int cap, const int ngroups, GLOBAL double *step_clock,
    CONSTANT sph_params *prm, GLOBAL const int *restrict nbr_count,
    GLOBAL const int *restrict nbr_j, GLOBAL const real *restrict pair_e,
    GLOBAL const real *restrict pair_dwv, GLOBAL const real *restrict pair_inv_r,
    GLOBAL const real *restrict pair_w, GLOBAL const real *restrict mass,
    GLOBAL const real *restrict vol, GLOBAL const real *restrict bmat, GLOBAL hreal *pos,
    GLOBAL real *vel, GLOBAL real *defgrad, GLOBAL real *pk1, GLOBAL hreal *rho, GLOBAL hreal *tau,
    GLOBAL hreal *acc_shear, GLOBAL real *partials,
    GLOBAL real *substep_sums TL_PLASTIC_STATE_PARAMS TL_CLAMP_PARAMS LOOP_BODY_PARAMS) {
    LOOP_SCRATCH;
    const int lid = get_local_id(0);
    for (int s = 0; s < substeps && step_clock[CLOCK_HALTED] == 0.0; ++s) {
        FOR_MY_PARTICLES(i) {
            tl_deformation(i, n, cap, step_clock, prm, nbr_count, nbr_j, pair_e, pair_dwv, pos, vel,
                           bmat, defgrad, pk1, rho, tau TL_PLASTIC_STATE_ARGS);
        }
        PASS_END;
        FOR_MY_PARTICLES(i) {
            tl_acceleration(i, n, cap, step_clock, prm, nbr_count, nbr_j, pair_e, pair_dwv,
                            pair_inv_r, pos, vel, mass, vol, bmat, defgrad, pk1, acc_shear,
                            pair_w TL_PLASTIC_SWITCH_ARGS);
        }
        PASS_END;
        FOR_MY_PARTICLES(i) {
            tl_update(i, n, step_clock, prm, acc_shear, pos, vel TL_CLAMP_ARGS);
        }
        PASS_END;
        LOOP_SUBSTEP_REDUCE(
            1, substep_contrib(i, n, dt, prm, vel, SPIN_ARG, BODY_ARG, TORQUE_ARGS, FLUID_ARGS, c));
    }
}

#elif SPH_HAS_EULERIAN
/* the fluids (eulerian_step.cl): the two stages and the update, or each
 * SSP-RK stage's rates and update; then the far field */
#    if SPH_FLUID_RK
#        define LOOP_STAGE_PARAMS , GLOBAL real *momentum_rate, GLOBAL real *state_saved
#    else
#        define LOOP_STAGE_PARAMS , GLOBAL real *vel_stage
#    endif
#    if SPH_HAS_COMPRESSIBLE
#        define LOOP_ENERGY_PARAMS                                                                 \
            , GLOBAL real *energy, GLOBAL real *energy_rate, GLOBAL real *sound_speed
#    else
#        define LOOP_ENERGY_PARAMS
#    endif
#    if SPH_FAR_FIELD
#        define LOOP_FAR_FIELD_PARAMS , GLOBAL const hreal *restrict pos
#    else
#        define LOOP_FAR_FIELD_PARAMS
#    endif
/* buffers of eulerian_substep_loop: reads nbr_count:int*n nbr_j:int*pairs pair_e:real*d*pairs
 * pair_dwv:real*pairs pair_inv_r:real*pairs vol pos fixed kind normal body; writes partials:small;
 * updates step_clock:small substep_sums:small rho vel mass pressure mass_rate
 * momentum_rate state_saved vel_stage energy energy_rate sound_speed wall_force */
__kernel __attribute__((reqd_work_group_size(SPH_LOOP_WG, 1, 1))) void eulerian_substep_loop(
    const int substeps, const int stages, const int n, const int cap, const int ngroups,
    GLOBAL double *step_clock, CONSTANT sph_params *prm, GLOBAL const int *restrict nbr_count,
    GLOBAL const int *restrict nbr_j, GLOBAL const real *restrict pair_e,
    GLOBAL const real *restrict pair_dwv, GLOBAL const real *restrict pair_inv_r,
    GLOBAL const real *restrict vol, GLOBAL hreal *rho, GLOBAL real *vel, GLOBAL real *mass,
    GLOBAL real *pressure, GLOBAL real *mass_rate, GLOBAL real *partials,
    GLOBAL real *substep_sums LOOP_STAGE_PARAMS LOOP_ENERGY_PARAMS LOOP_FAR_FIELD_PARAMS FIXED_PARAM
        KIND_PARAMS WALL_FORCE_PARAM LOOP_BODY_PARAMS) {
    LOOP_SCRATCH;
    const int lid = get_local_id(0);
    (void)stages;
    for (int s = 0; s < substeps && step_clock[CLOCK_HALTED] == 0.0; ++s) {
#    if SPH_FLUID_RK
        for (int stage = 0; stage < stages; ++stage) {
            FOR_MY_PARTICLES(i) {
                eulerian_rates(i, n, stage, step_clock, prm, PAIR_ROWS_ARGS, pair_e, pair_dwv,
                               pair_inv_r, rho, vel, vol, pressure, mass_rate,
                               momentum_rate ENERGY_RATE_ARGS SOUND_ARG KIND_ARGS WALL_FORCE_ARG);
            }
            PASS_END;
            FOR_MY_PARTICLES(i) {
                eulerian_rk_update(i, n, stage, stages, step_clock, prm, vel, mass, rho, vol,
                                   pressure, mass_rate, momentum_rate,
                                   state_saved ENERGY_RATE_ARGS SOUND_ARG FIXED_ARG KIND_ARGS);
            }
            PASS_END;
        }
#    else
        FOR_MY_PARTICLES(i) {
            eulerian_momentum_rate(
                i, n, step_clock, prm, PAIR_ROWS_ARGS, pair_e, pair_dwv, pair_inv_r, rho, vel, mass,
                vol, pressure, vel_stage ENERGY_ARG SOUND_ARG FIXED_ARG KIND_ARGS WALL_FORCE_ARG);
        }
        PASS_END;
        FOR_MY_PARTICLES(i) {
            eulerian_mass_energy_rate(i, n, step_clock, prm, PAIR_ROWS_ARGS, pair_e, pair_dwv,
                                      pair_inv_r, rho, vel_stage, vol, pressure,
                                      mass_rate ENERGY_RATE_ARGS SOUND_ARG KIND_ARGS);
        }
        PASS_END;
        FOR_MY_PARTICLES(i) {
            eulerian_update(i, n, step_clock, prm, vel, vel_stage, mass, rho, vol, pressure,
                            mass_rate ENERGY_RATE_ARGS SOUND_ARG FIXED_ARG KIND_ARGS);
        }
        PASS_END;
#    endif
#    if SPH_FAR_FIELD
        FOR_MY_PARTICLES(i) {
            eulerian_far_field(i, n, prm, PAIR_ROWS_ARGS, pos, rho, vel, mass, vol,
                               pressure ENERGY_ARG SOUND_ARG KIND_ARGS);
        }
        PASS_END;
#    endif
        LOOP_SUBSTEP_REDUCE(
            1, substep_contrib(i, n, dt, prm, vel, SPIN_ARG, BODY_ARG, TORQUE_ARGS, FLUID_ARGS, c));
    }
}

#else
/* the updated-Lagrangian solids (acoustic_step.cl): contact (several
 * bodies), pressure, velocity terms, the stress-divergence formulations'
 * shear force */
#    if SPH_HAS_CONTACT
#        define LOOP_CONTACT_PARAMS , GLOBAL const int *restrict contact_count
#    else
#        define LOOP_CONTACT_PARAMS
#    endif
/* the averaged rotation's increment and spin; the torque projection's
 * moments read the increment too */
#    if SPH_HAS_ROTATION_AVG || SPH_HAS_TORQUE_PROJECTION
#        define LOOP_DACC_PARAMS , GLOBAL real *dacc_shear
#    else
#        define LOOP_DACC_PARAMS
#    endif
#    if SPH_HAS_ROTATION_AVG
#        define LOOP_SPIN_PARAMS , GLOBAL real *spin
#    else
#        define LOOP_SPIN_PARAMS
#    endif
#    if SPH_HAS_STRESS_DIV
#        define LOOP_STRESS_PARAMS , GLOBAL real *acc_stress
#    else
#        define LOOP_STRESS_PARAMS
#    endif

/* buffers of acoustic_substep_loop: reads nbr_count:int*n nbr_j:int*pairs pair_pos:hreal*d*n
 * pair_e:real*d*pairs pair_dwv:real*pairs pair_inv_r:real*pairs mass vol bmat contact_count body
 * fixed material; writes partials:small gradv art_stress plastic_strain penalty_scale; updates
 * step_clock:small pos vel rho drho acc_diss tau acc_shear substep_sums:small dacc_shear spin
 * acc_stress */
__kernel __attribute__((reqd_work_group_size(SPH_LOOP_WG, 1, 1))) void acoustic_substep_loop(
    const int substeps, const int n, const int cap, const int ngroups, GLOBAL double *step_clock,
    CONSTANT sph_params *prm, GLOBAL const int *restrict nbr_count,
    GLOBAL const int *restrict nbr_j, PAIR_GEOMETRY_PARAMS, GLOBAL const real *restrict mass,
    GLOBAL const real *restrict vol, GLOBAL const real *restrict bmat, GLOBAL hreal *pos,
    GLOBAL real *vel, GLOBAL hreal *rho, GLOBAL real *drho, GLOBAL real *acc_diss,
    GLOBAL hreal *tau, GLOBAL hreal *acc_shear, GLOBAL real *partials,
    GLOBAL real *substep_sums LOOP_CONTACT_PARAMS LOOP_DACC_PARAMS LOOP_SPIN_PARAMS BODY_PARAMS
        CLAMP_PARAMS LOOP_STRESS_PARAMS GRADV_OUT_PARAMS ART_OUT_PARAMS PLASTIC_OUT_PARAMS
            MATERIAL_PARAMS) {
    LOOP_SCRATCH;
    const int lid = get_local_id(0);
    const int ncomp = substep_ncomp(prm);
    for (int s = 0; s < substeps && step_clock[CLOCK_HALTED] == 0.0; ++s) {
#    if SPH_HAS_CONTACT
        FOR_MY_PARTICLES(i) {
            acoustic_contact(i, n, cap, step_clock, prm, nbr_j, contact_count, pos, vel, mass, vol,
                             acc_diss MATERIAL_ARG);
        }
        PASS_END;
#    endif
        FOR_MY_PARTICLES(i) {
            acoustic_pressure(
                i, n, cap, step_clock, prm, nbr_count, nbr_j, PAIR_DIR_ARGS, rho, drho, mass, vol,
                acc_diss, acc_shear, pos,
                vel ROTATION_AVG_ARGS BODY_ARGS CLAMP_ARGS STRESS_DIV_ARGS MATERIAL_ARG);
        }
        PASS_END;
        FOR_MY_PARTICLES(i) {
            acoustic_velocity_terms(i, n, cap, step_clock, prm, nbr_count, nbr_j,
                                    PAIR_GEOMETRY_ARGS, vel, mass, vol, bmat, rho, drho, acc_diss,
                                    tau,
                                    acc_shear ROTATION_AVG_SPIN_ARGS GRADV_OUT_ARGS ART_OUT_ARGS
                                        PLASTIC_OUT_ARGS WALL_POS_ARGS MATERIAL_ARG);
        }
        PASS_END;
#    if SPH_HAS_STRESS_DIV
        FOR_MY_PARTICLES(i) {
            acoustic_shear_force(i, n, cap, step_clock, prm, nbr_count, nbr_j, PAIR_GEOMETRY_ARGS,
                                 mass, vol, rho, tau,
                                 acc_stress PENALTY_ARGS ART_IN_ARGS PENALTY_SCALE_ARGS
                                     PENALTY_AVG_ARGS MATERIAL_ARG);
        }
        PASS_END;
#    endif
        LOOP_SUBSTEP_REDUCE(ncomp, substep_contrib(i, n, dt, prm, vel, SPIN_ARG, BODY_ARG,
                                                   TORQUE_ARGS, FLUID_ARGS, c));
    }
}
#endif
