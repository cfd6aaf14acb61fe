/* sph_rotation.h — rotation of the accumulated shear acceleration.
 *
 * SPH-ENOG-A (003 §4.1): the accumulated shear acceleration is carried along
 * with the local rigid rotation, a^s <- R a^s + da^s (eq. 34/42), where R is
 * the exponential of the spin over one acoustic step given by Rodrigues'
 * formula (eqs. 38-40).  Eq. 41 averages R over all particles of a body so
 * that linear momentum stays exact.
 */
#ifndef SPH_ROTATION_H
#define SPH_ROTATION_H
#include "sph_vec.h"

/* R = I + sin(|w| dt) W^ + (1 - cos(|w| dt)) W^2,  W^ = Omega/|w|,
 * |w| = sqrt(-tr(Omega^2)/2)   (003 eqs. 38-40).
 * |w| is clamped to 0 when round-off makes -tr(Omega^2) negative, and R = I
 * when |w| dt is below machine epsilon (avoids 0/0). */
FN mat rodrigues(const mat omega, const real dt) {
    const mat omega2 = mat_mul(omega, omega);
    const real w2 = -R(0.5) * mat_trace(omega2);
    const real w = w2 > R(0) ? sqrt(w2) : R(0);
    const real theta = w * dt;
    if (theta < REAL_EPSILON) return mat_identity();
    /* s = sin(theta)/w and c = (1 - cos(theta))/w^2; an acoustic step turns
     * a particle by ~1e-3 rad, where the Taylor series (first omitted term
     * below theta^8/9! ~ 3e-22 relative for theta < 0.01) is exact to
     * rounding and much cheaper than sin and cos */
    real s, c;
    if (theta < R(0.01)) {
        const real t2 = theta * theta;
        /* (times the reciprocals, not six divisions per particle and substep:
         * 2-3 % of the 2D SPH-ENOG-A substep; the rounded 1/6, 1/20, ...
         * change the correction terms, ~theta^2 of the result, in their last
         * bit) */
        s = dt *
            (R(1) - t2 * R(1.0 / 6.0) * (R(1) - t2 * R(1.0 / 20.0) * (R(1) - t2 * R(1.0 / 42.0))));
        c = R(0.5) * dt * dt *
            (R(1) - t2 * R(1.0 / 12.0) * (R(1) - t2 * R(1.0 / 30.0) * (R(1) - t2 * R(1.0 / 56.0))));
    } else {
        s = sin(theta) / w;
        c = (R(1) - cos(theta)) / (w * w);
    }
    return mat_add(mat_identity(), mat_add(mat_scale(omega, s), mat_scale(omega2, c)));
}

#endif
