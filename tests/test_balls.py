#!/usr/bin/python3
"""test_balls.py BACKEND — the 3D colliding hollow rubber balls (cases/colliding_balls_3d).

000 §6.4: two hollow balls (r_in = 0.03, r_out = 0.04 m, rho0 = 1200, E = 1e7, nu = 0.4,
c0 = 117.851 m/s) whose centres start 0.09 m apart collide head on at v0 = 0.08 c0 each.
000 shows (Fig. 20, dp = 0.001, to t = 0.007 s) a smooth von Mises field and a uniform
particle set; it gives no number.  Here dp = 0.0034 (3958 particles a ball, the wall 2.9
spacings thick), both balls relaxed (placement "relaxed", 300 steps, as 000's level-set
pre-processing; on the lattice the flat lattice faces meeting in the contact disc trip the
zigzag check at t = 0.005 s at this dp, 0.0036 s at dp = 0.001: cases/colliding_balls_3d/
README.md), SPH-ENOG-A, to 0.009 s, past the rebound (the balls part near 0.006 s).
Checks, each bound with its reason and the value measured on the native backend:

- the set-up: the relaxed balls keep the lattice's particle count (3958 each) and mass
  rho0 dp^3, so the initial kinetic energy is sum m v0^2 / 2 = 16.5936 J, the continuum
  shells' 2 x (1/2) rho0 (4 pi / 3)(r_out^3 - r_in^3) v0^2 = 16.5318 J to the lattice's
  volume error (bound 2 %, measured +0.37 %);
- linear momentum, zero at the start, stays zero to round-off (1e-10 of m v0; pair forces
  are antisymmetric and R-bar is per body; measured 1.2e-15 kg m/s);
- the instability monitor stays quiet with its default thresholds (zigzag indicator < 0.3,
  closest pair > 0.5 dp): the run completes (measured: zigzag <= 0.21, closest pair
  0.76 dp);
- the head-on collision of equal balls stops both centres of mass at the deepest
  compression, when the kinetic energy left is the balls' internal motion only: the
  kinetic-energy minimum must fall below 5 % of KE0 (measured 0.86 % at 3.0 ms);
- the balls rebound and part: each ball's centre of mass moves away from the other at the
  end (restitution v_out / v0 between 0.5 and 1, measured 0.867) and their facing sides
  are more than 2 dp apart along the line of centres (measured 16.4 dp);
- energy: the total (kinetic plus the strain energy of the SPH stress field) never exceeds
  E0 by more than 2 % (no energy is created; the strain measure is not the exact energy of
  SPH-ENOG-A, cases/colliding_rings_2d/README.md) and ends between 0.7 and 1 of E0 (the
  Riemann dissipation of the impact, which scales with dp: measured 0.782; 000's rings at
  dp = 0.001 keep 0.844);
- the two balls' energies: the collision is symmetric up to the particle sets (each ball
  relaxed on its own), so their kinetic energies at the end agree within 3 % (measured
  6.354 and 6.388 J) and their centres of mass move with opposite velocities (momentum).
"""
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import SRC, check, finish, run_quiet, snapshot_paths  # noqa: E402

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
DP = 0.0034
RHO0, V0, R_IN, R_OUT = 1200.0, 9.4280904, 0.03, 0.04
tmp = tempfile.mkdtemp(prefix="sphsolid-balls-")
try:
    scene = os.path.join(SRC, "cases", "colliding_balls_3d", "scene.cfg")
    out = os.path.join(tmp, "balls")
    sets = ["resolution.dp=%.15g" % DP, "time.end=0.009", "output.snapshot_interval=0.003"]
    for b in ("left", "right"):
        sets += [f"bodies.{b}.placement=relaxed", f"bodies.{b}.relaxation.steps=300"]
    summ, ts = run_quiet(scene, BACKEND, out, sets, timeout=1800)
    if summ is not None:
        n = summ["particle_count"]
        check(n == 2 * 3958, f"particle count {n} (the lattice's 2 x 3958)")
        t, ke, e = ts["time"], ts["kinetic_energy"], ts["total_energy"]
        ke_shell = 2 * 0.5 * RHO0 * 4 * np.pi / 3 * (R_OUT**3 - R_IN**3) * V0**2
        check(abs(ke[0] / ke_shell - 1) < 0.02,
              f"KE0 {ke[0]:.4f} J against the shells' {ke_shell:.4f} J")
        mom = max(np.max(np.abs(ts["momentum_" + a])) for a in "xyz")
        mass = RHO0 * DP**3
        check(mom < 1e-10 * mass * V0 * n, f"linear momentum at round-off ({mom:.3g} kg m/s)")
        k_min = int(np.argmin(ke))
        check(ke[k_min] < 0.05 * ke[0], f"kinetic-energy minimum {ke[k_min] / ke[0]:.4f} KE0 "
              f"at {1e3 * t[k_min]:.2f} ms")
        check(np.max(e) <= 1.02 * e[0], f"energy never above 1.02 E0 (max {np.max(e) / e[0]:.4f})")
        check(0.7 <= e[-1] / e[0] <= 1.0, f"E(end)/E0 = {e[-1] / e[0]:.3f} in [0.7, 1]")
        with h5py.File(snapshot_paths(out)[-1], "r") as f:
            x = f["VTKHDF/Points"][:]
            v = f["VTKHDF/PointData/velocity"][:]
            body = f["VTKHDF/PointData/body_id"][:]
        left, right = body == 0, body == 1
        v_left, v_right = v[left, 0].mean(), v[right, 0].mean()
        rest = (-v_left / V0, v_right / V0)
        check(all(0.5 < c < 1.0 for c in rest),
              f"restitution {rest[0]:.3f}, {rest[1]:.3f} in (0.5, 1)")
        check(abs(v_left + v_right) < 1e-9 * V0, f"centres of mass at opposite velocities "
              f"({v_left:.6f}, {v_right:.6f} m/s)")
        ke_l = 0.5 * mass * np.sum(v[left] ** 2)
        ke_r = 0.5 * mass * np.sum(v[right] ** 2)
        check(abs(ke_l / ke_r - 1) < 0.03, f"the balls' kinetic energies at the end "
              f"{ke_l:.4f}, {ke_r:.4f} J")
        # the facing sides: the left ball's rightmost particle and the right's leftmost
        gap = float(np.min(x[right, 0]) - np.max(x[left, 0]))
        check(gap > 2 * DP, f"the balls apart at the end: {gap / DP:.1f} dp between their "
              "facing sides")
        print("colliding balls dp = %g: KE0 %.4f J (shells %.4f), KE minimum %.4f KE0 at %.2f ms, "
              "max E/E0 %.4f, E(end)/E0 %.3f, restitution %.3f / %.3f, end KE %.4f / %.4f J, "
              "gap %.1f dp, zigzag max %.3f, closest pair %.3f dp, momentum %.3g kg m/s" % (
                  DP, ke[0], ke_shell, ke[k_min] / ke[0], 1e3 * t[k_min], np.max(e) / e[0],
                  e[-1] / e[0], rest[0], rest[1], ke_l, ke_r, gap / DP,
                  np.max(ts["zigzag_indicator"]), np.min(ts["min_distance_ratio"]), mom))
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish("test_balls_" + BACKEND)
