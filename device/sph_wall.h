/* sph_wall.h — frictionless contact with rigid planar walls.
 *
 * A wall w is the half-space behind the plane through the point P_w with
 * the unit normal n_w pointing into the solid (scene `walls`,
 * docs/scene-format.md).  Particle i at the signed distance
 * d = (x_i - P_w).n_w from the wall's surface feels
 *
 *   a_i = 2 p_w Sigma(|d|) (V_i / m_i) n_w,      |d| < 2h,
 *   p_w = max(0, p_i)  +  c_Z rho0 c0 max(0, -v_n)
 *         +  c_K rho0 c0^2 max(0, 1 - 2 d / dp)^2,
 *
 * with v_n = v_i.n_w and p_i the particle's pressure.  This is the contact force of sph_contact.h,
 * m_i a_i = -2 sum_j p min(dW, 0) V_i V_j e_ij, summed over a continuum of
 * wall particles filling the half-space instead of a layer of discrete
 * ones: the sum of -dW V_j e_ij over the half-space is the gradient of the
 * kernel's integral over it, n_w Sigma(d), where Sigma(d) is the kernel
 * integrated over the wall's plane seen at the distance d,
 *
 *   2D: Sigma(d) = 2 int_0^S W(sqrt(d^2 + s^2)) ds,
 *   3D: Sigma(d) = 2 pi int_d^2h W(r) r dr,          S = sqrt(4h^2 - d^2).
 *
 * The half-space integral of W is 1/2 at d = 0, so int_0^inf Sigma = 1/2
 * and a column of particles dp apart feels, layer by layer, a total force
 * sum_k 2 p Sigma(d_k) V = p dp^(dim-1): the wall pressure p on the
 * column's face, spread over the layers within 2h of the wall as the
 * kernel spreads a boundary force.  There are no wall particles, no
 * neighbour search and no wall buffers; the wall is exactly flat.
 *
 *  - the particle's own pressure: the solid's pair sums miss the
 *    neighbours the wall's side would hold, and the missing pressure part
 *    of -sum (p_i + p_j) dW V_j e (p_j = p_i for the mirror image of the
 *    particle, the wall condition of the Riemann-based SPH of Zhang, Hu &
 *    Adams 2017, 000 ref. [36]) is exactly -2 p_i Sigma(d) n_w: the term
 *    gives it back, so a solid pressed on a wall feels its own stress from
 *    every layer within 2h, not from the penalty of the first layer alone
 *    (without it the first layers of the square Taylor bar collapsed to
 *    0.37 dp apart along the normal).  Only compression counts (no
 *    adhesion).  The deviatoric normal stress is left out: added the same
 *    way (p_i - n.tau_i.n) it made SPH-GNOG-A's elastic bar in
 *    tests/test_walls.py leave faster than it came (restitution 1.016) with
 *    zigzag at the wall (indicator 0.34); with the pressure alone 0.919 and
 *    0.14;
 *  - impedance: rho0 c0 |v_n| is the interface pressure of the acoustic
 *    Riemann problem of the solid against a rigid wall (000 eqs. 11-14 with
 *    the wall's side at rest and of infinite impedance: the interface
 *    velocity is 0), the pressure with which an elastic bar arriving at v_n
 *    is stopped; it acts only on approaching particles (no adhesion), and
 *    its power is -2 c_Z rho0 c0 Sigma V v_n^2 <= 0;
 *  - penalty: a particle whose lattice cell crosses the wall's surface
 *    (d < dp/2) is pushed back with the stiffness K = rho0 c0^2 and the
 *    quadratic ramp of sph_contact.h (the reference code's wall penalty,
 *    reference notes §6.5, also switches on once a particle crosses the
 *    surface); a function of d alone, it is a potential force.
 *
 * The public reference code models the wall by particles with normals
 * (its Taylor bar); this is the same contact law against the exact plane.
 * acoustic_pressure adds it to the acceleration of the velocity update at
 * the half-step position x + dt/2 v (as sph_contact.h).  c_Z, c_K: the
 * `contact` group's impedance and penalty (1, 1 by default). */
#ifndef SPH_WALL_H
#define SPH_WALL_H

#include "sph_vec.h"
#include "sph_smoothing_kernel.h"
#include "sph_contact.h"

/* The 8-point Gauss-Legendre rule on [-1, 1]: nodes +-x_k, weights w_k
 * (exact for the 3D Wendland integrand, a polynomial of degree 7). */
#define WALL_GL_POINTS 4
FN real wall_gl_node(const int k) {
    return k == 0   ? R(0.1834346424956498)
           : k == 1 ? R(0.5255324099163290)
           : k == 2 ? R(0.7966664774136267)
                    : R(0.9602898564975363);
}
FN real wall_gl_weight(const int k) {
    return k == 0   ? R(0.3626837833783620)
           : k == 1 ? R(0.3137066458778873)
           : k == 2 ? R(0.2223810344533745)
                    : R(0.1012285362903763);
}

/* Sigma(d): the kernel integrated over a plane at the distance d >= 0. */
FN real wall_plane_kernel(CONSTANT sph_params *prm, const real d) {
    const real cutoff = prm->cutoff;
    if (d >= cutoff) return R(0);
#if SPH_DIM == 2
    /* 2 int_0^S W(sqrt(d^2 + s^2)) ds, s = S (1 + x) / 2 */
    const real span = sqrt(cutoff * cutoff - d * d);
    real sum = R(0);
    for (int k = 0; k < WALL_GL_POINTS; ++k)
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            const real s = R(0.5) * span * (R(1) + (real)sgn * wall_gl_node(k));
            sum += wall_gl_weight(k) * kernel_w(prm, sqrt(d * d + s * s));
        }
    return span * sum; /* 2 * (span / 2) * sum */
#else
    /* 2 pi int_d^2h W(r) r dr, r = d + (2h - d)(1 + x) / 2 */
    const real span = cutoff - d;
    real sum = R(0);
    for (int k = 0; k < WALL_GL_POINTS; ++k)
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            const real r = d + R(0.5) * span * (R(1) + (real)sgn * wall_gl_node(k));
            sum += wall_gl_weight(k) * kernel_w(prm, r) * r;
        }
    return SPH_PI * span * sum; /* 2 pi * (span / 2) * sum */
#endif
}

/* Wall pressure p_w of a particle at the signed distance d, moving at v_n
 * along the wall's normal, with the pressure p_i. */
FN real wall_pressure(CONSTANT sph_params *prm, CONSTANT sph_params_material *props, const real d,
                      const real v_n, const real p_i) {
    /* the penalty's reach is half a spacing: the wall is the mirror plane
     * of a pair */
    return fmax(p_i, R(0)) + contact_impedance_pressure(prm, props, R(1), v_n) +
           contact_penalty_pressure(prm, props, R(1), d, R(0.5) * prm->dp);
}

/* Acceleration of a particle of material `props` at x (the half-step
 * position) moving at v, with pressure p and volume over mass vm, from
 * every wall of the scene. */
FN vec wall_acceleration(CONSTANT sph_params *prm, CONSTANT sph_params_material *props, const vec x,
                         const vec v, const real p, const real vm) {
    vec a = vec_zero();
    const int count = prm->nwalls;
    for (int w = 0; w < count; ++w) {
        CONSTANT sph_params_wall *wall = &prm->walls[w];
        vec normal = vec_zero();
        real d = R(0);
        UNROLL for (int c = 0; c < SPH_DIM; ++c) {
            normal.c[c] = wall->normal[c];
            d += (x.c[c] - wall->point[c]) * normal.c[c];
        }
        if (d >= prm->cutoff) continue;
        const real p_w = wall_pressure(prm, props, d, vec_dot(v, normal), p);
        a = vec_axpy(a, R(2) * p_w * wall_plane_kernel(prm, fabs(d)) * vm, normal);
    }
    return a;
}

/* The wall's share of particle i's continuity sum, sum_j u_ij dW V_j
 * (003 eq. 15), at the position x moving at v with the pressure p.  The
 * mirror image that gives the pressure term above its p_i also moves: at
 * v - 2 v_n n_w, so u_ij = 2 v_n over the mirrored half-space, and
 * sum_j e_ij dW V_j = grad_x of the kernel's integral over it = -Sigma(d) n_w:
 *
 *   sum = -2 v_n Sigma(|d|).
 *
 * With it the wall's pressure work 2 p Sigma V v_n and the change of the
 * particle's internal energy (p / rho^2) m drho/dt cancel: without it a
 * compressed foot kept its pressure while leaving the wall and pushed
 * itself off with energy the impact never stored (round Taylor bar,
 * R/dp = 6: the bar at rest at 30 us left the wall at 53 m/s, the total
 * energy rising 2.8 J).  It counts where the pressure term acts (p > 0) and
 * for approaching particles (a compression, whose work -2 p Sigma V v_n is
 * then <= 0): a particle in tension leaving the wall has no wall term in
 * either equation. */
FN real wall_divergence(CONSTANT sph_params *prm, const vec x, const vec v, const real p) {
    real sum = R(0);
    const int count = prm->nwalls;
    for (int w = 0; w < count; ++w) {
        CONSTANT sph_params_wall *wall = &prm->walls[w];
        real d = R(0), v_n = R(0);
        UNROLL for (int c = 0; c < SPH_DIM; ++c) {
            d += (x.c[c] - wall->point[c]) * wall->normal[c];
            v_n += v.c[c] * wall->normal[c];
        }
        if (d >= prm->cutoff || !(p > R(0) || v_n < R(0))) continue;
        sum -= R(2) * v_n * wall_plane_kernel(prm, fabs(d));
    }
    return sum;
}

#endif
