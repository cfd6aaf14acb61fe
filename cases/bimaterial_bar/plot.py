#!/usr/bin/python3
"""plot.py — the bimaterial bar's normal tractions against the 1D relations
(cases/bimaterial_bar).

    /usr/bin/python3 cases/bimaterial_bar/plot.py RUN_DIR [--out FILE.png]

RUN_DIR is a run of scene.cfg (any dp, either material first).  Plots the normal traction
t . n of the observers `incident` and `transmitted` against time, with the levels the 1D
relations give from the measured incident amplitude: R sigma_I (the reflected pulse at
`incident`) and T sigma_I (the transmitted pulse), T and R from summary.json's
*_theory values.  Prints the measured ratios beside the theory.  Writes FILE.png (default
bimaterial_bar.png in the current directory).  Exit status 2, with a message, when RUN_DIR
has no summary.json with the wave metrics.
"""
import argparse
import json
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run")
    ap.add_argument("--out", default="bimaterial_bar.png")
    a = ap.parse_args()
    try:
        with open(os.path.join(a.run, "summary.json")) as f:
            m = json.load(f)["metrics"]
        sigma_i, t_th, r_th = (m["incident_stress"], m["transmitted_stress_ratio_theory"],
                               m["reflected_stress_ratio_theory"])
    except (OSError, KeyError, ValueError) as e:
        print(f"plot.py: {a.run}: no summary.json with the wave metrics ({e})", file=sys.stderr)
        return 2
    ts = np.genfromtxt(os.path.join(a.run, "timeseries.csv"), delimiter=",", names=True)
    t_us = ts["time"] * 1e6
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(t_us, ts["incident_traction_x"] / 1e6, label="incident observer (x = 0.3 m)")
    ax.plot(t_us, ts["transmitted_traction_x"] / 1e6, label="transmitted observer (x = 0.7 m)")
    for level, text, style in ((sigma_i, "measured incident", ":"),
                               (r_th * sigma_i, f"R sigma_I, R = {r_th:.3f}", "--"),
                               (t_th * sigma_i, f"T sigma_I, T = {t_th:.3f}", "-.")):
        ax.axhline(level / 1e6, color="grey", linestyle=style, linewidth=1, label=text)
    ax.set_xlabel("t (us)")
    ax.set_ylabel("normal traction (MPa)")
    ax.legend(fontsize=8)
    ax.set_title(f"T = {m['transmitted_stress_ratio']:.4f} (theory {t_th:.4f}), "
                 f"R = {m['reflected_stress_ratio']:.4f} (theory {r_th:.4f})", fontsize=9)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"T {m['transmitted_stress_ratio']:.4f} theory {t_th:.4f}; "
          f"R {m['reflected_stress_ratio']:.4f} theory {r_th:.4f}; wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
