#!/usr/bin/python3
"""shu_osher_reference.py -- an independent finite-volume reference for cases/shu_osher_1d (issue #30).

Problem (seed 004 eq. 27, seed-digest 3.2.2): 1D Euler, ideal gas gamma = 1.4, x in [0, 10],
    (rho, u, p) = (3.857143, 2.629369, 10.3333)      for x <= 1,
                  (1 + 0.2 sin 5x, 0, 1)              otherwise,
final time t = 1.8.

Scheme (nothing shared with the SPH code):
  * finite volume on N uniform cells, cell averages of the initial state taken exactly
    (the sine is averaged analytically; x = 1 is a cell face whenever N is a multiple of 10);
  * WENO5-JS reconstruction (Jiang & Shu 1996, eps = 1e-6, p = 2) applied characteristic-wise:
    at each face the six stencil cells are projected onto the left eigenvectors of the
    Roe-averaged flux Jacobian, reconstructed component by component, and projected back;
    a face whose reconstructed rho or p is not positive falls back to first order (counted);
  * HLLC approximate Riemann solver (Toro, 3rd ed., sec. 10.4) with Einfeldt (Roe-average)
    wave-speed estimates;
  * SSP-RK3 (Shu & Osher 1988), dt = CFL dx / max(|u| + c), CFL = 0.45 by default,
    the last step shortened to land on t = 1.8 exactly;
  * transmissive (zero-gradient, 3 ghost cells) ends.  The left end is a supersonic inflow
    (u - c = 0.69 > 0 in the post-shock state) and nothing moves ahead of the shock, so
    both ends see constant states up to t = 1.8 and the choice of end condition is moot.

Usage:
  tools/shu_osher_reference.py --cells 16000 --out cases/shu_osher_1d/reference_density.csv
  tools/shu_osher_reference.py --convergence [--cells-list 2000 4000 8000 16000 32000]
        [--json conv.json] [--md conv.md] [--npz conv.npz] [--plot docs/shu-osher-reference.png]
        [--out CSV  (written from the run with --cells N, default 16000)]
  tools/shu_osher_reference.py --plot-only conv.npz --plot docs/shu-osher-reference.png

Sanity checks printed per run: shock position, mass balance (total mass change against the
exact boundary inflow rho_L u_L t), minimum density and pressure, first-order fallbacks.
"""
import argparse
import json
import math
import time

import numpy as np

GAMMA = 1.4
X0, X1 = 0.0, 10.0
T_END = 1.8
RHO_L, U_L, P_L = 3.857143, 2.629369, 10.3333
NG = 3  # ghost cells per side


def initial_state(n, phase=0.0):
    """Exact cell averages of eq. 27 on n cells (x = 1 must be a cell face); the density
    ahead of the shock is 1 + 0.2 sin(5x - phase) (phase = 25: the classic [-5, 5] setup
    shifted by +5)."""
    dx = (X1 - X0) / n
    faces = X0 + dx * np.arange(n + 1)
    a, b = faces[:-1], faces[1:]
    xc = 0.5 * (a + b)
    if abs(round(1.0 / dx) * dx - 1.0) > 1e-12:
        raise SystemExit("--cells must make x = 1 a cell face (a multiple of 10)")
    left = b <= 1.0 + 1e-12
    rho = np.where(left, RHO_L, 1.0 + 0.2 * (np.cos(5 * a - phase) - np.cos(5 * b - phase)) / (5 * dx))
    u = np.where(left, U_L, 0.0)
    p = np.where(left, P_L, 1.0)
    U = np.empty((3, n))
    U[0] = rho
    U[1] = rho * u
    U[2] = p / (GAMMA - 1) + 0.5 * rho * u * u
    return xc, dx, U


def primitives(U):
    rho = U[0]
    u = U[1] / rho
    p = (GAMMA - 1) * (U[2] - 0.5 * rho * u * u)
    return rho, u, p


def weno5(v0, v1, v2, v3, v4):
    """WENO5-JS value at the face between v2 and v3, biased to the v2 side."""
    eps = 1e-6
    b0 = 13 / 12 * (v0 - 2 * v1 + v2) ** 2 + 0.25 * (v0 - 4 * v1 + 3 * v2) ** 2
    b1 = 13 / 12 * (v1 - 2 * v2 + v3) ** 2 + 0.25 * (v1 - v3) ** 2
    b2 = 13 / 12 * (v2 - 2 * v3 + v4) ** 2 + 0.25 * (3 * v2 - 4 * v3 + v4) ** 2
    a0 = 0.1 / (eps + b0) ** 2
    a1 = 0.6 / (eps + b1) ** 2
    a2 = 0.3 / (eps + b2) ** 2
    q0 = (2 * v0 - 7 * v1 + 11 * v2) / 6
    q1 = (-v1 + 5 * v2 + 2 * v3) / 6
    q2 = (2 * v2 + 5 * v3 - v4) / 6
    return (a0 * q0 + a1 * q1 + a2 * q2) / (a0 + a1 + a2)


def reconstruct(Ug):
    """Characteristic-wise WENO5 face states.  Ug: (3, n + 6) with ghosts; returns UL, UR
    (3, n + 1) at the n + 1 faces, face k lying between cells k + 2 and k + 3 of Ug."""
    n1 = Ug.shape[1] - 5
    S = [Ug[:, k:k + n1] for k in range(6)]  # stencil cells i-2 .. i+3 of face i+1/2
    rl, ul, pl = primitives(S[2])
    rr, ur, pr = primitives(S[3])
    hl = (S[2][2] + pl) / rl
    hr = (S[3][2] + pr) / rr
    sl, sr = np.sqrt(rl), np.sqrt(rr)
    u = (sl * ul + sr * ur) / (sl + sr)
    h = (sl * hl + sr * hr) / (sl + sr)
    c = np.sqrt((GAMMA - 1) * (h - 0.5 * u * u))
    b1 = (GAMMA - 1) / (c * c)
    b2 = 0.5 * b1 * u * u
    uc = u / c
    # left eigenvectors (rows) of the Roe Jacobian, conserved variables
    L = ((0.5 * (b2 + uc), -0.5 * (b1 * u + 1 / c), 0.5 * b1),
         (1 - b2, b1 * u, -b1),
         (0.5 * (b2 - uc), -0.5 * (b1 * u - 1 / c), 0.5 * b1))
    W = [[L[m][0] * s[0] + L[m][1] * s[1] + L[m][2] * s[2] for s in S] for m in range(3)]
    wl = [weno5(*w[0:5]) for w in W]
    wr = [weno5(w[5], w[4], w[3], w[2], w[1]) for w in W]
    # right eigenvectors (columns): (1, u - c, h - u c), (1, u, u^2/2), (1, u + c, h + u c)
    def back(w):
        return np.array((w[0] + w[1] + w[2],
                         (u - c) * w[0] + u * w[1] + (u + c) * w[2],
                         (h - u * c) * w[0] + 0.5 * u * u * w[1] + (h + u * c) * w[2]))
    UL, UR = back(wl), back(wr)
    # positivity guard: first order at faces with a non-physical reconstructed state
    bad = np.zeros(n1, dtype=bool)
    for V in (UL, UR):
        r, _, p = primitives(V)
        bad |= ~((r > 0) & (p > 0))
    nbad = int(bad.sum())
    if nbad:
        UL[:, bad] = S[2][:, bad]
        UR[:, bad] = S[3][:, bad]
    return UL, UR, nbad


def hllc(UL, UR):
    rl, ul, pl = primitives(UL)
    rr, ur, pr = primitives(UR)
    cl = np.sqrt(GAMMA * pl / rl)
    cr = np.sqrt(GAMMA * pr / rr)
    sl_, sr_ = np.sqrt(rl), np.sqrt(rr)
    ut = (sl_ * ul + sr_ * ur) / (sl_ + sr_)
    ht = (sl_ * (UL[2] + pl) / rl + sr_ * (UR[2] + pr) / rr) / (sl_ + sr_)
    ct = np.sqrt((GAMMA - 1) * (ht - 0.5 * ut * ut))
    SL = np.minimum(ul - cl, ut - ct)
    SR = np.maximum(ur + cr, ut + ct)
    ml = rl * (SL - ul)
    mr = rr * (SR - ur)
    SM = (pr - pl + ml * ul - mr * ur) / (ml - mr)
    FL = np.array((UL[1], UL[1] * ul + pl, (UL[2] + pl) * ul))
    FR = np.array((UR[1], UR[1] * ur + pr, (UR[2] + pr) * ur))

    def star(U, r, u, p, S, m):
        f = m / (S - SM)
        return np.array((f, f * SM, f * (U[2] / r + (SM - u) * (SM + p / m))))
    FsL = FL + SL * (star(UL, rl, ul, pl, SL, ml) - UL)
    FsR = FR + SR * (star(UR, rr, ur, pr, SR, mr) - UR)
    return np.where(SL >= 0, FL, np.where(SM >= 0, FsL, np.where(SR > 0, FsR, FR)))


def with_ghosts(U):
    return np.concatenate((np.repeat(U[:, :1], NG, 1), U, np.repeat(U[:, -1:], NG, 1)), 1)


def rhs(U, dx, stats, m):
    """-dF/dx on cells [0, m); cells m .. m+2 serve as the right ghosts when they exist."""
    n = U.shape[1]
    if m + NG <= n:
        Ug = np.concatenate((np.repeat(U[:, :1], NG, 1), U[:, :m + NG]), 1)
    else:
        Ug = with_ghosts(U)
    UL, UR, nbad = reconstruct(Ug)
    stats["fallback_faces"] += nbad
    F = hllc(UL, UR)
    return -(F[:, 1:] - F[:, :-1]) / dx, F[0, 0], F[0, -1]


MARGIN = 24  # cells computed ahead of the last disturbed cell (an RK3 step reaches 9)


def active_cells(U, E0):
    """Cells [0, m) to update: the undisturbed gas ahead of the shock (u = 0, p = 1 exactly)
    has a zero flux divergence, so it is frozen rather than computed (a ~2x saving)."""
    moved = (np.abs(U[1]) > 1e-12) | (np.abs(U[2] - E0) > 1e-12)
    last = np.nonzero(moved)[0]
    return min(U.shape[1], (last.max() if last.size else 0) + MARGIN)


def solve(n, cfl=0.45, t_end=T_END, verbose=True, freeze=True, phase=0.0):
    xc, dx, U = initial_state(n, phase)
    E0 = U[2].copy()
    active = 0
    mass0 = U[0].sum() * dx
    t, steps = 0.0, 0
    stats = {"fallback_faces": 0}
    inflow = 0.0  # time integral of (F_mass(x=0) - F_mass(x=10)) along the RK3 weights
    rho_min, p_min = U[0].min(), primitives(U)[2].min()
    t0 = time.perf_counter()
    while t < t_end - 1e-14:
        rho, u, p = primitives(U)
        smax = np.max(np.abs(u) + np.sqrt(GAMMA * p / rho))
        dt = min(cfl * dx / smax, t_end - t)
        m = active_cells(U, E0) if freeze else n
        L0, a0, b0 = rhs(U, dx, stats, m)
        U1 = U.copy()
        U1[:, :m] += dt * L0
        L1, a1, b1 = rhs(U1, dx, stats, m)
        U2 = U.copy()
        U2[:, :m] = 0.75 * U[:, :m] + 0.25 * (U1[:, :m] + dt * L1)
        L2, a2, b2 = rhs(U2, dx, stats, m)
        U[:, :m] = U[:, :m] / 3 + 2 / 3 * (U2[:, :m] + dt * L2)
        active += m
        inflow += dt * ((a0 - b0) / 6 + (a1 - b1) / 6 + 2 * (a2 - b2) / 3)
        t += dt
        steps += 1
        rho, u, p = primitives(U)
        rho_min = min(rho_min, rho.min())
        p_min = min(p_min, p.min())
        if not (rho.min() > 0 and p.min() > 0):
            raise SystemExit(f"positivity lost at t = {t:.6g}, N = {n}")
        if verbose and steps % 2000 == 0:
            print(f"  N={n} step {steps} t={t:.4f} ({time.perf_counter() - t0:.1f} s)", flush=True)
    wall = time.perf_counter() - t0
    rho, u, p = primitives(U)
    mass1 = U[0].sum() * dx
    info = {
        "cells": n, "dx": dx, "phase": phase, "steps": steps, "t": t, "cfl": cfl, "wall_s": wall,
        "shock_x": shock_position(xc, p),
        "mass_change": mass1 - mass0,
        "mass_change_expected_exact": RHO_L * U_L * t_end,
        "mass_balance_error": (mass1 - mass0) - inflow,
        "mass_balance_vs_exact_inflow": (mass1 - mass0) - RHO_L * U_L * t_end,
        "rho_min": float(rho_min), "p_min": float(p_min),
        "fallback_faces": stats["fallback_faces"],
        "mean_active_fraction": active / (steps * n), "freeze_quiescent": freeze,
        "rho_left_end": float(rho[0]), "rho_right_end": float(rho[-1]),
    }
    return xc, rho, u, p, info


def shock_position(xc, p):
    """Rightmost crossing of p = (1 + p_behind) / 2, p_behind the pressure 0.05 behind it
    (the pre-shock pressure is exactly 1), linearly interpolated."""
    i = np.nonzero(p > 1.0 + 1e-6)[0].max()  # last disturbed cell
    j = np.searchsorted(xc, xc[i] - 0.05)
    level = 0.5 * (1.0 + p[j])
    k = np.nonzero(p[:i + 1] > level)[0].max()
    return float(xc[k] + (xc[k + 1] - xc[k]) * (p[k] - level) / (p[k] - p[k + 1]))


def write_csv(path, x, rho, info):
    with open(path, "w") as f:
        f.write("x,density\n")
        for a, b in zip(x, rho):
            f.write(f"{a:.8g},{b:.7g}\n")
    print(f"wrote {path} ({len(x)} cells, shock at x = {info['shock_x']:.4f})")


def restrict(rho, factor):
    return rho.reshape(-1, factor).mean(1)


def l1(xa, a, b, dx, window=None):
    d = np.abs(a - b)
    if window is not None:
        d = d[(xa >= window[0]) & (xa <= window[1])]
    return float(d.sum() * dx)


WINDOW = (5.0, 7.2)  # entropy-wave region behind the shock, shock itself excluded


def convergence(cells, runs):
    """L1 density differences (full domain and WINDOW), by conservative restriction of the
    finer cell averages onto the coarser grid."""
    rows = []
    finest = cells[-1]
    rf = runs[finest]["rho"]
    for k, n in enumerate(cells):
        x, r = runs[n]["x"], runs[n]["rho"]
        dx = (X1 - X0) / n
        row = {"cells": n, "wall_s": runs[n]["info"]["wall_s"], "steps": runs[n]["info"]["steps"],
               "shock_x": runs[n]["info"]["shock_x"]}
        if k + 1 < len(cells):
            m = cells[k + 1]
            rc = restrict(runs[m]["rho"], m // n)
            row["l1_next"] = l1(x, r, rc, dx)
            row["l1_next_window"] = l1(x, r, rc, dx, WINDOW)
        if n != finest:
            rc = restrict(rf, finest // n)
            row["l1_finest"] = l1(x, r, rc, dx)
            row["l1_finest_window"] = l1(x, r, rc, dx, WINDOW)
        rows.append(row)
    for k in range(len(rows) - 1):
        for key in ("l1_next", "l1_next_window"):
            a, b = rows[k].get(key), rows[k + 1].get(key)
            if a and b:
                rows[k + 1]["order_" + key[3:]] = math.log2(a / b)
    return rows


def table_md(rows, finest):
    def f(v, fmt):
        return fmt.format(v) if v is not None else "—"
    out = ["| N | steps | wall (s) | shock x | L1(ρ_N − ρ_2N) | order | "
           f"L1 on [{WINDOW[0]}, {WINDOW[1]}] | order | L1(ρ_N − ρ_{finest}) | "
           f"L1 on [{WINDOW[0]}, {WINDOW[1]}] vs {finest} |",
           "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {r['cells']} | {r['steps']} | {r['wall_s']:.1f} | {r['shock_x']:.4f} | "
                   f"{f(r.get('l1_next'), '{:.3e}')} | {f(r.get('order_next'), '{:.2f}')} | "
                   f"{f(r.get('l1_next_window'), '{:.3e}')} | "
                   f"{f(r.get('order_next_window'), '{:.2f}')} | "
                   f"{f(r.get('l1_finest'), '{:.3e}')} | {f(r.get('l1_finest_window'), '{:.3e}')} |")
    return "\n".join(out) + "\n"


def save_npz(path, runs):
    d = {f"rho_{m}": runs[m]["rho"] for m in runs}
    d.update({f"info_{m}": np.array(json.dumps(runs[m]["info"])) for m in runs})
    np.savez_compressed(path, **d)


def plot(npz_path, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    d = np.load(npz_path)
    cells = sorted(int(k[4:]) for k in d.files if k.startswith("rho_"))
    fig, (a, b) = plt.subplots(1, 2, figsize=(13, 4.8), gridspec_kw={"width_ratios": [1.3, 1]})
    for n in cells:
        x = (np.arange(n) + 0.5) * (X1 - X0) / n
        lw = 0.7 if n != cells[-1] else 1.0
        for ax in (a, b):
            ax.plot(x, d[f"rho_{n}"], lw=lw, label=f"N = {n}")
    a.set_xlim(X0, X1)
    a.axvspan(5, 7.5, color="0.9", zorder=0)
    b.set_xlim(5, 7.5)
    b.set_ylim(2.9, 4.9)
    for ax in (a, b):
        ax.set_xlabel("x")
        ax.set_ylabel("density")
        ax.grid(alpha=0.3)
    a.set_title("Shu-Osher (seed 004 eq. 27), t = 1.8, WENO5-char + HLLC + SSP-RK3")
    b.set_title("zoom: entropy-wave region x ∈ [5, 7.5]")
    b.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(png, dpi=130)
    print(f"wrote {png}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cells", type=int, default=16000)
    ap.add_argument("--cfl", type=float, default=0.45)
    ap.add_argument("--out", help="CSV x,density of the --cells run")
    ap.add_argument("--no-freeze", action="store_true",
                    help="compute the undisturbed gas ahead of the shock too (check)")
    ap.add_argument("--phase", type=float, default=0.0,
                    help="rho = 1 + 0.2 sin(5x - PHASE) ahead of the shock; 0 = seed eq. 27, "
                         "25 = the classic Shu-Osher [-5, 5] setup shifted by +5")
    ap.add_argument("--convergence", action="store_true")
    ap.add_argument("--cells-list", type=int, nargs="+", default=[2000, 4000, 8000, 16000, 32000])
    ap.add_argument("--json")
    ap.add_argument("--md")
    ap.add_argument("--npz", help="save every run's density (for --plot-only)")
    ap.add_argument("--plot", help="PNG of the density of the runs")
    ap.add_argument("--plot-only", metavar="NPZ")
    ap.add_argument("--combine", metavar="NPZ", nargs="+",
                    help="merge --npz files of separate runs (e.g. 32000 run on its own) and "
                         "redo the convergence table (--json, --md), --npz and --plot from them")
    a = ap.parse_args()
    if a.plot_only:
        plot(a.plot_only, a.plot)
        return
    if a.combine:
        runs = load_npz(a.combine)
        cells = sorted(runs)
        if a.npz:
            save_npz(a.npz, runs)
        report(cells, runs, a)
        return
    cells = sorted(set(a.cells_list)) if a.convergence else [a.cells]
    runs = {}
    for n in cells:
        x, rho, _, _, info = solve(n, a.cfl, freeze=not a.no_freeze, phase=a.phase)
        runs[n] = {"x": x, "rho": rho, "info": info}
        print(json.dumps(info))
        if a.npz:
            save_npz(a.npz, runs)
    if a.out:
        if a.cells not in runs:
            raise SystemExit(f"--out needs --cells {a.cells} among the runs")
        write_csv(a.out, runs[a.cells]["x"], runs[a.cells]["rho"], runs[a.cells]["info"])
    if a.convergence:
        report(cells, runs, a)
    elif a.plot and a.npz:
        plot(a.npz, a.plot)


def load_npz(paths):
    runs = {}
    for path in paths:
        d = np.load(path)
        for k in d.files:
            if k.startswith("rho_"):
                n = int(k[4:])
                runs[n] = {"x": (np.arange(n) + 0.5) * (X1 - X0) / n, "rho": d[k],
                           "info": json.loads(str(d[f"info_{n}"]))}
    return runs


def report(cells, runs, a):
    rows = convergence(cells, runs)
    md = table_md(rows, cells[-1])
    print(md)
    if a.md:
        with open(a.md, "w") as f:
            f.write(md)
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"window": WINDOW, "rows": rows,
                       "runs": [runs[n]["info"] for n in cells]}, f, indent=1)
    if a.plot and a.npz:
        plot(a.npz, a.plot)


if __name__ == "__main__":
    main()
