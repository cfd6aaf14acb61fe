#!/usr/bin/python3
"""test_gas_walls.py BACKEND — wall bodies in the ideal gas ("eulerian-compressible"): Sod's shock
reflected by a rigid wall (cases/shock_reflection_1d), against the exact solution.

The case's scene.cfg: a tube x in [0, 1], closed at both ends by wall bodies (particles at
dp/2), a strip of 10 rows periodic across (dp = 1/200, 2 480 particles), holds Sod's states
(rho, p) = (1, 1) left of x = 0.5 and (0.125, 0.1) right of it, at rest, gamma = 1.4, the
seed's eta_HLLC = 1, SSP-RK3, method.background_pressure = 0.1 (the walls bound the gas
without a far field: the scene must give it).  The exact Riemann solution (the case's
exact.py) sends a shock to the right at 1.75216 into the gas at rest; behind it (state 2)
p* = 0.303130, u* = 0.927453.  The shock meets the right wall at t = 0.28536 and comes back at
1.01019 through state 2, leaving the gas at rest at the state of the Rankine-Hugoniot
relations for a shock that stops u* (state 5): p5 = 0.780386, rho5 = 0.509395.  At t = 0.38 the
reflected shock is at x = 0.9044; the contact it will meet at t = 0.4068 is at 0.852.  Checks
(measured 2026-11-29, native backend, the source of this commit):

- between x = 0.93 and 0.99 (the gas at rest against the wall) the mean pressure within 2 % of
  p5 (measured 0.7720, -1.1 %; with eta = 5 0.7806, +0.03 %: the seed's eta = 1 leaves the
  reflected shock's oscillations, p in 0.65-0.91), the mean density within 2 % of rho5
  (0.5075, -0.4 %) and the mean velocity below 0.02 of u* (measured 0.0074);
- between x = 0.80 and 0.88 (state 2 and the contact, across which p and u do not jump; the
  reflected shock has not come this far) the pressure within 0.5 % of p* and the velocity
  within 0.5 % of u* (measured 0.30313 and 0.92745);
- the L1 density error of a row (cases/shock_reflection_1d/plot.py: the mean of |rho -
  rho_exact(x)| over it) at most 0.02 (measured 0.0171; most of it the zigzag that the left
  wall leaves where p - p_b = 0.9, README.md);
- the walls let no mass or energy through and do no work: the total mass and total energy
  stay constant to 1e-12 (measured 2.9e-14 and 2.8e-14 over 443 steps), the momentum across
  the tube at round-off.
"""
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import SRC, check, finish, run_quiet, snapshot_paths  # noqa: E402

CASE = os.path.join(SRC, "cases", "shock_reflection_1d")
sys.path.insert(0, CASE)
from exact import X0, Solution  # noqa: E402
from plot import measure  # noqa: E402

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
END = 0.38  # scene.cfg's time.end

exact = Solution()
p_star, u_star, p5, rho5 = exact.p_star, exact.u_star, exact.p5, exact.rho5
x_reflected, x_contact = exact.shock_position(END), X0 + u_star * END
print(f"exact: p* {p_star:.6f}, u* {u_star:.6f}, shock {exact.shock:.5f}; reflected at t = "
      f"{exact.t_wall:.5f}, speed {exact.reflected:.5f}; p5 {p5:.6f}, rho5 {rho5:.6f}; at "
      f"t = {END}: reflected shock x = {x_reflected:.4f}, contact x = {x_contact:.4f}")
# the windows below lie where the exact solution says they do: the reflected shock between
# them, not yet at the contact
assert END < exact.t_valid and x_contact < 0.88 < x_reflected < 0.93

tmp = tempfile.mkdtemp(prefix="test_gas_walls.")
try:
    out = os.path.join(tmp, "tube")
    summ, ts = run_quiet(os.path.join(CASE, "scene.cfg"), BACKEND, out)
    if summ is not None:
        with h5py.File(snapshot_paths(out)[-1], "r") as f:
            x = np.asarray(f["VTKHDF/Points"])[:, 0]
            point = f["VTKHDF/PointData"]
            p = np.asarray(point["pressure"])
            rho = np.asarray(point["density"])
            u = np.asarray(point["velocity"])[:, 0]

        def mean(field, lo, hi):
            return float(field[(x > lo) & (x < hi)].mean())

        p_rest, rho_rest, u_rest = mean(p, 0.93, 0.99), mean(rho, 0.93, 0.99), mean(u, 0.93, 0.99)
        print(f"t = {END}, x in (0.93, 0.99): p {p_rest:.4f}, rho {rho_rest:.4f}, u {u_rest:.4f}; "
              f"x in (0.80, 0.88): p {mean(p, 0.80, 0.88):.5f}, u {mean(u, 0.80, 0.88):.5f}")
        check(abs(p_rest / p5 - 1.0) <= 0.02,
              f"the reflected gas's pressure {p_rest:.4f} within 2 % of p5 = {p5:.4f}")
        check(abs(rho_rest / rho5 - 1.0) <= 0.02,
              f"the reflected gas's density {rho_rest:.4f} within 2 % of rho5 = {rho5:.4f}")
        check(abs(u_rest) <= 0.02 * u_star, f"the reflected gas at rest: u = {u_rest:.4f}")
        p2, u2 = mean(p, 0.80, 0.88), mean(u, 0.80, 0.88)
        check(abs(p2 / p_star - 1.0) <= 0.005 and abs(u2 / u_star - 1.0) <= 0.005,
              f"state 2 ahead of the reflected shock: p {p2:.5f}, u {u2:.5f} "
              f"(exact {p_star:.5f}, {u_star:.5f})")
        # the whole profile: the L1 density error of a row against the exact one
        l1 = measure(out, exact)["l1_density"]
        check(l1 <= 0.02, f"the L1 density error {l1:.5f} at most 0.02 (documented 0.0171)")
        for column in ("mass", "total_energy"):
            first, last = float(ts[column][0]), float(ts[column][-1])
            check(abs(last / first - 1.0) <= 1e-12,
                  f"the closed tube's {column} constant: {first!r} -> {last!r}")
        across = max(abs(float(v)) for v in ts["momentum_y"])
        check(across <= 1e-12 * float(ts["mass"][0]) * u_star,
              f"no momentum across the tube: {across:.3g}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish("test_gas_walls " + BACKEND)
