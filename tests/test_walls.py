#!/usr/bin/python3
"""test_walls.py BACKEND — frictionless contact with rigid walls (device/sph_wall.h).

An elastic bar moving along its axis at v0 = 1 m/s (0.0175 c0) hits a rigid wall end on,
in 2D (0.2 x 0.02, dp = 0.002, 1 000 particles; the plane-strain model with the in-plane
deviator, sph_elasticity.h, so the bar modulus is E_b = 4 G K / (K + G) with its free
faces) and in 3D (0.1 x 0.01 x 0.01, dp = 0.002, 1 250 particles, E_b = E).  One-dimensional
elastodynamics (the St-Venant bar impact): the wall pushes with the constant force
rho0 c_b v0 A (c_b = sqrt(E_b / rho0), the impact stress rho c v on the bar's end A) for
the time 2 L / c_b, after which the bar leaves at v0, free of stress.  Checks:

SPH-GNOG-A, whose shear force is the divergence of the stress (SPH-ENOG-A's Laplacian
shear force has other effective moduli: its 2D bar leaves 6 % early).

- the force plateau, the slope of the bar's momentum while it touches, against
  rho0 c_b v0 A: within 5 % in 2D (measured -1.4 %); within 8 % in 3D, where the bar is
  5 particles across and 16 of its 25 particle columns lie on the free surface, whose
  truncated kernels soften it: -6.6 % here, -3.0 % at dp = 0.001 (10 across), first
  order in dp;
- the contact ends, where the force falls through half its plateau, at 2 L / c_b
  within 5 % (measured -2.5 % and +1.7 %);
- the restitution v_out / v0 in [0.85, 1]: the wall and the solver may dissipate but never
  create energy; the runs here give 0.907 and 0.888, the Riemann dissipation of the shock
  at the bar's end taking the rest;
- no particle's centre crosses the wall's surface: at every snapshot the nearest stays
  more than dp/4 in front of it (measured 0.468 dp and 0.459 dp);
- momentum across the wall's normal and the angular momentum stay at round-off (the
  wall force is along the normal of every particle).

Then the square Taylor bar of cases/taylor_bar_square at L/dp = 8 (2 560 particles, J2 with
hardening, SPH-GNOG-A, 227 m/s onto the wall) to 60 us: the run completes with the monitor
quiet at the case's settings; no particle crosses the wall (nearest 0.46 dp); the bar comes
to rest (kinetic energy below 1 % of the initial, measured 0.14 %) with the total energy
below its initial value, and the J2 plastic work sum V (sigma_Y eps_p + kappa eps_p^2 / 2)
takes between half and all of the initial kinetic energy (measured 74 %); the square's
symmetry holds (momentum across the axis below 1e-9 of the initial momentum; the
observer's y below 1e-6 of the side: round-off that an antisymmetric mode of the squeezed
foot amplifies after 30 us, to 5e-11 m at 60 us); the foot spreads: the observer s at the
edge of the impact face moves out by 1.652 mm and the top comes down to 21.758 mm in the
documented run (cases/taylor_bar_square/README.md), held to 10 % and 2 %.  The published
observer position (003 Table 4, 5.21 mm at this resolution) is not reproduced: the
README's deviation.

Then the round Taylor bar of cases/taylor_bar_round at R/dp = 6 (4 032 relaxed particles,
perfectly plastic J2, 373 m/s): the monitor stays quiet; the initial kinetic energy is
N rho0 dp^3 v0^2 / 2; the bar is at rest at 30 us (below 1 % of KE0, measured 0.35 %;
the reference code's run 0.31 %); the wall is passive, so the total energy never rises
above its running minimum by more than 0.2 % of KE0 (measured 0.018 %; 1.3 % before the
wall's continuity term, sph_wall.h); momentum along the wall at round-off; no particle
crosses the wall; the plastic work takes between half and all of KE0; the top at 30 us
within 3 % of the public reference code's run (15.975 mm, its observer one spacing below
the top, R/dp = 12) and within 2 % of the documented 16.114 mm; the rim observer spreads to
the documented 6.675 mm within 5 %.

Under the sanitizers (sphtest.SANITIZED) both bars run to 10 us, a sixth of the case, the round
bar's particles relaxed in 200 steps instead of 1000 (residual
mean 0.0105 against 0.0103; the 1000 steps took 31 of its 67 s there); only the checks that hold
at any time are made (the monitor, the initial kinetic energy, the energy never above it or
the passive wall, the momentum across the axis or along the wall, the observer on the symmetry
plane, no crossing, plastic work within KE0); the states at 30 and 60 us are the release build's.
"""
import math
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import (SANITIZED, SRC, check, finish, plastic_work, run_results,  # noqa: E402
                     run_sphsolid, snapshot_paths)

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
tmp = tempfile.mkdtemp(prefix="sphsolid-walls-")

E, NU, RHO0, V0, DP = 2.0e6, 0.3975, 1000.0, 1.0, 0.002
K, G = E / (3 * (1 - 2 * NU)), E / (2 * (1 + NU))
BARS = {
    2: {"lower": "[0.0, -0.01]", "upper": "[0.2, 0.01]", "length": 0.2, "area": 0.02,
        "modulus": 4 * G * K / (K + G), "vel": "[-1.0, 0.0]", "point": "[0.0, 0.0]",
        "normal": "[1.0, 0.0]", "end": 0.016},
    3: {"lower": "[0.0, -0.005, -0.005]", "upper": "[0.1, 0.005, 0.005]", "length": 0.1,
        "area": 1e-4, "modulus": E, "vel": "[-1.0, 0.0, 0.0]", "point": "[0.0, 0.0, 0.0]",
        "normal": "[1.0, 0.0, 0.0]", "end": 0.009},
}
SCENE = """
title = "elastic bar against a rigid wall";
dimension = %(dim)d;
resolution = { dp = %(dp)g; };
method = { formulation = "gnog-a"; rotation = "averaged"; };
time = { end = %(end)g; output_interval = 0.0001; };
materials = { m = { density = %(rho)g; youngs_modulus = %(E)g; poisson_ratio = %(nu)g; }; };
shapes = { bar = { type = "box"; lower = %(lower)s; upper = %(upper)s; }; };
bodies = ( { name = "bar"; material = "m"; shape = "bar";
             initial_velocity = { type = "uniform"; vector = %(vel)s; }; } );
walls = ( { name = "wall"; point = %(point)s; normal = %(normal)s; } );
output = { snapshot_interval = 0.0005; fields = ["particle_id"]; };
"""



def nearest(out, axis):
    """The smallest coordinate along `axis` of any particle at any snapshot:
    how close the run came to a wall through the origin normal to it."""
    closest = np.inf
    for path in snapshot_paths(out):
        with h5py.File(path, "r") as f:
            closest = min(closest, float(np.min(f["VTKHDF/Points"][:, axis])))
    return closest


try:
    for dim, bar in BARS.items():
        path = os.path.join(tmp, "bar%d.cfg" % dim)
        with open(path, "w") as f:
            f.write(SCENE % dict(bar, dim=dim, dp=DP, rho=RHO0, E=E, nu=NU))
        out = os.path.join(tmp, "bar%d" % dim)
        code, err = run_sphsolid(path, BACKEND, out)
        check(code == 0, f"{dim}D bar: exit {code} ({err})")
        if code != 0:
            continue
        summ, ts = run_results(out)
        check(summ["features"]["walls"] == 1, f"{dim}D: the feature set names one wall")
        if BACKEND == "opencl":
            check("-DSPH_WALLS=1" in summ["build_options"],
                  f"{dim}D: the program is built with the wall")
        t, px = ts["time"], ts["momentum_x"]
        mass = RHO0 * bar["length"] * bar["area"]
        cb = math.sqrt(bar["modulus"] / RHO0)
        force = RHO0 * cb * V0 * bar["area"]
        duration = 2 * bar["length"] / cb
        check(abs(px[0] + mass * V0) < 1e-9 * mass, f"{dim}D: initial momentum -M v0")
        # the plateau: fit the momentum over the middle of the expected contact
        mid = (t > 0.15 * duration) & (t < 0.85 * duration)
        slope = np.polyfit(t[mid], px[mid], 1)[0]
        bound = 0.05 if dim == 2 else 0.08
        check(abs(slope / force - 1) < bound, f"{dim}D: wall force {slope:.5g} N against "
              f"rho0 c_b v0 A = {force:.5g} N ({100 * (slope / force - 1):+.2f} %)")
        p_end = px[-1]
        restitution = p_end / (mass * V0)
        span = p_end - px[0]
        # the contact ends where the wall force, released over a few spacings, falls
        # through half its plateau
        f_mid, t_mid = np.diff(px) / np.diff(t), 0.5 * (t[1:] + t[:-1])
        end = t_mid[np.nonzero(f_mid >= 0.5 * slope)[0][-1]]
        check(abs(end / duration - 1) < 0.05, f"{dim}D: contact ends at {1e3 * end:.3f} ms "
              f"against 2 L / c_b = {1e3 * duration:.3f} ms ({100 * (end / duration - 1):+.2f} %)")
        check(0.85 <= restitution <= 1.0, f"{dim}D: restitution {restitution:.4f} in [0.85, 1]")
        check(np.all(np.abs(ts["momentum_y"]) < 1e-9 * mass * V0),
              f"{dim}D: momentum across the normal at round-off "
              f"({np.max(np.abs(ts['momentum_y'])):.3g})")
        am = ts["angular_momentum"] if dim == 2 else ts["angular_momentum_z"]
        check(np.all(np.abs(am) < 1e-9 * mass * V0 * bar["length"]),
              f"{dim}D: no spin ({np.max(np.abs(am)):.3g})")
        closest = nearest(out, 0)
        check(closest > 0.25 * DP, f"{dim}D: nearest particle {closest / DP:.3f} dp in front "
              "of the wall (> dp/4)")
        print("%dD bar: force %+.2f %%, contact %.3f ms (2L/c_b %.3f ms, %+.2f %%), restitution "
              "%.4f, nearest %.3f dp" % (dim, 100 * (slope / force - 1), 1e3 * end, 1e3 * duration,
                                        100 * (end / duration - 1), restitution, closest / DP))

    # the square Taylor bar, L/dp = 8
    scene = os.path.join(SRC, "cases", "taylor_bar_square", "scene.cfg")
    out = os.path.join(tmp, "taylor")
    code, err = run_sphsolid(scene, BACKEND, out, ["time.end=1e-5"] if SANITIZED else [])
    check(code == 0, f"Taylor bar: exit {code} ({err})")
    if code == 0:
        summ, ts = run_results(out)
        check(summ["status"] == "completed" and "instability" not in summ,
              f"Taylor bar: monitor quiet ({summ.get('instability')})")
        dp, rho0, sigma_y, kappa = 0.00075, 8930.0, 4.0e8, 1.0e8
        ke0 = ts["kinetic_energy"][0]
        p0 = abs(ts["momentum_z"][0])
        check(abs(ke0 - 0.5 * rho0 * 0.006 * 0.006 * 0.03 * 227.0 ** 2) < 1e-9 * ke0,
              f"Taylor bar: initial kinetic energy {ke0:.6g} J")
        if not SANITIZED:
            check(ts["kinetic_energy"][-1] < 0.01 * ke0,
                  f"Taylor bar: at rest at 60 us (KE {ts['kinetic_energy'][-1] / ke0:.4f} KE0)")
        check(np.all(ts["total_energy"][1:] < ke0), "Taylor bar: energy never above its initial")
        sym = max(np.max(np.abs(ts["momentum_x"])), np.max(np.abs(ts["momentum_y"])))
        check(sym < 1e-9 * p0, f"Taylor bar: momentum across the axis {sym:.3g}")
        # the square's symmetry holds to round-off, which an antisymmetric mode of the
        # squeezed foot amplifies after 30 us (|s_y| 1e-18 m there, 5e-11 m at 60 us)
        check(np.max(np.abs(ts["s_y"])) < 1e-6 * 0.006,
              f"Taylor bar: observer on the symmetry plane ({np.max(np.abs(ts['s_y'])):.3g})")
        closest = nearest(out, 2)
        check(closest > 0.25 * dp, f"Taylor bar: nearest particle {closest / dp:.3f} dp above "
              "the wall")
        work = plastic_work(out, rho0 * dp ** 3, sigma_y, kappa)
        if SANITIZED:
            check(0 < work <= ke0, f"Taylor bar: plastic work {work:.4g} J = "
                  f"{work / ke0:.3f} KE0, in (0, 1] by 10 us")
        else:
            check(0.5 * ke0 <= work <= ke0, f"Taylor bar: plastic work {work:.4g} J = "
                  f"{work / ke0:.3f} KE0, in [0.5, 1]")
            spread = ts["s_x"][-1] - ts["s_x"][0]
            check(abs(spread / 1.652e-3 - 1) < 0.10,
                  f"Taylor bar: observer s moves out {1e3 * spread:.4f} mm (documented 1.652 mm)")
            check(abs(ts["top_z"][-1] / 0.021758 - 1) < 0.02,
                  f"Taylor bar: top at {1e3 * ts['top_z'][-1]:.3f} mm (documented 21.758 mm)")
        print("Taylor bar L/dp = 8: s from %.4f to %.4f mm, top %.3f mm, plastic work %.3f KE0, "
              "KE(end) %.4f KE0, nearest %.3f dp" % (1e3 * ts["s_x"][0], 1e3 * ts["s_x"][-1],
                                                   1e3 * ts["top_z"][-1], work / ke0,
                                                   ts["kinetic_energy"][-1] / ke0, closest / dp))

    # the round Taylor bar, R/dp = 6, relaxed particles
    scene = os.path.join(SRC, "cases", "taylor_bar_round", "scene.cfg")
    out = os.path.join(tmp, "round")
    code, err = run_sphsolid(scene, BACKEND, out, ["resolution.ratio=6"]
                             + (["time.end=1e-5", "bodies.bar.relaxation.steps=200"]
                                if SANITIZED else []))
    check(code == 0, f"round Taylor bar: exit {code} ({err})")
    if code == 0:
        summ, ts = run_results(out)
        check(summ["status"] == "completed" and "instability" not in summ,
              f"round Taylor bar: monitor quiet ({summ.get('instability')})")
        dp, rho0, v0, sigma_y = 3.91e-3 / 6, 2700.0, 373.0, 2.9e8
        ke, energy, t = ts["kinetic_energy"], ts["total_energy"], ts["time"]
        mass = summ["particle_count"] * rho0 * dp ** 3
        check(abs(ke[0] - 0.5 * mass * v0 ** 2) < 1e-9 * ke[0],
              f"round Taylor bar: initial kinetic energy {ke[0]:.6g} J")
        # the wall is passive: after the impact the energy may only fall
        gain = float(np.max(energy - np.minimum.accumulate(energy)))
        check(gain < 0.002 * ke[0], f"round Taylor bar: energy gain {gain:.4g} J = "
              f"{100 * gain / ke[0]:.4f} % KE0, below 0.2 %")
        lateral = max(np.max(np.abs(ts["momentum_x"])), np.max(np.abs(ts["momentum_y"])))
        check(lateral < 1e-9 * mass * v0,
              f"round Taylor bar: momentum along the wall {lateral:.3g}")
        closest = nearest(out, 2)
        check(closest > 0.25 * dp, f"round Taylor bar: nearest particle {closest / dp:.3f} dp "
              "above the wall")
        if SANITIZED:
            print("round Taylor bar R/dp = 6 to %g us (sanitized; the state at 30 us is the "
                  "release build's): energy gain %.2e KE0, nearest %.3f dp"
                  % (1e6 * t[-1], gain / ke[0], closest / dp))
        else:
            at30 = int(np.argmin(np.abs(t - 30e-6)))
            check(ke[at30] < 0.01 * ke[0],
                  f"round Taylor bar: at rest at 30 us (KE {100 * ke[at30] / ke[0]:.3f} % KE0)")
            work = plastic_work(out, rho0 * dp ** 3, sigma_y)
            check(0.5 * ke[0] <= work <= ke[0], f"round Taylor bar: plastic work {work:.4g} J = "
                  f"{work / ke[0]:.3f} KE0, in [0.5, 1]")
            # the public reference code's run (R/dp = 12, relaxed particles, its observer one
            # spacing below the top): 15.975 mm at 30 us (cases/taylor_bar_round/README.md)
            top = ts["top_z"][at30]
            check(abs(top / 0.015975 - 1) < 0.03, f"round Taylor bar: top at {1e3 * top:.3f} mm "
                  "at 30 us (reference code 15.975 mm)")
            check(abs(top / 0.016114 - 1) < 0.02,
                  f"round Taylor bar: top at {1e3 * top:.3f} mm at 30 us (documented 16.114 mm)")
            rim = float(np.max(ts["rim_x"]))
            check(abs(rim / 0.0066753 - 1) < 0.05,
                  f"round Taylor bar: rim out to {1e3 * rim:.3f} mm (documented 6.675 mm)")
            print("round Taylor bar R/dp = 6: top %.3f mm at 30 us, rim %.3f mm, KE(30 us) %.4f "
                  "KE0, energy gain %.2e KE0, plastic work %.3f KE0, nearest %.3f dp"
                  % (1e3 * top, 1e3 * rim, ke[at30] / ke[0], gain / ke[0], work / ke[0],
                     closest / dp))
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish("test_walls_" + BACKEND)
