#!/usr/bin/python3
"""bench_core.py — the core solver's benchmarks (issue: core solver).

  periods  2D oscillating plate at H/dp = 30, v_f = 0.001, 0.01, 0.03, 0.05, with
           SPH-OAS, SPH-ENOG, SPH-GNOG, SPH-ENOG-A and SPH-GNOG-A (--formulations): first
           period against 003 Table 1 / 000 Table 1 (target: within 2 % of each
           published value).
  tlsph    total-Lagrangian plate at H/dp = 10, Wendland against Laguerre-Gauss, for the six
           (v_f, nu) rows of 004 Table 6: first-period error against thin-plate theory
           (target: within 1.5 percentage points of each published error) and cost (target:
           equal within 5 %).
  precision  the precision modes (double, single, mixed) against double: the plate's first
           period at H/dp = 30 (target: single and mixed within 0.5 % of double) and the
           spinning plate's maximum angular-momentum error (dp = 0.05, t = 0.5 s), with
           the wall time of each.
  timing   wall time and particle-substeps per second of the plate to t = 1 s at
           H/dp = 10, 20, 30 on the native backend and on OpenCL (pocl without a GPU),
           dual- against single-criterion stepping (000 Table 2), and the speed-up
           over the public reference code (18.9 s for H/dp = 10 on a 2-core machine).
  threads  the native backend's thread team on the plate (SPH-GNOG-A, per-particle R) at
           several sizes (--resolutions, default H/dp = 3 4 5 6 8 10, to --end, default
           0.3 s) under OMP_WAIT_POLICY passive and active: one thread (OMP_NUM_THREADS=1)
           against the backend's own choice, best of --repeats alternated runs.  Target:
           the choice never slower than one thread beyond the spread, whatever the policy.

Writes JSON (--json) and prints Markdown tables.  Runs are sequential; each uses the
whole machine.  Usage:
  tools/bench_core.py periods --json bench-results/periods.json
  tools/bench_core.py timing --json bench-results/timing.json [--resolutions 10 20]
"""
import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("SPHSOLID_BIN", os.path.join(ROOT, "build", "sphsolid"))
PLATE = os.path.join(ROOT, "cases", "oscillating_plate_2d", "scene.cfg")
SPINNING = os.path.join(ROOT, "cases", "spinning_plate_2d", "scene.cfg")

# 003 Table 1 (ENOG-A), 000 / 003 Table 1 (ENOG), H/dp = 30
PAPER_PERIODS = {
    "oas": {0.001: 0.273, 0.01: 0.273, 0.03: 0.275, 0.05: 0.278},
    "enog": {0.001: 0.262, 0.01: 0.263, 0.03: 0.268, 0.05: 0.279},
    "gnog": {0.001: 0.275, 0.01: 0.273, 0.03: 0.272, 0.05: 0.272},
    "enog-a": {0.001: 0.265, 0.01: 0.265, 0.03: 0.266, 0.05: 0.269},
    "gnog-a": {0.001: 0.274, 0.01: 0.274, 0.03: 0.274, 0.05: 0.275},
}
ROTATING = ("enog-a", "gnog-a")
PRECISIONS = ("double", "single", "mixed")  # sphsolid run --precision
# 004 Table 6 (TLSPH, H/dp = 10): (v_f, nu) -> published period errors, Wendland and
# Laguerre-Gauss, in % of the thin-plate period
PAPER_TLSPH = {(0.05, 0.22): (10.3, 6.7), (0.1, 0.22): (10.0, 7.4), (0.05, 0.3): (10.3, 6.7),
               (0.1, 0.3): (10.3, 6.5), (0.05, 0.4): (10.4, 6.9), (0.1, 0.4): (10.6, 6.5)}
# 000 Table 2: wall time to t = 1 s on 32 cores (Xeon Gold 6226R), v_f = 0.05
PAPER_WALL = {10: {"dual": 25.8, "single": 43.0}, 20: {"dual": 66.3, "single": 139.5},
              30: {"dual": 130.1, "single": 333.0}}
REFERENCE_CODE_H10_SECONDS = 18.9  # SPHinXsys, GNOG-A, H/dp = 10, t = 1 s, 2 cores


def run(args, out, scene=PLATE):
    cmd = [BIN, "run", scene, "--quiet", "--out", out] + args
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"bench: {' '.join(cmd)} failed ({p.returncode}): {p.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def environment():
    env = {"date": datetime.datetime.now().isoformat(timespec="seconds"),
           "machine": platform.node(), "cpu": "", "cores": os.cpu_count(),
           "omp_wait_policy": os.environ.get("OMP_WAIT_POLICY", "(default)")}
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                env["cpu"] = line.split(":", 1)[1].strip()
                break
        env["commit"] = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], cwd=ROOT,
                                       capture_output=True, text=True).stdout.strip()
        env["dirty"] = bool(subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                                           cwd=ROOT, capture_output=True, text=True).stdout.strip())
    except OSError:
        pass
    return env


def periods(args, tmp):
    rows = []
    for form in args.formulations:
        rotation = "averaged" if form in ROTATING else "none"
        for vf in (0.001, 0.01, 0.03, 0.05):
            out = os.path.join(tmp, f"p-{form}-{vf}")
            s = run(["--backend", args.backend, "--set", f"resolution.ratio={args.ratio}",
                     "--set", f"time.end={args.end}", "--set", f"method.formulation={form}",
                     "--set", f"method.rotation={rotation}", "--set", "monitor.action=report",
                     "--set", "output.snapshot_interval=0",
                     "--set", f"bodies.plate.initial_velocity.amplitude_c0={vf}"], out)
            t = s["metrics"]["first_period"]
            ins = s.get("instability")
            paper = PAPER_PERIODS[form][vf]
            row = {"formulation": form, "v_f": vf, "first_period": t, "paper": paper,
                   "deviation": None if t is None else (t - paper) / paper,
                   "particles": s["particle_count"], "wall_time_s": s["wall_time_s"],
                   "device": s["device"], "instability": ins}
            rows.append(row)
            print(f"{form:7s} v_f={vf:<6} T={t:.4f} paper {paper:.3f} "
                  f"({100 * row['deviation']:+.2f} %), {s['wall_time_s']:.0f} s", flush=True)
    table = ["| formulation | v_f | first period (s) | paper (003/000 Table 1) | deviation | "
             "monitor (zigzag indicator > 0.3) | wall time (s) |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        ins = r["instability"]
        mon = f"tripped at t = {ins['time']:.3g} s ({ins['value']:.2f})" if ins else "quiet"
        table.append(f"| {r['formulation']} | {r['v_f']} | {r['first_period']:.4f} | "
                     f"{r['paper']:.3f} | {100 * r['deviation']:+.2f} % | {mon} | "
                     f"{r['wall_time_s']:.0f} |")
    worst = max(abs(r["deviation"]) for r in rows)
    table.append(f"\nworst deviation {100 * worst:.2f} % (target: within 2 %), "
                 f"H/dp = {args.ratio:g}, backend {args.backend}")
    print("\n" + "\n".join(table))
    return {"H/dp": args.ratio, "rows": rows, "worst_deviation": worst,
            "markdown": "\n".join(table)}


def thin_plate_period(nu, e=2.0e6, rho=1000.0, h=0.02, length=0.2, kl=1.875):
    """004 eq. 33 (003 eq. 52): omega^2 = E H^2 k^4 / (12 rho (1 - nu^2))."""
    import math
    k = kl / length
    return 2 * math.pi / math.sqrt(e * h * h * k ** 4 / (12 * rho * (1 - nu * nu)))


def tlsph(args, tmp):
    rows = []
    for (vf, nu), published in PAPER_TLSPH.items():
        for kernel, paper_err in zip(("wendland-c2", "laguerre-gauss"), published):
            out = os.path.join(tmp, f"tl-{vf}-{nu}-{kernel}")
            s = run(["--backend", args.backend, "--set", "resolution.ratio=10",
                     "--set", "time.end=0.34", "--set", "method.formulation=tlsph",
                     "--set", "method.rotation=none", "--set", f"method.kernel={kernel}",
                     "--set", "output.snapshot_interval=0", "--set", "monitor.action=report",
                     "--set", f"materials.plate.poisson_ratio={nu}",
                     "--set", f"bodies.plate.initial_velocity.amplitude_c0={vf}"], out)
            t = s["metrics"]["first_period"]
            theory = thin_plate_period(nu)
            err = 100 * (t - theory) / theory
            row = {"v_f": vf, "nu": nu, "kernel": kernel, "first_period": t, "theory": theory,
                   "error_percent": err, "paper_error_percent": paper_err,
                   "difference_points": err - paper_err, "wall_time_s": s["wall_time_s"],
                   "acoustic_steps": s["acoustic_steps"], "device": s["device"]}
            rows.append(row)
            print(f"v_f={vf} nu={nu} {kernel:15s} T={t:.5f} ({err:+.2f} %, paper {paper_err} %) "
                  f"{s['wall_time_s']:.1f} s", flush=True)
    table = ["| v_f | nu | theory (s) | kernel | T (s) | error | 004 Table 6 | difference | "
             "wall time (s) |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        table.append(f"| {r['v_f']} | {r['nu']} | {r['theory']:.5f} | {r['kernel']} | "
                     f"{r['first_period']:.5f} | {r['error_percent']:+.2f} % | "
                     f"{r['paper_error_percent']} % | {r['difference_points']:+.2f} points | "
                     f"{r['wall_time_s']:.1f} |")
    worst = max(abs(r["difference_points"]) for r in rows)
    cost = {k: sum(r["wall_time_s"] for r in rows if r["kernel"] == k)
            for k in ("wendland-c2", "laguerre-gauss")}
    ratio = cost["laguerre-gauss"] / cost["wendland-c2"]
    table.append(f"\nworst difference {worst:.2f} percentage points (target 1.5); total wall time "
                 f"Wendland {cost['wendland-c2']:.1f} s, Laguerre-Gauss "
                 f"{cost['laguerre-gauss']:.1f} s (ratio {ratio:.3f}, target within 5 %), "
                 f"backend {args.backend}")
    print("\n" + "\n".join(table))
    return {"rows": rows, "worst_difference_points": worst, "cost_ratio_lg_over_w": ratio,
            "markdown": "\n".join(table)}


def timing_row(s, ratio, backend, stepping):
    """A timing table row from a run's summary.json."""
    return {"H/dp": ratio, "backend": backend, "device": s["device"], "stepping": stepping,
            "particles": s["particle_count"], "acoustic_steps": s["acoustic_steps"],
            "advection_steps": s["advection_steps"], "wall_time_s": s["wall_time_s"],
            "particle_substeps_per_second": s["particle_substeps_per_second"],
            "first_period": s["metrics"].get("first_period")}


def timing(args, tmp):
    rows = []
    for ratio in args.resolutions:
        for backend in args.backends:
            for stepping in ("dual", "single"):
                if stepping == "single" and backend not in args.single_on:
                    continue
                out = os.path.join(tmp, f"t-{ratio}-{backend}-{stepping}")
                s = run(["--backend", backend, "--set", f"resolution.ratio={ratio}",
                         "--set", f"time.stepping={stepping}", "--set", f"time.end={args.end}"],
                        out)
                row = timing_row(s, ratio, backend, stepping)
                row["paper_32_core_s"] = PAPER_WALL.get(ratio, {}).get(stepping)
                rows.append(row)
                print(f"H/dp={ratio} {backend:6s} {stepping:6s} n={row['particles']} "
                      f"{row['wall_time_s']:.1f} s, "
                      f"{row['particle_substeps_per_second'] / 1e6:.2f} M particle-substeps/s",
                      flush=True)
    print("\n| H/dp | particles | backend | stepping | acoustic / advection steps | wall time (s) "
          "| M particle-substeps/s | paper, 32 cores (s) |\n|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['H/dp']} | {r['particles']} | {r['backend']} | {r['stepping']} | "
              f"{r['acoustic_steps']} / {r['advection_steps']} | {r['wall_time_s']:.1f} | "
              f"{r['particle_substeps_per_second'] / 1e6:.2f} | {r['paper_32_core_s']} |")
    result = {"end_time": args.end, "rows": rows}
    speedups = []
    for ratio in args.resolutions:
        for backend in args.backends:
            d = [r for r in rows if r["H/dp"] == ratio and r["backend"] == backend]
            dual = [r for r in d if r["stepping"] == "dual"]
            single = [r for r in d if r["stepping"] == "single"]
            if dual and single:
                x = single[0]["wall_time_s"] / dual[0]["wall_time_s"]
                speedups.append({"H/dp": ratio, "backend": backend, "dual_over_single": x})
                print(f"H/dp={ratio} {backend}: dual-criteria stepping {x:.2f}x faster than "
                      f"single (paper: {PAPER_WALL[ratio]['single'] / PAPER_WALL[ratio]['dual']:.2f}x)")
    result["dual_speedup"] = speedups
    h10 = [r for r in rows if r["H/dp"] == 10 and r["backend"] == "cpu" and r["stepping"] == "dual"]
    if h10 and args.end == 1.0:
        x = REFERENCE_CODE_H10_SECONDS / h10[0]["wall_time_s"]
        result["speedup_over_reference_code_h10"] = x
        print(f"H/dp=10 native, SPH-ENOG-A: {h10[0]['wall_time_s']:.1f} s against the reference "
              f"code's {REFERENCE_CODE_H10_SECONDS} s on the same kind of machine: {x:.2f}x faster")
        # the reference code's own method on the same scene: SPH-GNOG-A with the
        # per-particle rotation (reference notes §11), a third neighbour pass per substep
        s = run(["--backend", "cpu", "--set", "resolution.ratio=10", "--set", "time.end=1.0",
                 "--set", 'method.formulation="gnog-a"', "--set", 'method.rotation="per-particle"'],
                os.path.join(tmp, "t-10-cpu-gnog-a"))
        same = timing_row(s, 10, "cpu", "dual")
        same["formulation"] = "gnog-a, per-particle rotation"
        x = REFERENCE_CODE_H10_SECONDS / same["wall_time_s"]
        result["reference_method_h10"] = same
        result["speedup_over_reference_code_h10_same_method"] = x
        print(f"H/dp=10 native, SPH-GNOG-A per-particle (the reference code's method): "
              f"{same['wall_time_s']:.1f} s ({same['acoustic_steps']} acoustic steps): "
              f"{x:.2f}x faster (target 3x)")
    return result


def precision(args, tmp):
    rows = []
    for backend in args.backends:
        for prec in args.precisions:
            base = ["--backend", backend, "--precision", prec, "--set", "monitor.action=report",
                    "--set", "output.snapshot_interval=0"]
            plate = run(base + ["--set", f"resolution.ratio={args.ratio}",
                                "--set", f"time.end={args.end}"],
                        os.path.join(tmp, f"pr-plate-{backend}-{prec}"))
            spin = run(base, os.path.join(tmp, f"pr-spin-{backend}-{prec}"), SPINNING)
            row = {"backend": backend, "precision": prec, "device": plate["device"],
                   "first_period": plate["metrics"]["first_period"],
                   "plate_wall_time_s": plate["wall_time_s"],
                   "plate_particles": plate["particle_count"],
                   "angular_momentum_error": spin["metrics"]["max_angular_momentum_error"],
                   "spinning_wall_time_s": spin["wall_time_s"]}
            rows.append(row)
            print(f"{backend:6s} {prec:6s} T={row['first_period']:.7f} "
                  f"({row['plate_wall_time_s']:.1f} s), spinning plate "
                  f"{100 * row['angular_momentum_error']:.4f} % "
                  f"({row['spinning_wall_time_s']:.1f} s)", flush=True)
    table = [f"| backend | precision | first period, H/dp = {args.ratio:g} (s) | against double | "
             "wall time (s) | spinning plate: max angular-momentum error | against double | "
             "wall time (s) |", "|---|---|---|---|---|---|---|---|"]
    worst = 0.0
    for r in rows:
        ref = [d for d in rows if d["backend"] == r["backend"] and d["precision"] == "double"]
        dt = dl = None
        if ref:
            dt = r["first_period"] / ref[0]["first_period"] - 1
            dl = r["angular_momentum_error"] - ref[0]["angular_momentum_error"]
            worst = max(worst, abs(dt))
        table.append(f"| {r['backend']} | {r['precision']} | {r['first_period']:.7f} | "
                     + (f"{100 * dt:+.5f} %" if dt is not None else "-") + " | "
                     f"{r['plate_wall_time_s']:.1f} | {100 * r['angular_momentum_error']:.4f} % | "
                     + (f"{100 * dl:+.4f} points" if dl is not None else "-") + " | "
                     f"{r['spinning_wall_time_s']:.1f} |")
    table.append(f"\nworst first-period difference from double {100 * worst:.5f} % "
                 "(target: within 0.5 %); plate v_f = 0.05 to t = "
                 f"{args.end:g} s, spinning plate dp = 0.05 to t = 0.5 s, SPH-ENOG-A")
    print("\n" + "\n".join(table))
    return {"H/dp": args.ratio, "rows": rows, "worst_period_difference": worst,
            "markdown": "\n".join(table)}


def threads(args, tmp):
    rows = []
    for ratio in args.resolutions:
        for policy in ("passive", "active"):
            best = {}
            for rep in range(args.repeats):
                for mode in ("1", "auto"):
                    env = dict(os.environ, OMP_WAIT_POLICY=policy)
                    env.pop("OMP_NUM_THREADS", None)
                    if mode == "1":
                        env["OMP_NUM_THREADS"] = "1"
                    out = os.path.join(tmp, f"t-{ratio}-{policy}-{mode}")
                    cmd = [BIN, "run", PLATE, "--quiet", "--backend", "cpu", "--out", out,
                           "--no-work-limit", "--set", f"resolution.ratio={ratio}",
                           "--set", f"time.end={args.end}", "--set", "method.formulation=gnog-a",
                           "--set", "method.rotation=per-particle",
                           "--set", "output.snapshot_interval=0"]
                    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
                    if p.returncode != 0:
                        sys.exit(f"bench: {' '.join(cmd)} failed ({p.returncode}): {p.stderr}")
                    with open(os.path.join(out, "summary.json")) as f:
                        s = json.load(f)
                    wall = s["wall_time_s"]
                    if mode not in best or wall < best[mode]["wall"]:
                        best[mode] = {"wall": wall, "device": s["device"],
                                      "particles": s["particle_count"]}
            row = {"ratio": ratio, "policy": policy, "particles": best["1"]["particles"],
                   "one_thread_s": best["1"]["wall"], "chosen_s": best["auto"]["wall"],
                   "chosen_device": best["auto"]["device"]}
            rows.append(row)
            print(f"H/dp={ratio:<3} {row['particles']:6d} particles {policy:8s} one thread "
                  f"{row['one_thread_s']:.3f} s, chosen {row['chosen_s']:.3f} s "
                  f"({row['chosen_device']})", flush=True)
    table = ["| H/dp | particles | OMP_WAIT_POLICY | one thread (s) | the backend's choice (s) "
             "| threads chosen | speed-up |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        chosen = r["chosen_device"].split(",")[-1].strip()
        table.append(f"| {r['ratio']:g} | {r['particles']} | {r['policy']} | "
                     f"{r['one_thread_s']:.3f} | {r['chosen_s']:.3f} | {chosen} | "
                     f"{r['one_thread_s'] / r['chosen_s']:.2f} |")
    print("\n" + "\n".join(table))
    return {"end_time": args.end, "repeats": args.repeats, "rows": rows,
            "markdown": "\n".join(table)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("what", choices=["periods", "tlsph", "timing", "precision", "threads"])
    ap.add_argument("--json", required=True, help="output JSON file")
    ap.add_argument("--backend", default="cpu", help="periods: backend (default cpu)")
    ap.add_argument("--ratio", type=float, default=30, help="periods: H/dp (default 30)")
    ap.add_argument("--end", type=float, default=None,
                    help="end time (periods: 0.32 s, timing: 1 s)")
    ap.add_argument("--formulations", nargs="+", default=list(PAPER_PERIODS),
                    choices=list(PAPER_PERIODS), help="periods: formulations (default: all)")
    ap.add_argument("--resolutions", type=int, nargs="+", default=None,
                    help="timing: H/dp (default 10 20 30); threads: 3 4 5 6 8 10")
    ap.add_argument("--repeats", type=int, default=3, help="threads: runs of each (best kept)")
    ap.add_argument("--backends", nargs="+", default=["cpu", "opencl"])
    ap.add_argument("--precisions", nargs="+", default=PRECISIONS, choices=PRECISIONS,
                    help="precision: the modes")
    ap.add_argument("--single-on", nargs="+", default=["cpu"],
                    help="timing: backends that also run single-criterion stepping")
    args = ap.parse_args()
    if args.end is None:
        args.end = {"periods": 0.32, "precision": 0.32, "threads": 0.3}.get(args.what, 1.0)
    if args.resolutions is None:
        args.resolutions = [3, 4, 5, 6, 8, 10] if args.what == "threads" else [10, 20, 30]
    with tempfile.TemporaryDirectory(prefix="sphsolid-bench-") as tmp:
        body = {"periods": periods, "tlsph": tlsph, "timing": timing,
                "precision": precision, "threads": threads}[args.what](args, tmp)
    result = {"benchmark": args.what, "environment": environment(), **body}
    os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
    with open(args.json + ".partial", "w") as f:
        json.dump(result, f, indent=2)
    os.replace(args.json + ".partial", args.json)
    print(f"\nwrote {args.json}")
    if "markdown" in body:
        md = os.path.splitext(args.json)[0] + ".md"
        with open(md + ".partial", "w") as f:
            f.write(f"<!-- {result['environment']} -->\n" + body["markdown"] + "\n")
        os.replace(md + ".partial", md)
        print(f"wrote {md}")


if __name__ == "__main__":
    main()
