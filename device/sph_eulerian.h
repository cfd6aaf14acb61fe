/* sph_eulerian.h — the interface state of a particle pair in extended
 * Eulerian SPH (004 §3.1): the equations of state and the two Riemann
 * solvers with their dissipation limiters.
 *
 * Conventions (as the public reference code, eulerian-sph-reference.md §1):
 * e_ij points from j to i; the left state is particle i, the right state j,
 * and the normal velocities are u_l = -e_ij . v_i, u_r = -e_ij . v_j, so
 * u_l - u_r > 0 when the pair approaches.  The interface state (rho*, v*,
 * p*, E*) enters the fluxes of eq. 14 (eulerian_step.cl).
 *
 * Every function gives the same state when called from j's side (e_ij and
 * u flipped, left and right swapped) bit for bit: sums of two terms are
 * commutative, and the negations and swaps are exact in IEEE arithmetic
 * (with contraction off, sph_prelude.h / -ffp-contract=off).  The pair
 * fluxes are therefore exactly antisymmetric and the sums of mass, momentum
 * and energy change only by the rounding of their accumulation.
 */
#ifndef SPH_EULERIAN_H
#define SPH_EULERIAN_H
#include "sph_riemann.h"
#include "sph_vec.h"

/* One side of a pair. */
typedef struct {
    real rho, p, u; /* density, pressure, normal velocity -e_ij . v */
    vec v;
    real energy; /* total energy per unit volume (compressible), else 0 */
    real c;      /* sound speed (compressible: the particle's own), else 0 */
} fluid_side;

typedef struct {
    real rho, p;
    vec v;
    real energy; /* total energy per unit volume (compressible) */
} fluid_state;

/* The momentum flux of an interface state along e (eq. 14's
 * rho* v* (v* . e) + p* e), with the background pressure p_b taken from p*
 * (0 but for the ideal gas: eulerian_step.cl, SOLVER_BACKGROUND). */
FN vec fluid_momentum_flux(const fluid_state s, const vec e, const real p_b) {
    return vec_axpy(vec_scale(s.v, s.rho * vec_dot(s.v, e)), s.p - p_b, e);
}

/* curl += g x dv, the pair's share of curl v = sum_j g_ij x (v_j - v_i)
 * with g_ij = grad'W_ij w_j: in 2D its z component (c[0]), in 3D all
 * three (NSPIN components), in 1D none. */
FN vec curl_add(vec curl, const vec g, const vec dv) {
#if SPH_DIM == 1
    (void)g;
    (void)dv;
#elif SPH_DIM == 2
    curl.c[0] += g.c[0] * dv.c[1] - g.c[1] * dv.c[0];
#else
    curl.c[0] += g.c[1] * dv.c[2] - g.c[2] * dv.c[1];
    curl.c[1] += g.c[2] * dv.c[0] - g.c[0] * dv.c[2];
    curl.c[2] += g.c[0] * dv.c[1] - g.c[1] * dv.c[0];
#endif
    return curl;
}

/* Weakly compressible EOS (004 eq. 11): p = c0^2 (rho - rho0). */
FN real eos_weakly_compressible(const real rho, const real rho0, const real c0) {
    return c0 * c0 * (rho - rho0);
}
/* Ideal gas (004 eq. 11): p = (gamma - 1) (E - rho |v|^2 / 2), E per volume. */
FN real eos_ideal_gas(const real energy, const real rho, const vec v, const real gamma) {
    return (gamma - R(1)) * (energy - R(0.5) * rho * vec_dot(v, v));
}
/* Its inverse: the total energy per volume E = p / (gamma - 1) + rho |v|^2 / 2. */
FN real ideal_gas_energy(const real p, const real rho, const vec v, const real gamma) {
    return p / (gamma - R(1)) + R(0.5) * rho * vec_dot(v, v);
}
FN real ideal_gas_sound_speed(const real p, const real rho, const real gamma) {
    return sqrt(gamma * p / rho);
}

/* The dissipation limiter of eqs. 19-22, beta = min(eta max(u_l - u_r, 0) / c, 1),
 * is the solids' riemann_limiter (sph_riemann.h). */

/* Linearised (acoustic) solver with the limiter, eqs. 17, 21-22, as the
 * public code's current AcousticRiemannSolver: impedance Z = rho0 c0,
 * arithmetic means of the two sides,
 *   p* = pbar + Z (u_l - u_r) beta / 2,
 *   v* = vbar - e_ij (p_i - p_j) beta^2 / (2 Z)   (u* = ubar + (p_l - p_r) beta^2 / (2 Z)),
 *   rho* = rhobar. */
/* Its constants, formed once per particle (per pass on the native
 * backend) rather than per pair (no division in the pair loop): Z / 2,
 * 1 / (2 Z), eta / c0 (0: unlimited) and beta_floor, 1 unlimited and else 0
 * (the lanes' beta without a branch, below). */
typedef struct {
    real half_z, inv_two_z, eta_over_c0, beta_floor;
} linearised_solver;
FN linearised_solver linearised_solver_make(const real rho0, const real c0, const real eta) {
    linearised_solver k;
    k.half_z = R(0.5) * rho0 * c0;
    k.inv_two_z = R(1) / (R(2) * rho0 * c0);
    k.eta_over_c0 = eta > R(0) ? eta / c0 : R(0);
    k.beta_floor = eta > R(0) ? R(0) : R(1);
    return k;
}
FN fluid_state riemann_linearised(const fluid_side l, const fluid_side r, const vec e_ij,
                                  const linearised_solver k) {
    const real du = l.u - r.u;
    const real beta =
        k.eta_over_c0 > R(0) ? at_most_one(du > R(0) ? k.eta_over_c0 * du : R(0)) : R(1);
    fluid_state s;
    s.rho = R(0.5) * (l.rho + r.rho);
    s.p = R(0.5) * (l.p + r.p) + k.half_z * du * beta;
    s.v = vec_axpy(vec_scale(vec_add(l.v, r.v), R(0.5)), -(l.p - r.p) * beta * beta * k.inv_two_z,
                   e_ij);
    s.energy = R(0);
    return s;
}

/* Lanes of pairs of one particle (SPH_PAIR_LANES, sph_prelude.h; one lane,
 * the plain scalar, in OpenCL): a vector per lane set, the side and the
 * interface state of each lane. */
typedef struct {
    lanes c[SPH_DIM];
} lanes_vec;
typedef struct {
    lanes rho, p, u; /* u = -e_ij . v */
    lanes_vec v;
} fluid_side_lanes;
typedef struct {
    lanes rho, p;
    lanes_vec v;
    lanes energy; /* compressible, else 0 */
} fluid_state_lanes;

FN lanes lanes_dot(const lanes_vec x, const lanes_vec y) {
    lanes s = lanes_zero();
    UNROLL for (int a = 0; a < SPH_DIM; ++a) s += x.c[a] * y.c[a];
    return s;
}

/* riemann_linearised on lanes: the same operations in the same order, so
 * each lane's state is the one-pair solver's bit for bit. */
FN fluid_state_lanes riemann_linearised_lanes(const fluid_side_lanes l, const fluid_side_lanes r,
                                              const lanes_vec e_ij, const linearised_solver k) {
    const lanes du = l.u - r.u;
    /* beta without a branch: limited (eta/c0 > 0, so eta/c0 du > 0 exactly
     * where du > 0), the positive part plus a floor of 0, which changes no
     * bit of it; unlimited (eta/c0 = 0), 0 (max(0 du, 0), NaN included) plus
     * a floor of 1, so 1 */
    const lanes beta = lanes_at_most_one(lanes_positive_part(k.eta_over_c0 * du) + k.beta_floor);
    fluid_state_lanes s;
    s.rho = R(0.5) * (l.rho + r.rho);
    s.p = R(0.5) * (l.p + r.p) + k.half_z * du * beta;
    const lanes w = -(l.p - r.p) * beta * beta * k.inv_two_z;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) s.v.c[a] =
        (l.v.c[a] + r.v.c[a]) * R(0.5) + w * e_ij.c[a];
    s.energy = lanes_zero();
    return s;
}

/* fluid_momentum_flux on lanes, component a. */
FN lanes fluid_momentum_flux_lanes(const fluid_state_lanes s, const lanes vn, const lanes_vec e,
                                   const int a, const real p_b) {
    return s.v.c[a] * (s.rho * vn) + (s.p - p_b) * e.c[a];
}

/* HLLC with the dissipation limiter, eqs. 15-16 and 19-20, in the physical
 * form (eulerian-sph-reference.md §2; documented in docs/fluids.md):
 *  - wave speeds S_l = u_l - c_l, S_r = u_r + c_r (eq. 15);
 *  - beta from (u_l - u_r) / cbar, cbar = (rho_l c_l + rho_r c_r)/(rho_l + rho_r);
 *  - S* = [rho_l (S_l - u_l) u_l - rho_r (S_r - u_r) u_r + (p_r - p_l) beta^2]
 *         / [rho_l (S_l - u_l) - rho_r (S_r - u_r)]   (eq. 19; beta = 1: eq. 15);
 *  - p* = (p_l + p_r)/2 + beta [rho_r c_r (S* - u_r) + rho_l c_l (u_l - S*)] / 2:
 *    eq. 19 prints "-" before the left term; compression (u_l > S* > u_r)
 *    must raise p*, so both terms add (the public code has "+");
 *  - star states rho*_K = rho_K (S_K - u_K)/(S_K - S*), v*_K = v_K - e_ij (S* - u_K)
 *    (the upwind tangential velocity, not eq. 16's printed mean of the two
 *    sides, which would carry the downwind side's tangential momentum
 *    across a contact), E*_K = [(S_K - u_K) E_K - p_K u_K + p* S*]/(S_K - S*);
 *  - the side by the signs of S_l, S*, S_r (left state, left star, right
 *    star, right state); outside the star region the side's own pressure.
 * A degenerate denominator (two vacuum-like sides) falls back to the mean
 * normal velocity, as the public code does below 1e-14. */
FN fluid_state riemann_hllc(const fluid_side l, const fluid_side r, const vec e_ij,
                            const real eta) {
    const real c_l = l.c, c_r = r.c;
    const real s_l = l.u - c_l, s_r = r.u + c_r;
    const real cbar = (l.rho * c_l + r.rho * c_r) / (l.rho + r.rho);
    const real beta = riemann_limiter(l.u - r.u, cbar, eta);
    const real ml = l.rho * (s_l - l.u), mr = r.rho * (s_r - r.u);
    const real den = ml - mr;
    const real s_star = fabs(den) > R(1e-14)
                            ? (ml * l.u - mr * r.u + (r.p - l.p) * beta * beta) / den
                            : R(0.5) * (l.u + r.u);
    const real p_star =
        R(0.5) * (l.p + r.p) +
        R(0.5) * beta * (r.rho * c_r * (s_star - r.u) + l.rho * c_l * (l.u - s_star));
    fluid_state s;
    if (R(0) < s_l) {
        s.rho = l.rho, s.v = l.v, s.p = l.p, s.energy = l.energy;
    } else if (R(0) >= s_r) {
        s.rho = r.rho, s.v = r.v, s.p = r.p, s.energy = r.energy;
    } else {
        /* the star state of the side the interface lies in */
        const fluid_side k = R(0) < s_star ? l : r;
        const real s_k = R(0) < s_star ? s_l : s_r;
        const real inv = R(1) / (s_k - s_star);
        s.rho = k.rho * (s_k - k.u) * inv;
        s.v = vec_axpy(k.v, -(s_star - k.u), e_ij);
        s.energy = ((s_k - k.u) * k.energy - k.p * k.u + p_star * s_star) * inv;
        s.p = p_star;
    }
    return s;
}

#endif
