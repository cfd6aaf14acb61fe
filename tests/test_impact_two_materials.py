#!/usr/bin/python3
"""test_impact_two_materials.py BACKEND — a steel rod strikes a free aluminium plate with J2
at 20 m/s (cases/impact_two_materials: two bodies of two materials in contact, SPH-GNOG-A).

At dp = 1 mm (3 600 particles) on the given backend:
- the run completes with the monitor quiet; snapshots carry material_id 0 for the rod's
  particles and 1 for the plate's (their body ids 0 and 1);
- momentum conserved to round-off: summary max_linear_momentum_drift <= 1e-12;
- no interpenetration beyond dp/4: min_distance_ratio >= 0.75 at every output;
- energy bounded: E(t) <= E(0) (1 + 1e-6).
On the native backend, also at the scene's dp = 0.5 mm:
- J2 acts in the plate only: some plate particle has yielded, no rod particle has;
- the contact stress at the centre, rod_face_first_pulse, approaches the acoustic estimate
  Z_s Z_a/(Z_s + Z_a) v0 from below (README.md): below it at both resolutions, and the
  shortfall at 0.5 mm at most 0.6 of that at 1 mm (first order: measured 0.45).
"""
import math
import os
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import SANITIZED, SRC, check, finish, run_quiet, snapshot_paths  # noqa: E402

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
SCENE = os.path.join(SRC, "cases", "impact_two_materials", "scene.cfg")


def impedance(rho, e, nu):
    """sqrt(rho0 (K + G)) of the 2D model (host/run/analysis.h)"""
    k, g = e / (3 * (1 - 2 * nu)), e / (2 * (1 + nu))
    return math.sqrt(rho * (k + g))


Z_S, Z_A = impedance(7800.0, 2.0e11, 0.3), impedance(2700.0, 6.9e10, 0.33)
ESTIMATE = Z_S * Z_A / (Z_S + Z_A) * 20.0  # Pa, compressive


def run(tmp, dp, plastic_check):
    out = os.path.join(tmp, f"dp{dp}")
    summ, ts = run_quiet(SCENE, BACKEND, out, [f"resolution.dp={dp}"])
    if summ is None:
        return None
    m = summ["metrics"]
    check(m["max_linear_momentum_drift"] <= 1e-12,
          f"dp {dp}: momentum drift {m['max_linear_momentum_drift']:.2e}")
    closest = float(np.min(ts["min_distance_ratio"]))
    check(closest >= 0.75, f"dp {dp}: closest pair {closest:.4f} dp (>= 0.75)")
    e = ts["total_energy"]
    check(np.max(e) <= e[0] * (1 + 1e-6), f"dp {dp}: E(t) <= E(0): max {np.max(e) / e[0]:.8f}")
    with h5py.File(snapshot_paths(out)[-1], "r") as f:
        body = f["VTKHDF/PointData/body_id"][:]
        material = f["VTKHDF/PointData/material_id"][:]
        alpha = f["VTKHDF/PointData/plastic_strain"][:]
    check(np.array_equal(material, body), "material_id is 0 on the rod, 1 on the plate")
    if plastic_check:
        check(np.max(alpha[body == 1]) > 0 and np.max(alpha[body == 0]) == 0,
              f"dp {dp}: the plate yields (alpha up to {np.max(alpha[body == 1]):.2e}), "
              f"the rod does not ({np.max(alpha[body == 0]):.1e})")
    pulse = -m["rod_face_first_pulse"]
    print(f"impact dp = {dp} ({BACKEND}): contact stress {pulse / 1e6:.1f} MPa of "
          f"{ESTIMATE / 1e6:.1f} ({pulse / ESTIMATE:.3f}), closest {closest:.4f} dp, momentum "
          f"drift {m['max_linear_momentum_drift']:.1e}, E(end)/E(0) {e[-1] / e[0]:.4f}")
    return pulse


with tempfile.TemporaryDirectory(prefix="test_impact_two_materials.") as tmp:
    coarse = run(tmp, 0.001, False)
    if BACKEND == "cpu" and not SANITIZED and coarse is not None:
        fine = run(tmp, 0.0005, True)
        if fine is not None:
            gap_coarse, gap_fine = ESTIMATE - coarse, ESTIMATE - fine
            check(gap_coarse > 0 and gap_fine > 0 and gap_fine <= 0.6 * gap_coarse,
                  f"shortfall to the estimate {gap_coarse / ESTIMATE:.3f} at 1 mm, "
                  f"{gap_fine / ESTIMATE:.3f} at 0.5 mm (<= 0.6 of it)")
finish("test_impact_two_materials")
