/* sph_smoothing_kernel.h — smoothing kernels W(r, h) and dW/dr.
 *
 * Convention (reference notes §5): q = r/h, W = alpha_d f(q),
 * dW/dr = alpha_d f'(q) / h, support 2h.  The papers (000, 003) use the
 * Wendland C2 kernel with h = 1.3 dp, cut-off 2.6 dp.
 */
#ifndef SPH_SMOOTHING_KERNEL_H
#define SPH_SMOOTHING_KERNEL_H
#include "sph_prelude.h"

#define SPH_PI R(3.14159265358979323846)

/* Wendland C2: f(q) = (1 - q/2)^4 (1 + 2q) on [0, 2];
 * alpha_2D = 7 / (4 pi h^2), alpha_3D = 21 / (16 pi h^3). */
FN real wendland_c2_alpha(const real h) {
#if SPH_DIM == 2
    return R(7) / (R(4) * SPH_PI * h * h);
#else
    return R(21) / (R(16) * SPH_PI * h * h * h);
#endif
}
FN real wendland_c2_f(const real q) {
    if (q >= R(2)) return R(0);
    const real t = R(1) - R(0.5) * q;
    const real t2 = t * t;
    return t2 * t2 * (R(1) + R(2) * q);
}
/* f'(q) = (5/8) q (q - 2)^3 = -5 q (1 - q/2)^3 */
FN real wendland_c2_df(const real q) {
    if (q >= R(2)) return R(0);
    const real t = R(1) - R(0.5) * q;
    return R(-5) * q * t * t * t;
}

FN real kernel_w(CONSTANT real *prm, const real r) {
    const real h = prm[PRM_H];
    (void)prm;
    switch (RUNTIME_KERNEL) {
    default:
        return wendland_c2_alpha(h) * wendland_c2_f(r / h);
    }
}
/* dW/dr (<= 0) */
FN real kernel_dw(CONSTANT real *prm, const real r) {
    const real h = prm[PRM_H];
    switch (RUNTIME_KERNEL) {
    default:
        return wendland_c2_alpha(h) * wendland_c2_df(r / h) / h;
    }
}

#endif
