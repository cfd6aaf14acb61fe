#!/usr/bin/python3
"""test_impact.py BACKEND — the high-velocity impact of cases/high_velocity_impact (003 §5.2.3).

A disc projectile (D = 0.01) hits an unconstrained plate (t = 0.002 thick, 0.05 high) at
v0 = 3100 m/s; both elastic-perfectly plastic (rho0 = 8930, c0 = 5328 given as sound_speed,
G = E / (2 (1 + nu)) = 2.76e10, sigma_Y = 3e8), SPH-GNOG-A, contact between the two bodies.
003 shows the shapes at 8 us (Fig. 23) and gives no number, so the checks are the laws the
run must keep and what mechanics predicts:

At dp = 4e-4 (1 114 particles; the case's dp is 2e-4) to 8 us, the case's monitor settings:
- the run completes with the monitor quiet; the initial kinetic energy is N_p rho0 dp^2 v0^2 / 2
  and the momentum N_p rho0 dp^2 v0;
- momentum along the axis conserved to round-off (contact and continuum terms are pairwise
  antisymmetric; no wall, no constraint); momentum across the axis and the angular momentum
  at round-off, and the final particles mirror-symmetric about the axis to 1e-9 D (the
  lattice is; measured 4.9e-11 D);
- energy: no external work, so the total energy (kinetic + strain) never rises above its
  running minimum by more than 1e-3 E0 (measured 0 here, 2.9e-4 E0 at dp = 2e-4), and what
  it lost by 8 us is at least the J2 plastic work sum V sigma_Y eps_p (the rest is the
  Riemann dissipation, the shock's entropy production: measured 7.15e5 J/m lost, plastic
  work 4.6e4 J/m);
- perforation: every projectile particle is past the plate's rear face (x > 0.002; measured
  x >= 0.00914) and the plate's hole is at least as wide as the projectile (no plate particle
  within |y| < D/2 of the axis at x < 0.004; measured 9.55 mm);
- the projectile's centre-of-mass speed at 8 us against the momentum balance of a plug
  (the plate material in the projectile's path, mass rho0 t D per unit depth, carried along
  at the projectile's speed): v0 (pi D^2 / 4) / (pi D^2 / 4 + t D) = 0.797 v0 = 2 471 m/s,
  within 5 % (measured 2 462 m/s; 2 506 at dp = 2e-4);
- no clustering: the closest pair stays above 0.1 dp all run (measured 0.126 dp);
- the baseline SPH-OG (003's formulations' ancestor, no hourglass control) on the same
  scene is stopped by the monitor's clustering check before 3 us (measured: pairs at
  0.008 dp at 2.4 us), where SPH-GNOG-A stays at >= 0.126 dp.

The shock at first contact: on the axis the impact is planar until the contact edge,
which runs ahead faster than the shock, falls behind it (t ~ D v0 / (4 U^2) = 0.2 us), so
the on-axis pressure reaches the one-dimensional impedance-matching value of two equal
bodies: particle speed u = v0 / 2, and with the linear equation of state p = c0^2
(rho - rho0), shock speed U = (u + sqrt(u^2 + 4 c0^2)) / 2 = 6 159 m/s and
p = rho0 U u = 85.25 GPa (the deviator adds 2/3 sigma_Y = 0.2 GPa to the normal stress,
not to p).  The largest pressure within 3 dp of the axis over t <= 0.6 us, sampled every
0.05 us: within [0.8, 1.05] p at dp = 2e-4 (measured 0.873: the shock's rise over about
4 h is not short against 0.2 us) and within [0.93, 1.05] p at dp = 1e-4 (measured 0.969),
the error falling with dp.
"""
import math
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import (SRC, check, finish, plastic_work, run_quiet, run_results,  # noqa: E402
                     run_sphsolid, snapshot_paths)

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
SCENE = os.path.join(SRC, "cases", "high_velocity_impact", "scene.cfg")
tmp = tempfile.mkdtemp(prefix="sphsolid-impact-")

RHO0, C0, V0, SIGMA_Y = 8930.0, 5328.0, 3100.0, 3.0e8
D, T_PLATE = 0.01, 0.002
FIELDS = 'output.fields=["particle_id", "body_id", "velocity", "density", "plastic_strain", ' \
    '"pressure"]'


def read(path):
    """(positions, point data) of a snapshot, rows ordered by particle id."""
    with h5py.File(path, "r") as f:
        pd = f["VTKHDF/PointData"]
        order = np.argsort(pd["particle_id"][:])
        return f["VTKHDF/Points"][:][order], {k: pd[k][:][order] for k in pd}


def mirror_partners(x, dp):
    """For each particle, the row of the particle at its mirror image about y = 0 (the lattice
    is symmetric about the axis)."""
    key = {(round(2 * p[0] / dp), round(2 * p[1] / dp)): k for k, p in enumerate(x)}
    return np.array([key[(round(2 * p[0] / dp), round(-2 * p[1] / dp))] for p in x])


def peak_axis_pressure(dp):
    """The largest pressure within 3 dp of the axis over t <= 0.6 us."""
    out = os.path.join(tmp, "shock-%g" % dp)
    code, err = run_sphsolid(SCENE, BACKEND, out, [
        "resolution.dp=%g" % dp, "time.end=6e-7", "time.output_interval=5e-8",
        "output.snapshot_interval=5e-8", 'output.fields=["pressure"]',
        'monitor.action="off"'])
    check(code == 0, f"shock run at dp = {dp:g}: exit {code} ({err})")
    if code != 0:
        return float("nan")
    peak = -np.inf
    for path in snapshot_paths(out):
        with h5py.File(path, "r") as f:
            y, p = f["VTKHDF/Points"][:, 1], f["VTKHDF/PointData/pressure"][:]
        peak = max(peak, float(np.max(p[np.abs(y) < 3 * dp])))
    return peak


try:
    dp = 4e-4
    out = os.path.join(tmp, "gnog-a")
    summ, ts = run_quiet(SCENE, BACKEND, out, ["resolution.dp=%g" % dp, FIELDS])
    if summ is not None:
        feats = summ["features"]
        check(feats["material_model"] == "j2-plastic" and feats["bodies"] == 2 and
              feats["contact"], f"features: J2, 2 bodies in contact ({feats})")
        x0, d0 = read(snapshot_paths(out)[0])
        x1, d1 = read(snapshot_paths(out)[-1])
        proj = d0["body_id"] == 0
        mass = RHO0 * dp * dp
        n_p = int(np.sum(proj))
        p0 = n_p * mass * V0
        check(abs(ts["kinetic_energy"][0] / (0.5 * n_p * mass * V0 ** 2) - 1) < 1e-12,
              f"KE0 {ts['kinetic_energy'][0]:.10g} = N_p rho0 dp^2 v0^2 / 2 ({n_p} particles)")
        check(abs(ts["momentum_x"][0] / p0 - 1) < 1e-12, "initial momentum N_p rho0 dp^2 v0")
        drift = np.max(np.abs(ts["momentum_x"] - ts["momentum_x"][0])) / p0
        check(drift < 1e-12, f"momentum along the axis conserved: drift {drift:.2e} p0")
        across = np.max(np.abs(ts["momentum_y"])) / p0
        check(across < 1e-12, f"momentum across the axis {across:.2e} p0")
        spin = np.max(np.abs(ts["angular_momentum"])) / (p0 * D)
        check(spin < 1e-12, f"angular momentum {spin:.2e} p0 D")
        # Mirror symmetry about the axis.  The asymmetry starts at round-off
        # (3.5e-16 D in the first snapshot) and, once the disc perforates the
        # plate, grows by about 3.2x every 0.4 us (documented runs, native
        # backend, snapshots every 0.4 us): from 2.0e-15 D at 2 us to 1.7e-10 D
        # at 8 us with neighbour sums taken in sequence (as on OpenCL; pocl:
        # 9.6e-11 D), from 4.2e-15 D to 2.8e-9 D with the native backend's
        # 4-lane sums (3.3e-9 D with 2 lanes).  A term that breaks the
        # symmetry shows before the growth: the 2 us bound is 25x the
        # round-off measured there; the 8 us bound is 3.6x the largest
        # amplified round-off measured.
        partner = mirror_partners(x0, dp)

        def asymmetry(x):
            return np.max(np.abs(x[:, 0] - x[partner, 0]) + np.abs(x[:, 1] + x[partner, 1])) / D

        x2, _ = read(snapshot_paths(out)[2])
        early = asymmetry(x2)
        check(early < 1e-13, f"mirror symmetry at 2 us: {early:.2e} D")
        asym = asymmetry(x1)
        check(asym < 1e-8, f"mirror symmetry at 8 us: {asym:.2e} D")

        e = ts["total_energy"]
        rise = float(np.max(e - np.minimum.accumulate(e))) / e[0]
        check(rise < 1e-3, f"the total energy rises {rise:.2e} E0 above its running minimum")
        work = plastic_work(out, mass, SIGMA_Y)
        lost = e[0] - e[-1]
        check(lost >= work > 0, f"energy lost {lost:.4g} J/m >= plastic work {work:.4g} J/m")

        p1 = d1["body_id"] == 0
        check(np.min(x1[p1, 0]) > T_PLATE,
              f"perforation: projectile behind x = {np.min(x1[p1, 0]):.5f} > {T_PLATE}")
        plate = (~p1) & (x1[:, 0] < 0.004)
        hole = float(np.min(np.abs(x1[plate, 1])))
        check(hole >= D / 2, f"hole half-width {hole * 1e3:.2f} mm >= D/2")
        v_cm = float(np.mean(d1["velocity"][p1, 0]))
        area = math.pi * D * D / 4
        v_plug = V0 * area / (area + T_PLATE * D)
        check(abs(v_cm / v_plug - 1) < 0.05,
              f"projectile speed at 8 us {v_cm:.0f} m/s against the plug balance {v_plug:.0f}")
        closest = float(np.min(ts["min_distance_ratio"]))
        check(closest > 0.1, f"closest pair {closest:.3f} dp > 0.1 dp")
        print(f"GNOG-A dp = {dp:g}: drift {drift:.1e}, asymmetry {asym:.1e} D "
              f"(2 us: {early:.1e} D), energy rise {rise:.1e}, lost {lost:.4g} >= plastic "
              f"{work:.4g} J/m, hole {hole * 1e3:.2f} mm, v_cm {v_cm:.0f} m/s "
              f"(plug {v_plug:.0f}), closest {closest:.3f} dp")

    out = os.path.join(tmp, "og")
    code, err = run_sphsolid(SCENE, BACKEND, out, ["resolution.dp=%g" % dp,
                                                   "method.formulation=\"og\"",
                                                   "method.rotation=\"none\"",
                                                   "monitor.action=\"stop\""])
    check(code == 4, f"SPH-OG: stopped by the monitor (exit {code}: {err})")
    if code == 4:
        ins = run_results(out)[0]["instability"]
        check(ins["quantity"].startswith("minimum pair distance") and ins["time"] < 3e-6,
              f"SPH-OG: clustering before 3 us ({ins['quantity']} {ins['value']:.3g} at "
              f"t = {ins['time']:.3g})")

    u = V0 / 2
    shock = (u + math.sqrt(u * u + 4 * C0 * C0)) / 2
    p1d = RHO0 * shock * u
    ratios = {}
    for dp, lo in ((2e-4, 0.8), (1e-4, 0.93)):
        ratios[dp] = peak_axis_pressure(dp) / p1d
        check(lo <= ratios[dp] <= 1.05, f"peak on-axis pressure at dp = {dp:g}: "
              f"{ratios[dp]:.3f} of the 1D impedance match {p1d / 1e9:.2f} GPa, in [{lo}, 1.05]")
    check(abs(ratios[1e-4] - 1) < abs(ratios[2e-4] - 1), "the shock pressure converges")
    print("peak on-axis pressure / %.2f GPa: dp = 2e-4 %.3f, dp = 1e-4 %.3f" % (
        p1d / 1e9, ratios[2e-4], ratios[1e-4]))
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish("test_impact_" + BACKEND)
