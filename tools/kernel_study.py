#!/usr/bin/python3
"""kernel_study.py — 004's kernel study (Tables 1-4, Fig. 2) beside the seed's numbers.

Runs `sphsolid kernel-study --out DIR` (or reads an existing DIR with --dir), then writes
  * the results section of docs/kernel-study.md (between the markers
    <!-- kernel-study results begin --> and <!-- kernel-study results end -->; the prose
    around them is kept), tables laid out like the seed's with the seed's number beside
    each of ours,
  * docs/kernel-study.png, like 004 Fig. 2: the relaxed particles coloured by their
    relaxation residue |2 sum_j V_j grad_i W_ij|, one panel per kernel at kappa = 1.3,
  * a copy of DIR/kernel_study.json (--json, e.g. bench-results/kernel_study.json).

usage: tools/kernel_study.py [--bin build/sphsolid] [--out DIR | --dir DIR] [--md FILE]
                             [--png FILE] [--json FILE] [-- extra kernel-study flags]
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time

import numpy as np

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

KERNELS = ["wendland-c2", "laguerre-wendland", "laguerre-gauss"]
LABEL = {"wendland-c2": "Wendland", "laguerre-wendland": "Laguerre-Wendland",
         "laguerre-gauss": "Laguerre-Gauss"}
FUNCTIONS = ["one", "sin"]
COLUMNS = [("l1", "one"), ("l1", "sin"), ("linf", "one"), ("linf", "sin")]

# 004 Tables 1-4 (seed 004_ce9f8a8c2b8169e3.txt; digest §3.2.1): per (kernel, kappa) and
# corrected (False: Tables 1, 3; True: Tables 2, 4) the row L1 f=1, L1 sin, Linf f=1, Linf sin
SEED_TABLES = {
    False: {
        ("wendland-c2", 1.3): (0.034, 0.123, 0.259, 0.400),
        ("laguerre-wendland", 1.3): (0.070, 0.673, 1.880, 3.506),
        ("wendland-c2", 2.0): (0.014, 0.073, 0.027, 0.150),
        ("laguerre-wendland", 2.0): (0.010, 0.018, 0.028, 0.046),
        ("wendland-c2", 2.5): (0.018, 0.078, 0.032, 0.161),
        ("laguerre-wendland", 2.5): (0.005, 0.009, 0.017, 0.030),
        ("laguerre-gauss", 1.1): (0.021, 0.259, 0.614, 1.253),
        ("laguerre-gauss", 1.3): (0.004, 0.123, 0.011, 0.204),
        ("laguerre-gauss", 1.6): (0.007, 0.210, 0.822, 0.817),
    },
    True: {
        ("wendland-c2", 1.3): (0.039, 0.052, 0.209, 0.187),
        ("laguerre-wendland", 1.3): (0.077, 0.067, 2.334, 2.319),
        ("wendland-c2", 2.0): (0.014, 0.042, 0.026, 0.067),
        ("laguerre-wendland", 2.0): (0.011, 0.007, 0.029, 0.028),
        ("wendland-c2", 2.5): (0.018, 0.043, 0.033, 0.068),
        ("laguerre-wendland", 2.5): (0.005, 0.003, 0.017, 0.015),
        ("laguerre-gauss", 1.1): (0.021, 0.061, 0.603, 0.448),
        ("laguerre-gauss", 1.3): (0.004, 0.004, 0.011, 0.009),
        ("laguerre-gauss", 1.6): (0.006, 0.024, 0.784, 0.364),
    },
}
# 004 §2.3.2 and Fig. 2 (kappa = 1.3): residue mean and max - min.  Laguerre-Gauss: 0.004 and
# 0.011; Wendland: about ten and twenty times those (the text gives only the ratios);
# Laguerre-Wendland: mean 0.07, maximum 1.88 (its spread, the minimum being ~0)
SEED_RESIDUES = {
    "wendland-c2": (0.04, 0.22, "≈10× and ≈20× Laguerre-Gauss's (text)"),
    "laguerre-wendland": (0.07, 1.88, "max 1.88 (text)"),
    "laguerre-gauss": (0.004, 0.011, "text"),
}


def within(ours, seed):
    """The issue's acceptance: within 30 % or 0.005 of the seed's, whichever is larger."""
    return abs(ours - seed) <= max(0.3 * abs(seed), 0.005)


def key(kappa):
    return round(float(kappa), 6)


def load(out_dirs):
    """One study's kernel_study.json, or several (a study split by kernel or kappa) merged:
    the settings of the first, the lists concatenated; each case remembers its directory."""
    data = None
    for d in out_dirs:
        with open(os.path.join(d, "kernel_study.json")) as f:
            part = json.load(f)
        for c in part["cases"]:
            c["particles_file"] = os.path.join(os.path.abspath(d), c["particles_file"])
        if data is None:
            data = part
        else:
            for k in ("errors", "residues", "cases"):
                data[k] += part[k]
    errors = {}
    for e in data["errors"]:
        errors[(e["kernel"], key(e["kappa"]), e["corrected"], e["function"])] = e
    residues = {(r["kernel"], key(r["kappa"])): r for r in data["residues"]}
    return data, errors, residues


def cell(ours, seed):
    if seed is None:
        return "%.4f" % ours
    mark = "" if within(ours, seed) else " ✗"
    return "%.4f (%.3f)%s" % (ours, seed, mark)


def error_table(errors, corrected, cases):
    title = "with" if corrected else "without"
    lines = ["**Tables %s — df/dx truncation errors %s the correction matrix B** "
             "(ours, the seed's in brackets; ✗: beyond max(30 %%, 0.005))"
             % ("2 and 4" if corrected else "1 and 3", title), "",
             "| Kernel | κ | L1 f=1 | L1 f=sin(2πx) | L∞ f=1 | L∞ f=sin(2πx) |",
             "|---|---|---|---|---|---|"]
    for kernel, kappa in cases:
        seed = SEED_TABLES[corrected].get((kernel, kappa))
        row = ["%s" % LABEL[kernel], "%g" % kappa]
        for i, (norm, fn) in enumerate(COLUMNS):
            e = errors.get((kernel, kappa, corrected, fn))
            row.append(cell(e[norm], seed[i] if seed else None) if e else "—")
        lines.append("| " + " | ".join(row) + " |")
    return lines


def acceptance(errors, residues):
    """At kappa = 1.3: (entries within, entries compared, list of misses) and the orderings."""
    inside, total, misses = 0, 0, []
    for corrected in (False, True):
        for kernel in KERNELS:
            seed = SEED_TABLES[corrected].get((kernel, 1.3))
            for i, (norm, fn) in enumerate(COLUMNS):
                e = errors.get((kernel, 1.3, corrected, fn))
                if not e or not seed:
                    continue
                total += 1
                if within(e[norm], seed[i]):
                    inside += 1
                else:
                    misses.append("%s %s %s %s: %.4f (seed %.3f)" % (
                        LABEL[kernel], "with B" if corrected else "without B", norm,
                        "f=1" if fn == "one" else "sin", e[norm], seed[i]))
    checks = []
    sin_b = {k: errors.get((k, 1.3, True, "sin")) for k in KERNELS}
    if all(sin_b.values()):
        for norm in ("l1", "linf"):
            best = min(KERNELS, key=lambda k: sin_b[k][norm])
            checks.append(("with B, Laguerre-Gauss has the smallest %s error for sin(2πx)"
                           % norm, best == "laguerre-gauss"))
        for corrected in (False, True):
            for norm, fn in COLUMNS:
                vals = {k: errors[(k, 1.3, corrected, fn)][norm] for k in KERNELS}
                checks.append(("Laguerre-Wendland worst at κ = 1.3, %s B, %s %s" % (
                    "with" if corrected else "without", norm, "f=1" if fn == "one" else "sin"),
                    max(vals, key=vals.get) == "laguerre-wendland"))
    lg = residues.get(("laguerre-gauss", 1.3))
    if lg:
        checks.append(("Laguerre-Gauss residue mean %.4f ≤ 0.006 (seed 0.004)" % lg["mean"],
                       lg["mean"] <= 0.006))
    return inside, total, misses, checks


def markdown(data, errors, residues, runtime):
    cases = []
    for c in data["cases"]:
        kc = (c["kernel"], key(c["kappa"]))
        if kc not in cases:
            cases.append(kc)
    order = {k: i for i, k in enumerate(KERNELS)}
    cases.sort(key=lambda kc: (kc[0] == "laguerre-gauss", kc[1], order[kc[0]]))
    s = data["settings"]
    lines = ["<!-- kernel-study results begin (written by tools/kernel_study.py) -->", "",
             "Measured with `sphsolid kernel-study` at dp = %.6g for κ = 1.3 (h = %.6g for every "
             "κ), %d relaxation steps, seed %d, boundary band %g h excluded%s."
             % (s["dp_reference"], s["h"], s["relaxation_steps"], s["seed"], s.get("exclude_h", 2.0),
                "; the whole study took %.0f s on this machine" % runtime if runtime else ""),
             ""]
    for corrected in (False, True):
        lines += error_table(errors, corrected, cases) + [""]
    lines += ["**Relaxation residue** |2 Σ_j V_j ∇_i W_ij| (1/m, unscaled; 004 Fig. 2) over the "
              "interior particles", "",
              "| Kernel | κ | mean | max − min | seed mean | seed max − min | particles (interior)"
              " | relax s |", "|---|---|---|---|---|---|---|---|"]
    by_case = {(c["kernel"], key(c["kappa"])): c for c in data["cases"]}
    for kernel, kappa in cases:
        r = residues[(kernel, kappa)]
        c = by_case[(kernel, kappa)]
        seed = SEED_RESIDUES.get(kernel) if kappa == 1.3 else None
        lines.append("| %s | %g | %.4f | %.4f | %s | %s | %d (%d) | %.0f |" % (
            LABEL[kernel], kappa, r["mean"], r["max"] - r["min"],
            "%.3g" % seed[0] if seed else "—", "%.3g (%s)" % (seed[1], seed[2]) if seed else "—",
            c["particles"], c["interior_particles"], c["relax_seconds"]))
    inside, total, misses, checks = acceptance(errors, residues)
    lines += ["", "**Acceptance at κ = 1.3** (issue #31): %d of %d table entries within "
              "max(30 %%, 0.005) of the seed's." % (inside, total)]
    if misses:
        lines += ["", "Beyond it:", ""] + ["- " + m for m in misses]
    lines += ["", "Orderings and residue:", ""]
    lines += ["- %s: %s" % (what, "holds" if ok else "**does not hold**") for what, ok in checks]
    lines += ["", "<!-- kernel-study results end -->"]
    return "\n".join(lines) + "\n"


def write_markdown(path, section):
    begin, end = "<!-- kernel-study results begin", "<!-- kernel-study results end -->"
    text = open(path).read() if os.path.exists(path) else ""
    if begin in text and end in text:
        head = text[:text.index(begin)]
        tail = text[text.index(end) + len(end):].lstrip("\n")
        text = head + section + ("\n" + tail if tail else "")
    else:
        text = text + ("\n" if text else "") + section
    tmp = path + ".partial"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def figure(data, path, kappa=1.3):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    panels = [c for c in data["cases"] if key(c["kappa"]) == kappa]
    panels.sort(key=lambda c: KERNELS.index(c["kernel"]))
    if not panels:
        print("kernel_study.py: no case at kappa = %g, no figure" % kappa, file=sys.stderr)
        return
    # 004 Fig. 2's colour range, 3.4e-6 to 4.0e-2
    norm = LogNorm(vmin=3.4e-6, vmax=4.0e-2)
    cmap = plt.get_cmap("jet", 48)  # 48 levels: the 256-colour PNG below keeps them all
    fig, axes = plt.subplots(1, len(panels), figsize=(4.6 * len(panels), 4.6),
                             constrained_layout=True)
    axes = np.atleast_1d(axes)
    sc = None
    for ax, c in zip(axes, panels):
        p = np.genfromtxt(c["particles_file"], delimiter=",", names=True)
        inner = p["interior"] > 0
        # a marker about one spacing wide (points: 72 per inch, the panel ~2.1 units wide)
        size = (0.95 * c["dp"] * 72.0 * 4.0 / 2.1) ** 2
        ax.scatter(p["x"][~inner], p["y"][~inner], s=size, c="0.8", linewidths=0)
        sc = ax.scatter(p["x"][inner], p["y"][inner], s=size,
                        c=np.clip(p["residue"][inner], 3.4e-6, None), cmap=cmap, norm=norm,
                        linewidths=0)
        r = [x for x in data["residues"] if x["kernel"] == c["kernel"]
             and key(x["kappa"]) == kappa][0]
        ax.set_title("%s, κ = %g\nresidue mean %.4f, max − min %.4f"
                     % (LABEL[c["kernel"]], kappa, r["mean"], r["max"] - r["min"]), fontsize=10)
        ax.set_aspect("equal")
        ax.set_xlim(-1.02, 1.02)
        ax.set_ylim(-1.02, 1.02)
        ax.set_xticks([-1, 0, 1])
        ax.set_yticks([-1, 0, 1])
    fig.colorbar(sc, ax=list(axes), shrink=0.8,
                 label="relaxation residue |2 Σ V_j ∇W_ij| (1/m); grey: boundary band")
    tmp = path + ".partial.png"
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    # 256 colours: a quarter of the bytes of the RGBA image, the same picture
    from PIL import Image
    Image.open(tmp).convert("RGB").quantize(256, method=Image.Quantize.FASTOCTREE).save(
        tmp, optimize=True)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.environ.get("SPHSOLID_BIN",
                                                    os.path.join(SRC, "build", "sphsolid")))
    ap.add_argument("--out", default="runs/kernel-study",
                    help="run the study into this directory")
    ap.add_argument("--dir", action="append",
                    help="read an existing study directory instead of running (repeat to merge "
                    "a study split by kernel or kappa)")
    ap.add_argument("--md", default=os.path.join(SRC, "docs", "kernel-study.md"))
    ap.add_argument("--png", default=os.path.join(SRC, "docs", "kernel-study.png"))
    ap.add_argument("--json", help="copy kernel_study.json here")
    ap.add_argument("extra", nargs="*", help="flags passed to `sphsolid kernel-study`")
    a = ap.parse_args()
    runtime = None
    dirs = a.dir
    if not dirs:
        out_dir = a.out
        dirs = [out_dir]
        t0 = time.monotonic()
        p = subprocess.run([a.bin, "kernel-study", "--out", out_dir] + a.extra)
        runtime = time.monotonic() - t0
        if p.returncode != 0:
            sys.exit(p.returncode)
        print("kernel_study.py: the study took %.1f s" % runtime)
    data, errors, residues = load(dirs)
    write_markdown(a.md, markdown(data, errors, residues, runtime))
    figure(data, a.png)
    if a.json:
        if len(dirs) == 1:
            shutil.copyfile(os.path.join(dirs[0], "kernel_study.json"), a.json)
        else:
            for c in data["cases"]:
                c["particles_file"] = os.path.basename(c["particles_file"])
            with open(a.json + ".partial", "w") as f:
                json.dump(data, f, indent=2)
            os.replace(a.json + ".partial", a.json)
    inside, total, misses, checks = acceptance(errors, residues)
    print("kernel_study.py: %d of %d entries at kappa = 1.3 within the acceptance; %s, %s"
          % (inside, total, a.md, a.png))
    for what, ok in checks:
        print("  %s: %s" % (what, "holds" if ok else "DOES NOT HOLD"))


if __name__ == "__main__":
    main()
