/* monitor.cl — the instability monitor's per-particle measures, reduced on
 * the device at output times (cheap enough to leave on).
 *
 *  - clustering: the smallest distance to a neighbour, in units of dp;
 *  - zigzag (hourglass) measure: the relative velocity a particle's
 *    neighbours have beyond the linear field of its own velocity gradient,
 *        m_i = sqrt( sum_j w_ij ((v_ij - L_i r_ij) . e_ij / r_ij)^2 / sum_j w_ij ),
 *    w_ij = |dW_ij| V_j, the velocity mismatch of 003 eq. 44 seen from i,
 *    as a strain rate.  A smooth (locally linear) motion gives m_i of order
 *    h |grad grad v|; a zigzag at the particle scale gives m_i of the order
 *    of the velocity gradient itself.  The host divides the largest m_i by
 *    the largest |L_i| (Frobenius norm) of the run so far (host/run/solver.c),
 *    so the indicator is dimensionless and does not depend on the amplitude
 *    of the motion, nor blow up where a vibration turns and every |L_i|
 *    passes through zero;
 *  - non-finite state: 1 where a position or velocity component is NaN or
 *    infinite (a NaN elsewhere reaches the velocity within a substep);
 *  - the bounding box of the particles (max x, max -x), for the check that
 *    no particle has left the monitored domain.
 * Which particle tripped a check is found on the host afterwards
 * (host/run/instability.c, through monitor_contrib on downloaded fields).
 * Positions and velocities are the current ones; B_i and the neighbour
 * lists those of the last configuration rebuild.
 */
#include "sph_vec.h"
#include "sph_smoothing_kernel.h"

/* Components, all combined by max; the layout is SPH_MONITOR_* in
 * sph_constants.h, shared with the host. */
#define MONITOR_NCOMP SPH_MONITOR_NCOMP(SPH_DIM)

FN void monitor_contrib(const int i, const int n, const int cap, CONSTANT sph_params *prm,
                        GLOBAL const int *nbr_count, GLOBAL const int *nbr_j,
                        GLOBAL const hreal *pos, GLOBAL const real *vel, GLOBAL const real *vol,
                        GLOBAL const real *bmat, real *c) {
    const vec x_i = hvec_load(pos, n, i), v_i = vec_load(vel, n, i);
    real state_sum = R(0);
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        c[SPH_MONITOR_MAX_X + a] = x_i.c[a];
        c[SPH_MONITOR_MAX_X + SPH_DIM + a] = -x_i.c[a];
        state_sum += fabs(x_i.c[a]) + fabs(v_i.c[a]);
    }
    /* an infinite or NaN component makes the sum non-finite */
    c[SPH_MONITOR_NONFINITE] = isfinite(state_sum) ? R(0) : R(1);
    real min_r = prm->cutoff;
#if SPH_HAS_EULERIAN
    /* the particles of an Eulerian run do not move: the pair measures
     * (clustering, zigzag) are the solids' and the host does not check them
     * for fluids (host/run/solver.c): skipped (a two-pass loop over every
     * particle's pairs at each output) */
    (void)cap;
    (void)nbr_count;
    (void)nbr_j;
    (void)vol;
    (void)bmat;
    c[SPH_MONITOR_NEG_MIN_DIST] = -min_r / prm->dp;
    c[SPH_MONITOR_MISMATCH] = R(0);
    c[SPH_MONITOR_GRADV] = R(0);
#else
    const mat b_i = sym_load(bmat, n, i);
    const int count = nbr_count[i];
    mat grad_sum = mat_zero();
    for (int k = 0; k < count; ++k) {
        const int j = nbr_j[NBR_AT(i, k)];
        const vec d = hvec_diff(pos, n, i, j);
        const real r = sqrt(vec_dot(d, d));
        min_r = fmin(min_r, r);
        if (r <= R(0)) continue;
        const vec e = vec_scale(d, R(1) / r);
        grad_sum = mat_add_outer(grad_sum, kernel_dw(prm, r) * vol[j],
                                 vec_sub(v_i, vec_load(vel, n, j)), e);
    }
    /* L_i as in acoustic_velocity_terms (003 eq. 20) */
    const mat grad_v = mat_scale(mat_mul(grad_sum, b_i), R(-1));
    real sum_w = R(0), sum_m2 = R(0);
    for (int k = 0; k < count; ++k) {
        const int j = nbr_j[NBR_AT(i, k)];
        const vec d = hvec_diff(pos, n, i, j);
        const real r = sqrt(vec_dot(d, d));
        if (r <= R(0)) continue;
        const vec e = vec_scale(d, R(1) / r);
        const vec mismatch = vec_sub(vec_sub(v_i, vec_load(vel, n, j)), mat_vec(grad_v, d));
        const real rate = vec_dot(mismatch, e) / r;
        const real w = fabs(kernel_dw(prm, r)) * vol[j];
        sum_w += w;
        sum_m2 += w * rate * rate;
    }
    c[SPH_MONITOR_NEG_MIN_DIST] = -min_r / prm->dp;
    c[SPH_MONITOR_MISMATCH] = sum_w > R(0) ? sqrt(sum_m2 / sum_w) : R(0);
    c[SPH_MONITOR_GRADV] = sqrt(mat_ddot(grad_v, grad_v));
#endif
}

#if SPH_OPENCL
/* buffers of monitor_reduce: reads nbr_count:int*n nbr_j:int*pairs pos vel vol bmat; writes
 * partials:small */
__kernel __attribute__((reqd_work_group_size(SPH_WG, 1, 1))) void
monitor_reduce(const int n, const int cap, CONSTANT sph_params *prm,
               GLOBAL const int *restrict nbr_count, GLOBAL const int *restrict nbr_j,
               GLOBAL const hreal *restrict pos, GLOBAL const real *restrict vel,
               GLOBAL const real *restrict vol, GLOBAL const real *restrict bmat,
               GLOBAL real *restrict partials) {
    REDUCE_SCRATCH;
    REDUCE_PARTICLES(MONITOR_NCOMP, MONITOR_NCOMP, MONITOR_NCOMP,
                     monitor_contrib(i, n, cap, prm, nbr_count, nbr_j, pos, vel, vol, bmat, c));
}
#endif
