#!/usr/bin/python3
"""test_cylinder.py BACKEND — the flow around a cylinder (seed 004 §4.3) in the public reference
code's small configuration, cases/cylinder_flow_2d/small.cfg: wall bodies (the cylinder's
particles at dp/2, relaxed), the far field on every side, the forces on the wall.

1. Native backend, release build: the run to t = 80 (the public code's end time) completes with
   the monitor quiet, and the viscous force on the cylinder, the only force the public code
   stores (eulerian-sph-reference.md §5.2: 0.938 at t = 5, then 0.885 to 0.902 at every output
   to t = 80), is within 10 % of it at t = 5 (documented run: 0.847, -9.7 %) and within 10 % of
   the 0.885-0.902 band at every output from t = 35 on (documented run: 0.829-0.835, 6-7 % low;
   cases/cylinder_flow_2d/README.md).
   Between t = 10 and 30 our flow sheds its first vortices (C_L up to 2.1 at t = 25) and the
   viscous force dips to 0.70 (cases/cylinder_flow_2d/README.md): not checked there.  The drag
   is positive, the mean C_D over the summary's window (t = 40-80) within 10 % of the documented
   1.642, the lift oscillates about zero (|mean C_L| < 0.2 of its amplitude), and the summary's
   Strouhal number lies within 10 % of the documented 0.140.
2. Both backends: the first second (35 steps) on the native backend and on OpenCL agree to
   1e-10 of each field's scale (`sphsolid compare --rtol 1e-10`): the wall, far-field and force
   code is the same physics source on both.

3. Both backends (the native one also under the sanitizers): a uniform stream is a steady state
   of the far field.  A box 10 x 6 at dp = 0.25 (960 particles) with far-field faces all round,
   the fluid starting at the free stream (rho_inf = 1, U_inf = (1, 0)), to t = 2 (two sound
   crossings of the box): every particle's density and velocity stay the free stream's to
   1e-12 (measured: exactly).  Before the far-field particles held their state through the step
   and their pairs with the interior took the inner particle's B (eulerian_step.cl,
   IS_FAR_FIELD), the particles within 2h of the faces moved by 2e-3 in density and 2e-2 in
   velocity in the first 0.1 s, and the interior settled 0.1 % below rho_inf.

4. Both backends (the native one also under the sanitizers): the ideal gas
   ("eulerian-compressible") with its far field and a wall body.  (a) The uniform stream of 3.
   as a gas (p_inf = 71.4285714285714, c_inf = 10, Mach 0.1) stays the free stream's density,
   velocity and pressure to 1e-12 (measured: exactly).  (b) small.cfg as a gas with the far
   field at rest (U_inf = 0): the gas around the cylinder stays at rest, every |v| below 1e-12
   at t = 1 (measured 1e-15; the kinetic energy 6e-28).  The momentum fluxes are taken relative
   to the background pressure p_b = p_inf (eulerian_step.cl, SOLVER_BACKGROUND); with p_b = 0
   the wall pairs' error of p ~ 71 set the gas moving (kinetic energy 33 at t = 2, C_D -10).
   (c) The gas cylinder in a stream, its first second on the native backend and on OpenCL,
   agrees to 1e-10 of each field's scale.

Under the sanitizers (SPHSOLID_SANITIZED) the native backend runs the first second only (the
drag positive, the viscous force along the stream); part 1 is left to the release build.
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import (BIN, SANITIZED, SRC, check, finish, run_quiet, run_sphsolid,  # noqa: E402
                     snapshot_paths)

UNIFORM_STREAM = """title = "a uniform stream through far-field faces";
dimension = 2;
resolution = { dp = 0.25; };
method = { formulation = "eulerian-wc"; kernel = "laguerre-gauss"; riemann_limiter = 15.0; };
time = { end = 2.0; output_interval = 1.0; };
output = { snapshot_interval = 1.0; };
materials = { fluid = { density = 1.0; sound_speed = 10.0; viscosity = 0.02; }; };
shapes = { box = { type = "box"; lower = [0.0, 0.0]; upper = [10.0, 6.0]; }; };
boundary = { lower = [0.0, 0.0]; upper = [10.0, 6.0];
             far_field = { density = 1.0; velocity = [1.0, 0.0]; }; };
bodies = ( { name = "fluid"; material = "fluid"; shape = "box";
             initial_velocity = { type = "uniform"; vector = [1.0, 0.0]; }; } );
"""

P_INF = "71.4285714285714"  # the ideal gas at rho = 1 with c = 10: gamma p / rho = 100
GAS = ["method.formulation=eulerian-compressible",
       "materials.fluid={ density = 1.0; gamma = 1.4; viscosity = 0.02; }",
       "bodies.fluid.initial_pressure=" + P_INF, "boundary.far_field.pressure=" + P_INF]

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
SMALL = os.path.join(SRC, "cases", "cylinder_flow_2d", "small.cfg")
BAND = (0.885, 0.902)  # the public code's stored viscous force from t = 10 to 80


def cross_check(label, sets):
    """small.cfg with `sets` on the native backend and on OpenCL: the runs agree to 1e-10."""
    name = label.replace(" ", "-")
    a, b = os.path.join(tmp, name + "-native"), os.path.join(tmp, name + "-opencl")
    code_a, err_a = run_sphsolid(SMALL, "cpu", a, sets)
    code_b, err_b = run_sphsolid(SMALL, "opencl", b, sets)
    check(code_a == 0 and code_b == 0, f"{label}: short runs: {code_a} ({err_a}), {code_b} ({err_b})")
    if code_a == 0 and code_b == 0:
        p = subprocess.run([BIN, "compare", a, b, "--rtol", "1e-10"], capture_output=True, text=True)
        check(p.returncode == 0, f"{label}: native and OpenCL agree to 1e-10: " + p.stdout[-600:])


def column(ts, name, t):
    rows = [k for k in range(len(ts["time"])) if abs(ts["time"][k] - t) < 1e-9]
    return float(ts[name][rows[0]]) if rows else float("nan")


tmp = tempfile.mkdtemp(prefix="test_cylinder.")
try:
    # the relaxed cylinder once, reused by every run below (the relaxation's table of the
    # surface term takes most of a run's set-up)
    relaxed = os.path.join(tmp, "cylinder_relaxed.h5")
    keep = ["bodies.cylinder.relaxation.file=" + relaxed]

    if BACKEND == "cpu" and not SANITIZED:
        out = os.path.join(tmp, "small")
        summ, ts = run_quiet(SMALL, "cpu", out, keep, options=["--checkpoint-every", "80"])
        if summ is not None:
            f5 = column(ts, "viscous_force_x", 5.0)
            check(abs(f5 - 0.938) <= 0.1 * 0.938, f"viscous force at t = 5: {f5} (public 0.938)")
            late = [(float(t), float(f)) for t, f in zip(ts["time"], ts["viscous_force_x"])
                    if t >= 35.0 - 1e-9]
            check(len(late) == 10, f"10 outputs from t = 35 to 80, got {len(late)}")
            for t, f in late:
                check(0.9 * BAND[0] <= f <= 1.1 * BAND[1],
                      f"viscous force at t = {t}: {f} within 10 % of {BAND}")
            m = summ["metrics"]
            check(all(float(c) > 0 for c in ts["drag_coefficient"][1:]), "drag positive")
            check(abs(m["mean_drag_coefficient"] - 1.642) <= 0.1 * 1.642,
                  f"mean C_D {m['mean_drag_coefficient']} (documented 1.642)")
            lift = [float(c) for t, c in zip(ts["time"], ts["lift_coefficient"]) if t >= 40.0]
            check(abs(sum(lift) / len(lift)) < 0.2 * m["lift_amplitude"],
                  f"C_L about zero: mean {sum(lift) / len(lift)}, amplitude {m['lift_amplitude']}")
            st = m["strouhal_number"]
            check(st is not None and abs(st - 0.140) <= 0.1 * 0.140,
                  f"Strouhal number {st} (documented 0.140)")
            check(m["angular_momentum_not_conserved"] == "wall body 'cylinder'; far field",
                  f"why L is not reported: {m['angular_momentum_not_conserved']}")
            # the public code's force sums on the final state (public_force_estimator.py):
            # its own estimate is the timeseries' at t = 80, and the public code's viscous sum
            # agrees with it within 5 % (measured 0.842 against 0.835; its pressure sum has no
            # meaning at 4 particles per radius, cases/cylinder_flow_2d/README.md)
            p = subprocess.run([sys.executable, os.path.join(os.path.dirname(SMALL),
                                                             "public_force_estimator.py"),
                                os.path.join(out, "checkpoint", "checkpoint.h5")],
                               capture_output=True, text=True, timeout=300)
            rows = {line[:36].strip(): line[36:].split() for line in p.stdout.splitlines()
                    if line.startswith(("sphsolid", "public"))}
            ours, public = rows.get("sphsolid (momentum exchange)"), rows.get("public code")
            check(p.returncode == 0 and ours and public,
                  f"public_force_estimator.py: exit {p.returncode}: {p.stdout}{p.stderr}")
            if ours and public:
                drag80 = column(ts, "drag_coefficient", 80.0)
                check(abs(float(ours[0]) - drag80) <= 1e-4,
                      f"the script's C_D of sphsolid {ours[0]} is the timeseries' {drag80}")
                check(abs(float(public[2]) / float(ours[2]) - 1.0) <= 0.05,
                      f"the public code's viscous sum {public[2]} within 5 % of ours {ours[2]}")
            # plot_forces.py draws the run and names it by its summary: dp = 1/4 and the
            # window's mean C_D, lift amplitude and St, as summary.json has them
            png = os.path.join(tmp, "forces.png")
            p = subprocess.run([sys.executable, os.path.join(os.path.dirname(SMALL),
                                                             "plot_forces.py"), out,
                                "--out", png], capture_output=True, text=True, timeout=300)
            named = "dp = 1/4, two-stage: C_D %.3f, C_L ±%.3f, St %.4f" % (
                m["mean_drag_coefficient"], m["lift_amplitude"], m["strouhal_number"])
            check(p.returncode == 0 and named in p.stdout and os.path.exists(png)
                  and os.path.getsize(png) > 10000,
                  f"plot_forces.py: exit {p.returncode}, {p.stdout}{p.stderr} (expected {named})")

    # under the sanitizers: the wall, far-field and force code on a short run
    if BACKEND == "cpu" and SANITIZED:
        out = os.path.join(tmp, "short")
        summ, ts = run_quiet(SMALL, "cpu", out, ["time.end=1.0", "time.output_interval=0.5"] + keep)
        if summ is not None:
            check(float(ts["drag_coefficient"][-1]) > 0, "drag positive at t = 1")
            check(float(ts["viscous_force_x"][-1]) > 0, "viscous force along the stream")

    # 2. native against OpenCL over the first second
    if BACKEND == "opencl" or not SANITIZED:
        cross_check("the fluid", ["time.end=1.0", "time.output_interval=0.5"] + keep)

    # 3. a uniform stream through far-field faces stays uniform
    scene = os.path.join(tmp, "uniform_stream.cfg")
    with open(scene, "w") as f:
        f.write(UNIFORM_STREAM)
    out = os.path.join(tmp, "uniform")
    summ, ts = run_quiet(scene, BACKEND, out)
    if summ is not None:
        last = snapshot_paths(out)[-1]
        with h5py.File(last, "r") as f:
            point = f["VTKHDF"]["PointData"]
            rho = np.asarray(point["density"])
            vel = np.asarray(point["velocity"])
        check(len(rho) == 960, f"960 particles, got {len(rho)}")
        drho = float(np.max(np.abs(rho - 1.0)))
        dvel = float(np.max(np.abs(vel[:, :2] - np.array([1.0, 0.0]))))
        check(drho <= 1e-12 and dvel <= 1e-12,
              f"uniform stream at t = 2 ({os.path.basename(last)}): max |rho - 1| = {drho:.3g}, "
              f"max |v - U| = {dvel:.3g}")

    # 4. the ideal gas: (a) the uniform stream
    out = os.path.join(tmp, "uniform-gas")
    summ, ts = run_quiet(scene, BACKEND, out, GAS)
    if summ is not None:
        with h5py.File(snapshot_paths(out)[-1], "r") as f:
            point = f["VTKHDF"]["PointData"]
            rho = np.asarray(point["density"])
            vel = np.asarray(point["velocity"])
            p = np.asarray(point["pressure"])
        dev = max(float(np.max(np.abs(rho - 1.0))),
                  float(np.max(np.abs(vel[:, :2] - np.array([1.0, 0.0])))),
                  float(np.max(np.abs(p / float(P_INF) - 1.0))))
        check(dev <= 1e-12, f"the gas's uniform stream at t = 2: largest departure {dev:.3g}")
    # (b) the gas at rest around the cylinder
    out = os.path.join(tmp, "rest-gas")
    summ, ts = run_quiet(SMALL, BACKEND, out, GAS + keep + [
        "time.end=1.0", "time.output_interval=0.5", "boundary.far_field.velocity=[0.0, 0.0]",
        "forces.reference_speed=1.0"])
    if summ is not None:
        with h5py.File(snapshot_paths(out)[-1], "r") as f:
            vel = np.asarray(f["VTKHDF"]["PointData"]["velocity"])
        speed = float(np.max(np.linalg.norm(vel, axis=1)))
        check(speed <= 1e-12, f"the gas at rest around the cylinder: max |v| = {speed:.3g}")
    # (c) native against OpenCL, the gas in a stream over the first second
    if BACKEND == "opencl" or not SANITIZED:
        cross_check("the gas", GAS + ["time.end=1.0", "time.output_interval=0.5"] + keep)
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish("test_cylinder " + BACKEND)
