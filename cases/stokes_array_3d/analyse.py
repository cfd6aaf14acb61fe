#!/usr/bin/python3
"""analyse.py RUN_DIR [--json FILE] — the drag of the sphere in a run of
cases/stokes_array_3d/scene.cfg against Hasimoto's (1959) simple cubic array.

The steady mean velocity U over the cell (timeseries.csv's momentum_x: rho = 1
to Mach 1e-4, L = 1) is the Aitken extrapolation of its last three outputs;
F = rho g L^3 balances the driving over the whole cell, and
K = F / (6 pi mu a U) is compared with 1 / (1 - 1.7601 c^(1/3) + c - 1.5593 c^2).
The wall body's force (pressure_force_x + viscous_force_x) plus the rate of
the fluid's momentum balances gravity on the fluid, rho g (1 - c) L^3 on the
lattice's fluid volume; its pressure and viscous shares are printed (an
isolated sphere in Stokes flow: 1/3 and 2/3)."""
import argparse
import csv
import json
import math
import os
import re


def scene_numbers(run_dir):
    """(dp, g, mu, a) from the scene the run resolved (summary.json, overrides applied)."""
    with open(os.path.join(run_dir, "summary.json")) as f:
        text = json.load(f)["scene"]["resolved_text"]

    def number(pattern):
        return float(re.search(pattern, text).group(1))
    return (number(r"\bdp\s*=\s*([0-9.eE+-]+)"), number(r"gravity\s*=\s*\[\s*([0-9.eE+-]+)"),
            number(r"viscosity\s*=\s*([0-9.eE+-]+)"), number(r"radius\s*=\s*([0-9.eE+-]+)"))


def analyse(run_dir):
    with open(os.path.join(run_dir, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    t = [float(r["time"]) for r in rows]
    u = [float(r["momentum_x"]) for r in rows]
    dp, g, mu, a = scene_numbers(run_dir)
    c = 4.0 * math.pi * a ** 3 / 3.0
    hasimoto = 1.0 / (1.0 - 1.7601 * c ** (1.0 / 3.0) + c - 1.5593 * c * c)
    u0, u1, u2 = u[-3], u[-2], u[-1]
    ratio = (u2 - u1) / (u1 - u0)
    steady = u2 + (u2 - u1) * ratio / (1.0 - ratio)
    k = g / (6.0 * math.pi * mu * a * steady)
    pressure, viscous = float(rows[-1]["pressure_force_x"]), float(rows[-1]["viscous_force_x"])
    rate = (u2 - u1) / (t[-1] - t[-2])
    return {"dp": dp, "radius_over_dp": a / dp, "solid_fraction": c, "time": t[-1],
            "velocity_last": u2, "velocity_steady": steady, "aitken_ratio": ratio,
            "aitken_correction": steady / u2 - 1.0, "K": k, "K_hasimoto": hasimoto,
            "K_error": k / hasimoto - 1.0, "wall_force": pressure + viscous,
            "pressure_share": pressure / (pressure + viscous),
            "momentum_rate": rate, "gravity_on_fluid": g * (1.0 - c)}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("run_dir")
    p.add_argument("--json", help="write the numbers to this file")
    args = p.parse_args()
    r = analyse(args.run_dir)
    print("dp = %.6g (a = %.2f dp), c = %.4g, to t = %g" % (r["dp"], r["radius_over_dp"],
                                                            r["solid_fraction"], r["time"]))
    print("U(t) = %.7g, steady %.7g (Aitken ratio %.3f, correction %+.3g)"
          % (r["velocity_last"], r["velocity_steady"], r["aitken_ratio"], r["aitken_correction"]))
    print("K = F / (6 pi mu a U) = %.5f against Hasimoto's %.5f (%+.3g)"
          % (r["K"], r["K_hasimoto"], r["K_error"]))
    print("wall force %.6g (pressure %.3f, viscous %.3f) + dP/dt %.3g against rho g (1 - c) L^3 "
          "%.6g (the lattice's fluid volume differs from 1 - c by its surface)"
          % (r["wall_force"], r["pressure_share"], 1.0 - r["pressure_share"], r["momentum_rate"],
             r["gravity_on_fluid"]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(r, f, indent=1)


if __name__ == "__main__":
    main()
