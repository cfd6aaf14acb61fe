#!/usr/bin/python3
"""plot.py — density, velocity and pressure of cases/shock_reflection_1d against the exact solution.

    /usr/bin/python3 cases/shock_reflection_1d/plot.py RUN_DIR [RUN_DIR ...] [--out FILE.png]

Each RUN_DIR is a run of scene.cfg (any dp, limiter or integrator); its last snapshot is read,
at a time the exact solution holds (below t = 0.4068, exact.py).  Every row of the strip is a
copy of the 1D solution; the gas particles of the row nearest y = dp/2 are plotted against
exact.py's profile.  For each run it prints, as README.md reports them:
  - L1: the mean over the row of |rho - rho_exact(x)|;
  - the means of p, rho and u over x in (0.93, 0.99), the gas at rest between the reflected
    shock and the wall, against p5, rho5 and 0;
  - the reflected shock's position: the largest x right of the contact where p is still
    below (p* + p5)/2, against the exact position.
Writes FILE.png (default shock_reflection.png in the current directory).  Exit status 2, with
a message, when a RUN_DIR holds no snapshot or its time is outside the exact solution's range.
"""
import argparse
import json
import os
import sys

import h5py
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exact import X0, Solution  # noqa: E402

WINDOW = (0.93, 0.99)  # the gas at rest against the wall at t = 0.38


def last_row(run):
    """(time, x, rho, u, p, label) of the gas particles in the row nearest y = dp/2 of the
    run's last snapshot, sorted by x."""
    with open(os.path.join(run, "snapshots.hdf.series")) as f:
        last = json.load(f)["files"][-1]
    with h5py.File(os.path.join(run, last["name"]), "r") as f:
        g = f["VTKHDF"]
        pos = g["Points"][:]
        rho, vel, p = g["PointData/density"][:], g["PointData/velocity"][:], g["PointData/pressure"][:]
    gas = (pos[:, 0] > 0.0) & (pos[:, 0] < 1.0)
    ys = pos[gas, 1]
    y_row = ys[np.argmin(ys)]
    sel = gas & (np.abs(pos[:, 1] - y_row) < 1e-9)
    order = np.argsort(pos[sel, 0])
    label = os.path.basename(os.path.normpath(run))
    try:
        with open(os.path.join(run, "summary.json")) as f:
            s = json.load(f)
        label = "dp = 1/%d, eta = %g" % (round(1.0 / s["resolved"]["dp"]),
                                         s["resolved"]["riemann_limiter"])
    except (OSError, ValueError, KeyError, TypeError, ZeroDivisionError):
        pass
    return (float(last["time"]), pos[sel, 0][order], rho[sel][order], vel[sel, 0][order],
            p[sel][order], label)


def measure(run, solution=None):
    """The numbers of the docstring for one run, as a dict."""
    s = solution or Solution()
    t, x, rho, u, p, label = last_row(run)
    if not 0.0 < t < s.t_valid:
        raise ValueError(f"{run}: t = {t:g} is outside the exact solution's range (0, "
                         f"{s.t_valid:.5f})")
    exact = np.array([s.profile(xi, t) for xi in x])
    w = (x > WINDOW[0]) & (x < WINDOW[1])
    middle = 0.5 * (s.p_star + s.p5)
    below = x[(x > X0 + s.u_star * t) & (p < middle)]
    return {"label": label, "time": t, "particles_in_row": int(len(x)),
            "l1_density": float(np.mean(np.abs(rho - exact[:, 0]))),
            "wall_pressure": float(p[w].mean()), "wall_density": float(rho[w].mean()),
            "wall_velocity": float(u[w].mean()),
            "wall_pressure_range": [float(p[w].min()), float(p[w].max())],
            "reflected_shock": float(below.max()) if len(below) else float("nan"),
            "reflected_shock_exact": s.shock_position(t)}


def main(argv):
    ap = argparse.ArgumentParser(prog="plot.py", description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+", metavar="RUN_DIR")
    ap.add_argument("--out", default="shock_reflection.png")
    args = ap.parse_args(argv)
    s = Solution()
    fig, axes = plt.subplots(3, 1, figsize=(9, 10), sharex=True)
    t_plot = None
    for run in args.runs:
        try:
            m = measure(run, s)
            t, x, rho, u, p, label = last_row(run)
        except (OSError, ValueError, KeyError, IndexError) as e:
            print(f"plot.py: {run}: {e}", file=sys.stderr)
            return 2
        t_plot = t
        print(f"{m['label']}: t = {t:g}, L1 density {m['l1_density']:.5f}; x in {WINDOW}: "
              f"p {m['wall_pressure']:.4f} (p5 {s.p5:.4f}), rho {m['wall_density']:.4f} "
              f"(rho5 {s.rho5:.4f}), u {m['wall_velocity']:.4f}; reflected shock at "
              f"{m['reflected_shock']:.4f} (exact {m['reflected_shock_exact']:.4f})")
        for ax, field in zip(axes, (rho, u, p)):
            ax.plot(x, field, ".", ms=3, label=label)
    xs = np.linspace(0.0, 1.0, 2001)
    exact = np.array([s.profile(xi, t_plot) for xi in xs])
    for ax, k, name in zip(axes, range(3), ("density", "velocity", "pressure")):
        ax.plot(xs, exact[:, k], "k-", lw=1.0, label="exact")
        ax.set_ylabel(name)
        ax.axvline(1.0, color="0.5", lw=3)
    axes[0].set_title(f"Sod's shock reflected by a wall, t = {t_plot:g}")
    axes[0].legend(fontsize=8)
    axes[2].set_xlabel("x")
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
