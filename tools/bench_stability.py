#!/usr/bin/python3
"""bench_stability.py — the stiff and extreme suite (issue 7).

For each formulation (default SPH-OG, SPH-OAS, SPH-ENOG, SPH-ENOG-A, SPH-GNOG-A):

  nu       the 2D oscillating plate (cases/oscillating_plate_2d) and the 2D spinning plate
           (cases/spinning_plate_2d) at Poisson's ratio 0.3, 0.45, 0.49, 0.499, Young's
           modulus kept, so c0 grows as 1/sqrt(1 - 2 nu).  The plate keeps the case's tip
           speed, 0.05 c0 at its nu = 0.3975 (2.851 m/s), so that only the material changes
           (--plate-speed c0 gives it 0.05 of each nu's own c0 instead: 9.1 m/s at 0.49 and
           29 m/s at 0.499, a tip amplitude of about 1.8 and 5.7 plate lengths in linear
           theory); its first period is compared with thin-plate theory at that nu;
  long     the plate over >= 30 oscillation periods (energy decay, any late zigzag);
  tensile  cases/tensile_2d: a 1 x 1 m plate, E = 2.1e10, pulled at 500 m/s to 1 ms (its
           scene does not stop on the zigzag indicator: the grips' velocity jump reads as
           one; see its README);
  rings    cases/colliding_rings_2d (dp = 0.001) at v0 = 0.06, 0.07, 0.08 c0;
  ballplate cases/ball_plate_2d (dp = 0.0025, nu = 0.49) at v0 = 0.02, 0.06, 0.12 c0;

each run with the instability monitor on (monitor.action = "stop": a run that breaks stops
there, and the table says when and why).  Columns: stable or not (time and quantity of the
trip), minimum pair distance over dp, energy drift (final and largest E/E0 - 1),
angular-momentum error (spinning plate), wall time.  The papers' expectation: SPH-OG fails
early, SPH-OAS degrades, SPH-ENOG-A and SPH-GNOG-A stay stable.

The plastic impacts (the round and square Taylor bars, the 3100 m/s impact) are run by
tools/bench_cases.py against their published numbers; the table lists them there.

Writes JSON (--json) and a Markdown table (--markdown).  Usage:
  tools/bench_stability.py --json bench-results/stability.json --markdown docs/stability.md
  tools/bench_stability.py --formulations enog-a og --suites nu     (a subset)
Low resolutions keep the whole suite to a few minutes per formulation on 2 cores
(--plate-ratio, --spin-dp, --end, --long-periods change them).
"""
import argparse
import csv
import datetime
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_core import thin_plate_period  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("SPHSOLID_BIN", os.path.join(ROOT, "build", "sphsolid"))
PLATE = os.path.join(ROOT, "cases", "oscillating_plate_2d", "scene.cfg")
SPIN = os.path.join(ROOT, "cases", "spinning_plate_2d", "scene.cfg")
TENSILE = os.path.join(ROOT, "cases", "tensile_2d", "scene.cfg")
RINGS = os.path.join(ROOT, "cases", "colliding_rings_2d", "scene.cfg")
BALL_PLATE = os.path.join(ROOT, "cases", "ball_plate_2d", "scene.cfg")


def bulk_sound_speed(e, nu, rho0):
    """c0 = sqrt(K / rho0), K = E / (3 (1 - 2 nu)): the scenes' c0 from E and nu."""
    return math.sqrt(e / (3.0 * (1.0 - 2.0 * nu) * rho0))


RING_C0 = bulk_sound_speed(1.0e7, 0.4, 1200.0)   # 117.85 m/s, the rings' rubber
BALL_C0 = bulk_sound_speed(1.0e7, 0.49, 1200.0)  # 372.68 m/s, the ball-plate's
PLATE_E, PLATE_RHO, PLATE_NU, PLATE_VF = 2.0e6, 1000.0, 0.3975, 0.05  # the plate case's


def plate_c0(nu):
    """The plate's c0 at Poisson's ratio nu, its E kept."""
    return bulk_sound_speed(PLATE_E, nu, PLATE_RHO)


PLATE_TIP_SPEED = PLATE_VF * plate_c0(PLATE_NU)  # 2.851 m/s
FORMULATIONS = ["og", "oas", "enog", "enog-a", "gnog", "gnog-a"]
DEFAULT_FORMULATIONS = ["og", "oas", "enog", "enog-a", "gnog-a"]
ROTATING = ("enog-a", "gnog-a")
NUS = [0.3, 0.45, 0.49, 0.499]
ELSEWHERE = [
    ("round Taylor bar, 373 m/s", "cases/taylor_bar_round: the top against the reference "
     "code's run"),
    ("square Taylor bar, 227 m/s", "cases/taylor_bar_square: the observer against 003 Table 4"),
    ("high-velocity impact, 3100 m/s", "cases/high_velocity_impact: the projectile's speed at "
     "8 µs"),
]


def run_case(scene, material, form, sets, out_root, backend, label):
    out = os.path.join(out_root, label)
    args = [BIN, "run", scene, "--out", out, "--quiet", "--backend", backend,
            "--set", f"method.formulation={form}",
            "--set", f"method.rotation={'averaged' if form in ROTATING else 'none'}",
            "--set", "output.snapshot_interval=0", "--set", "monitor.action=stop"]
    for s in sets:
        args += ["--set", s]
    t0 = time.monotonic()
    p = subprocess.run(args, capture_output=True, text=True)
    wall = time.monotonic() - t0
    row = {"formulation": form, "exit_status": p.returncode, "wall_s": wall,
           "settings": sets}
    if p.returncode not in (0, 4):
        row.update(status="error", message=p.stderr.strip()[-400:])
        return row
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    e0 = float(rows[0]["total_energy"])
    energies = [float(r["total_energy"]) for r in rows]
    ins = s.get("instability")
    row.update(
        status="stable" if s["status"] == "completed" else "unstable",
        instability=ins,
        end_time=float(rows[-1]["time"]),
        min_distance_ratio=min(float(r["min_distance_ratio"]) for r in rows),
        max_zigzag=max(float(r["zigzag_indicator"]) for r in rows),
        energy_drift_final=energies[-1] / e0 - 1.0 if e0 > 0 else None,
        energy_growth_max=max(energies) / e0 - 1.0 if e0 > 0 else None,
        angular_momentum_error=s["metrics"].get("max_angular_momentum_error"),
        first_period=s["metrics"].get("first_period"),
        particles=s.get("particles") or s.get("particle_count"),
        acoustic_steps=s.get("acoustic_steps"))
    return row


def fmt(x, spec):
    return "—" if x is None else format(x, spec)


def stable_cell(r):
    if r["status"] == "error":
        return "error"
    if r["status"] == "stable":
        return "stable"
    ins = r["instability"] or {}
    q = ins.get("quantity", "")
    return f"**fails** t = {ins.get('time', float('nan')):.3g} s ({q})"


def markdown(results, meta):
    lines = ["# Stiff and extreme suite\n",
             f"Produced by `{meta['command']}` on {meta['date']} ({meta['host']}, backend "
             f"{meta['backend']}, commit {meta['commit']}). Every run has the instability "
             f"monitor on with its default thresholds (`docs/scene-format.md`, `monitor`) and "
             f"`monitor.action = \"stop\"`: an unstable run stops at the trip.\n"]
    for suite, title in (("plate_nu", "2D oscillating plate, Poisson's ratio"),
                         ("spin_nu", "2D spinning plate, Poisson's ratio"),
                         ("long", "2D oscillating plate, long run"),
                         ("tensile", "2D tensile test, E = 2.1e10"),
                         ("rings", "2D colliding rubber rings"),
                         ("ballplate", "2D rubber ball-plate, ν = 0.49")):
        rs = [r for r in results if r["suite"] == suite]
        if not rs:
            continue
        lines.append(f"## {title}\n")
        lines.append(rs[0]["description"] + "\n")
        col = "v0 / c0" if suite in ("rings", "ballplate") else "ν"
        periods = suite == "plate_nu"
        extra = (" tip speed (m/s) | first period (s) | thin plate (s) | deviation |"
                 if periods else "")
        lines.append(f"| formulation | {col} | stable | min r/dp | max zigzag | E(end)/E0 − 1 | "
                     f"max E/E0 − 1 | max AM error | wall (s) |{extra}")
        lines.append("|---|---|---|---|---|---|---|---|---|" + ("---|" * 4 if periods else ""))
        for r in rs:
            am = r.get("angular_momentum_error") if suite == "spin_nu" else None
            cells = ""
            if periods:
                t, theory = r.get("first_period"), r.get("thin_plate_period")
                dev = None if t is None else 100.0 * (t / theory - 1.0)
                cells = (f" {fmt(r.get('tip_speed'), '.3f')} | {fmt(t, '.4f')} | "
                         f"{fmt(theory, '.4f')} | {fmt(dev, '+.1f')}{'' if dev is None else ' %'} |")
            lines.append(
                f"| {r['formulation']} | {r.get('v0_c0', r['nu'])} | {stable_cell(r)} | "
                f"{fmt(r.get('min_distance_ratio'), '.3f')} | {fmt(r.get('max_zigzag'), '.3g')} | "
                f"{fmt(r.get('energy_drift_final'), '+.3g')} | "
                f"{fmt(r.get('energy_growth_max'), '+.2g')} | "
                f"{fmt(None if am is None else 100 * am, '.2f')}{'' if am is None else ' %'} | "
                f"{r['wall_s']:.1f} |{cells}")
        lines.append("")
    lines.append("## Plastic impacts (`tools/bench_cases.py`, `docs/cases.md`)\n")
    lines.append("| case | scene and quantity |")
    lines.append("|---|---|")
    for case, what in ELSEWHERE:
        lines.append(f"| {case} | {what} |")
    lines.append("")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--formulations", nargs="+", default=DEFAULT_FORMULATIONS,
                    choices=FORMULATIONS)
    ap.add_argument("--suites", nargs="+", default=["nu", "long", "tensile", "rings", "ballplate"],
                    choices=["nu", "long", "tensile", "rings", "ballplate"])
    ap.add_argument("--nus", nargs="+", type=float, default=NUS)
    ap.add_argument("--backend", default="cpu", choices=["cpu", "opencl"])
    ap.add_argument("--plate-ratio", type=float, default=6.0, help="plate H/dp (default 6)")
    ap.add_argument("--plate-speed", default="fixed", choices=["fixed", "c0"],
                    help="nu suite's plate: the case's tip speed at every nu (fixed, "
                         f"{PLATE_TIP_SPEED:.3f} m/s) or {PLATE_VF} of each nu's c0")
    ap.add_argument("--spin-dp", type=float, default=0.05, help="spinning plate dp")
    ap.add_argument("--end", type=float, default=0.5, help="end time of the nu runs (s)")
    ap.add_argument("--long-periods", type=float, default=30.0)
    ap.add_argument("--json")
    ap.add_argument("--markdown")
    args = ap.parse_args()
    if not os.path.exists(BIN):
        sys.exit(f"bench_stability.py: {BIN} not found: build first (bash tools/setup.sh)")
    out_root = tempfile.mkdtemp(prefix="sphsolid-stability-")
    results = []
    plate_sets = [f"resolution.ratio={args.plate_ratio}"]
    for form in args.formulations:
        if "nu" in args.suites:
            for nu in args.nus:
                vf = PLATE_TIP_SPEED / plate_c0(nu) if args.plate_speed == "fixed" else PLATE_VF
                r = run_case(PLATE, "plate", form,
                             plate_sets + [f"materials.plate.poisson_ratio={nu}",
                                           f"bodies.plate.initial_velocity.amplitude_c0={vf:.10g}",
                                           f"time.end={args.end}"],
                             out_root, args.backend, f"plate-{form}-{nu}")
                speed = ("the case's tip speed at every ν, 0.05 c0 at its ν = 0.3975 "
                         f"({PLATE_TIP_SPEED:.3f} m/s)" if args.plate_speed == "fixed" else
                         f"a tip speed of {PLATE_VF} of each ν's own c0")
                r.update(suite="plate_nu", nu=nu, tip_speed=vf * plate_c0(nu),
                         thin_plate_period=thin_plate_period(nu), description=(
                             f"Plate of cases/oscillating_plate_2d at H/dp = {args.plate_ratio:g} "
                             f"to t = {args.end:g} s, E = 2e6 Pa kept, ν varied, with {speed}; "
                             "first period against thin-plate theory at that ν (003 eq. 52, "
                             "plane strain)."))
                results.append(r)
                print(f"plate  {form:7s} nu={nu:<6} {stable_cell(r):45s} "
                      f"min r/dp {fmt(r.get('min_distance_ratio'), '.3f')} "
                      f"wall {r['wall_s']:.1f} s", flush=True)
                r = run_case(SPIN, "rubber", form,
                             [f"resolution.dp={args.spin_dp}",
                              f"materials.rubber.poisson_ratio={nu}", f"time.end={args.end}"],
                             out_root, args.backend, f"spin-{form}-{nu}")
                r.update(suite="spin_nu", nu=nu, description=(
                    f"Spinning plate of cases/spinning_plate_2d at dp = {args.spin_dp:g} to "
                    f"t = {args.end:g} s (ω = 50 rad/s), E = 1.7e7 Pa kept, ν varied."))
                results.append(r)
                am = r.get("angular_momentum_error")
                print(f"spin   {form:7s} nu={nu:<6} {stable_cell(r):45s} "
                      f"AM err {fmt(None if am is None else 100 * am, '.2f')} % "
                      f"wall {r['wall_s']:.1f} s", flush=True)
        if "long" in args.suites:
            # thin-plate period 0.254 s (003 eq. 52); coarse plates are slower (0.29 s at
            # H/dp = 4), so 0.3 s per period is a safe upper bound
            end = args.long_periods * 0.3
            r = run_case(PLATE, "plate", form, plate_sets + [f"time.end={end}"], out_root,
                         args.backend, f"long-{form}")
            r.update(suite="long", nu=0.3975, description=(
                f"Plate of cases/oscillating_plate_2d at H/dp = {args.plate_ratio:g} to "
                f"t = {end:g} s (≥ {args.long_periods:g} periods of ≤ 0.3 s), ν = 0.3975."))
            results.append(r)
            print(f"long   {form:7s} {stable_cell(r):52s} E(end)/E0-1 "
                  f"{fmt(r.get('energy_drift_final'), '+.3g')} wall {r['wall_s']:.1f} s",
                  flush=True)
        if "tensile" in args.suites:
            r = run_case(TENSILE, "steel", form, [], out_root, args.backend, f"tensile-{form}")
            r.update(suite="tensile", nu=0.3, description=(
                "cases/tensile_2d at dp = 0.025 to 1 ms: bottom fixed, top pulled at 500 m/s "
                "(0.32 c0); the energy column includes the grips' work (energy grows)."))
            results.append(r)
            print(f"tensile {form:7s} {stable_cell(r):51s} min r/dp "
                  f"{fmt(r.get('min_distance_ratio'), '.3f')} wall {r['wall_s']:.1f} s",
                  flush=True)
        if "rings" in args.suites:
            for m in (0.06, 0.07, 0.08):
                v = m * RING_C0
                r = run_case(RINGS, "rubber", form,
                             [f"bodies.left.initial_velocity.vector=[{v:.9g}, 0.0]",
                              f"bodies.right.initial_velocity.vector=[{-v:.9g}, 0.0]",
                              "output.snapshot_interval=0"],
                             out_root, args.backend, f"rings-{form}-{m}")
                r.update(suite="rings", nu=0.4, v0_c0=m, description=(
                    "cases/colliding_rings_2d at dp = 0.001 (lattice particles) to 0.014 s; "
                    "000 §6.3 at 0.06 c0: E(end)/E0 = 55.61/65.88 - 1 = -0.156; SPH-OG "
                    "fractures, SPH-OAS zigzags (fractures at 0.08 c0), SPH-ENOG smooth."))
                results.append(r)
                print(f"rings  {form:7s} v0={m} c0 {stable_cell(r):45s} E(end)/E0-1 "
                      f"{fmt(r.get('energy_drift_final'), '+.3g')} wall {r['wall_s']:.1f} s",
                      flush=True)
        if "ballplate" in args.suites:
            for m in (0.02, 0.06, 0.12):
                r = run_case(BALL_PLATE, "rubber", form,
                             [f"bodies.ball.initial_velocity.vector=[0.0, {-m * BALL_C0:.9g}]",
                              "output.snapshot_interval=0"],
                             out_root, args.backend, f"ballplate-{form}-{m}")
                r.update(suite="ballplate", nu=0.49, v0_c0=m, description=(
                    "cases/ball_plate_2d at dp = 0.0025 to 0.05 s (plate clamped at both "
                    "ends, ν = 0.49); 000: SPH-ENOG stable at every v0."))
                results.append(r)
                print(f"ball   {form:7s} v0={m} c0 {stable_cell(r):45s} min r/dp "
                      f"{fmt(r.get('min_distance_ratio'), '.3f')} wall {r['wall_s']:.1f} s",
                      flush=True)
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True).stdout.strip()
    if commit and dirty:
        commit += " with uncommitted changes"
    meta = {"command": "tools/bench_stability.py " + " ".join(sys.argv[1:]),
            "date": datetime.date.today().isoformat(),
            "host": f"{platform.node()}, {os.cpu_count()} cores",
            "backend": args.backend, "commit": commit or "unknown"}
    md = markdown(results, meta)
    print(md)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"meta": meta, "results": results}, f, indent=1)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(md)


if __name__ == "__main__":
    main()
