#!/usr/bin/python3
"""test_fluids.py BACKEND — the eulerian formulations (seed 004's extended Eulerian SPH) on the
cases cases/taylor_green_2d and cases/shu_osher_1d.

1. Conservation on the periodic box (both backends, also under the sanitizers): the
   Taylor-Green vortex at dp = 0.05 (400 particles) to t = 0.5, weakly compressible
   (scene.cfg) and as an ideal gas with HLLC (public_code.cfg), each with the two-stage update
   and with time.integrator = "ssp-rk2" and "ssp-rk3" (which allocate their own buffers and compile their own
   passes, not the other's).  The fluxes are pairwise
   antisymmetric and the particles fixed, so over the run the relative change of the mass and,
   for the ideal gas, of the total energy (the viscous work enters the internal energy
   pairwise) is round-off, <= 1e-12 (measured 2e-15 and 5.7e-15 native, 0 on pocl: the 15
   digits timeseries.csv prints), and the momentum stays at round-off of its physical scale
   sqrt(2 KE0 M) = 0.707, <= 1e-12 of it (measured 5e-17 to 9e-16; a physical effect would
   be O(1) of it).  The kinetic energy decays (viscosity), and the weakly compressible run's
   total energy, KE + the EOS's internal energy, never rises.  Every snapshot's vorticity is
   the curl of the velocity beside it (check_vorticity); snapshots without the vorticity give
   neither its buffer nor its pass.
2. The weakly compressible vortex at the seed's dp = 1/50 to t = 5 (native backend of the
   release build): KE(5) within 30 % of the exact 0.25 exp(-16 pi^2 t / 100) = 9.309e-5 with
   the Laguerre-Gauss kernel (the issue's acceptance; measured 8.545e-5, -8.2 %), and
   Laguerre-Gauss closer to exact than Wendland (5.631e-5, -39.5 %): 004 Fig. 4's ordering.
   Its error converges at second order, as 004 says: with Laguerre-Gauss the error of KE(5)
   at dp = 1/25 is at least 3 times that at dp = 1/50 (the issue's "at least 3x smaller per
   halving of dp"; measured 6.507e-5, -30.1 %: 3.67 times; dp = 1/100, not run here: -2.07 %,
   3.97 times smaller again, docs/benchmarks-fluids.md).
3. The vortex the public reference code's way (public_code.cfg: ideal gas, HLLC with eta = 5,
   Laguerre-Gauss, dp = 1/50; native, release): KE(1) and KE(5) within 5 % of the public code's
   stored regression values 0.0420539 and 6.861e-5 (measured 0.0422921, +0.57 %, and
   7.0642e-5, +2.96 %); mass and total energy constant to 1e-12.
4. Shu-Osher (cases/shu_osher_1d at dp = 1/200, t = 1.8; native, release): the L1 density
   error of one row against reference_density.csv (the mean over the row's particles of
   |rho - rho_ref(x)|, rho_ref linearly interpolated; README.md) smaller with Laguerre-Gauss than
   with Wendland (004 Fig. 3: the issue's acceptance; measured 0.0235 against 0.0556) and
   below 0.03 with Laguerre-Gauss; every row of the strip the same 1D solution (1e-9 of the
   density range; measured 2.5e-12 LG, 1.5e-14 W); the changes of mass, x momentum and total
   energy equal to the exact fluxes through the two fixed-state buffers, rho_L u_L t H,
   (rho_L u_L^2 + p_L - p_R) t H and (E_L + p_L) u_L t H, within 1e-6 (measured -9.5e-9 LG,
   -1.05e-8 W: the interior conserves, the buffers feed the inflow).
4b. The same tube as a true 1D line (line.cfg, dimension = 1; both backends, the native one also
   under the sanitizers): Laguerre-Gauss's L1 density error below Wendland's and below 0.035
   (measured 0.0303 and 0.0504 on 2026-11-27, README.md "Strip or line"); mass, momentum and
   energy against the buffers' fluxes per unit cross-section within 1e-6.
5. Bad input and the monitor: a negative initial pressure, as a number and as an expression,
   exits 2 naming bodies.<name>.initial_pressure (the expression's row names the particle and
   the value); an ideal gas torn apart (+-20 c0 from the middle) loses positive pressure at once
   and the instability monitor stops it (exit 4, summary.json's instability record: the time,
   particle and body).

6. The native backend (also under the sanitizers): the vortex at dp = 1/100 (10 000
   particles, periodic on both axes), weakly compressible and as an ideal gas, gives the same
   bits on 1 and on 2 threads (the fluid pairs summed once, docs/backends.md).
7. Every backend: a density bump of 1 % carried by a uniform stream at Mach 0.1 through a
   periodic box: the public code's two-stage update amplifies its short waves (acoustic energy
   more than 10 times its start by t = 5; measured 40 times), SSP-RK3 does not (the energy never
   rises above its start and halves by t = 20; measured 3.17e-3 from 7.85e-3).
8. Three dimensions, every backend: the vortex extruded in z (extruded_3d.cfg, 3200 particles,
   Wendland C2, t = 0.5) conserves mass and momentum as in 1, stays two-dimensional (no z
   velocity beyond round-off), its kinetic energy decays and its total energy never rises; on
   the native release build its KE(0.5) error at dp = 0.025 is at least 2 times smaller than at
   0.05 (measured 2.6 times).  The Laguerre kernels in 3D are refused (exit 2, nothing written):
   there they turn the Riemann dissipation into a source of kinetic energy.

Under the sanitizers (SPHSOLID_SANITIZED) 2-4 are left to the release build; on the OpenCL
backend 2-4 are not run (the native backend is the reference; test_cross_check compares the
backends on these cases to 1e-10).
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, SANITIZED, SRC, check, finish, run_results, run_sphsolid  # noqa: E402

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
LONG_RUNS = BACKEND == "cpu" and not SANITIZED
TGV = os.path.join(SRC, "cases", "taylor_green_2d", "scene.cfg")
TGV_GAS = os.path.join(SRC, "cases", "taylor_green_2d", "public_code.cfg")
SHU_OSHER = os.path.join(SRC, "cases", "shu_osher_1d", "scene.cfg")
SHU_OSHER_LINE = os.path.join(SRC, "cases", "shu_osher_1d", "line.cfg")
REFERENCE = os.path.join(SRC, "cases", "shu_osher_1d", "reference_density.csv")
tmp = tempfile.mkdtemp(prefix="sphsolid-fluids-")


def exact_ke(t):
    """The Taylor-Green vortex's kinetic energy at Re = 100."""
    return 0.25 * math.exp(-16.0 * math.pi ** 2 * t / 100.0)


def run(scene, name, sets=()):
    """Run a scene that must complete: (summary, time series) or (None, None)."""
    out = os.path.join(tmp, name)
    code, err = run_sphsolid(scene, BACKEND, out, sets)
    check(code == 0, "%s: exit %d (%s)" % (name, code, err))
    if code != 0:
        return None, None
    summ, ts = run_results(out)
    check(summ["status"] == "completed" and "instability" not in summ,
          "%s: monitor quiet (%s)" % (name, summ.get("instability")))
    return summ, ts


def at(ts, column, t):
    """The column's value at the output time t."""
    i = int(np.argmin(np.abs(ts["time"] - t)))
    check(abs(ts["time"][i] - t) < 1e-9, "an output at t = %g (nearest %g)" % (t, ts["time"][i]))
    return float(ts[column][i])


def rel_change(ts, column):
    """max |q(t) - q(0)| / |q(0)| over the run."""
    q = ts[column]
    return float(np.max(np.abs(q - q[0])) / abs(q[0]))


def check_vorticity(label, out):
    """Every snapshot's vorticity is the curl of the velocity written beside it: the vortex's
    velocity U (-cos 2 pi x sin 2 pi y, sin 2 pi x cos 2 pi y) has the curl 4 pi U cos 2 pi x
    cos 2 pi y, so the vorticity's amplitude in that shape over the velocity's, both fitted by
    least squares, is 1 up to the discrete curl's error (measured 6.85e-4 at dp = 0.05 in every
    snapshot, t = 0 included, on both backends; the curl of the first stage's v', which the steps
    formed before, gave 6.83e-4 at t = 0.5 and nothing at t = 0)."""
    with open(os.path.join(out, "snapshots.hdf.series")) as f:
        files = json.load(f)["files"]
    check(len(files) >= 2, "%s: snapshots at t = 0 and after (%d)" % (label, len(files)))
    for entry in files:
        with h5py.File(os.path.join(out, entry["name"]), "r") as f:
            x = f["VTKHDF/Points"][:]
            v = f["VTKHDF/PointData/velocity"][:]
            w = f["VTKHDF/PointData/vorticity"][:].ravel()
        cx, sx = np.cos(2 * np.pi * x[:, 0]), np.sin(2 * np.pi * x[:, 0])
        cy, sy = np.cos(2 * np.pi * x[:, 1]), np.sin(2 * np.pi * x[:, 1])
        shape_v = np.concatenate([-cx * sy, sx * cy])
        shape_w = 4.0 * np.pi * cx * cy
        a_v = shape_v @ np.concatenate([v[:, 0], v[:, 1]]) / (shape_v @ shape_v)
        a_w = shape_w @ w / (shape_w @ shape_w)
        check(a_v > 0.1 and abs(a_w / a_v - 1.0) <= 1e-3,
              "%s: the vorticity at t = %g is the curl of the velocity (amplitudes %.6g, %.6g)"
              % (label, entry["time"], a_v, a_w))


# --- 1. conservation on the periodic box, both backends
for label, scene, integrator in (("weakly compressible", TGV, None),
                                 ("ideal gas", TGV_GAS, None),
                                 ("weakly compressible, SSP-RK2", TGV, "ssp-rk2"),
                                 ("ideal gas, SSP-RK2", TGV_GAS, "ssp-rk2"),
                                 ("weakly compressible, SSP-RK3", TGV, "ssp-rk3"),
                                 ("ideal gas, SSP-RK3", TGV_GAS, "ssp-rk3")):
    runge_kutta = integrator is not None  # SSP-RK: its own buffers and passes
    name = "tgv-%s-%s" % ("gas" if scene == TGV_GAS else "wc", integrator or "two-stage")
    summ, ts = run(scene, name, ["resolution.dp=0.05", "time.end=0.5", "time.output_interval=0.05"]
                   + (["time.integrator=" + integrator] if integrator else []))
    if summ is None:
        continue
    check(summ["particle_count"] == 400, "%s: 400 particles (%d)" % (label, summ["particle_count"]))
    # only what a fluid scene uses is allocated and compiled in (host/model/fields.c): the fluid's
    # conserved variables and rates, none of the solid's stress, rotation or acoustic buffers
    buffers = {b["name"] for b in summ["memory"]["buffers"]}
    # the update's own buffers: v' of the two stages, or SSP-RK's momentum rate and U^n
    update = {"momentum_rate", "state_saved"} if runge_kutta else {"vel_stage"}
    other_update = {"vel_stage"} if runge_kutta else {"momentum_rate", "state_saved"}
    needed = {"pressure", "mass_rate", "vorticity"} | update | (
        {"energy", "energy_rate", "sound_speed"} if scene == TGV_GAS else set())
    solid = {"tau", "drho", "acc_diss", "acc_shear", "dacc_shear", "spin", "defgrad", "pk1"}
    unused = solid | other_update | (
        set() if scene == TGV_GAS else {"energy", "energy_rate", "sound_speed"})
    check(needed <= buffers, "%s: the fluid's buffers allocated (missing %s)"
          % (label, sorted(needed - buffers)))
    check(not (unused & buffers), "%s: no buffer it does not use (%s)"
          % (label, sorted(unused & buffers)))
    if BACKEND == "opencl":
        kernels = {k.split("(")[0] for k in summ["program_kernels"]}
        passes = {"eulerian_rates", "eulerian_rk_update"} if runge_kutta else {
            "eulerian_momentum_rate", "eulerian_mass_energy_rate", "eulerian_update"}
        others = {"eulerian_momentum_rate", "eulerian_rates"} - passes
        check(passes <= kernels and not (others & kernels) and not any(
            k.startswith(("acoustic_", "tl_")) for k in kernels),
            "%s: the program has its update's passes, not the other's, and no solid pass (%s)"
            % (label, sorted(kernels)))
        check("eulerian_vorticity" in kernels and "-DSPH_FLUID_VORTICITY=1" in summ["build_options"],
              "%s: the snapshots' vorticity pass in the program" % label)
    ke0, mass0 = ts["kinetic_energy"][0], ts["mass"][0]
    check(abs(ke0 - 0.25) < 1e-12, "%s: KE(0) = 0.25 on the lattice (%.17g)" % (label, ke0))
    check_vorticity(label, os.path.join(tmp, name))
    dm = rel_change(ts, "mass")
    p_scale = math.sqrt(2.0 * ke0 * mass0)
    dp = float(np.max(np.hypot(ts["momentum_x"], ts["momentum_y"]))) / p_scale
    print("%s, %s, dp = 0.05 to t = 0.5: mass change %.3g, |momentum| %.3g of sqrt(2 KE0 M), "
          "KE(0.5) %.6g (exact %.6g)" % (label, BACKEND, dm, dp, ts["kinetic_energy"][-1],
                                         exact_ke(0.5)))
    # round-off bounds: a few orders above the measurements, far below any physical effect
    check(dm <= 1e-12, "%s: mass conserved (%.3g > 1e-12)" % (label, dm))
    check(dp <= 1e-12, "%s: momentum at round-off (%.3g of its scale > 1e-12)" % (label, dp))
    check(np.all(np.diff(ts["kinetic_energy"]) < 0.0), "%s: kinetic energy decays" % label)
    if scene == TGV_GAS:
        de = rel_change(ts, "total_energy")
        print("    total energy change %.3g" % de)
        check(de <= 1e-12, "ideal gas: total energy conserved (%.3g > 1e-12)" % de)
    else:
        # the viscous work and the Riemann dissipation leave the weakly compressible fluid
        rise = float(np.max(np.diff(ts["total_energy"])))
        check(rise <= 1e-12 * ts["total_energy"][0],
              "weakly compressible: total energy never rises (%.3g)" % rise)

# snapshots without the vorticity: neither its buffer nor its pass
summ, ts = run(TGV, "tgv-no-vorticity", ["resolution.dp=0.05", "time.end=0.1",
                                         'output.fields=["velocity", "pressure"]'])
if summ is not None:
    buffers = {b["name"] for b in summ["memory"]["buffers"]}
    check("vorticity" not in buffers, "no vorticity buffer when no snapshot writes it (%s)"
          % sorted(buffers))
    if BACKEND == "opencl":
        kernels = {k.split("(")[0] for k in summ["program_kernels"]}
        check("eulerian_vorticity" not in kernels and "SPH_FLUID_VORTICITY" not in
              summ["build_options"], "no vorticity pass in the program (%s)" % sorted(kernels))

# --- 2. the weakly compressible vortex at dp = 1/50 to t = 5: Laguerre-Gauss against Wendland
if LONG_RUNS:
    ke5 = {}
    for kernel in ("laguerre-gauss", "wendland-c2"):
        summ, ts = run(TGV, "tgv-wc-" + kernel, ["method.kernel=" + kernel])
        if summ is not None:
            ke5[kernel] = at(ts, "kinetic_energy", 5.0)
            print("weakly compressible, %s, dp = 1/50: KE(5) = %.5g (exact %.5g, %+.2f %%), "
                  "%.1f s" % (kernel, ke5[kernel], exact_ke(5.0),
                              100.0 * (ke5[kernel] / exact_ke(5.0) - 1.0), summ["wall_time_s"]))
    summ, ts = run(TGV, "tgv-wc-lg-coarse", ["resolution.dp=0.04"])
    if summ is not None and "laguerre-gauss" in ke5:
        coarse = at(ts, "kinetic_energy", 5.0)
        err_coarse = abs(coarse / exact_ke(5.0) - 1.0)
        err_mid = abs(ke5["laguerre-gauss"] / exact_ke(5.0) - 1.0)
        print("weakly compressible, laguerre-gauss, dp = 1/25: KE(5) = %.5g (%+.2f %%): %.2f times "
              "the error at dp = 1/50" % (coarse, 100.0 * (coarse / exact_ke(5.0) - 1.0),
                                          err_coarse / err_mid))
        check(err_coarse >= 3.0 * err_mid,
              "KE(5) error at dp = 1/25 at least 3x that at 1/50 (second order; %.3g, %.3g)"
              % (err_coarse, err_mid))
    if len(ke5) == 2:
        lg, w = ke5["laguerre-gauss"], ke5["wendland-c2"]
        check(abs(lg / exact_ke(5.0) - 1.0) <= 0.30,
              "Laguerre-Gauss KE(5) within 30 %% of exact (%.5g vs %.5g)" % (lg, exact_ke(5.0)))
        check(abs(lg - exact_ke(5.0)) < abs(w - exact_ke(5.0)),
              "Laguerre-Gauss closer to exact than Wendland (%.5g, %.5g; exact %.5g)"
              % (lg, w, exact_ke(5.0)))

# --- 3. the public code's run: ideal gas, HLLC with eta = 5, Laguerre-Gauss, dp = 1/50
if LONG_RUNS:
    summ, ts = run(TGV_GAS, "tgv-gas-lg")
    if summ is not None:
        for t, stored in ((1.0, 0.0420539), (5.0, 6.861e-5)):
            ke = at(ts, "kinetic_energy", t)
            print("ideal gas (HLLC, eta = 5), Laguerre-Gauss, dp = 1/50: KE(%g) = %.6g, the public "
                  "code's %.6g (%+.2f %%)" % (t, ke, stored, 100.0 * (ke / stored - 1.0)))
            check(abs(ke / stored - 1.0) <= 0.05,
                  "KE(%g) within 5 %% of the public code's %.6g (%.6g)" % (t, stored, ke))
        dm, de = rel_change(ts, "mass"), rel_change(ts, "total_energy")
        print("    to t = 5: mass change %.3g, total energy change %.3g, %.1f s"
              % (dm, de, summ["wall_time_s"]))
        check(dm <= 1e-12 and de <= 1e-12, "mass and total energy constant (%.3g, %.3g)" % (dm, de))


# --- 4. Shu-Osher at dp = 1/200: Laguerre-Gauss against Wendland and the WENO5 reference
def shu_osher_rows(out):
    """The last snapshot's time, x of the first row, the density of every row ([rows, n]
    sorted by x) and the row at y nearest 0.0125."""
    with open(os.path.join(out, "snapshots.hdf.series")) as f:
        last = json.load(f)["files"][-1]
    with h5py.File(os.path.join(out, last["name"]), "r") as f:
        pos, rho = f["VTKHDF/Points"][:], f["VTKHDF/PointData/density"][:]
    ys = np.unique(np.round(pos[:, 1], 9))
    rows = []
    for y in ys:
        sel = np.abs(pos[:, 1] - y) < 1e-8
        order = np.argsort(pos[sel, 0])
        rows.append((pos[sel, 0][order], rho[sel][order]))
    k = int(np.argmin(np.abs(ys - 0.0125)))
    return float(last["time"]), rows, k


# the reference density (REFERENCE.md) and what the buffers let in through the strip
# (height 0.03) over t = 1.8: the inflow's fluxes less the far end's pressure
_ref = np.genfromtxt(REFERENCE, delimiter=",", names=True)
REF_X, REF_RHO = _ref["x"], _ref["density"]
_rho_l, _u_l, _p_l, _p_r, _gamma, _H, _T = 3.857143, 2.629369, 10.33333, 1.0, 1.4, 0.03, 1.8
_e_l = _p_l / (_gamma - 1.0) + 0.5 * _rho_l * _u_l ** 2
SO_INFLOW = {"mass": _rho_l * _u_l * _T * _H,
             "momentum_x": (_rho_l * _u_l ** 2 + _p_l - _p_r) * _T * _H,
             "total_energy": (_e_l + _p_l) * _u_l * _T * _H}

def buffer_balance(ts, height):
    """The changes of mass, x momentum and total energy over the run relative to what the
    buffers let in through a tube of the given cross-section, minus 1 (0: exact)."""
    return {c: (ts[c][-1] - ts[c][0]) / (v * height / _H) - 1.0 for c, v in SO_INFLOW.items()}


def check_buffer_balance(label, balance):
    for c, b in balance.items():
        check(abs(b) <= 1e-6, "%s: the change of %s equals the buffers' flux (%.3g)"
              % (label, c, b))


if LONG_RUNS:
    l1 = {}
    for kernel in ("laguerre-gauss", "wendland-c2"):
        name = "shu-osher-" + kernel
        summ, ts = run(SHU_OSHER, name, ["method.kernel=" + kernel])
        if summ is None:
            continue
        t_end, rows, k = shu_osher_rows(os.path.join(tmp, name))
        check(abs(t_end - _T) < 1e-9, "%s: the last snapshot at t = 1.8 (%g)" % (kernel, t_end))
        check(len(rows) == 6 and all(len(r[0]) == 2000 for r in rows),
              "%s: 6 rows of 2000 particles (%s)" % (kernel, [len(r[0]) for r in rows]))
        x, r = rows[k]
        l1[kernel] = float(np.mean(np.abs(r - np.interp(x, REF_X, REF_RHO))))
        spread = max(float(np.max(np.abs(ri - r))) for _, ri in rows) / float(np.ptp(r))
        balance = buffer_balance(ts, _H)
        print("Shu-Osher, %s, dp = 1/200: L1 density error %.4g; rows differ by %.3g of the "
              "range; mass, momentum, energy against the buffers' fluxes %.3g, %.3g, %.3g; "
              "%.1f s" % (kernel, l1[kernel], spread, balance["mass"], balance["momentum_x"],
                          balance["total_energy"], summ["wall_time_s"]))
        check(spread <= 1e-9, "%s: every row the same 1D solution (%.3g)" % (kernel, spread))
        check_buffer_balance(kernel, balance)
    if len(l1) == 2:
        check(l1["laguerre-gauss"] < l1["wendland-c2"],
              "Laguerre-Gauss L1 below Wendland's (%.4g, %.4g)"
              % (l1["laguerre-gauss"], l1["wendland-c2"]))
        check(l1["laguerre-gauss"] < 0.03,
              "Laguerre-Gauss L1 below 0.03 (%.4g)" % l1["laguerre-gauss"])

# --- 4b. the same tube as a true 1D line (line.cfg, dimension 1), every backend: cheap
if not SANITIZED or BACKEND == "cpu":
    l1_line = {}
    for kernel in ("laguerre-gauss", "wendland-c2"):
        name = "shu-osher-line-" + kernel
        summ, ts = run(SHU_OSHER_LINE, name, ["method.kernel=" + kernel])
        if summ is None:
            continue
        t_end, rows, _ = shu_osher_rows(os.path.join(tmp, name))
        check(abs(t_end - 1.8) < 1e-9 and len(rows) == 1 and len(rows[0][0]) == 2000,
              "line, %s: one row of 2000 particles at t = 1.8 (%g, %s)"
              % (kernel, t_end, [len(r[0]) for r in rows]))
        x, r = rows[0]
        l1_line[kernel] = float(np.mean(np.abs(r - np.interp(x, REF_X, REF_RHO))))
        balance = buffer_balance(ts, 1.0)  # per unit cross-section
        print("Shu-Osher line, %s, %s, dp = 1/200: L1 density error %.4g; mass, momentum, "
              "energy against the buffers' fluxes %.3g, %.3g, %.3g; %.1f s"
              % (kernel, BACKEND, l1_line[kernel], balance["mass"], balance["momentum_x"],
                 balance["total_energy"], summ["wall_time_s"]))
        check_buffer_balance("line, " + kernel, balance)
    if len(l1_line) == 2:
        check(l1_line["laguerre-gauss"] < l1_line["wendland-c2"],
              "line: Laguerre-Gauss L1 below Wendland's (%.4g, %.4g)"
              % (l1_line["laguerre-gauss"], l1_line["wendland-c2"]))
        check(l1_line["laguerre-gauss"] < 0.035,
              "line: Laguerre-Gauss L1 below 0.035 (%.4g)" % l1_line["laguerre-gauss"])

# --- 5. bad input and the monitor
GAS_TEXT = open(TGV_GAS).read()
# the scene file's line that holds the key (1-based)
P_LINE = GAS_TEXT[:GAS_TEXT.index('initial_pressure = "100.0 / 1.4";')].count("\n") + 1
BAD = [
    ('initial_pressure = -1.0;',
     ":%d: bodies.fluid.initial_pressure: an initial pressure must be > 0, got -1" % P_LINE),
    ('initial_pressure = "71.4 - 100 * x";',
     ':%d: bodies.fluid.initial_pressure: the expression "71.4 - 100 * x" gives -1.1 at the '
     "particle at (0.725, 0.025) of body 'fluid': initial pressures must be finite and > 0"
     % P_LINE),
]
for i, (line, message) in enumerate(BAD):
    text = GAS_TEXT.replace('initial_pressure = "100.0 / 1.4";', line)
    check(text != GAS_TEXT, "the bad-input row edits the scene (%s)" % line)
    path = os.path.join(tmp, "bad%d.cfg" % i)
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(tmp, "bad%d" % i)
    code, err = run_sphsolid(path, BACKEND, out, ["resolution.dp=0.05"])
    check(code == 2 and (path + message) in err,
          "%s: exit 2 naming the key (exit %d: %s)" % (line, code, err))
    check(not os.path.exists(os.path.join(out, "summary.json")),
          "%s: no complete-looking result" % line)

TORN = """dimension = 2;
resolution = { dp = 0.02; };
method = { formulation = "eulerian-compressible"; };
time = { end = 0.2; output_interval = 0.01; };
materials = { gas = { density = 1.0; gamma = 1.4; }; };
shapes = { tube = { type = "box"; lower = [0.0, 0.0]; upper = [1.0, 0.12]; }; };
boundary = { periodic = ["x", "y"]; lower = [0.0, 0.0]; upper = [1.0, 0.12]; };
bodies = ( { name = "gas"; material = "gas"; shape = "tube"; initial_pressure = 0.4;
             initial_velocity = { type = "expression"; x = "x < 0.5 ? -20 : 20"; y = "0"; }; } );
"""
path = os.path.join(tmp, "torn.cfg")
with open(path, "w") as f:
    f.write(TORN)
out = os.path.join(tmp, "torn")
code, err = run_sphsolid(path, BACKEND, out)
check(code == 4, "a gas torn apart: exit 4 (exit %d: %s)" % (code, err))
if code == 4:
    summ, _ = run_results(out)
    inst = summ.get("instability") or {}
    print("a gas torn apart at +-20 c0: %s" % err)
    check(summ["status"] != "completed" and inst.get("stopped") is True
          and inst.get("body") == "gas" and isinstance(inst.get("particle"), int)
          and 0.0 < inst.get("time", 0.0) < 0.01,
          "the monitor's record names the time, particle and body (%s)" % inst)

# --- 6. the native backend's results do not depend on its thread count
# (docs/backends.md): its rate passes (the two stages' and SSP-RK's) sum each fluid pair once,
# scattering into the neighbour's sums over fixed blocks of particles, and the pairs across a
# periodic axis after the blocks (eulerian_step.cl).  The vortex at dp = 1/100 (10 000
# particles: the backend's threads run it; periodic on both axes), weakly compressible and as an
# ideal gas, and the ideal gas with SSP-RK3, 30 steps on 1 and on 2 threads: the same bits.
if BACKEND == "cpu":
    for label, scene, extra in (("weakly compressible", TGV, []), ("ideal gas", TGV_GAS, []),
                                ("ideal gas ssp-rk3", TGV_GAS,
                                 ["--set", "time.integrator=ssp-rk3"])):
        outs = []
        for threads in (1, 2):
            out = os.path.join(tmp, "threads-%s-%d" % (label.replace(" ", "-"), threads))
            env = dict(os.environ, OMP_NUM_THREADS=str(threads))
            p = subprocess.run([BIN, "run", scene, "--backend", "cpu", "--quiet", "--out", out,
                                "--set", "resolution.dp=0.01", "--set", "time.end=0.02",
                                "--set", "time.output_interval=0.01"] + extra,
                               capture_output=True, text=True, env=env, timeout=900)
            check(p.returncode == 0, "%s on %d threads: exit %d (%s)"
                  % (label, threads, p.returncode, p.stderr.strip()))
            outs.append(out)
        p = subprocess.run([BIN, "compare", outs[0], outs[1], "--rtol", "0"],
                           capture_output=True, text=True)
        check(p.returncode == 0, "%s: 1 and 2 threads give the same bits: %s"
              % (label, p.stdout[-600:]))

# --- 7. a stream carries a small disturbance without amplifying it only under SSP-RK3
# (docs/fluids.md, "One step, and what it conserves"): a density bump of 1 % in a uniform stream
# U = (1, 0) (Mach 0.1) through a periodic box 10 x 6 at dp = 0.25 (960 particles), at the
# cylinder's acoustic CFL 0.5 (the 2D default 0.3 amplifies too, more slowly).  Its acoustic
# energy (timeseries.csv's internal_energy, sum w p^2 / (2 rho0 c0^2)) starts at 7.85e-3.  The
# central fluxes of a stream (the limited dissipation vanishes with the velocity jump) under the
# two forward stages amplify short waves: the public code's update multiplies it by about 40 by
# t = 5 (measured 0.310; by t = 10 the monitor stops the run, the total energy up 54 %).  Under
# SSP-RK3 it only radiates and decays: 3.17e-3 at t = 20 (measured), below its start.
BUMP = """title = "a density bump carried by a uniform stream";
dimension = 2;
resolution = { dp = 0.25; };
method = { formulation = "eulerian-wc"; kernel = "laguerre-gauss"; };
time = { end = 20.0; output_interval = 1.0; cfl_acoustic = 0.5; };
output = { snapshot_interval = 20.0; };
materials = { fluid = { density = 1.0; sound_speed = 10.0; viscosity = 0.02; }; };
shapes = { box = { type = "box"; lower = [0.0, 0.0]; upper = [10.0, 6.0]; }; };
boundary = { periodic = ["x", "y"]; lower = [0.0, 0.0]; upper = [10.0, 6.0]; };
bodies = ( { name = "fluid"; material = "fluid"; shape = "box";
             initial_density = "1 + 0.01 * exp(-((x - 5)^2 + (y - 3)^2))";
             initial_velocity = { type = "uniform"; vector = [1.0, 0.0]; }; } );
"""
bump = os.path.join(tmp, "bump.cfg")
with open(bump, "w") as f:
    f.write(BUMP)
summ, ts = run(bump, "bump-two-stage", ["time.end=5.0"])
if summ is not None:
    e0, e5 = float(ts["internal_energy"][0]), at(ts, "internal_energy", 5.0)
    print("bump in a stream, two stages: acoustic energy %.3g at t = 0, %.3g at t = 5" % (e0, e5))
    check(e5 > 10.0 * e0, "two stages: the stream amplifies the bump's short waves (%.3g -> %.3g)"
          % (e0, e5))
summ, ts = run(bump, "bump-ssp-rk3", ["time.integrator=ssp-rk3"])
if summ is not None:
    e0, e20 = float(ts["internal_energy"][0]), at(ts, "internal_energy", 20.0)
    peak = float(np.max(ts["internal_energy"]))
    print("bump in a stream, SSP-RK3: acoustic energy %.3g at t = 0, %.3g at t = 20, at most %.3g"
          % (e0, e20, peak))
    check(peak <= e0 * (1.0 + 1e-9) and e20 < 0.5 * e0,
          "SSP-RK3: the bump's acoustic energy never rises and halves by t = 20 (%.3g, max %.3g, "
          "at t = 20 %.3g)" % (e0, peak, e20))

# --- 8. three dimensions: the vortex extruded in z (extruded_3d.cfg: 20 x 20 x 8 particles at
# dp = 0.05, periodic on the three axes, Wendland C2), every backend.  The flow stays
# two-dimensional, so its exact decay is the 2D one.
TGV_3D = os.path.join(SRC, "cases", "taylor_green_2d", "extruded_3d.cfg")


def ke_error_3d(ts):
    """KE(0.5) / exact - 1 of the extruded vortex (KE(0) = 0.25 x the z period 0.4)."""
    return at(ts, "kinetic_energy", 0.5) / (0.4 * exact_ke(0.5)) - 1.0


summ, ts = run(TGV_3D, "tgv-3d")
if summ is not None:
    label = "the vortex extruded in z (3D)"
    check(summ["particle_count"] == 3200, "%s: 3200 particles (%d)"
          % (label, summ["particle_count"]))
    ke0, mass0 = ts["kinetic_energy"][0], ts["mass"][0]
    check(abs(ke0 - 0.1) < 1e-12, "%s: KE(0) = 0.1 on the lattice (%.17g)" % (label, ke0))
    dm = rel_change(ts, "mass")
    momentum = np.sqrt(ts["momentum_x"] ** 2 + ts["momentum_y"] ** 2 + ts["momentum_z"] ** 2)
    dp = float(np.max(momentum)) / math.sqrt(2.0 * ke0 * mass0)
    # the flow stays two-dimensional: the z velocity of the last snapshot at round-off of the
    # velocity scale U = 1 (measured 4.8e-15 native)
    with open(os.path.join(tmp, "tgv-3d", "snapshots.hdf.series")) as f:
        last = json.load(f)["files"][-1]
    with h5py.File(os.path.join(tmp, "tgv-3d", last["name"]), "r") as f:
        w_max = float(np.max(np.abs(f["VTKHDF/PointData/velocity"][:, 2])))
    print("%s, %s: mass change %.3g, |momentum| %.3g of sqrt(2 KE0 M), max |w| %.3g at t = %g, "
          "KE(0.5) / exact - 1 = %.4f" % (label, BACKEND, dm, dp, w_max, last["time"],
                                          ke_error_3d(ts)))
    check(dm <= 1e-12, "%s: mass conserved (%.3g > 1e-12)" % (label, dm))
    check(dp <= 1e-12, "%s: momentum at round-off (%.3g of its scale > 1e-12)" % (label, dp))
    check(last["time"] == 0.5 and w_max <= 1e-12,
          "%s: no z velocity at t = %g (max |w| %.3g)" % (label, last["time"], w_max))
    check(np.all(np.diff(ts["kinetic_energy"]) < 0.0), "%s: kinetic energy decays" % label)
    rise = float(np.max(np.diff(ts["total_energy"])))
    check(rise <= 1e-12 * ts["total_energy"][0], "%s: total energy never rises (%.3g)"
          % (label, rise))
    if LONG_RUNS:
        # the error of KE(0.5) converges: at dp = 0.025 (25 600 particles) at least 2 times
        # smaller than at 0.05 (measured 2026-11-28: 0.531 and 0.204, 2.6 times; in 2D the
        # same flow with Wendland C2 gives 0.602 and 0.249)
        summ_f, ts_f = run(TGV_3D, "tgv-3d-fine", ["resolution.dp=0.025"])
        if summ_f is not None:
            coarse, fine = abs(ke_error_3d(ts)), abs(ke_error_3d(ts_f))
            print("%s: KE(0.5) error %.4f at dp = 0.05, %.4f at 0.025 (%.2f times)"
                  % (label, coarse, fine, coarse / fine))
            check(coarse >= 2.0 * fine, "%s: the KE error halves with dp (%.4f, %.4f)"
                  % (label, coarse, fine))
# the Laguerre kernels are refused for fluids in 3D (docs/fluids.md, "Kernels in 3D")
for kernel in ("laguerre-gauss", "laguerre-wendland"):
    out = os.path.join(tmp, "tgv-3d-" + kernel)
    code, err = run_sphsolid(TGV_3D, BACKEND, out, ["method.kernel=" + kernel])
    check(code == 2 and ('method.kernel: "%s" is unstable for the fluid formulations in 3D'
                         % kernel) in err and not os.path.exists(out),
          "3D: %s refused, nothing written (exit %d: %s)" % (kernel, code, err.strip()))

shutil.rmtree(tmp, ignore_errors=True)
finish("test_fluids_" + BACKEND)
