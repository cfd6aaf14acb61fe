#!/usr/bin/python3
"""plot.py — the Taylor-Green vortex's kinetic energy against time (cases/taylor_green_2d).

    /usr/bin/python3 cases/taylor_green_2d/plot.py RUN_DIR [RUN_DIR ...] [--out FILE.png]

Each RUN_DIR is a run of scene.cfg or public_code.cfg (any kernel, any dp); its curve is
labelled with the formulation, kernel and dp read from its summary.json.  Drawn with them, on a
logarithmic axis: the exact decay KE(t) = 0.25 exp(-16 pi^2 t / Re), Re = 100, and the public
reference code's stored kinetic energy of the ideal-gas run (HLLC, eta = 5, dp = 1/50;
README.md), Laguerre-Gauss and Wendland, as points.  Writes FILE.png (default
taylor_green_ke.png in the current directory) and prints its path.  Exit status 2, with a
message, when a RUN_DIR holds no timeseries.csv.
"""
import argparse
import json
import math
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RE = 100.0
# the public reference code's regression data (SPHinXsys 2d_eulerian_taylor_green_LG and its
# deleted Wendland twin; ../shared/reference/eulerian-sph-reference.md §5.1)
PUBLIC_T = [0.1, 1.0, 2.0, 3.0, 4.0, 5.0]
PUBLIC_LG = [0.207145, 0.0420539, 0.00801214, 0.00160755, 3.30498e-4, 6.86100e-5]
PUBLIC_W = [0.198424, 0.0321755, 0.00556699, 0.00107388, 2.17561e-4, 4.47931e-5]


def exact_ke(t):
    return 0.25 * np.exp(-16.0 * math.pi ** 2 * np.asarray(t) / RE)


def label_of(run):
    """'formulation, kernel, dp = 1/N' from the run's summary.json (the directory name if none)."""
    try:
        with open(os.path.join(run, "summary.json")) as f:
            s = json.load(f)
        return "%s, %s, dp = 1/%d" % (s["formulation"], s["kernel"],
                                     round(1.0 / s["resolved"]["dp"]))
    except (OSError, ValueError, KeyError, TypeError, ZeroDivisionError):
        return os.path.basename(os.path.normpath(run))


def main(argv):
    ap = argparse.ArgumentParser(prog="plot.py", description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+", metavar="RUN_DIR")
    ap.add_argument("--out", default="taylor_green_ke.png")
    args = ap.parse_args(argv)
    fig, ax = plt.subplots(figsize=(8, 6))
    t_end = 5.0
    for run in args.runs:
        path = os.path.join(run, "timeseries.csv")
        if not os.path.exists(path):
            print("plot.py: %s: no timeseries.csv" % run, file=sys.stderr)
            return 2
        ts = np.genfromtxt(path, delimiter=",", names=True)
        ax.semilogy(ts["time"], ts["kinetic_energy"], label=label_of(run))
        t_end = max(t_end, float(ts["time"][-1]))
    t = np.linspace(0.0, t_end, 400)
    ax.semilogy(t, exact_ke(t), "k--", label="exact 0.25 exp(-16 $\\pi^2$ t / Re)")
    for ke, marker, kernel in ((PUBLIC_LG, "o", "Laguerre-Gauss"), (PUBLIC_W, "s", "Wendland")):
        ax.semilogy(PUBLIC_T, ke, marker, mfc="none",
                    label="public code, %s (ideal gas, HLLC, $\\eta$ = 5)" % kernel)
    ax.set_xlabel("t")
    ax.set_ylabel("kinetic energy")
    ax.set_title("Taylor-Green vortex, Re = 100 (004 §4.2)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
