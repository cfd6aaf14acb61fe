#!/usr/bin/python3
"""error_vs_runtime.py — accuracy against cost (issue 5): for each formulation, precision and
backend, a resolution ladder of the 2D plate, the 2D spinning plate and the 3D plate; error
against wall time, as CSV, JSON and a log-log PNG.

  plate     cases/oscillating_plate_2d at H/dp = 5, 8, 10, 15, 20, 30 (--ratios) to t = 0.35 s
            (the first period needs ~0.29 s): error of `first_period` against thin-plate
            theory, 0.25406 s (003 eq. 52, bench_core.thin_plate_period), and against the
            finest run of the same formulation, precision and backend
  spinning  cases/spinning_plate_2d at dp = 0.1, 0.05, 0.025 (--dps) to t = 0.5 s: the
            maximum angular-momentum error max |L(t) - L(0)| / |L(0)|
  plate3d   cases/oscillating_plate_3d, mode (2,2), at H/dp = 3 (--plate3d-ratios; 3 5 9 on a
            GPU: 44 652, 204 020 and 1 179 396 particles) to t = 0.02 s: error of the first
            period against thin-plate theory, 0.013305 s (000 eq. 36), and against the finest
            run

Wall time is plotted per simulated second (wall_time_s / end time), so runs to 0.35 s and the
public reference code's measured run (2D plate H/dp = 10, GNOG-A, 18.9 s to t = 1 s on 2 cores,
first period 0.2874 s: its second zero crossing; reference notes §11) share one axis.
--reference-run adds, for each method, the H/dp = 10 plate run to t = 1 s (native backend only),
the like-for-like point, which checks that scaling.

Runs are cached: each has its own directory under --work (default runs/error-vs-runtime); a run
whose summary.json exists is not run again, so an interrupted ladder continues where it
stopped, and --no-run only collects and plots what exists (labelled partial when runs of the
requested grid are missing).  Cheap runs go first.

  tools/error_vs_runtime.py                                # the full grid
  tools/error_vs_runtime.py --formulations enog-a --precisions double --ratios 5 8 \\
      --dps 0.1 --label "validation, measured under load" --png /tmp/e.png --csv /tmp/e.csv
  tools/error_vs_runtime.py --backends cpu --plate3d-ratios --reference-run --grid \\
      enog-a:double,single,mixed gnog-a:double,single,mixed enog gnog oas   # every method
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_core import (BIN, PLATE, PRECISIONS, REFERENCE_CODE_H10_SECONDS, ROOT,  # noqa: E402
                        ROTATING, thin_plate_period)
from bench import (PLATE_3D, PLATE_3D_THICKNESS, SPINNING, full_environment,  # noqa: E402
                   loadavg)

FORMULATIONS = ["enog-a", "gnog-a", "enog", "gnog", "oas"]
THEORY = thin_plate_period(0.3975)  # 0.25406 s, the plate's nu


def plate3d_theory(m=2, n=2, length=0.4, width=0.4, h=PLATE_3D_THICKNESS, e=1.0e8, nu=0.3,
                   rho=1000.0):
    """000 eq. 36: T = (2/pi) [(m/L)^2 + (n/W)^2]^-1 sqrt(rho H / D), D = E H^3 / 12(1 - nu^2)."""
    d = e * h ** 3 / (12 * (1 - nu * nu))
    return 2 / math.pi / ((m / length) ** 2 + (n / width) ** 2) * math.sqrt(rho * h / d)


THEORY_3D = plate3d_theory()  # 0.013305 s, cases/oscillating_plate_3d's (2,2) mode
THEORIES = {"plate": THEORY, "plate3d": THEORY_3D}
# The public reference code (SPHinXsys, GNOG-A, per-particle rotation), H/dp = 10,
# v_f = 0.05, t = 1 s on an idle 2-core machine: zero crossings 0.1434, 0.2874, ... s
# (reference notes §11); its first period by our definition (second zero crossing)
REFERENCE_FIRST_PERIOD = 0.2874
LABELS = {"enog-a": "SPH-ENOG-A", "gnog-a": "SPH-GNOG-A", "enog": "SPH-ENOG", "gnog": "SPH-GNOG",
          "oas": "SPH-OAS"}
COLOURS = {"enog-a": "tab:blue", "gnog-a": "tab:orange", "enog": "tab:green", "gnog": "tab:purple",
           "oas": "tab:red"}
# one marker per precision: filled circle double, open square mixed, open triangle single
PRECISION_MARKERS = {"double": "o", "mixed": "s", "single": "^"}


def method_sets(form):
    rotation = "averaged" if form in ROTATING else "none"
    return [f"method.formulation={form}", f"method.rotation={rotation}",
            "monitor.action=report", "output.snapshot_interval=0"]


def grid(args):
    """(formulation, precisions) pairs: --grid's, else every --formulations with every
    --precisions."""
    if not args.grid:
        return [(form, args.precisions) for form in args.formulations]
    pairs = []
    for entry in args.grid:
        form, _, precs = entry.partition(":")
        precisions = precs.split(",") if precs else ["double"]
        bad = ([form] if form not in FORMULATIONS else []) + \
            [x for x in precisions if x not in PRECISIONS]
        if bad:
            sys.exit(f"error_vs_runtime.py: --grid {entry}: unknown {', '.join(bad)} "
                     f"(formulations {', '.join(FORMULATIONS)}; {', '.join(PRECISIONS)})")
        pairs.append((form, precisions))
    return pairs


def plan(args):
    """Every requested run: (key fields, scene, --set list, run directory)."""
    # case, scene, ladder, end time, the --set that gives a rung its resolution
    ladders = [("plate", PLATE, args.ratios, args.plate_end, lambda r: f"resolution.ratio={r:g}"),
               ("plate3d", PLATE_3D, args.plate3d_ratios, args.plate3d_end,
                lambda r: f"resolution.dp={PLATE_3D_THICKNESS / r:.15g}"),
               ("spinning", SPINNING, args.dps, args.spinning_end,
                lambda dp: f"resolution.dp={dp:g}")]
    runs = []
    for form, precisions in grid(args):
        for prec in precisions:
            for be in args.backends:
                def run(case, scene, resolution, end, resolution_set, reference_run=False):
                    return {"case": case, "formulation": form, "precision": prec, "backend": be,
                            "resolution": resolution, "end_time": end, "scene": scene,
                            "reference_run": reference_run,
                            "sets": [resolution_set(resolution), f"time.end={end:g}"] +
                            method_sets(form)}
                for case, scene, ladder, end, resolution_set in ladders:
                    runs += [run(case, scene, x, end, resolution_set) for x in ladder]
                    if case == "plate" and args.reference_run and be == "cpu":
                        runs.append(run(case, scene, 10.0, 1.0, resolution_set, True))
    for r in runs:
        name = (f"{r['case']}-{r['formulation']}-{r['precision']}-{r['backend']}-"
                f"{'dp' if r['case'] == 'spinning' else 'r'}{r['resolution']:g}-t{r['end_time']:g}")
        r["dir"] = os.path.join(args.work, re.sub(r"[^A-Za-z0-9.=-]+", "_", name))

    # cheap first: particle count grows as ratio^2 (plate), dp^-2 (spinning) and ratio^3
    # (3D plate; the acoustic step count as the ratio too); OpenCL after
    def cost(r):
        n = {"plate": r["resolution"] ** 2 * 16, "plate3d": r["resolution"] ** 4 * 1.6e5,
             "spinning": 1.0 / r["resolution"] ** 2}[r["case"]]
        return (n * r["end_time"] * (4 if r["backend"] == "opencl" else 1), r["dir"])
    return sorted(runs, key=cost)


def execute(r, device):
    cmd = [BIN, "run", r["scene"], "--quiet", "--out", r["dir"], "--backend", r["backend"],
           "--precision", r["precision"]]
    if device is not None and r["backend"] == "opencl":
        cmd += ["--device", str(device)]
    for s in r["sets"]:
        cmd += ["--set", s]
    before = loadavg()
    p = subprocess.run(cmd, capture_output=True, text=True)
    meta = {"command": cmd, "exit_status": p.returncode, "stderr": p.stderr[-2000:],
            "load_average": {"before": before, "after": loadavg()}}
    os.makedirs(r["dir"], exist_ok=True)
    with open(os.path.join(r["dir"], "error-vs-runtime.json"), "w") as f:
        json.dump(meta, f, indent=2)
    if p.returncode not in (0, 4):
        print(f"error_vs_runtime: {' '.join(cmd)} failed ({p.returncode}): {p.stderr.strip()}",
              file=sys.stderr)
    return p.returncode


def collect(r):
    """The run's row, or None when it has no summary.json."""
    path = os.path.join(r["dir"], "summary.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        s = json.load(f)
    meta = {}
    if os.path.exists(os.path.join(r["dir"], "error-vs-runtime.json")):
        with open(os.path.join(r["dir"], "error-vs-runtime.json")) as f:
            meta = json.load(f)
    m = s["metrics"]
    ins = s.get("instability")
    load = meta.get("load_average", {})
    return {"case": r["case"], "formulation": r["formulation"], "precision": r["precision"],
            "backend": r["backend"], "resolution": r["resolution"],
            "reference_run": r.get("reference_run", False),
            "particles": s["particle_count"], "end_time": s["simulated_time"],
            "wall_time_s": s["wall_time_s"],
            "wall_per_simulated_s": s["wall_time_s"] / s["simulated_time"],
            "acoustic_steps": s["acoustic_steps"], "first_period": m.get("first_period"),
            "period_error_theory": None, "period_error_finest": None,
            # (the clamped plate's L is not conserved: only the spinning plate's is an error)
            "max_angular_momentum_error": (m.get("max_angular_momentum_error")
                                           if r["case"] == "spinning" else None),
            "status": s.get("status"),
            "monitor": (f"{ins['quantity']} {ins['value']:.3g} at t = {ins['time']:.3g} s"
                        if ins else "quiet"),
            "device": s["device"], "load_before": load.get("before"),
            "load_after": load.get("after"), "run_dir": shown_path(r["dir"])}


def shown_path(path):
    """Relative to the repository when inside it, else absolute."""
    path = os.path.abspath(path)
    return os.path.relpath(path, ROOT) if path.startswith(ROOT + os.sep) else path


def add_errors(rows):
    for row in rows:
        theory = THEORIES.get(row["case"])
        if theory and row["first_period"] is not None:
            row["period_error_theory"] = abs(row["first_period"] - theory) / theory
    groups = {}
    for row in rows:
        if row["case"] in THEORIES and not row["reference_run"] and row["first_period"]:
            groups.setdefault((row["case"], row["formulation"], row["precision"],
                               row["backend"]), []).append(row)
    for members in groups.values():
        finest = max(members, key=lambda x: x["resolution"])
        for row in members:
            row["finest_resolution"] = finest["resolution"]
            row["period_error_finest"] = (abs(row["first_period"] - finest["first_period"]) /
                                          finest["first_period"])
    for row in rows:  # the 1-s runs: same first period as the ladder's run at that H/dp
        if row["reference_run"]:
            for m in groups.get((row["case"], row["formulation"], row["precision"],
                                 row["backend"]), []):
                if m["resolution"] == row["resolution"]:
                    row["period_error_finest"] = m["period_error_finest"]


def minor_label(v, _):
    """Label the minor log ticks at 2, 3 and 5 times a power of ten."""
    if v <= 0:
        return ""
    mantissa = v / 10 ** math.floor(math.log10(v) + 1e-9)
    return f"{v:.2g}" if round(mantissa) in (2, 3, 5) and abs(mantissa - round(mantissa)) < 0.01 \
        else ""


def plot(rows, png, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter
    panels = [("plate", "period_error_theory",
               f"plate: first-period error vs thin-plate theory ({THEORY:.5f} s)"),
              ("plate", "period_error_finest", "plate: first-period error vs the finest run"),
              ("spinning", "max_angular_momentum_error",
               "spinning plate: max angular-momentum error")]
    if any(row["case"] == "plate3d" and row["period_error_theory"] for row in rows):
        panels.append(("plate3d", "period_error_theory",
                       f"3D plate (2,2): first-period error vs thin-plate theory "
                       f"({THEORY_3D:.6f} s)"))
    # only the panels with data (a ladder may leave out a case)
    panels = [p for p in panels
              if any(row["case"] == p[0] and row[p[1]] and not row["reference_run"]
                     for row in rows)] or panels[:1]
    fig, axes = plt.subplots(1, len(panels), figsize=(max(5.7 * len(panels), 11), 7),
                             squeeze=False)
    axes = axes[0]
    for ax, (case, key, heading) in zip(axes, panels):
        series = {}
        for row in rows:
            if row["case"] == case and row[key] and not row["reference_run"]:
                series.setdefault((row["formulation"], row["precision"], row["backend"]),
                                  []).append(row)
        for (form, prec, be), pts in sorted(series.items()):
            pts.sort(key=lambda x: x["wall_per_simulated_s"])
            ax.loglog([p["wall_per_simulated_s"] for p in pts], [p[key] for p in pts],
                      color=COLOURS.get(form, "k"), linestyle="-" if be == "cpu" else "--",
                      marker=PRECISION_MARKERS.get(prec, "o"),
                      fillstyle="full" if prec == "double" else "none",
                      label=f"{LABELS.get(form, form)}, {prec}, {be}")
            for p in pts:
                res = f"{p['resolution']:g}"
                ax.annotate(res, (p["wall_per_simulated_s"], p[key]), fontsize=7,
                            textcoords="offset points", xytext=(3, 3), color="0.35")
        for row in rows:
            if row["case"] == case and row["reference_run"] and row[key]:
                ax.loglog([row["wall_per_simulated_s"]], [row[key]], marker="*", markersize=11,
                          linestyle="none", color=COLOURS.get(row["formulation"], "k"),
                          label=f"{LABELS.get(row['formulation'])}, H/dp = 10 to t = 1 s, "
                                f"{row['precision']}, {row['backend']}")
        if key == "period_error_theory":
            err = abs(REFERENCE_FIRST_PERIOD - THEORY) / THEORY
            ax.loglog([REFERENCE_CODE_H10_SECONDS], [err], marker="X", markersize=11,
                      linestyle="none", color="k",
                      label=f"reference code (GNOG-A, H/dp = 10, {REFERENCE_CODE_H10_SECONDS} s "
                            f"to t = 1 s, 2 cores)")
        ylo, yhi = ax.get_ylim()
        if yhi < 4 * ylo:  # at least a factor of 4 in view, readable tick labels
            mid = (ylo * yhi) ** 0.5
            ax.set_ylim(mid / 2, mid * 2)
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.3g}"))
            axis.set_minor_formatter(FuncFormatter(minor_label))
        ax.set_title(heading, fontsize=10)
        ax.set_xlabel("wall time per simulated second (s)")
        ax.set_ylabel("relative error")
        ax.grid(True, which="both", alpha=0.3)
    handles = {}
    for ax in axes:  # one legend for the three panels, below them
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    ncol = 4
    rows_needed = max(1, -(-len(handles) // ncol))
    bottom = 0.06 + 0.035 * rows_needed
    if handles:
        fig.legend(list(handles.values()), list(handles.keys()), loc="lower center", ncol=ncol,
                   fontsize=8, frameon=False)
    fig.suptitle("\n".join(textwrap.wrap(title, 170)), fontsize=10)
    fig.tight_layout(rect=(0, bottom, 1, 0.95))
    os.makedirs(os.path.dirname(os.path.abspath(png)), exist_ok=True)
    fig.savefig(png + ".partial.png", dpi=110)
    os.replace(png + ".partial.png", png)


COLUMNS = ["case", "formulation", "precision", "backend", "resolution", "reference_run",
           "particles", "end_time", "wall_time_s", "wall_per_simulated_s", "acoustic_steps",
           "first_period", "period_error_theory", "finest_resolution", "period_error_finest",
           "max_angular_momentum_error", "status", "monitor", "device", "load_before",
           "load_after", "run_dir"]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--formulations", nargs="+", default=FORMULATIONS, choices=FORMULATIONS)
    ap.add_argument("--precisions", nargs="+", default=PRECISIONS, choices=PRECISIONS)
    ap.add_argument("--grid", nargs="+", metavar="FORM[:PREC,...]",
                    help="formulations each with its own precisions, e.g. enog-a:double,single "
                         "oas:double (precision double when none is given); replaces "
                         "--formulations x --precisions")
    ap.add_argument("--backends", nargs="+", default=["cpu", "opencl"], choices=["cpu", "opencl"])
    ap.add_argument("--device", type=int, default=None, help="OpenCL device (sphsolid devices)")
    ap.add_argument("--ratios", type=float, nargs="*", default=[5, 8, 10, 15, 20, 30],
                    help="plate H/dp ladder (none: skip the plate)")
    ap.add_argument("--plate-end", type=float, default=0.35, help="plate end time (0.35 s)")
    ap.add_argument("--dps", type=float, nargs="*", default=[0.1, 0.05, 0.025],
                    help="spinning plate dp ladder (none: skip it)")
    ap.add_argument("--spinning-end", type=float, default=0.5,
                    help="spinning plate end time (0.5 s)")
    ap.add_argument("--plate3d-ratios", type=float, nargs="*", default=[3],
                    help="3D plate H/dp ladder (default 3; a GPU: 3 5 9; none: skip it)")
    ap.add_argument("--plate3d-end", type=float, default=0.02,
                    help="3D plate end time (0.02 s: the first period is 0.0141-0.0157 s)")
    ap.add_argument("--reference-run", action="store_true",
                    help="also run the plate at H/dp = 10 to t = 1 s (native backend)")
    ap.add_argument("--work", default=os.path.join(ROOT, "runs", "error-vs-runtime"),
                    help="run directories (cache; default runs/error-vs-runtime)")
    ap.add_argument("--no-run", action="store_true", help="only collect existing runs and plot")
    ap.add_argument("--csv", default=os.path.join(ROOT, "bench-results", "error-vs-runtime.csv"))
    ap.add_argument("--png", default=os.path.join(ROOT, "docs", "error-vs-runtime.png"))
    ap.add_argument("--label", default="", help="a note for the plot title and the JSON, e.g. "
                                                "\"measured under load\"")
    args = ap.parse_args()

    runs = plan(args)
    done = 0
    for k, r in enumerate(runs):
        if os.path.exists(os.path.join(r["dir"], "summary.json")):
            done += 1
            continue
        if args.no_run:
            continue
        print(f"[{k + 1}/{len(runs)}] {os.path.basename(r['dir'])}", flush=True)
        if execute(r, args.device) in (0, 4):
            done += 1
    rows = [row for row in (collect(r) for r in runs) if row]
    add_errors(rows)
    missing = len(runs) - len(rows)

    os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
    with open(args.csv + ".partial", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow({k: ("" if row.get(k) is None else row.get(k)) for k in COLUMNS})
    os.replace(args.csv + ".partial", args.csv)
    env = full_environment()
    result = {"benchmark": "error_vs_runtime", "label": args.label, "environment": env,
              "theory_first_period": THEORY, "requested_runs": len(runs), "runs": len(rows),
              "reference_code": {"wall_time_to_1s": REFERENCE_CODE_H10_SECONDS,
                                 "first_period": REFERENCE_FIRST_PERIOD, "H/dp": 10},
              "rows": rows}
    jpath = os.path.splitext(args.csv)[0] + ".json"
    with open(jpath + ".partial", "w") as f:
        json.dump(result, f, indent=2)
    os.replace(jpath + ".partial", jpath)

    title = (f"error against wall time, {env['date'][:10]}, commit {env.get('commit', '?')}, "
             f"{env['cpu']} ({env['cores']} cores), OMP_WAIT_POLICY {env['omp_wait_policy']}")
    if missing:
        title += f" — PARTIAL: {len(rows)} of {len(runs)} runs"
    if args.label:
        title += f" — {args.label}"
    plot(rows, args.png, title)

    for row in rows:
        err = (row["max_angular_momentum_error"] if row["case"] == "spinning"
               else row["period_error_theory"])
        fine = row["period_error_finest"]
        err_s = "" if err is None else f"{100 * err:.2f} %"
        fine_s = "" if fine is None else f" (vs finest {100 * fine:.2f} %)"
        print(f"{row['case']:8s} {row['formulation']:6s} {row['precision']:6s} "
              f"{row['backend']:6s} {row['resolution']:<6g} t={row['end_time']:<5g} "
              f"wall {row['wall_time_s']:8.2f} s ({row['wall_per_simulated_s']:8.2f} s/s) "
              f"error {err_s}{fine_s} {row['monitor']}")
    print(f"\nwrote {args.csv}, {jpath} and {args.png} ({len(rows)} of {len(runs)} runs)")


if __name__ == "__main__":
    main()
