/* sph_step_clock.h — the acoustic step clock: the time, the size of the next
 * acoustic substep and when the advection step it belongs to ends (000 §4,
 * the dual-criteria time stepping: dt_ac = CFL_ac h / (c0 + max |v|) within
 * an advection step of CFL_ad h / max |v|).
 *
 * One source for the host and the device.  The native backend and devices
 * without double precision advance it on the host after every substep; an
 * OpenCL device with cl_khr_fp64 advances it in the substep's last kernel
 * (substep_finalize, reduction.cl), so the host enqueues an advection step's
 * substeps without waiting for each one's max |v| (issue 5: no host
 * synchronisation inside the acoustic loop).  Its arithmetic is in double on
 * both sides, in the order the host used before, so both give the same step
 * sizes bit for bit (IEEE division and square root are correctly rounded in
 * C and in OpenCL C for double; FP_CONTRACT is off in both builds).
 *
 * The clock is an array of SPH_CLOCK_LEN doubles; CLOCK_HALTED says whether
 * the substeps of this advection step may go on (0) or why they stop. */
#ifndef SPH_STEP_CLOCK_H
#define SPH_STEP_CLOCK_H

#ifndef __OPENCL_VERSION__
#    include <math.h>
#    include <stdbool.h>
#endif

#define CLOCK_T           0  /* time after the last substep */
#define CLOCK_DT          1  /* size of the next substep */
#define CLOCK_AT_OUTPUT   2  /* 1: the next substep lands on the output time */
#define CLOCK_T_ADV_END   3  /* the advection step ends once t reaches this */
#define CLOCK_NEXT_OUTPUT 4  /* the output time no substep steps past */
#define CLOCK_CFL_H       5  /* CFL_ac h */
#define CLOCK_C0          6  /* the sound speed */
#define CLOCK_ONE_SUBSTEP 7  /* 1: every advection step is one substep */
#define CLOCK_SPEED_LIMIT 8  /* the monitor's speed limit, INFINITY when off */
#define CLOCK_MAX_SPEED2  9  /* max |v|^2 after the last substep */
#define CLOCK_COUNT       10 /* substeps taken since the host last reset it */
#define CLOCK_HALTED      11 /* CLOCK_RUNNING or one of the reasons below */
#define CLOCK_STEP_ENDED  12 /* 1: the last substep ended the advection step */
#define CLOCK_ON_OUTPUT   13 /* 1: the last substep landed on the output time */
#define SPH_CLOCK_LEN     14

#define CLOCK_RUNNING   0
#define CLOCK_STEP_DONE 1 /* the advection step is complete */
#define CLOCK_NONFINITE 2 /* max |v|^2 is NaN or infinite */
#define CLOCK_TOO_FAST  3 /* max |v| beyond CLOCK_SPEED_LIMIT */

#ifndef CLOCK_MEM
#    define CLOCK_MEM
#endif

/* The next substep: CFL_ac h / (c0 + max |v|), cut so that it lands exactly
 * on the output time and never steps past it. */
static inline void step_clock_plan(CLOCK_MEM double *c) {
    double dt = c[CLOCK_CFL_H] / (c[CLOCK_C0] + sqrt(c[CLOCK_MAX_SPEED2]));
    c[CLOCK_AT_OUTPUT] = 0.0;
    if (c[CLOCK_T] + dt >= c[CLOCK_NEXT_OUTPUT] * (1.0 - 1e-12)) {
        dt = c[CLOCK_NEXT_OUTPUT] - c[CLOCK_T];
        c[CLOCK_AT_OUTPUT] = 1.0;
    }
    c[CLOCK_DT] = dt;
}

/* After a substep of size c[CLOCK_DT] that left max |v|^2 = max_speed2:
 * advance the time, check the speed (a blow-up shrinks the substep with the
 * growing speed, so it might never reach the next output time and the
 * monitor there), and either halt or plan the next substep. */
static inline void step_clock_finish(CLOCK_MEM double *c, const double max_speed2) {
    const bool on_output = c[CLOCK_AT_OUTPUT] != 0.0;
    c[CLOCK_MAX_SPEED2] = max_speed2;
    c[CLOCK_T] = on_output ? c[CLOCK_NEXT_OUTPUT] : c[CLOCK_T] + c[CLOCK_DT];
    c[CLOCK_COUNT] += 1.0;
    c[CLOCK_ON_OUTPUT] = on_output ? 1.0 : 0.0;
    const bool ended = on_output || c[CLOCK_ONE_SUBSTEP] != 0.0 || c[CLOCK_T] >= c[CLOCK_T_ADV_END];
    c[CLOCK_STEP_ENDED] = ended ? 1.0 : 0.0;
    if (!isfinite(max_speed2))
        c[CLOCK_HALTED] = CLOCK_NONFINITE;
    else if (sqrt(max_speed2) > c[CLOCK_SPEED_LIMIT])
        c[CLOCK_HALTED] = CLOCK_TOO_FAST;
    else if (ended)
        c[CLOCK_HALTED] = CLOCK_STEP_DONE;
    else
        step_clock_plan(c);
}

#endif
