#!/usr/bin/python3
"""plot.py — the Shu-Osher density against x with the reference (cases/shu_osher_1d).

    /usr/bin/python3 cases/shu_osher_1d/plot.py RUN_DIR [RUN_DIR ...] [--out FILE.png]
                                                [--row Y]

Each RUN_DIR is a run of scene.cfg or line.cfg (any kernel, any dp) to t = 1.8; its last snapshot
is read.
One row of the strip is plotted (the particles whose y is nearest Y, default 0.0125: every
row is a copy of the 1D solution), with reference_density.csv (WENO5, 16000 cells;
REFERENCE.md) as a line, over the whole tube and in a zoom on the entropy waves behind the
shock (x in [4.5, 7.5]).  For each run it prints the L1 error of README.md: the mean over the
particles of the row of |rho - rho_ref(x)|, rho_ref linearly interpolated in the reference.
Writes FILE.png (default shu_osher_density.png in the current directory).  Exit status 2, with
a message, when a RUN_DIR holds no snapshot.
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

HERE = os.path.dirname(os.path.abspath(__file__))
REFERENCE = os.path.join(HERE, "reference_density.csv")


def reference():
    """(x, density) of reference_density.csv."""
    ref = np.genfromtxt(REFERENCE, delimiter=",", names=True)
    return ref["x"], ref["density"]


def last_snapshot(run):
    """(time, positions [n, 3], density [n], label) of the run's last snapshot."""
    with open(os.path.join(run, "snapshots.hdf.series")) as f:
        last = json.load(f)["files"][-1]
    with h5py.File(os.path.join(run, last["name"]), "r") as f:
        g = f["VTKHDF"]
        pos, rho = g["Points"][:], g["PointData/density"][:]
    label = os.path.basename(os.path.normpath(run))
    try:
        with open(os.path.join(run, "summary.json")) as f:
            s = json.load(f)
        label = "%s, dp = 1/%d%s" % (s["kernel"], round(1.0 / s["resolved"]["dp"]),
                                     ", 1D line" if s["resolved"].get("dimension") == 1 else "")
    except (OSError, ValueError, KeyError, TypeError, ZeroDivisionError):
        pass
    return float(last["time"]), pos, rho, label


def row_l1(pos, rho, y=0.0125):
    """The particles of the row nearest y, sorted by x: (x, rho, L1), where L1 is the mean of
    |rho - rho_ref(x)| over them, rho_ref linearly interpolated in the reference."""
    ys = pos[:, 1]
    y_row = ys[np.argmin(np.abs(ys - y))]
    sel = np.abs(ys - y_row) < 1e-9 * max(1.0, abs(y_row)) + 1e-12
    order = np.argsort(pos[sel, 0])
    x, r = pos[sel, 0][order], rho[sel][order]
    xr, rr = reference()
    return x, r, float(np.mean(np.abs(r - np.interp(x, xr, rr))))


def main(argv):
    ap = argparse.ArgumentParser(prog="plot.py", description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+", metavar="RUN_DIR")
    ap.add_argument("--out", default="shu_osher_density.png")
    ap.add_argument("--row", type=float, default=0.0125)
    args = ap.parse_args(argv)
    xr, rr = reference()
    fig, (ax, az) = plt.subplots(2, 1, figsize=(10, 9))
    for a in (ax, az):
        a.plot(xr, rr, "k-", lw=1.0, label="reference (WENO5, 16000 cells)")
    for run in args.runs:
        try:
            t, pos, rho, label = last_snapshot(run)
        except (OSError, KeyError, IndexError, ValueError) as e:
            print("plot.py: %s: no snapshot (%s)" % (run, e), file=sys.stderr)
            return 2
        x, r, l1 = row_l1(pos, rho, args.row)
        print("%s: t = %g, %d particles in the row, L1 density error %.4g" %
              (run, t, len(x), l1))
        for a in (ax, az):
            a.plot(x, r, ".-", ms=2.5, lw=0.6, label="%s (L1 %.4f)" % (label, l1))
    az.set_xlim(4.5, 7.5)
    for a in (ax, az):
        a.set_xlabel("x")
        a.set_ylabel("density")
        a.grid(True, alpha=0.3)
    ax.set_title("Shu-Osher, t = 1.8 (004 §4.1, eq. 27)")
    az.set_title("zoom: the entropy waves behind the shock")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
