/* sph_riemann.h — the inter-particle acoustic Riemann terms.
 *
 * The continuity equation (003 eq. 15) and the pressure acceleration
 * (003 eqs. 16-18, 000 eqs. 11-16) are written with a linearised acoustic
 * Riemann solver along e_ij (pointing from j to i).  For one material the
 * interface pressure is
 *     P* = (p_i + p_j)/2 + (beta/2) rho0 c0 (U_L - U_R),   U = -v.e_ij,
 * i.e. P* = mean pressure - (beta/2) Z u_ij with u_ij = (v_i - v_j).e_ij.
 *
 * Placement of the dissipation (documented choice, following the reference
 * code, reference notes §3.7 and its issue #577): the pressure half-step uses
 * the non-dissipative mean pressure; the dissipative part -(beta/2) Z u_ij,
 * with beta = 1 (unlimited), is evaluated in the density half-step from the
 * new velocities and applied as an acceleration in the next velocity update.
 * The continuity equation itself carries no pressure-jump dissipation.
 * Putting the dissipation into the density half-step keeps linear momentum
 * exact (every pair term below is antisymmetric in i <-> j) and damps the
 * acoustic noise of the weakly compressible model without entering the
 * pressure of the same step.
 */
#ifndef SPH_RIEMANN_H
#define SPH_RIEMANN_H
#include "sph_vec.h"

/* min(x, 1) and the limiter's max(u, 0) as comparisons: fmin and fmax are
 * library calls in the native build (-fno-fast-math keeps their NaN rules;
 * 8 % of a Taylor-Green run went to them), and the comparisons give the
 * same values, NaN included (NaN > 0 and NaN < 1 are false: 0 and 1, as
 * fmax(NaN, 0) and fmin(NaN, 1)). */
FN real at_most_one(const real x) {
    return x < R(1) ? x : R(1);
}

/* Dissipation limiter beta (003; the fluids' eqs. 19-22 of 004).
 * slope <= 0: unlimited (beta = 1, what the elastic cases use); slope > 0:
 * truncated linear min(slope max(u,0)/c, 1). */
FN real riemann_limiter(const real u, const real c, const real slope) {
    if (slope <= R(0)) return R(1);
    return at_most_one(u > R(0) ? slope * u / c : R(0));
}

/* Pair contributions for one material (Z_i = Z_j = rho0 c0, so the interface
 * pressure is the mean (p_i + p_j)/2 and the pair impedance is Z): per unit
 * of (V_i/m_i) and with dwv = dW/dr V_j (< 0),
 *   pressure:     -2 P* dW V_j e_ij = -(p_i + p_j) dwv e_ij       (003 eq. 16)
 *   dissipation:  beta u_ij dwv e_ij, times Z after the sum      (the -(beta/2)
 *                 Z u part of -2P*)
 *   continuity:   u_ij dwv  (drho_i/dt = rho_i sum u_ij dW V_j, 003 eq. 15)
 * The constants are applied once per particle, outside the neighbour loop.
 * The momentum terms are antisymmetric under i <-> j (p_i + p_j and u_ij are
 * symmetric, e_ij flips), so the sum over all pairs of m_i a_i vanishes. */
/* The scalar factors of the pressure and continuity terms, for one pair or
 * for lanes of pairs (sph_prelude.h): the acoustic passes sum them in lanes,
 * the pair functions below wrap them. */
#define RIEMANN_PRESSURE_FACTOR(p_i, p_j, dwv) (-((p_i) + (p_j)) * (dwv))
#define RIEMANN_CONTINUITY_FACTOR(u_ij, dwv)   ((u_ij) * (dwv))
FN vec riemann_pressure_pair(const real p_i, const real p_j, const real dwv, const vec e_ij) {
    return vec_scale(e_ij, RIEMANN_PRESSURE_FACTOR(p_i, p_j, dwv));
}
FN real riemann_dissipation_factor(const real u_ij, const real c0, const real limiter_slope,
                                   const real dwv) {
    return riemann_limiter(u_ij, c0, limiter_slope) * u_ij * dwv;
}
FN vec riemann_dissipation_pair(const real u_ij, const real c0, const real limiter_slope,
                                const real dwv, const vec e_ij) {
    return vec_scale(e_ij, riemann_dissipation_factor(u_ij, c0, limiter_slope, dwv));
}
FN real riemann_continuity_pair(const real u_ij, const real dwv) {
    return RIEMANN_CONTINUITY_FACTOR(u_ij, dwv);
}

#endif
