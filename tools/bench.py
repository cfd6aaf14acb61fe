#!/usr/bin/python3
"""bench.py — performance benchmark of the solver (issue 5): fixed cases, wall time,
particle-substeps per second, where the time goes (per phase, from `--profile`) and the
memory bandwidth each phase achieves against the device's measured copy bandwidth.

Cases (fixed):
  plate     2D oscillating plate (cases/oscillating_plate_2d) at H/dp = 10, 20, 30 to t = 1 s
  spinning  2D spinning plate (cases/spinning_plate_2d, dp = 0.05) to t = 0.5 s
  3D plate  the simply supported plate (cases/oscillating_plate_3d), mode (2,2), at
            H/dp = 3, 5, 9 to t = 0.1 s (000 Table 4: 122.6, 981.3, 10629.4 s on 32 cores);
            --plate3d-ratios picks which (default 3: H/dp = 5 takes about an hour on two
            CPU cores, H/dp = 9 with 1.18 M particles is for a GPU)

For every case, backend (--backends cpu opencl) and precision (--precisions):
  * a timing run (no --profile): wall time to the end time, particle-substeps per second;
  * a profiled run (--profile): the time of every phase (rebuild, acoustic substep kernels,
    reductions; the rest of the wall time -- host loop, output -- is the remainder), its
    share, and the achieved bandwidth = the bytes `--profile` reports for the phase (from
    the kernels' own buffer declarations in device/, host/backend/kernel_bytes.c) / its
    time, against `sphsolid bandwidth` (a copy kernel / OpenMP copy on the same device)
    (docs/benchmarks.md, "Bandwidth from the kernels' declarations").
Targets (issue 5): plate H/dp = 10 to 1 s at least 3x faster than the reference code's 18.9 s
(2 cores, native, double); H/dp = 30 to 1 s against 000 Table 2's 130.1 s on 32 cores; pocl
within 1.5x of the native backend.

Writes JSON (--json) and a Markdown table next to it (.md).  Runs are sequential; each uses
the whole machine: timings taken on a shared machine are contaminated (--label says so).

  tools/bench.py --json bench-results/bench.json
  tools/bench.py --json /tmp/b.json --plate-ratios 5 --plate-end 0.35 --spinning-end 0.05 \\
      --label "validation, measured under load"
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_core import (BIN, PAPER_WALL, PLATE, PRECISIONS,  # noqa: E402
                        REFERENCE_CODE_H10_SECONDS, ROOT, environment)

SPINNING = os.path.join(ROOT, "cases", "spinning_plate_2d", "scene.cfg")
PLATE_3D = os.path.join(ROOT, "cases", "oscillating_plate_3d", "scene.cfg")
PLATE_3D_THICKNESS = 0.01  # m (cases/oscillating_plate_3d): dp = thickness / (H/dp)
# 3D plate, mode (m,n) = (2,2), to t = 0.1 s: 000 Table 4 (32 cores, dual-criteria stepping)
PAPER_3D_WALL = {3: 122.6, 5: 981.3, 9: 10629.4}
# issue 5's GPU targets for H/dp = 9 (1.18 M particles) to t = 0.1 s
GPU_3D_TARGET_S = {"single": 100.0, "mixed": 100.0, "double": 200.0}


def plate3d_case(ratio):
    return f"3D plate (2,2) H/dp={ratio:g}"


def pending_3d(ratios_run):
    return [{"case": plate3d_case(r), "end_time": 0.1, "paper_32_core_s": t,
             "status": "not run (--plate3d-ratios)"}
            for r, t in PAPER_3D_WALL.items() if r not in ratios_run]

# ---- profile phases -> groups --------------------------------------------------------------
GROUP_REBUILD, GROUP_SUBSTEP, GROUP_REDUCE, GROUP_OTHER = (
    "rebuild", "acoustic substep", "reductions", "host and output (remainder)")
REDUCTION_PHASES = {"rebuild_reduce", "substep_reduce", "diagnostics_reduce", "monitor_reduce",
                    "reduce_finalize", "substep_finalize", "substep_reduce_finish",
                    "step clock read", "max speed read"}
SUBSTEP_PHASES = {"acoustic substep", "acoustic_contact", "acoustic_pressure",
                  "acoustic_velocity_terms", "acoustic_shear_force", "tl_deformation",
                  "tl_acceleration", "tl_update", "acoustic_substep_loop"}


def phase_group(name):
    if name in REDUCTION_PHASES:
        return GROUP_REDUCE
    if name in SUBSTEP_PHASES:
        return GROUP_SUBSTEP
    return GROUP_REBUILD  # cell keys, sort, permutation, cell ranges, neighbour build


# ---- running -------------------------------------------------------------------------------
def loadavg():
    try:
        return float(open("/proc/loadavg").read().split()[0])
    except (OSError, ValueError, IndexError):
        return None


def full_environment():
    """bench_core.environment() plus whether the tree is modified, the load and the binary."""
    env = environment()
    env["dirty"] = bool(subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                                       cwd=ROOT, capture_output=True, text=True).stdout.strip())
    env["load_average_start"] = loadavg()
    # the binary relative to the repository (no path of the measuring machine)
    rel = os.path.relpath(os.path.abspath(BIN), ROOT)
    env["sphsolid"] = rel if not rel.startswith("..") else os.path.basename(BIN)
    return env


def run_case(scene, sets, backend, device, precision, out, profile):
    cmd = [BIN, "run", scene, "--quiet", "--out", out, "--backend", backend,
           "--precision", precision]
    if device is not None and backend == "opencl":
        cmd += ["--device", str(device)]
    for s in sets:
        cmd += ["--set", s]
    if profile:
        cmd.append("--profile")
    before = loadavg()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 4):
        sys.exit(f"bench: {' '.join(cmd)} failed ({p.returncode}): {p.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    s["_load"] = {"before": before, "after": loadavg()}
    return s


def peak_bandwidth(backend, device, size_mb):
    cmd = [BIN, "bandwidth", "--backend", backend, "--json", "--size-mb", str(size_mb)]
    if device is not None and backend == "opencl":
        cmd += ["--device", str(device)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"bench: {' '.join(cmd)} failed ({p.returncode}): {p.stderr}")
    return json.loads(p.stdout)


def analyse(timing, prof, peak):
    """One result row: timing-run figures, and the profiled run's phases and groups.  The
    bytes of a phase are those `--profile` reports (summary.json: bytes_per_call, from the
    kernels' own buffer declarations, host/backend/kernel_bytes.c); a group's bandwidth is
    that of its phases with bytes (their bytes over their time)."""
    cutoff = prof["resolved"]["cutoff"]
    sizes = prof.get("profile_sizes") or {}
    nbrs = sizes["pair_slots"] / prof["particle_count"] if "pair_slots" in sizes else None
    wall = prof["wall_time_s"]
    peak_gbs = peak["best_gbs"] if peak else None
    phases, groups = [], {}
    for p in prof.get("profile", []):
        per_call = p.get("bytes_per_call")
        b = per_call * p["calls"] if per_call is not None else None
        row = {"phase": p["phase"], "group": phase_group(p["phase"]), "calls": p["calls"],
               "seconds": p["seconds"], "share": p["seconds"] / wall, "bytes": b,
               "model": p.get("bytes_of", "no declared kernel")}
        row["gbs"] = b / p["seconds"] / 1e9 if b is not None and p["seconds"] > 0 else None
        row["fraction_of_peak"] = row["gbs"] / peak_gbs if row["gbs"] and peak_gbs else None
        phases.append(row)
        g = groups.setdefault(row["group"], {"group": row["group"], "seconds": 0.0,
                                             "bytes": None, "seconds_with_bytes": 0.0})
        g["seconds"] += p["seconds"]
        if b is not None:
            g["bytes"] = (g["bytes"] or 0.0) + b
            g["seconds_with_bytes"] += p["seconds"]
    profiled = sum(g["seconds"] for g in groups.values())
    groups[GROUP_OTHER] = {"group": GROUP_OTHER, "seconds": max(wall - profiled, 0.0),
                           "bytes": None}
    order = [GROUP_REBUILD, GROUP_SUBSTEP, GROUP_REDUCE, GROUP_OTHER]
    glist = []
    for name in order:
        if name not in groups:
            continue
        g = groups[name]
        g["share"] = g["seconds"] / wall
        counted = g.get("seconds_with_bytes", 0.0)
        g["gbs"] = g["bytes"] / counted / 1e9 if g["bytes"] and counted > 0 else None
        g["fraction_of_peak"] = g["gbs"] / peak_gbs if g["gbs"] and peak_gbs else None
        glist.append(g)
    return {
        "device": timing["device"], "particles": timing["particle_count"],
        "acoustic_steps": timing["acoustic_steps"], "advection_steps": timing["advection_steps"],
        "wall_time_s": timing["wall_time_s"], "setup_time_s": timing.get("setup_time_s"),
        "particle_substeps_per_second": timing["particle_substeps_per_second"],
        "first_period": timing["metrics"].get("first_period"),
        "max_angular_momentum_error": timing["metrics"].get("max_angular_momentum_error"),
        "status": timing.get("status"),
        "load_average": {"timing_run": timing["_load"], "profiled_run": prof["_load"]},
        "profiled_run": {"wall_time_s": wall, "cutoff": cutoff, "mean_neighbours": nbrs,
                         "phases": phases, "groups": glist},
    }


def cpu_opencl(device):
    """An OpenCL CPU device (pocl), from the device string of summary.json."""
    return "Portable Computing Language" in device or "pthread" in device


def targets(rows, plate_end):
    out = []

    def find(case, backend, precision="double"):
        return next((r for r in rows if r["case"] == case and r["backend"] == backend and
                     r["precision"] == precision), None)
    r10 = find("plate H/dp=10", "cpu")
    if r10 and plate_end == 1.0:
        x = REFERENCE_CODE_H10_SECONDS / r10["wall_time_s"]
        out.append({"target": "plate H/dp = 10 to 1 s, native double: >= 3x faster than the "
                              f"reference code's {REFERENCE_CODE_H10_SECONDS} s (2 cores)",
                    "measured_s": r10["wall_time_s"], "speedup": x, "met": x >= 3.0})
    else:
        out.append({"target": "plate H/dp = 10 to 1 s vs the reference code's 18.9 s",
                    "met": None, "note": "not run (needs H/dp = 10, native, double, t = 1 s)"})
    r30 = find("plate H/dp=30", "cpu")
    if r30 and plate_end == 1.0:
        paper = PAPER_WALL[30]["dual"]
        out.append({"target": f"plate H/dp = 30 to 1 s vs 000 Table 2: {paper} s on 32 cores",
                    "measured_s": r30["wall_time_s"], "ratio_to_paper": r30["wall_time_s"] / paper,
                    "met": r30["wall_time_s"] <= paper})
    else:
        out.append({"target": "plate H/dp = 30 to 1 s vs 000 Table 2 (130.1 s, 32 cores)",
                    "met": None, "note": "not run (needs H/dp = 30, native, double, t = 1 s)"})
    for ratio, paper in PAPER_3D_WALL.items():
        for r in rows:
            if r["case"] != plate3d_case(ratio) or r["end_time"] != 0.1:
                continue
            t = {"target": f"{r['case']} to 0.1 s, {r['backend']} {r['precision']}: against "
                           f"000 Table 4's {paper} s on 32 cores",
                 "measured_s": r["wall_time_s"], "ratio_to_paper": r["wall_time_s"] / paper,
                 "met": None}
            if ratio == 9 and r["backend"] == "opencl" and not cpu_opencl(r["device"]):
                limit = GPU_3D_TARGET_S[r["precision"]]
                t["target"] += f"; issue 5: <= {limit:g} s on a GPU"
                t["met"] = r["wall_time_s"] <= limit
            out.append(t)
    for r in rows:
        if r["backend"] != "opencl":
            continue
        native = find(r["case"], "cpu", r["precision"])
        if not native:
            continue
        ratio = r["wall_time_s"] / native["wall_time_s"]
        cpu_device = cpu_opencl(r["device"])
        out.append({"target": f"{r['case']}, {r['precision']}: OpenCL "
                              f"{'(pocl) within 1.5x of' if cpu_device else 'against'} native",
                    "opencl_s": r["wall_time_s"], "native_s": native["wall_time_s"],
                    "ratio": ratio, "met": ratio <= 1.5 if cpu_device else None})
    return out


def fmt(x, spec=".1f", none="–"):
    return none if x is None else format(x, spec)


def markdown(result):
    lines = []
    label = result.get("label")
    env = result["environment"]
    lines.append(f"Benchmark `tools/bench.py`, {env['date']}, commit {env.get('commit', '?')}"
                 f"{' (modified tree)' if env.get('dirty') else ''}, host {env['machine']} "
                 f"({env['cpu']}, {env['cores']} cores), OMP_WAIT_POLICY "
                 f"{env['omp_wait_policy']}." + (f" **{label}.**" if label else ""))
    lines.append("")
    def device(p):
        if not p["opencl_version"]:
            return p["device"]
        return f"{p['device']}, {p['opencl_version']}, driver {p['driver_version']}"
    lines.append("Peak (copy, read + write counted, `sphsolid bandwidth`): " + "; ".join(
        f"{b}: {p['best_gbs']:.1f} GB/s ({device(p)})"
        for b, p in result["peak_bandwidth"].items()))
    lines.append("")
    lines.append("| case | end (s) | backend | precision | particles | acoustic / advection steps "
                 "| wall (s) | M particle-substeps/s | rebuild | acoustic substep | reductions "
                 "| host and output |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in result["cases"]:
        shares = {g["group"]: g["share"] for g in r["profiled_run"]["groups"]}
        lines.append(
            f"| {r['case']} | {r['end_time']:g} | {r['backend']} | {r['precision']} | "
            f"{r['particles']} | {r['acoustic_steps']} / {r['advection_steps']} | "
            f"{r['wall_time_s']:.2f} | {r['particle_substeps_per_second'] / 1e6:.2f} | " +
            " | ".join(fmt(100 * shares[g] if g in shares else None, ".0f") + " %"
                       for g in (GROUP_REBUILD, GROUP_SUBSTEP, GROUP_REDUCE, GROUP_OTHER)) + " |")
    for p in result["pending"]:
        lines.append(f"| {p['case']} | {p['end_time']:g} | | | | | {p['status']}; paper "
                     f"{p['paper_32_core_s']} s on 32 cores | | | | | |")
    lines.append("")
    lines.append("Shares are of the profiled run's wall time (profiling serialises the OpenCL "
                 "queue). Achieved bandwidth = declared bytes / phase time (the kernels' "
                 "buffer declarations, docs/benchmarks.md, \"Bandwidth from the kernels' "
                 "declarations\"; a group's over its phases with bytes):")
    lines.append("")
    lines.append("| case | backend | precision | phase | calls | time (s) | share | MB moved "
                 "| GB/s | % of copy peak |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|")
    for r in result["cases"]:
        pr = r["profiled_run"]
        items = [(g["group"], "", g) for g in pr["groups"]] + \
                [(p["phase"], p["calls"], p) for p in pr["phases"]]
        for name, calls, g in items:
            bold = "**" if calls == "" else ""
            lines.append(
                f"| {r['case']} | {r['backend']} | {r['precision']} | {bold}{name}{bold} | "
                f"{calls} | {g['seconds']:.3f} | {100 * g['share']:.1f} % | "
                f"{fmt(g['bytes'] / 1e6 if g['bytes'] else None, '.0f')} | "
                f"{fmt(g['gbs'], '.2f')} | "
                f"{fmt(100 * g['fraction_of_peak'] if g['fraction_of_peak'] else None, '.0f')} |")
    lines.append("")
    lines.append("| target | measured | met |")
    lines.append("|---|---|---|")
    for t in result["targets"]:
        if "speedup" in t:
            m = f"{t['measured_s']:.2f} s ({t['speedup']:.2f}x faster)"
        elif "ratio_to_paper" in t:
            m = f"{t['measured_s']:.1f} s ({t['ratio_to_paper']:.2f}x the paper's time)"
        elif "ratio" in t:
            m = f"{t['opencl_s']:.2f} s vs {t['native_s']:.2f} s ({t['ratio']:.2f}x)"
        else:
            m = t.get("note", "")
        met = {True: "yes", False: "**no**", None: "–"}[t["met"]]
        lines.append(f"| {t['target']} | {m} | {met} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", required=True, help="output JSON file (Markdown next to it)")
    ap.add_argument("--backends", nargs="+", default=["cpu", "opencl"], choices=["cpu", "opencl"])
    ap.add_argument("--device", type=int, default=None, help="OpenCL device (sphsolid devices)")
    ap.add_argument("--precisions", nargs="+", default=["double"], choices=PRECISIONS)
    ap.add_argument("--plate-ratios", type=float, nargs="*", default=[10, 20, 30],
                    help="plate H/dp values (default 10 20 30; none: skip the plate)")
    ap.add_argument("--plate-end", type=float, default=1.0, help="plate end time (default 1 s)")
    ap.add_argument("--plate3d-ratios", type=float, nargs="*", default=[3],
                    help="3D plate H/dp values, to t = 0.1 s (default 3; a GPU: 3 5 9)")
    ap.add_argument("--plate3d-end", type=float, default=0.1,
                    help="3D plate end time (default 0.1 s, 000 Table 4)")
    ap.add_argument("--spinning-end", type=float, default=0.5,
                    help="spinning plate end time (default 0.5 s; 0: skip)")
    ap.add_argument("--single-run", action="store_true",
                    help="take the wall time from the profiled run (no separate timing run; "
                         "profiling slows OpenCL)")
    ap.add_argument("--bandwidth-mb", type=float, default=256,
                    help="MiB per buffer of the peak copy (default 256)")
    ap.add_argument("--label", default="",
                    help="a note stored with the results, e.g. \"measured under load\"")
    ap.add_argument("--keep", default=None, help="keep the run directories here")
    args = ap.parse_args()

    env = full_environment()
    if env["omp_wait_policy"].lower() == "passive":
        print("bench: OMP_WAIT_POLICY=passive: the native backend's team sleeps between its "
              "rebuild loops (docs/backends.md)", file=sys.stderr)
    peak = {b: peak_bandwidth(b, args.device, args.bandwidth_mb) for b in args.backends}
    for b, p in peak.items():
        print(f"peak {b}: {p['best_gbs']:.2f} GB/s ({p['device']})", flush=True)

    cases = [(f"plate H/dp={r:g}", PLATE, [f"resolution.ratio={r:g}", f"time.end={args.plate_end}"],
              args.plate_end) for r in args.plate_ratios]
    if args.spinning_end > 0:
        cases.append(("spinning plate dp=0.05", SPINNING, [f"time.end={args.spinning_end}"],
                      args.spinning_end))
    for r in args.plate3d_ratios:
        cases.append((plate3d_case(r), PLATE_3D, [f"resolution.dp={PLATE_3D_THICKNESS / r:.15g}",
                                                  f"time.end={args.plate3d_end}"],
                      args.plate3d_end))
    rows = []
    tmp = args.keep or tempfile.mkdtemp(prefix="sphsolid-bench-")
    try:
        for case, scene, sets, end in cases:
            for precision in args.precisions:
                for backend in args.backends:
                    tag = re.sub(r"[^A-Za-z0-9.=-]+", "_", f"{case}-{backend}-{precision}")
                    prof = run_case(scene, sets, backend, args.device, precision,
                                    os.path.join(tmp, tag + "-profile"), True)
                    timing = prof if args.single_run else run_case(
                        scene, sets, backend, args.device, precision,
                        os.path.join(tmp, tag + "-timing"), False)
                    row = {"case": case, "end_time": end, "backend": backend,
                           "precision": precision, "formulation": timing["formulation"],
                           "timing_from_profiled_run": args.single_run}
                    row.update(analyse(timing, prof, peak.get(backend)))
                    rows.append(row)
                    shares = ", ".join(f"{g['group']} {100 * g['share']:.0f} %"
                                       for g in row["profiled_run"]["groups"])
                    print(f"{case} {backend} {precision}: {row['wall_time_s']:.2f} s, "
                          f"{row['particle_substeps_per_second'] / 1e6:.2f} M particle-substeps/s "
                          f"({shares})", flush=True)
    finally:
        if not args.keep:
            import shutil
            shutil.rmtree(tmp, ignore_errors=True)
    env["load_average_end"] = loadavg()
    result = {"benchmark": "bench", "label": args.label, "environment": env,
              "peak_bandwidth": peak,
              "bandwidth_model": "bytes a phase moves as `--profile` reports them: every "
                                 "global buffer its kernels declare (device/*.cl, 'buffers of "
                                 "NAME: reads ...; writes ...; updates ...') once per call over "
                                 "its extent in this run (n x bytes per particle; per-pair arrays "
                                 "x the pair slots of the last rebuild), read-only and write-only "
                                 "once, read-and-written twice, absent buffers zero; neighbour "
                                 "gathers assumed to hit cache (docs/benchmarks.md)",
              "cases": rows, "pending": pending_3d(args.plate3d_ratios),
              "targets": targets(rows, args.plate_end)}
    result["markdown"] = markdown(result)
    print("\n" + result["markdown"])
    os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
    with open(args.json + ".partial", "w") as f:
        json.dump(result, f, indent=2)
    os.replace(args.json + ".partial", args.json)
    md = os.path.splitext(args.json)[0] + ".md"
    with open(md + ".partial", "w") as f:
        f.write(result["markdown"] + "\n")
    os.replace(md + ".partial", md)
    print(f"\nwrote {args.json} and {md}")


if __name__ == "__main__":
    main()
