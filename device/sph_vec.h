/* sph_vec.h — dimension-generic small vectors and matrices.
 *
 * Plain structs with fixed-size arrays: the loops over SPH_DIM unroll, the
 * structs stay in registers on a GPU and both compilers see ordinary C.
 * Field storage is structure-of-arrays: component c of particle i lives at
 * buf[c * n + i]; vec_load/vec_store do the (de)interleaving.
 */
#ifndef SPH_VEC_H
#define SPH_VEC_H
#include "sph_prelude.h"

typedef struct {
    real c[SPH_DIM];
} vec;
typedef struct {
    real m[SPH_DIM][SPH_DIM]; /* m[row][col] */
} mat;

FN vec vec_zero(void) {
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) r.c[a] = R(0);
    return r;
}
FN vec vec_load(GLOBAL const real *buf, const int n, const int i) {
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) r.c[a] = buf[a * n + i];
    return r;
}
FN void vec_store(GLOBAL real *buf, const int n, const int i, const vec v) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) buf[a * n + i] = v.c[a];
}
/* History fields (hreal, sph_prelude.h): loads round to real, updates add a
 * real increment in hreal, differences of two particles are taken in hreal
 * (a relative position keeps the digits its absolute values would lose). */
FN vec hvec_load(GLOBAL const hreal *buf, const int n, const int i) {
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) r.c[a] = (real)buf[a * n + i];
    return r;
}
FN void hvec_store(GLOBAL hreal *buf, const int n, const int i, const vec v) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) buf[a * n + i] = (hreal)v.c[a];
}
/* buf_i += dv */
FN void hvec_add_store(GLOBAL hreal *buf, const int n, const int i, const vec dv) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) buf[a * n + i] += (hreal)dv.c[a];
}
/* buf_i - buf_j */
FN vec hvec_diff(GLOBAL const hreal *buf, const int n, const int i, const int j) {
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) r.c[a] = (real)(buf[a * n + i] - buf[a * n + j]);
    return r;
}
FN vec vec_add(const vec x, const vec y) {
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) r.c[a] = x.c[a] + y.c[a];
    return r;
}
FN vec vec_sub(const vec x, const vec y) {
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) r.c[a] = x.c[a] - y.c[a];
    return r;
}
FN vec vec_scale(const vec x, const real s) {
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) r.c[a] = x.c[a] * s;
    return r;
}
/* x + s*y */
FN vec vec_axpy(const vec x, const real s, const vec y) {
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) r.c[a] = x.c[a] + s * y.c[a];
    return r;
}
FN real vec_dot(const vec x, const vec y) {
    real s = R(0);
    UNROLL for (int a = 0; a < SPH_DIM; ++a) s += x.c[a] * y.c[a];
    return s;
}

FN mat mat_zero(void) {
    mat r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) r.m[a][b] =
        R(0);
    return r;
}
FN mat mat_identity(void) {
    mat r = mat_zero();
    UNROLL for (int a = 0; a < SPH_DIM; ++a) r.m[a][a] = R(1);
    return r;
}
FN mat mat_add(const mat x, const mat y) {
    mat r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) r.m[a][b] =
        x.m[a][b] + y.m[a][b];
    return r;
}
FN mat mat_scale(const mat x, const real s) {
    mat r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) r.m[a][b] =
        x.m[a][b] * s;
    return r;
}
FN mat mat_transpose(const mat x) {
    mat r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) r.m[a][b] =
        x.m[b][a];
    return r;
}
FN mat mat_mul(const mat x, const mat y) {
    mat r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) {
        real s = R(0);
        UNROLL for (int k = 0; k < SPH_DIM; ++k) s += x.m[a][k] * y.m[k][b];
        r.m[a][b] = s;
    }
    return r;
}
FN vec mat_vec(const mat x, const vec v) {
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        real s = R(0);
        UNROLL for (int b = 0; b < SPH_DIM; ++b) s += x.m[a][b] * v.c[b];
        r.c[a] = s;
    }
    return r;
}
/* x + s * (u (x) w), the outer product u_a w_b */
FN mat mat_add_outer(const mat x, const real s, const vec u, const vec w) {
    mat r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) r.m[a][b] =
        x.m[a][b] + s * u.c[a] * w.c[b];
    return r;
}
FN real mat_trace(const mat x) {
    real s = R(0);
    UNROLL for (int a = 0; a < SPH_DIM; ++a) s += x.m[a][a];
    return s;
}
/* Double contraction x : y */
FN real mat_ddot(const mat x, const mat y) {
    real s = R(0);
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) s +=
        x.m[a][b] * y.m[a][b];
    return s;
}
FN real mat_det(const mat x) {
#if SPH_DIM == 1
    return x.m[0][0];
#elif SPH_DIM == 2
    return x.m[0][0] * x.m[1][1] - x.m[0][1] * x.m[1][0];
#else
    return x.m[0][0] * (x.m[1][1] * x.m[2][2] - x.m[1][2] * x.m[2][1]) -
           x.m[0][1] * (x.m[1][0] * x.m[2][2] - x.m[1][2] * x.m[2][0]) +
           x.m[0][2] * (x.m[1][0] * x.m[2][1] - x.m[1][1] * x.m[2][0]);
#endif
}
/* Inverse by the adjugate; the caller guarantees det != 0. */
FN mat mat_inverse(const mat x) {
    mat r;
    const real inv_det = R(1) / mat_det(x);
#if SPH_DIM == 1
    r.m[0][0] = inv_det;
#elif SPH_DIM == 2
    r.m[0][0] = x.m[1][1] * inv_det;
    r.m[0][1] = -x.m[0][1] * inv_det;
    r.m[1][0] = -x.m[1][0] * inv_det;
    r.m[1][1] = x.m[0][0] * inv_det;
#else
    r.m[0][0] = (x.m[1][1] * x.m[2][2] - x.m[1][2] * x.m[2][1]) * inv_det;
    r.m[0][1] = (x.m[0][2] * x.m[2][1] - x.m[0][1] * x.m[2][2]) * inv_det;
    r.m[0][2] = (x.m[0][1] * x.m[1][2] - x.m[0][2] * x.m[1][1]) * inv_det;
    r.m[1][0] = (x.m[1][2] * x.m[2][0] - x.m[1][0] * x.m[2][2]) * inv_det;
    r.m[1][1] = (x.m[0][0] * x.m[2][2] - x.m[0][2] * x.m[2][0]) * inv_det;
    r.m[1][2] = (x.m[0][2] * x.m[1][0] - x.m[0][0] * x.m[1][2]) * inv_det;
    r.m[2][0] = (x.m[1][0] * x.m[2][1] - x.m[1][1] * x.m[2][0]) * inv_det;
    r.m[2][1] = (x.m[0][1] * x.m[2][0] - x.m[0][0] * x.m[2][1]) * inv_det;
    r.m[2][2] = (x.m[0][0] * x.m[1][1] - x.m[0][1] * x.m[1][0]) * inv_det;
#endif
    return r;
}

/* Symmetric tensors are stored as NSYM components: 2D (xx, xy, yy),
 * 3D (xx, xy, xz, yy, yz, zz). */
/* Full d x d tensor, component (a, b) at (a * SPH_DIM + b) * n + i. */
FN mat mat_load(GLOBAL const real *buf, const int n, const int i) {
    mat r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) r.m[a][b] =
        buf[(a * SPH_DIM + b) * n + i];
    return r;
}
FN void mat_store(GLOBAL real *buf, const int n, const int i, const mat x) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b)
        buf[(a * SPH_DIM + b) * n + i] = x.m[a][b];
}

FN int sym_index(const int a, const int b) {
    const int lo = a < b ? a : b, hi = a < b ? b : a;
#if SPH_DIM == 1
    (void)lo;
    (void)hi;
    return 0;
#elif SPH_DIM == 2
    return lo + hi;
#else
    return lo == 0 ? hi : (lo == 1 ? 2 + hi : 5);
#endif
}
FN mat sym_load(GLOBAL const real *buf, const int n, const int i) {
    mat r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) r.m[a][b] =
        buf[sym_index(a, b) * n + i];
    return r;
}
FN void sym_store(GLOBAL real *buf, const int n, const int i, const mat x) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = a; b < SPH_DIM; ++b)
        buf[sym_index(a, b) * n + i] = x.m[a][b];
}

/* buf_i <- rot (buf_i + pre) + post, the products summed in hreal; returns
 * the new value (the turned part rounded to real, then post added).  Turns an accumulated
 * acceleration with the body (003 eqs. 34, 42, 47) without rounding it to real, and adds what
 * follows the turn in the same pass. */
FN vec hvec_rotate(GLOBAL hreal *buf, const int n, const int i, const mat rot, const vec pre,
                   const vec post) {
    hreal s[SPH_DIM];
    UNROLL for (int a = 0; a < SPH_DIM; ++a) s[a] = buf[a * n + i] + (hreal)pre.c[a];
    vec r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        hreal t = (hreal)0;
        UNROLL for (int b = 0; b < SPH_DIM; ++b) t += (hreal)rot.m[a][b] * s[b];
        buf[a * n + i] = t + (hreal)post.c[a];
        r.c[a] = (real)t + post.c[a];
    }
    return r;
}
FN mat hsym_load(GLOBAL const hreal *buf, const int n, const int i) {
    mat r;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = 0; b < SPH_DIM; ++b) r.m[a][b] =
        (real)buf[sym_index(a, b) * n + i];
    return r;
}
FN void hsym_store(GLOBAL hreal *buf, const int n, const int i, const mat x) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = a; b < SPH_DIM; ++b)
        buf[sym_index(a, b) * n + i] = (hreal)x.m[a][b];
}
/* buf_i += dx (dx symmetric) */
FN void hsym_add_store(GLOBAL hreal *buf, const int n, const int i, const mat dx) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = a; b < SPH_DIM; ++b)
        buf[sym_index(a, b) * n + i] += (hreal)dx.m[a][b];
}
/* buf_i *= s */
FN void hsym_scale_store(GLOBAL hreal *buf, const int n, const int i, const real s) {
    UNROLL for (int a = 0; a < SPH_DIM; ++a) UNROLL for (int b = a; b < SPH_DIM; ++b)
        buf[sym_index(a, b) * n + i] *= (hreal)s;
}

/* Spin tensor Omega = (L - L^T)/2 <-> its independent components
 * 2D: w = Omega_yx;  3D: (Omega_zy, Omega_xz, Omega_yx) = the angular
 * velocity vector of a rigid rotation. */
FN void spin_components(const mat omega, real w[NSPIN]) {
#if SPH_DIM == 1
    (void)omega; /* a line has no spin */
    (void)w;
#elif SPH_DIM == 2
    w[0] = omega.m[1][0];
#else
    w[0] = omega.m[2][1];
    w[1] = omega.m[0][2];
    w[2] = omega.m[1][0];
#endif
}
FN mat spin_matrix(const real w[NSPIN]) {
    mat r = mat_zero();
#if SPH_DIM == 1
    (void)w;
#elif SPH_DIM == 2
    r.m[1][0] = w[0];
    r.m[0][1] = -w[0];
#else
    r.m[2][1] = w[0];
    r.m[1][2] = -w[0];
    r.m[0][2] = w[1];
    r.m[2][0] = -w[1];
    r.m[1][0] = w[2];
    r.m[0][1] = -w[2];
#endif
    return r;
}

/* The scene's gravity g (sph_params.h: 0 beyond the dimension), added to
 * the solids' acceleration (verlet_advance, the step clock's signal) and to
 * the fluids' momentum rate (eulerian_step.cl). */
FN vec gravity_of(CONSTANT sph_params *prm) {
    vec g = vec_zero();
    UNROLL for (int a = 0; a < SPH_DIM; ++a) g.c[a] = prm->gravity[a];
    return g;
}

#endif
