#!/usr/bin/python3
"""plot_forces.py RUN [RUN ...] [--out PNG] [--from T] — the cylinder's drag and lift
coefficients against time, one curve per run, beside Table 5 of seed 004 (Laguerre-Gauss,
dp = 1/30: C_D = 1.33, C_L = +-0.340, St = 0.169).

Each RUN is a run directory of this case (`sphsolid run cases/cylinder_flow_2d/scene.cfg`):
its timeseries.csv (drag_coefficient, lift_coefficient) and, when present, its summary.json,
whose resolved dp and integrator name the curve and whose metrics (mean_drag_coefficient,
lift_amplitude, strouhal_number over the window from force_window_start) go into the legend.
Two panels: C_D with Table 5's 1.33 and the issue's band of +-3 %, C_L with +-0.340 and
+-10 %; the first --from seconds (default 50: the start from rest) are left out so that the
shedding is readable.  Writes --out (default forces.png) and prints one line per run.
"""
import argparse
import csv
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TABLE5 = {"C_D": 1.33, "C_L": 0.340, "St": 0.169}  # seed 004, Table 5 (LG, dp = 1/30)
BANDS = {"C_D": 0.03, "C_L": 0.10}  # the fluids issue's acceptance at dp = 1/20


def load(run):
    path = os.path.join(run, "timeseries.csv")
    if not os.path.exists(path):
        path += ".partial"  # a run still going, or killed
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows or "drag_coefficient" not in rows[0]:
        raise SystemExit("%s: no drag_coefficient column (a scene with a wall body and "
                         "forces.reference_* is expected)" % path)
    t = [float(r["time"]) for r in rows]
    cd = [float(r["drag_coefficient"]) for r in rows]
    cl = [float(r["lift_coefficient"]) for r in rows]
    summary = {}
    if os.path.exists(os.path.join(run, "summary.json")):
        with open(os.path.join(run, "summary.json")) as f:
            summary = json.load(f)
    return t, cd, cl, summary


def label_of(run, summary):
    resolved = summary.get("resolved", {})
    dp = resolved.get("dp")
    name = "dp = 1/%d" % round(1.0 / dp) if dp else os.path.basename(os.path.normpath(run))
    integrator = resolved.get("integrator")
    if integrator:
        name += ", " + integrator
    # a box other than the scene's, set on the command line (README, "The box")
    box = [o.split("=", 1)[1] for o in summary.get("scene", {}).get("overrides", [])
           if o.startswith(("boundary.lower=", "boundary.upper="))]
    if box:
        name += ", box " + " to ".join(box)
    m = summary.get("metrics", {})
    if m.get("mean_drag_coefficient") is not None:
        name += ": C_D %.3f, C_L ±%.3f, St %.4f (t ≥ %g)" % (
            m["mean_drag_coefficient"], m["lift_amplitude"], m["strouhal_number"],
            m["force_window_start"])
    return name


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+", help="run directories of cases/cylinder_flow_2d")
    ap.add_argument("--out", default="forces.png", help="the PNG to write (default forces.png)")
    ap.add_argument("--from", dest="t_from", type=float, default=50.0,
                    help="leave out t < T (default 50: the start from rest)")
    args = ap.parse_args()
    fig, (ax_d, ax_l) = plt.subplots(2, 1, figsize=(10, 7), sharex=True)
    for run in args.runs:
        t, cd, cl, summary = load(run)
        keep = [k for k, tt in enumerate(t) if tt >= args.t_from]
        label = label_of(run, summary)
        ax_d.plot([t[k] for k in keep], [cd[k] for k in keep], lw=1, label=label)
        ax_l.plot([t[k] for k in keep], [cl[k] for k in keep], lw=1)
        start = summary.get("metrics", {}).get("force_window_start")
        if start is not None:
            for ax in (ax_d, ax_l):
                ax.axvline(start, color="0.6", lw=0.8, ls=":")
        print("%s: %s" % (run, label))
    cd0, cl0 = TABLE5["C_D"], TABLE5["C_L"]
    ax_d.axhline(cd0, color="k", lw=1, ls="--", label="Table 5 (dp = 1/30): %.2f" % cd0)
    ax_d.axhspan(cd0 * (1 - BANDS["C_D"]), cd0 * (1 + BANDS["C_D"]), color="0.85", zorder=0,
                 label="±3 %")
    for sign in (1, -1):
        ax_l.axhline(sign * cl0, color="k", lw=1, ls="--",
                     label="Table 5: ±%.3f" % cl0 if sign > 0 else None)
        ax_l.axhspan(sign * cl0 * (1 - BANDS["C_L"]), sign * cl0 * (1 + BANDS["C_L"]),
                     color="0.85", zorder=0, label="±10 %" if sign > 0 else None)
    ax_d.set_ylabel("drag coefficient $C_D$")
    ax_l.set_ylabel("lift coefficient $C_L$")
    ax_l.set_xlabel("time")
    for ax in (ax_d, ax_l):
        ax.grid(alpha=0.3)
    # where the curves are not: low on the right for C_D once the wake sheds, early for C_L
    ax_d.legend(fontsize=8, loc="lower right")
    ax_l.legend(fontsize=8, loc="upper left")
    fig.suptitle("Flow around a cylinder, Re = 100 (seed 004 §4.3; Table 5: St = %.3f)"
                 % TABLE5["St"])
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print("wrote %s" % args.out)


if __name__ == "__main__":
    main()
