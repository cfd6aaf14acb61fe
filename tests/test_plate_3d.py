#!/usr/bin/python3
"""test_plate_3d.py BACKEND — the 3D simply supported plate (cases/oscillating_plate_3d).

Mode (2, 2) at H/dp = 3 (44 652 particles, SPH-ENOG-A, h = 1.15 dp as the case states) to
t = 0.016 s, past the first period.  The public reference code ran this
very lattice (reference notes §6.3: one ring of particles outside the edges, the mid-plane
layer of the ring held in z) and stored its kinetic energy, 0.200006 at t = 0, 0.196374 at
its first maximum after the start.  Checks:

- the initial kinetic energy equals the reference code's 0.200006 J to 1e-4 (0.2000091:
  the lattice's sum of (1/2) m sin^2 sin^2, the continuum value being 0.2 J);
- the supports hold: the mid-plane ring particles never move along z (displacement
  exactly 0);
- the plate returns its energy: the first kinetic-energy maximum after the start lies
  within 2 % of the reference code's 0.196374 (measured 0.1983), so the scheme's
  dissipation over half a period is the reference's;
- the motion keeps the mode's symmetry: linear momentum at round-off, the observers at
  (L/4, W/4) and at the centre (a node of (2, 2)) as the mode shape says: the centre's z
  stays below 1e-3 of the quarter point's amplitude;
- the first period (the quarter point's second pass through z = 0 after the start, the solver's
  `first_period`) lies within 3 % of 003 Table 3's 0.0149 s (issue 4's bound; measured
  0.014853 s; 0.01566 s, +5.1 %, with the h = 1.3 dp that 003's text states, the case's
  README), and the half period (its first downward pass) within 3 % of 7.45 ms;
- the first period within 1 % of the flexural period of the same lattice's linearised
  operator (tools/plate3d_operator_period.py: continuity, pressure and the ENOG Laplacian on
  an infinite three-layer slab, 0.014839 s; the run: 0.014853 s).
"""
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import SRC, check, finish, run_quiet, snapshot_paths  # noqa: E402

sys.path.insert(0, os.path.join(SRC, "tools"))
from plate3d_operator_period import TABLE3, TABLE3_RATIOS, operator_period  # noqa: E402

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
tmp = tempfile.mkdtemp(prefix="sphsolid-plate3d-")
try:
    scene = os.path.join(SRC, "cases", "oscillating_plate_3d", "scene.cfg")
    out = os.path.join(tmp, "plate")
    sets = ["time.end=0.016", "output.snapshot_interval=0.003", "analysis.period.observer=quarter"]
    summ, ts = run_quiet(scene, BACKEND, out, sets, timeout=1800)
    if summ is not None:
        t, ke = ts["time"], ts["kinetic_energy"]
        check(abs(ke[0] / 0.200006 - 1) < 1e-4, f"initial kinetic energy {ke[0]:.7f} J "
              "(reference code 0.200006)")
        first_half = int(np.searchsorted(t, 0.009))  # to past the first maximum
        k_min = int(np.argmin(ke[:first_half]))
        k_max = k_min + int(np.argmax(ke[k_min:first_half]))
        check(abs(ke[k_max] / 0.196374 - 1) < 0.02, f"first kinetic-energy maximum "
              f"{ke[k_max]:.5f} J at {1e3 * t[k_max]:.2f} ms (reference code 0.196374)")
        zq, zc = ts["quarter_z"], ts["centre_z"]
        check(np.max(np.abs(zc)) < 1e-3 * np.max(np.abs(zq)),
              f"the centre, a node of (2, 2), stays put ({np.max(np.abs(zc)):.3g} m)")
        mom = max(np.max(np.abs(ts["momentum_x"])), np.max(np.abs(ts["momentum_y"])))
        check(mom < 1e-9 * ke[0], f"in-plane momentum at round-off ({mom:.3g})")
        drift = 0.0
        for path in snapshot_paths(out):
            with h5py.File(path, "r") as f:
                x = f["VTKHDF/Points"][:]
                u = f["VTKHDF/PointData/displacement"][:]
            x0 = x - u
            ring = ((x0[:, 0] < 0) | (x0[:, 0] > 0.4) | (x0[:, 1] < 0) | (x0[:, 1] > 0.4)) & \
                (np.abs(x0[:, 2]) < 1e-6)
            drift = max(drift, float(np.max(np.abs(u[ring, 2]))))
        check(drift == 0.0, f"the supports hold: mid-plane ring z displacement {drift:.3g} m")
        up = np.nonzero((zq[1:] <= 0) & (zq[:-1] > 0))[0]
        half = t[up[0]] + (t[up[0] + 1] - t[up[0]]) * zq[up[0]] / (zq[up[0]] - zq[up[0] + 1]) \
            if len(up) else float("nan")
        period = summ.get("metrics", {}).get("first_period")
        published = TABLE3["enog-a"][(2, 2)][TABLE3_RATIOS.index(3)]  # 0.0149 s
        check(period is not None and abs(period / published - 1) <= 0.03,
              f"first period {period} s within 3 % of 003's {published} s")
        check(abs(half / (published / 2) - 1) <= 0.03,
              f"half period {1e3 * half:.3f} ms within 3 % of {500 * published:.2f} ms")
        # the same lattice's linearised operator, without time stepping or edges:
        # the run is that operator's dynamics
        res = summ["resolved"]
        t_op = operator_period(3, (2, 2), res["smoothing_length"] / res["dp"])
        check(period is not None and abs(period / t_op - 1) <= 0.01,
              f"first period {period} s within 1 % of the linearised operator's {t_op:.6f} s")
        print("3D plate (2,2) H/dp = 3: KE0 %.7f J, first KE maximum %.5f J at %.2f ms, half "
              "period %.2f ms, first period %.3f ms (003: 14.9 ms), supports %.3g m" %
              (ke[0], ke[k_max], 1e3 * t[k_max], 1e3 * half, 1e3 * (period or 0), drift))
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish("test_plate_3d_" + BACKEND)
