#!/usr/bin/python3
"""test_spinning_cube.py BACKEND — the 3D spinning cube of 003 §5.1.4 (cases/spinning_cube_3d).

A unit cube in rigid rotation at omega = (0, 0, 50) rad/s, nu = 0.3, single-criterion
stepping at acoustic CFL 0.1, h = 1.15 dp (the case's), to t = 0.5 s (0.25 s on OpenCL:
pocl's rebuild after every step takes 3 minutes for the whole run; 0.1 s under the
sanitizers, SPHSOLID_SANITIZED), SPH-GNOG-A with the averaged rotation, at dp = 0.1 (1 000
particles; the paper's dp = 0.05 is the benchmark, tools/bench_cases.py).  Checks:

- the initial kinetic energy is the lattice's rigid-body value sum (1/2) m omega^2
  (x^2 + y^2), to 1e-12;
- the maximum angular-momentum error over the run is at most 1.2 x 003's 1.18 %, the
  issue's bound (measured 0.225 % at this dp, 0.125 % at dp = 0.05);
- linear momentum is conserved to round-off and the angular momentum stays about z
  (its x and y components below 1e-12 of L0).

SPH-ENOG-A as 003 prints it (the case's default), on the native backend: the maximum
angular-momentum error is at most 1.2 x 003's 2.67 % (measured 1.29 % at this dp to 0.5 s,
0.93 % at dp = 0.05; at the 1.3 dp of 003's text 1.93 % and 20.1 %,
cases/spinning_cube_3d/README.md), linear momentum at round-off.  The OpenCL run of the same
kernels is the torque-projected one below, which differs by the projection only.
SPH-ENOG-A with method.torque_projection (device/sph_torque_projection.h), both backends: to
the same end time, its maximum angular-momentum error is at most 0.05 % (measured 0.004 % at
dp = 0.1 to 0.5 s), linear momentum at round-off, and the cube stays orderly (zigzag
indicator below 0.05, measured 0.010; the monitor trips at 0.3).
"""
import os
import shutil
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import SANITIZED, SRC, check, finish, run_results, run_sphsolid  # noqa: E402

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
tmp = tempfile.mkdtemp(prefix="sphsolid-cube-")
scene = os.path.join(SRC, "cases", "spinning_cube_3d", "scene.cfg")
dp, rho0, omega = 0.1, 1100.0, 50.0
# pocl rebuilds 5 570 times more slowly (single stepping): half the run there; under the
# sanitizers (SPHSOLID_SANITIZED) a fifth, which exercises the same code
end = 0.5 if BACKEND == "cpu" else 0.25
if SANITIZED:
    end = 0.1


def run_cube(name, label, sets, bound, bound_text):
    """Run the cube at dp to `end` with `sets`; check that it completes, its maximum
    angular-momentum error against `bound` and its linear momentum at round-off.
    Returns (summary, series, error, drift), or None when the run failed."""
    out = os.path.join(tmp, name)
    code, err = run_sphsolid(scene, BACKEND, out, ["resolution.dp=%g" % dp,
                                                   "time.end=%g" % end] + sets, timeout=1800)
    check(code == 0, f"{label}: exit {code} ({err})")
    if code != 0:
        return None
    summ, ts = run_results(out)
    err_l = summ["metrics"]["max_angular_momentum_error"]
    check(abs(ts["time"][-1] - end) < 1e-12, f"{label}: reached t = {end} s ({ts['time'][-1]})")
    check(err_l <= bound, f"{label}: maximum angular-momentum error {100 * err_l:.4f} % "
          f"(bound {bound_text})")
    drift = summ["metrics"]["max_linear_momentum_drift"]
    check(drift < 1e-9, f"{label}: linear momentum drift {drift:.3g}")
    return summ, ts, err_l, drift


try:
    gnog = run_cube("cube", "SPH-GNOG-A", ["method.formulation=gnog-a"], 1.2 * 0.0118,
                    "1.2 x 003's 1.18 %")
    if BACKEND == "cpu":
        r = run_cube("cube-enog-a", "SPH-ENOG-A", [], 1.2 * 0.0267, "1.2 x 003's 2.67 %")
        if r:
            print("spinning cube dp = %g, SPH-ENOG-A: max angular-momentum error %.3f %%, "
                  "momentum drift %.3g" % (dp, 100 * r[2], r[3]))
    r = run_cube("cube-enog-a-projected", "SPH-ENOG-A with the torque projection",
                 ["method.torque_projection=true"], 5e-4, "0.05 %")
    if r:
        summ, ts, err_l, drift = r
        check(summ["features"]["torque_projection"] is True, "summary lists the projection")
        zigzag = float(np.max(ts["zigzag_indicator"]))
        check(zigzag < 0.05, f"zigzag indicator {zigzag:.4f}")
        print("spinning cube dp = %g, SPH-ENOG-A with the torque projection: max angular-momentum "
              "error %.4f %%, momentum drift %.3g, zigzag %.4f, E/E0 %.4f" % (
                  dp, 100 * err_l, drift, zigzag,
                  ts["total_energy"][-1] / ts["total_energy"][0]))
    if gnog:
        summ, ts, err, drift = gnog
        c = (np.arange(10) + 0.5) * dp - 0.5
        x, y = np.meshgrid(c, c, indexing="ij")
        ke0 = 10 * np.sum(0.5 * rho0 * dp ** 3 * omega ** 2 * (x ** 2 + y ** 2))
        check(abs(ts["kinetic_energy"][0] / ke0 - 1) < 1e-12,
              f"initial kinetic energy {ts['kinetic_energy'][0]:.10g} against {ke0:.10g}")
        l0 = ts["angular_momentum_z"][0]
        tilt = max(np.max(np.abs(ts["angular_momentum_x"])),
                   np.max(np.abs(ts["angular_momentum_y"])))
        check(tilt < 1e-12 * l0, f"angular momentum stays about z ({tilt / l0:.3g} L0)")
        print("spinning cube dp = %g, SPH-GNOG-A: KE0 %.6g J, max angular-momentum error %.3f %%, "
              "momentum drift %.3g, %d steps" % (dp, ts["kinetic_energy"][0], 100 * err, drift,
                                                  summ.get("acoustic_steps", -1)))
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish("test_spinning_cube_" + BACKEND)
