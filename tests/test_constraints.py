#!/usr/bin/python3
"""test_constraints.py BACKEND — kinematic constraints (fixed, fixed_axes, velocity).

1. A uniaxial-strain wave.  A column 0.2 m wide and 1 m high (dp = 0.02, nu = 0.3) between
   roller walls (3 particle columns grown on each side, fixed_axes x), fixed at the bottom
   by a 3-row grip, is pushed down from a 3-row top grip at v = 0.01 c0 (SPH-GNOG-A: the
   divergence of the Jaumann stress).  With no lateral motion the strain is uniaxial, and
   the 2D model's longitudinal modulus is lambda + 2 mu = (K - G) + 2 G = K + G (in-plane
   deviator, sph_elasticity.h), so linear elastodynamics gives a compression front moving
   at c_L = sqrt((K + G) / rho0) (1.15 c0 at nu = 0.3) with the strain v / c_L behind it.
   At t = 0.5 H / c_L the plateau strain behind the front (0.75 < y < 0.93 m), from the
   displacement gradient and from the density, must be v / c_L within 5 %.  Measured at
   dp = 0.04, 0.02, 0.01: displacement +3.62, +4.27, +3.62 %, density +1.98, +2.01,
   +1.23 % -- a softness that does not shrink with resolution and we have not explained (docs/method.md,
   "Known deviations"); SPH-ENOG-A reads -17 %, its Laplacian shear force not being the
   divergence of that stress.  The column 4 dp ahead of the front must be at rest, and
   the constraints must hold exactly: the bottom grip at rest to the bit, the top grip
   displaced by v t to 1e-12 m, the roller walls without lateral displacement.
2. The tensile test of cases/tensile_2d at dp = 0.05 to its end (1 ms, the top grip
   pulled 0.5 m at 500 m/s, E = 2.1e10): the monitor stays quiet with the scene's settings
   (no clustering below 0.5 dp, no runaway speed, no NaN), the grips move exactly, the
   centre of the specimen moves up.
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
from sphtest import BIN, SRC, check, finish  # noqa: E402

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
tmp = tempfile.mkdtemp(prefix="sphsolid-constraints-")

COLUMN = """
title = "uniaxial strain column";
dimension = 2;
resolution = { dp = 0.02; };
method = { formulation = "gnog-a"; rotation = "averaged"; };
time = { end = %(end).12g; output_interval = %(end).12g; stepping = "dual"; };
materials = { m = { density = 1000.0; youngs_modulus = 1.0e6; poisson_ratio = 0.3; }; };
shapes = {
  core = { type = "box"; lower = [0.0, 0.0]; upper = [0.2, 1.0];
           lower_pad_dp = [3.0, 0.0]; upper_pad_dp = [3.0, 0.0]; };
  bottom = { type = "box"; lower = [0.0, 0.0]; upper = [0.2, 0.0];
             lower_pad_dp = [3.0, 3.0]; upper_pad_dp = [3.0, 0.0]; };
  top = { type = "box"; lower = [0.0, 1.0]; upper = [0.2, 1.0];
          lower_pad_dp = [3.0, 0.0]; upper_pad_dp = [3.0, 3.0]; };
  column = { type = "union"; parts = ["core", "bottom", "top"]; };
  walls = { type = "union";
            parts = ( { type = "box"; lower = [0.0, 0.0]; upper = [0.0, 1.0]; lower_pad_dp = [3.0, 0.0]; },
                      { type = "box"; lower = [0.2, 0.0]; upper = [0.2, 1.0]; upper_pad_dp = [3.0, 0.0]; } ); };
};
bodies = ( { name = "column"; material = "m"; shape = "column";
             constraints = ( { type = "fixed"; region = "bottom"; },
                             { type = "velocity"; region = "top"; velocity = [0.0, %(v).12g]; },
                             { type = "fixed_axes"; region = "walls"; axes = ["x"]; } ); } );
output = { snapshot_interval = %(end).12g; fields = ["displacement", "density", "particle_id"]; };
"""


def run(scene_text, name, extra=()):
    path = os.path.join(tmp, name + ".cfg")
    with open(path, "w") as f:
        f.write(scene_text)
    out = os.path.join(tmp, name)
    p = subprocess.run([BIN, "run", path, "--backend", BACKEND, "--quiet", "--out", out,
                        *extra], capture_output=True, text=True, timeout=900)
    return out, p.returncode, p.stderr.strip()


def last_snapshot(out):
    with open(os.path.join(out, "snapshots.hdf.series")) as f:
        files = json.load(f)["files"]
    with h5py.File(os.path.join(out, files[-1]["name"]), "r") as f:
        pd = f["VTKHDF/PointData"]
        return {"x": f["VTKHDF/Points"][:, :2], "u": pd["displacement"][:, :2],
                "rho": pd["density"][:], "id": pd["particle_id"][:], "time": files[-1]["time"]}


try:
    # material constants as the solver derives them (2D plane strain)
    E, nu, rho0 = 1.0e6, 0.3, 1000.0
    K, G = E / (3 * (1 - 2 * nu)), E / (2 * (1 + nu))
    c0, cl = math.sqrt(K / rho0), math.sqrt((K + G) / rho0)
    H, dp = 1.0, 0.02
    # rounded as the scene file holds them
    v = float("%.12g" % (-0.01 * c0))
    t = float("%.12g" % (0.5 * H / cl))
    out, code, err = run(COLUMN % {"end": t, "v": v}, "column")
    check(code == 0, f"column: exit {code} ({err})")
    s = last_snapshot(out)
    x0 = s["x"] - s["u"]
    y0 = x0[:, 1]
    bottom, top = y0 < 0.0, y0 > H
    walls = (x0[:, 0] < 0.0) | (x0[:, 0] > 0.2)
    check(np.all(s["u"][bottom] == 0.0), "bottom grip at rest to the bit")
    check(np.max(np.abs(s["u"][top][:, 1] - v * t)) < 1e-12 and np.all(s["u"][top][:, 0] == 0.0),
          f"top grip displaced by v t = {v * t:.6g} m: max error "
          f"{np.max(np.abs(s['u'][top][:, 1] - v * t)):.3g}")
    check(np.all(s["u"][walls & ~bottom & ~top][:, 0] == 0.0), "roller walls: no lateral motion")
    core = ~walls & ~bottom & ~top
    rows = np.round((y0 - dp / 2) / dp).astype(int)
    ks = sorted(set(rows[core]))
    yk = np.array([(k + 0.5) * dp for k in ks])
    uy = np.array([np.mean(s["u"][core & (rows == k), 1]) for k in ks])
    strain_rho = np.array([np.mean(s["rho"][core & (rows == k)]) / rho0 - 1.0 for k in ks])
    expected = abs(v) / cl
    front = H - cl * t
    plateau = (yk > 0.75) & (yk < 0.93)
    strain_u = -np.polyfit(yk[plateau], uy[plateau], 1)[0]
    rel_u, rel_rho = strain_u / expected - 1.0, np.mean(strain_rho[plateau]) / expected - 1.0
    check(abs(rel_u) < 0.05, f"plateau strain from the displacement {strain_u:.5g} against "
          f"v/c_L = {expected:.5g} ({100 * rel_u:+.2f} %)")
    check(abs(rel_rho) < 0.05, f"plateau strain from the density against v/c_L "
          f"({100 * rel_rho:+.2f} %)")
    check(np.max(np.abs(strain_rho[yk < front - 4 * dp])) < 0.05 * expected,
          "ahead of the front the column is at rest")
    print("column: plateau strain %.5g from the displacement (%+.2f %% of v/c_L), %+.2f %% from "
          "the density" % (strain_u, 100 * rel_u, 100 * rel_rho))

    # the tensile test of cases/tensile_2d at dp = 0.05
    scene = os.path.join(SRC, "cases", "tensile_2d", "scene.cfg")
    out = os.path.join(tmp, "tensile")
    p = subprocess.run([BIN, "run", scene, "--backend", BACKEND, "--quiet", "--out", out,
                        "--set", "resolution.dp=0.05"], capture_output=True, text=True,
                       timeout=900)
    check(p.returncode == 0, f"tensile: exit {p.returncode} ({p.stderr.strip()})")
    with open(os.path.join(out, "summary.json")) as f:
        summ = json.load(f)
    check(summ["status"] == "completed" and "instability" not in summ,
          f"tensile: monitor quiet ({summ.get('instability')})")
    s = last_snapshot(out)
    check(abs(s["time"] - 1e-3) < 1e-15, f"tensile: reached 1 ms ({s['time']})")
    y0 = (s["x"] - s["u"])[:, 1]
    top, bottom = y0 > 1.0, y0 < 0.0
    check(np.all(s["u"][bottom] == 0.0), "tensile: bottom grip at rest")
    check(np.max(np.abs(s["u"][top][:, 1] - 0.5)) < 1e-12, "tensile: top grip pulled 0.5 m")
    import csv
    with open(os.path.join(out, "timeseries.csv")) as f:
        series = list(csv.DictReader(f))
    check(min(float(r["min_distance_ratio"]) for r in series) > 0.5, "tensile: no clustering")
    check(float(series[-1]["centre_y"]) > 0.55, "tensile: the specimen's centre moves up")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish("test_constraints_" + BACKEND)
