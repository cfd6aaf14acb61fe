#!/usr/bin/python3
"""test_plot.py — tools/plot_run.py on a synthetic run directory written with h5py to the
layout of docs/output-format.md: a 2D 10 x 4 block of particles whose von Mises stress is a
known linear function of x, four snapshots, and a timeseries whose observer moves on a sine
of known amplitude.  The script runs as a file and fed on stdin (as the binary runs it); the
PNGs must exist, decode, have the sizes the script reports, not be blank, and the script's
summary lines must report the synthetic displacement amplitude and von Mises range.  A
directory without a timeseries gives exit status 2.  The angular momentum panel shows
|L - L0| / |L0| only where summary.json says angular momentum is conserved (issue #34:
the clamped plate's 200 % swing is not an error), |L| and the reason otherwise."""
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import SRC, check, finish  # noqa: E402

SCRIPT = os.path.join(SRC, "tools", "plot_run.py")
PY = "/usr/bin/python3"


# the synthetic run -------------------------------------------------------------------------
DP = 0.01
NX, NY = 10, 4
AMPLITUDE = 0.1135                      # observer y displacement amplitude [m]
PERIOD = 0.4
VM0, VM_SLOPE = 1000.0, 2.0e5           # von_mises = VM0 + VM_SLOPE * x0  [Pa]
SNAP_TIMES = [0.0, 0.1, 0.2, 0.3]
X0 = (np.arange(NX) + 0.5) * DP
VM_MIN, VM_MAX = VM0 + VM_SLOPE * X0[0], VM0 + VM_SLOPE * X0[-1]


def write_snapshot(path, pts, fields, time, index, dp):
    n = len(pts)
    with h5py.File(path, "w") as f:
        g = f.create_group("VTKHDF")
        g.attrs["Version"] = np.array([1, 0], dtype=np.int64)
        g.attrs.create("Type", np.bytes_("UnstructuredGrid"),
                       dtype=h5py.string_dtype("ascii", len("UnstructuredGrid")))
        g["NumberOfPoints"] = np.array([n], np.int64)
        g["NumberOfCells"] = np.array([n], np.int64)
        g["NumberOfConnectivityIds"] = np.array([n], np.int64)
        g["Points"] = pts.astype(np.float64)
        g["Connectivity"] = np.arange(n, dtype=np.int64)
        g["Offsets"] = np.arange(n + 1, dtype=np.int64)
        g["Types"] = np.ones(n, np.uint8)
        pd = g.create_group("PointData")
        for name, value in fields.items():
            pd[name] = value
        s = f.create_group("sphsolid")
        s.attrs["time"] = float(time)
        s.attrs["snapshot_index"] = np.int64(index)
        s.attrs["formulation"] = "enog-a"
        s.attrs["parameters"] = json.dumps({"dimension": 2, "dp": dp})


def make_run(run, with_von_mises=True, with_summary=True, partial=False, metrics=None):
    os.makedirs(os.path.join(run, "snapshots"))
    # timeseries: tip y = 0.05 + A sin(2 pi t / T), sampled where |sin| reaches 1 exactly
    ts = "timeseries.csv.partial" if partial else "timeseries.csv"
    with open(os.path.join(run, ts), "w") as f:
        f.write("time,kinetic_energy,strain_energy,total_energy,momentum_x,momentum_y,"
                "angular_momentum,tip_x,tip_y\n")
        for k in range(101):
            t = 0.01 * k
            s = math.sin(2 * math.pi * t / PERIOD)
            ke, se = 2.0 * (1 - s * s), 2.0 * s * s
            f.write(",".join(repr(v) for v in (
                t, ke, se, ke + se, 0.01 * s, 0.3 * math.cos(2 * math.pi * t / PERIOD),
                0.5 + 0.001 * t, 0.1 - 0.01 * (1 - math.cos(2 * math.pi * t / PERIOD)),
                0.05 + AMPLITUDE * s)) + "\n")
        if partial:
            f.write("1.01,2.0")                       # the torn row of a killed run
    if with_summary:
        with open(os.path.join(run, "summary.json"), "w") as f:
            json.dump({"status": "completed", "scene": {"title": "synthetic block"},
                       "formulation": "enog-a", "backend": "cpu", "precision": "double",
                       "particle_count": NX * NY,
                       "resolved": {"dimension": 2, "dp": DP},
                       **({"metrics": metrics} if metrics is not None else {})}, f)
    xs, ys = np.meshgrid(X0, (np.arange(NY) + 0.5) * DP)
    p0 = np.stack([xs.ravel(), ys.ravel(), np.zeros(NX * NY)], axis=1)
    entries = []
    for k, t in enumerate(SNAP_TIMES):
        pts = p0.copy()
        pts[:, 1] += 0.2 * math.sin(2 * math.pi * t / PERIOD) * p0[:, 0] ** 2 / X0[-1]
        fields = {"velocity": np.zeros((NX * NY, 3)), "displacement": pts - p0,
                  "density": np.full(NX * NY, 1000.0), "pressure": 10.0 * p0[:, 1],
                  "body_id": np.zeros(NX * NY, np.int32),
                  "particle_id": np.arange(NX * NY, dtype=np.int32)}
        if with_von_mises:
            fields["von_mises"] = VM0 + VM_SLOPE * p0[:, 0]
        name = f"snapshots/snapshot_{k:06d}.hdf"
        write_snapshot(os.path.join(run, name), pts, fields, t, k, DP)
        entries.append({"name": name, "time": t})
    with open(os.path.join(run, "snapshots.hdf.series"), "w") as f:
        json.dump({"file-series-version": "1.0", "files": entries}, f)


def run_script(args, stdin=False):
    if stdin:
        with open(SCRIPT) as f:
            p = subprocess.run([PY, "-"] + args, stdin=f, capture_output=True, text=True,
                               timeout=300)
    else:
        p = subprocess.run([PY, SCRIPT] + args, capture_output=True, text=True, timeout=300)
    return p.returncode, p.stdout, p.stderr


def png_lines(out):
    """{png path: the rest of its line} from the script's output."""
    lines = {}
    for line in out.splitlines():
        m = re.match(r"(.+\.png): (.*)$", line)
        if m:
            lines[m.group(1)] = m.group(2)
    return lines


def near(a, b, rel=1e-4):
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-30)


def check_png(path, what, size=None):
    check(os.path.isfile(path), f"{what}: {path} written")
    if not os.path.isfile(path):
        return None
    img = mpimg.imread(path)
    check(img.ndim == 3 and img.shape[2] in (3, 4), f"{what}: RGB(A) image, got {img.shape}")
    if size is not None:
        check(img.shape[1] == size[0] and img.shape[0] == size[1],
              f"{what}: {img.shape[1]}x{img.shape[0]} px, expected {size[0]}x{size[1]}")
    check(float(img[..., :3].std()) > 0.0, f"{what}: not blank")
    return img


def check_timeseries(lines, plots, what):
    path = os.path.join(plots, "timeseries.png")
    check(path in lines, f"{what}: a line for {path}: {sorted(lines)}")
    check_png(path, f"{what} timeseries", (1080, 1200))
    m = re.search(r"tip (\w) max \|displacement\| = ([0-9.eE+-]+) m", lines.get(path, ""))
    check(m is not None, f"{what}: displacement amplitude reported: {lines.get(path)!r}")
    if m:
        check(m.group(1) == "y", f"{what}: the largest excursion is tip y, got tip {m.group(1)}")
        check(near(float(m.group(2)), AMPLITUDE),
              f"{what}: max |displacement| {m.group(2)} m, expected {AMPLITUDE}")


def check_snapshot(lines, plots, index, what, field="von_mises", lo=VM_MIN, hi=VM_MAX):
    path = os.path.join(plots, f"snapshot_{index:06d}.png")
    line = lines.get(path, "")
    check(path in lines, f"{what}: a line for {path}: {sorted(lines)}")
    m = re.search(field + r" \[([0-9.eE+-]+), ([0-9.eE+-]+)\] Pa \(colour scale "
                  r"\[([0-9.eE+-]+), ([0-9.eE+-]+)\]\), (\d+)x(\d+) px", line)
    check(m is not None, f"{what}: {field} range and size reported: {line!r}")
    if not m:
        return
    vmin, vmax, cmin, cmax = (float(m.group(k)) for k in range(1, 5))
    check(near(vmin, lo) and near(vmax, hi),
          f"{what}: {field} range [{vmin}, {vmax}], expected [{lo}, {hi}]")
    check(near(cmin, lo) and near(cmax, hi),
          f"{what}: colour scale [{cmin}, {cmax}], expected [{lo}, {hi}]")
    t = re.search(r"t = ([0-9.eE+-]+) s", line)
    check(t is not None and abs(float(t.group(1)) - SNAP_TIMES[index]) < 1e-9,
          f"{what}: time {t and t.group(1)}, expected {SNAP_TIMES[index]}")
    width, height = int(m.group(5)), int(m.group(6))
    check(width == 1200, f"{what}: width {width} px, expected 1200")
    img = check_png(path, f"{what} snapshot {index}", (width, height))
    if img is not None:
        # the particles are drawn as a solid body: a good part of the picture is coloured
        rgb = img[..., :3]
        coloured = float(np.mean(rgb.max(axis=2) - rgb.min(axis=2) > 0.2))
        check(coloured > 0.1, f"{what}: {coloured:.3f} of the pixels coloured, expected > 0.1")


tmp = tempfile.mkdtemp(prefix="sphsolid-plot-")
try:
    run = os.path.join(tmp, "run")
    make_run(run)

    # as a file, default: timeseries + 4 snapshots (all of them) into RUN_DIR/plots
    code, out, err = run_script([run])
    check(code == 0, f"plot_run.py RUN_DIR: exit {code}: {err.strip()}")
    lines = png_lines(out)
    plots = os.path.join(run, "plots")
    check(len(lines) == 5 and len(out.splitlines()) == 5,
          f"one line per PNG, 5 PNGs: {out!r}")
    check_timeseries(lines, plots, "file")
    for k in range(4):
        check_snapshot(lines, plots, k, "file")

    # on stdin, as the binary runs it, with --out and --times
    plots2 = os.path.join(tmp, "plots-stdin")
    code, out, err = run_script([run, "--out", plots2, "--times", "0.09,0.31"], stdin=True)
    check(code == 0, f"stdin: exit {code}: {err.strip()}")
    lines = png_lines(out)
    check(sorted(os.path.basename(p) for p in lines) ==
          ["snapshot_000001.png", "snapshot_000003.png", "timeseries.png"],
          f"stdin --times 0.09,0.31: the snapshots nearest: {sorted(lines)}")
    check_timeseries(lines, plots2, "stdin")
    check_snapshot(lines, plots2, 1, "stdin")
    check_snapshot(lines, plots2, 3, "stdin")

    # --snapshots 2: the first and the last
    plots3 = os.path.join(tmp, "plots-2")
    code, out, err = run_script([run, "--out", plots3, "--snapshots", "2"])
    lines = png_lines(out)
    check(code == 0 and sorted(os.path.basename(p) for p in lines) ==
          ["snapshot_000000.png", "snapshot_000003.png", "timeseries.png"],
          f"--snapshots 2: first and last: {code} {sorted(lines)} {err.strip()}")

    # no von_mises, no summary.json (dp estimated), a killed run's timeseries.csv.partial:
    # coloured by the first scalar field (pressure = 10 y0)
    run2 = os.path.join(tmp, "run-partial")
    make_run(run2, with_von_mises=False, with_summary=False, partial=True)
    code, out, err = run_script([run2, "--snapshots", "1"])
    check(code == 0, f"partial run: exit {code}: {err.strip()}")
    lines = png_lines(out)
    plots4 = os.path.join(run2, "plots")
    check_timeseries(lines, plots4, "partial")
    y0 = (np.arange(NY) + 0.5) * DP
    check_snapshot(lines, plots4, 3, "partial, pressure", "pressure", 10 * y0[0], 10 * y0[-1])

    # angular momentum (0.5 + 0.001 t): the relative error where summary.json says it is
    # conserved, |L| and the reason where a constraint exerts a torque, or without metrics
    ts_line = {}
    for label, metrics in [
            ("conserved", {"max_angular_momentum_error": 0.002,
                           "angular_momentum_not_conserved": None}),
            ("clamped", {"max_angular_momentum_error": None,
                         "angular_momentum_not_conserved":
                         "constraint 'fixed' on region 'clamp' of body 'plate'"}),
            ("no spin", {"max_angular_momentum_error": None,
                         "angular_momentum_not_conserved": None}),
            ("no metrics", None)]:
        run_l = os.path.join(tmp, "run-L-" + label.replace(" ", "-"))
        make_run(run_l, metrics=metrics)
        code, out, err = run_script([run_l, "--snapshots", "0"])
        lines = png_lines(out)
        ts_line[label] = lines.get(os.path.join(run_l, "plots", "timeseries.png"), "")
        check(code == 0 and ts_line[label], f"angular momentum, {label}: exit {code} {err!r}")
        check_png(os.path.join(run_l, "plots", "timeseries.png"), f"angular momentum, {label}",
                  (1080, 1200))
    check("max |L - L0|/|L0| = 0.002" in ts_line["conserved"],
          f"conserved: the relative error is plotted: {ts_line['conserved']!r}")
    check("angular momentum not conserved (constraint 'fixed' on region 'clamp' of body "
          "'plate'): |L| plotted" in ts_line["clamped"] and "|L - L0|/|L0| =" not in
          ts_line["clamped"], f"clamped: |L| and the reason, no error: {ts_line['clamped']!r}")
    check("no spin (L0 = 0): |L| plotted" in ts_line["no spin"],
          f"no spin: |L| and the reason: {ts_line['no spin']!r}")
    check("|L| plotted" in ts_line["no metrics"] and "|L - L0|/|L0| =" not in
          ts_line["no metrics"], f"no metrics: |L|, not an error: {ts_line['no metrics']!r}")

    # a fluid run with a wall body: the drag and lift panel with the trailing window's mean
    # C_D from summary.json; the force columns (pressure_force_x, ...) are not observers
    run_f = os.path.join(tmp, "run-fluid")
    os.makedirs(run_f)
    with open(os.path.join(run_f, "timeseries.csv"), "w") as f:
        f.write("time,kinetic_energy,total_energy,mass,momentum_x,momentum_y,drag_coefficient,"
                "lift_coefficient,pressure_force_x,pressure_force_y,viscous_force_x,"
                "viscous_force_y\n")
        for k in range(201):
            t = 0.5 * k
            cl = 0.34 * math.sin(2 * math.pi * 0.169 * t / 2.0)
            f.write(",".join(repr(v) for v in (t, 50.0, 50.0, 1.0, 1.0, 0.0, 1.33, cl, 1.0, cl,
                                               0.33, 0.0)) + "\n")
    with open(os.path.join(run_f, "summary.json"), "w") as f:
        json.dump({"status": "completed", "formulation": "eulerian-wc",
                   "resolved": {"dimension": 2, "dp": 0.1},
                   "metrics": {"mean_drag_coefficient": 1.33, "lift_amplitude": 0.34,
                               "strouhal_number": 0.169, "force_window_start": 50.0}}, f)
    code, out, err = run_script([run_f, "--snapshots", "0"])
    line = png_lines(out).get(os.path.join(run_f, "plots", "timeseries.png"), "")
    check(code == 0 and "mean C_D = 1.33 from t = 50, C_L amplitude = 0.34, St = 0.169" in line,
          f"fluid run: the force coefficients reported: exit {code} {line!r} {err!r}")
    check("displacement" not in line, f"fluid run: no force column taken for an observer: {line!r}")
    check("clipped" not in line, f"fluid run: nothing to clip: {line!r}")
    check_png(os.path.join(run_f, "plots", "timeseries.png"), "fluid run")
    # the same run with a start-up transient (C_D 16 at t = 0.5, as the cylinder started from
    # rest has): the panel spans the run after its first tenth and says what it clips
    with open(os.path.join(run_f, "timeseries.csv")) as f:
        lines = f.read().splitlines()
    spike = lines[2].split(",")
    spike[6] = "16.0"
    lines[2] = ",".join(spike)
    with open(os.path.join(run_f, "timeseries.csv"), "w") as f:
        f.write("\n".join(lines) + "\n")
    code, out, err = run_script([run_f, "--snapshots", "0"])
    line = png_lines(out).get(os.path.join(run_f, "plots", "timeseries.png"), "")
    check(code == 0 and "the start before t = 10 clipped (coefficients -0.34 to 16)" in line,
          f"fluid run with a start-up transient: the clip reported: exit {code} {line!r} {err!r}")

    # a 1D run (a line of particles): the field against x, its range reported
    run_1 = os.path.join(tmp, "run-line")
    os.makedirs(os.path.join(run_1, "snapshots"))
    with open(os.path.join(run_1, "timeseries.csv"), "w") as f:
        f.write("time,kinetic_energy,total_energy,mass,momentum_x\n0,1,2,1,0\n1,1,2,1,0\n")
    with open(os.path.join(run_1, "summary.json"), "w") as f:
        json.dump({"status": "completed", "formulation": "eulerian-compressible",
                   "resolved": {"dimension": 1, "dp": 0.1}}, f)
    x1 = (np.arange(50) + 0.5) * 0.1
    pts1 = np.stack([x1, np.zeros(50), np.zeros(50)], axis=1)
    write_snapshot(os.path.join(run_1, "snapshots", "snapshot_000000.hdf"), pts1,
                   {"pressure": 1.0 + 0.5 * np.sin(x1)}, 0.0, 0, 0.1)
    with open(os.path.join(run_1, "snapshots.hdf.series"), "w") as f:
        json.dump({"file-series-version": "1.0",
                   "files": [{"name": "snapshots/snapshot_000000.hdf", "time": 0.0}]}, f)
    code, out, err = run_script([run_1])
    line = png_lines(out).get(os.path.join(run_1, "plots", "snapshot_000000.png"), "")
    lo, hi = float(np.min(1.0 + 0.5 * np.sin(x1))), float(np.max(1.0 + 0.5 * np.sin(x1)))
    check(code == 0 and f"pressure [{lo:.6g}, {hi:.6g}] Pa against x" in line,
          f"1D run: the pressure against x: exit {code} {line!r} {err!r}")
    check_png(os.path.join(run_1, "plots", "snapshot_000000.png"), "1D run")

    # no timeseries: exit 2 with a message; a missing directory too
    empty = os.path.join(tmp, "empty")
    os.makedirs(empty)
    for where in (empty, os.path.join(tmp, "missing")):
        code, out, err = run_script([where])
        check(code == 2, f"{where}: exit {code}, expected 2")
        check("error" in err and where in err, f"{where}: a message naming it: {err.strip()!r}")
        check(not os.path.exists(os.path.join(where, "plots")), f"{where}: no plots written")
    code, out, err = run_script([empty], stdin=True)
    check(code == 2 and "timeseries.csv" in err, f"stdin, no timeseries: {code} {err.strip()!r}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish("test_plot")
