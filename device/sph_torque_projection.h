/* sph_torque_projection.h — the accumulated ENOG shear acceleration kept
 * free of net torque over each body (method.torque_projection, SPH-ENOG-A).
 *
 * Why.  The shear acceleration of SPH-ENOG-A is a sum of increments, each a
 * set of central pair forces (003 eq. 28) and so free of net torque in the
 * configuration it was computed in; 003 eq. 42 turns the sum with the body by
 * the mean rotation R-bar.  Once the body has deformed since an increment
 * was added, its pair forces are no longer along the pairs, and the sum
 * keeps the net torque that the deformation gave it.  Rigid motion adds no
 * increment that could take it back (e.v_ij = 0), so the torque stays:
 * on the spinning cube (003 §5.1.4) it builds up in the first 0.04 s of
 * centrifugal stretching and then spins the cube up at a constant rate
 * (cases/spinning_cube_3d/README.md).  Internal forces have no net torque,
 * so this removes, at every substep, the rigid angular acceleration that
 * carries the sum's net torque:
 *
 *   a^s_i <- Rbar (a^s_i + da^s_i) - alpha x (x_i - c),   I alpha = tau,
 *   tau = sum_i m_i (x_i - c) x Rbar (a^s_i + da^s_i),
 *
 * with x the substep's kick positions x + dt/2 v (position Verlet changes
 * the angular momentum by dt sum m x^{n+1/2} x a exactly, 000 eqs. 27-29),
 * c their centre of mass and I their inertia tensor (2D: sum m |x - c|^2),
 * per body.  sum_i m_i alpha x (x_i - c) = 0, so linear momentum is
 * untouched.
 *
 * How.  The substep reduction (reduction.cl) sums, per body, the moments
 * below of y = x^{n+1}, w = v^{n+1} and b = a^s + da^s as the velocity pass
 * leaves them; acoustic_pressure of the next substep forms tau from them
 * with that substep's Rbar and dt, x + dt/2 v being y + dt/2 w, exactly.
 * The inertia is that of y (not of y + dt/2 w): it sizes alpha only, whose
 * torque then misses tau by the relative change of I over half a step
 * (~1e-3 of a correction that is itself ~1e-4 of the angular momentum per
 * step on the cube).
 */
#ifndef SPH_TORQUE_PROJECTION_H
#define SPH_TORQUE_PROJECTION_H
#include "sph_vec.h"

/* A body's moments in the substep sums, from its offset (reduction.cl). */
#define TORQUE_Y     0                               /* sum m y (d) */
#define TORQUE_W     SPH_DIM                         /* sum m w (d) */
#define TORQUE_B     (2 * SPH_DIM)                   /* sum m b (d) */
#define TORQUE_M     (3 * SPH_DIM)                   /* sum m */
#define TORQUE_YB    (3 * SPH_DIM + 1)               /* sum m y (x) b (d x d) */
#define TORQUE_WB    (TORQUE_YB + SPH_DIM * SPH_DIM) /* sum m w (x) b (d x d) */
#define TORQUE_YY    (TORQUE_WB + SPH_DIM * SPH_DIM) /* sum m y (x) y (NSYM) */
#define TORQUE_NCOMP (TORQUE_YY + NSYM)              /* 18 in 2D, 34 in 3D */
/* the host sizes its buffers by SPH_TORQUE_NCOMP (sph_constants.h) */
typedef char torque_ncomp_matches_host[TORQUE_NCOMP == SPH_TORQUE_NCOMP(SPH_DIM) ? 1 : -1];

/* Where body b's moments start in the substep sums: after max |v|^2 and
 * the bodies' summed Rodrigues matrices (reduction.cl, substep_contrib). */
FN int torque_offset(CONSTANT sph_params *prm, const int b) {
    (void)prm;
    return 1 + RUNTIME_NBODIES * SPH_DIM * SPH_DIM + b * TORQUE_NCOMP;
}

/* Particle i's moments into c (TORQUE_NCOMP values). */
FN void torque_moments(const real m, const vec y, const vec w, const vec b, real *c) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        c[TORQUE_Y + a] = m * y.c[a];
        c[TORQUE_W + a] = m * w.c[a];
        c[TORQUE_B + a] = m * b.c[a];
        UNROLL for (int e = 0; e < SPH_DIM; ++e) {
            c[TORQUE_YB + a * SPH_DIM + e] = m * y.c[a] * b.c[e];
            c[TORQUE_WB + a * SPH_DIM + e] = m * w.c[a] * b.c[e];
        }
        UNROLL for (int e = a; e < SPH_DIM; ++e) c[TORQUE_YY + sym_index(a, e)] =
            m * y.c[a] * y.c[e];
    }
    c[TORQUE_M] = m;
}

/* The rigid field alpha x (x - c) that carries the net torque of the body's
 * turned sum Rbar b at the kick positions y + dt/2 w: alpha (NSPIN, the
 * angular-velocity components of spin_components) and c.  alpha = 0 for a
 * body with no moments yet (the first substep) or no inertia to speak of. */
FN void torque_field(GLOBAL const real *s, const mat rbar, const real dt, real alpha[NSPIN],
                     vec *centre) {
    UNROLL for (int a = 0; a < NSPIN; ++a) alpha[a] = R(0);
    *centre = vec_zero();
    const real m = s[TORQUE_M];
    if (!(m > R(0))) return;
    const real half_dt = R(0.5) * dt;
    vec c, c_y, mb;
    mat k, yy;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        c.c[a] = (s[TORQUE_Y + a] + half_dt * s[TORQUE_W + a]) / m;
        c_y.c[a] = s[TORQUE_Y + a] / m;
        mb.c[a] = s[TORQUE_B + a];
    }
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        UNROLL for (int e = 0; e < SPH_DIM; ++e) {
            /* sum m x (x) b at the kick positions */
            k.m[a][e] = s[TORQUE_YB + a * SPH_DIM + e] + half_dt * s[TORQUE_WB + a * SPH_DIM + e];
            yy.m[a][e] = s[TORQUE_YY + sym_index(a, e)] - m * c_y.c[a] * c_y.c[e];
        }
    }
    *centre = c;
    /* A = sum m (x - c) (x) Rbar b = K Rbar^T - c (x) Rbar sum m b; its
     * antisymmetric part is the torque: tau = axial(A^T - A) */
    const vec rmb = mat_vec(rbar, mb);
    mat a_mat = mat_mul(k, mat_transpose(rbar));
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int e = 0; e < SPH_DIM; ++e)
        a_mat.m[a][e] -= c.c[a] * rmb.c[e];
    real tau[NSPIN];
    spin_components(mat_add(mat_transpose(a_mat), mat_scale(a_mat, R(-1))), tau);
    const real trace = mat_trace(yy);
#if SPH_DIM == 2
    /* I = sum m |x - c|^2 */
    if (trace > R(0)) alpha[0] = tau[0] / trace;
#else
    /* I = tr(S) 1 - S, S = sum m (x - c) (x) (x - c) */
    const mat inertia = mat_add(mat_scale(mat_identity(), trace), mat_scale(yy, R(-1)));
    const real det = mat_det(inertia);
    if (!(det > R(1e-12) * trace * trace * trace)) return;
    const mat inv = mat_inverse(inertia);
    UNROLL for (int a = 0; a < NSPIN; ++a) {
        real t = R(0);
        UNROLL for (int e = 0; e < NSPIN; ++e) t += inv.m[a][e] * tau[e];
        alpha[a] = t;
    }
#endif
}

/* alpha x (x - c) at x */
FN vec torque_field_at(const real alpha[NSPIN], const vec centre, const vec x) {
    return mat_vec(spin_matrix(alpha), vec_sub(x, centre));
}

#endif
