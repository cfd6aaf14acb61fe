/* sph_smoothing_kernel.h — smoothing kernels W(r, h) and dW/dr.
 *
 * Convention (reference notes §5): q = r/h, W = alpha_d f(q),
 * dW/dr = alpha_d f'(q) / h, support 2h for every kernel (the host sets the
 * neighbour cut-off prm->cutoff = 2h whatever the kernel).  The papers
 * (000, 003) use the Wendland C2 kernel with h = 1.3 dp, cut-off 2.6 dp;
 * 004 adds the truncated Laguerre-Gauss and Laguerre-Wendland kernels.
 * Selected per scene by method.kernel (KERNEL_*, RUNTIME_KERNEL): a
 * compile-time constant in OpenCL, so the switches below fold away there.
 */
#ifndef SPH_SMOOTHING_KERNEL_H
#define SPH_SMOOTHING_KERNEL_H
#include "sph_prelude.h"

#define SPH_PI R(3.14159265358979323846)

/* Wendland C2: f(q) = (1 - q/2)^4 (1 + 2q) on [0, 2];
 * alpha_1D = 3 / (4 h), alpha_2D = 7 / (4 pi h^2), alpha_3D = 21 / (16 pi h^3). */
FN real wendland_c2_alpha(const real h) {
#if SPH_DIM == 1
    return R(3) / (R(4) * h);
#elif SPH_DIM == 2
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

/* Truncated Laguerre-Gauss (004 eq. 8; the printed "s^2/2" is a typo for
 * s^2, reference notes §5 and seed digest §3.1):
 * f(q) = (1 - q^2 + q^4/6) e^(-q^2) for q <= 2, 0 beyond;
 * alpha_1D = 8 / (5 sqrt(pi) h), alpha_2D = 3 / (pi h^2),
 * alpha_3D = 8 / (pi^(3/2) h^3).
 * Truncated at 2h WITHOUT renormalisation, as in 004 and SPHinXsys: the
 * alphas normalise the untruncated kernel, so int W dV over the support is
 * 0.99808 in 1D, 1 - e^-4 = 0.98168 in 2D and erf(2) - 44 e^-4 / (3 sqrt(pi)) = 0.84376 in
 * 3D, and W jumps from alpha f(2) = -alpha e^-4 / 3 to 0 at r = 2h.  (The
 * kernel correction matrix B, 003 eq. 21, absorbs the missing moment.) */
FN real laguerre_gauss_alpha(const real h) {
#if SPH_DIM == 1
    /* sqrt(pi) = 1.772453850905516 */
    return R(8) / (R(5) * R(1.7724538509055160273) * h);
#elif SPH_DIM == 2
    return R(3) / (SPH_PI * h * h);
#else
    /* pi^(3/2) = 5.568327996831708 */
    return R(8) / (R(5.568327996831707845) * h * h * h);
#endif
}
FN real laguerre_gauss_f(const real q) {
    if (q > R(2)) return R(0);
    const real q2 = q * q;
    return (R(1) - q2 + q2 * q2 / R(6)) * exp(-q2);
}
/* f'(q) = (-q^5/3 + 8 q^3/3 - 4 q) e^(-q^2) (reference notes §5) */
FN real laguerre_gauss_df(const real q) {
    if (q > R(2)) return R(0);
    const real q2 = q * q;
    return q * (-q2 * q2 / R(3) + R(8) * q2 / R(3) - R(4)) * exp(-q2);
}

/* Laguerre-Wendland (Litvinov, Hu & Adams 2015, J. Comput. Phys. 301, the
 * 4th-order kernel revisited in 004 §2.2; 004 does not print it).  The paper
 * text was not available here: the form is the first author's own
 * implementation (lammps-sph, USER-SDPD "laguerrewendland4"), on unit
 * support x = r / r_c:
 *   w(x) = (1 - x)^6 (1 + 6x + 35x^2/3) (1 - 9x^2 + 27x^4/2),
 *   sigma_2D = 1287 / (47 pi), sigma_3D = 9009 / (64 pi),
 * i.e. the Wendland C4 function times the Laguerre factor 1 - s^2 + s^4/6 of
 * eq. 8 in s = 3x.  Rescaled to support 2h (x = q/2, W = sigma w / (2h)^d):
 *   f(q) = t^6 (1 + 3q + 35q^2/12) (1 - 9q^2/4 + 27q^4/32),  t = 1 - q/2,
 *   alpha_2D = 1287 / (188 pi h^2), alpha_3D = 9009 / (512 pi h^3);
 *   alpha_1D = 3861 / (2848 h) (int_0^2 f dq = 1424 / 3861, exact).
 * (Normalisation checked by quadrature in tests/test_physics_units.c.) */
FN real laguerre_wendland_alpha(const real h) {
#if SPH_DIM == 1
    return R(3861) / (R(2848) * h);
#elif SPH_DIM == 2
    return R(1287) / (R(188) * SPH_PI * h * h);
#else
    return R(9009) / (R(512) * SPH_PI * h * h * h);
#endif
}
FN real laguerre_wendland_f(const real q) {
    if (q >= R(2)) return R(0);
    const real t = R(1) - R(0.5) * q;
    const real t2 = t * t;
    const real q2 = q * q;
    const real wc4 = t2 * t2 * t2 * (R(1) + R(3) * q + R(35) / R(12) * q2);
    return wc4 * (R(1) - R(2.25) * q2 + R(0.84375) * q2 * q2);
}
/* f'(q) = t^5 [ -(14/3) q (1 + 5q/2) L(q) + t (1 + 3q + 35q^2/12) L'(q) ],
 * L = 1 - 9q^2/4 + 27q^4/32, L' = -9q/2 + 27q^3/8; the first term uses
 * the Wendland C4 derivative d/dx[(1-x)^6 (1+6x+35x^2/3)] = -(56/3) x (1+5x)
 * (1-x)^5 with dx/dq = 1/2. */
FN real laguerre_wendland_df(const real q) {
    if (q >= R(2)) return R(0);
    const real t = R(1) - R(0.5) * q;
    const real t2 = t * t;
    const real q2 = q * q;
    const real lag = R(1) - R(2.25) * q2 + R(0.84375) * q2 * q2;
    const real dlag = q * (R(-4.5) + R(3.375) * q2);
    const real poly = R(1) + R(3) * q + R(35) / R(12) * q2;
    return t2 * t2 * t * (R(-14) / R(3) * q * (R(1) + R(2.5) * q) * lag + t * poly * dlag);
}

/* Cubic B-spline (Monaghan & Lattanzio 1985; reference notes §5):
 * f = 1 - (3/2) q^2 (1 - q/2) for q < 1, (2 - q)^3 / 4 for 1 <= q < 2;
 * alpha_1D = 2 / (3 h), alpha_2D = 10 / (7 pi h^2), alpha_3D = 1 / (pi h^3). */
FN real cubic_bspline_alpha(const real h) {
#if SPH_DIM == 1
    return R(2) / (R(3) * h);
#elif SPH_DIM == 2
    return R(10) / (R(7) * SPH_PI * h * h);
#else
    return R(1) / (SPH_PI * h * h * h);
#endif
}
FN real cubic_bspline_f(const real q) {
    if (q >= R(2)) return R(0);
    if (q < R(1)) return R(1) - R(1.5) * q * q * (R(1) - R(0.5) * q);
    const real t = R(2) - q;
    return R(0.25) * t * t * t;
}
/* f' = -3q + (9/4) q^2 for q < 1, -(3/4)(2 - q)^2 for 1 <= q < 2 */
FN real cubic_bspline_df(const real q) {
    if (q >= R(2)) return R(0);
    if (q < R(1)) return q * (R(-3) + R(2.25) * q);
    const real t = R(2) - q;
    return R(-0.75) * t * t;
}

FN real kernel_w(CONSTANT sph_params *prm, const real r) {
    const real h = prm->h;
    (void)prm;
    switch (RUNTIME_KERNEL) {
    case KERNEL_LAGUERRE_GAUSS:
        return laguerre_gauss_alpha(h) * laguerre_gauss_f(r / h);
    case KERNEL_LAGUERRE_WENDLAND:
        return laguerre_wendland_alpha(h) * laguerre_wendland_f(r / h);
    case KERNEL_CUBIC_BSPLINE:
        return cubic_bspline_alpha(h) * cubic_bspline_f(r / h);
    case KERNEL_WENDLAND_C2:
    default:
        return wendland_c2_alpha(h) * wendland_c2_f(r / h);
    }
}
/* The kernel gradient's constants, taken once where dW/dr is evaluated for
 * many pairs (the neighbour build): alpha_d(h) and the kernel.  Per pair
 * there remain r / h and the final / h, the same operations as before in
 * the same order, so the values are bit-identical; folding 1 / h into
 * the constant or into q would save those two divisions too, but moves the
 * single-precision Laguerre-Gauss dW/dr(2h) by 3.5 ulp, beyond what
 * test_physics_units accepts. */
typedef struct {
    real h;
    real alpha; /* alpha_d(h) */
    int kind;   /* KERNEL_* (RUNTIME_KERNEL: a constant in OpenCL) */
} kernel_gradient;

FN kernel_gradient kernel_gradient_of(CONSTANT sph_params *prm) {
    kernel_gradient g;
    g.h = prm->h;
    g.kind = RUNTIME_KERNEL;
    switch (g.kind) {
    case KERNEL_LAGUERRE_GAUSS:
        g.alpha = laguerre_gauss_alpha(g.h);
        break;
    case KERNEL_LAGUERRE_WENDLAND:
        g.alpha = laguerre_wendland_alpha(g.h);
        break;
    case KERNEL_CUBIC_BSPLINE:
        g.alpha = cubic_bspline_alpha(g.h);
        break;
    case KERNEL_WENDLAND_C2:
    default:
        g.alpha = wendland_c2_alpha(g.h);
        break;
    }
    return g;
}

/* dW/dr at r (<= 0 for the monotonic kernels; the Laguerre kernels change
 * sign) */
FN real kernel_dw_at(const kernel_gradient g, const real r) {
    switch (g.kind) {
    case KERNEL_LAGUERRE_GAUSS:
        return g.alpha * laguerre_gauss_df(r / g.h) / g.h;
    case KERNEL_LAGUERRE_WENDLAND:
        return g.alpha * laguerre_wendland_df(r / g.h) / g.h;
    case KERNEL_CUBIC_BSPLINE:
        return g.alpha * cubic_bspline_df(r / g.h) / g.h;
    case KERNEL_WENDLAND_C2:
    default:
        return g.alpha * wendland_c2_df(r / g.h) / g.h;
    }
}

/* dW/dr for one pair */
FN real kernel_dw(CONSTANT sph_params *prm, const real r) {
    return kernel_dw_at(kernel_gradient_of(prm), r);
}

#endif
