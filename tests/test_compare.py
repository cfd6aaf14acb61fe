#!/usr/bin/python3
"""test_compare.py — `sphsolid compare RUN_A RUN_B`: exit status 0 for runs within
tolerance, 3 for a difference beyond it (the report names the field, particle,
component and time), 2 for bad flags and missing run directories, 1 for an
unreadable snapshot.  The run directories are synthetic, written with h5py
exactly as docs/output-format.md describes, so the test does not depend on the
solver or the snapshot writer.

Issue #34: quantities zero in theory (the linear momentum of a spinning plate) are
measured against the physical scale of summary.json "scales", so the native and the
OpenCL spinning plate (pocl, when present) agree at the default tolerance while a 1e-6
perturbation still fails; an incomplete run (a killed run: no summary.json, only
timeseries.csv.partial) fails the comparison unless --common-prefix asks for the part
both runs have."""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, SRC, check, finish  # noqa: E402


def compare(*args):
    p = subprocess.run([BIN, "compare"] + [str(a) for a in args], capture_output=True, text=True,
                       timeout=120)
    return p.returncode, p.stdout, p.stderr


N = 40
SNAPSHOT_TIMES = [0.0, 0.1, 0.2]
CSV_COLUMNS = ["time", "kinetic_energy", "strain_energy", "total_energy", "momentum_x",
               "momentum_y", "angular_momentum", "tip_x", "tip_y"]


def base_data(n=N):
    """Snapshots (time, points, point data) and time-series rows of a small 2D run."""
    rng = np.random.default_rng(12345)
    x0 = np.zeros((n, 3))
    x0[:, 0] = rng.uniform(0.0, 0.2, n)
    x0[:, 1] = rng.uniform(0.0, 0.02, n)
    snapshots = []
    for t in SNAPSHOT_TIMES:
        vel = np.zeros((n, 3))
        vel[:, :2] = rng.uniform(-1.0, 1.0, (n, 2))
        vel[17, 1] = 0.9  # the particle the perturbation tests change
        disp = np.zeros((n, 3))
        disp[:, :2] = t * vel[:, :2]
        density = 1000.0 + rng.uniform(-1.0, 1.0, n)
        fields = {
            "velocity": vel,
            "displacement": disp,
            "density": density,
            "pressure": 2500.0 * (density - 1000.0),
            "von_mises": rng.uniform(0.0, 1e4, n),
            "body_id": np.zeros(n, dtype=np.int32),
            "particle_id": np.arange(n, dtype=np.int32),
        }
        snapshots.append((t, x0 + disp, fields))
    times = np.linspace(0.0, 0.2, 21)
    rows = np.column_stack([times] + [rng.uniform(-1.0, 1.0, times.size) * 10.0 ** k
                                      for k in range(len(CSV_COLUMNS) - 1)])
    return snapshots, rows


def copy_data(data):
    snapshots, rows = data
    return ([(t, p.copy(), {k: v.copy() for k, v in f.items()}) for t, p, f in snapshots],
            rows.copy())


def write_run(path, data, real=np.float64, columns=CSV_COLUMNS, snapshots_on=True,
              timeseries_on=True, summary=None):
    """A run directory as in docs/output-format.md: timeseries.csv,
    snapshots.hdf.series, snapshots/snapshot_NNNNNN.hdf and summary.json (the marker of
    a finished run: {"status": "completed"} unless `summary` says otherwise)."""
    snapshots, rows = data
    os.makedirs(path)
    with open(os.path.join(path, "summary.json"), "w") as f:
        json.dump(summary if summary is not None else {"status": "completed"}, f)
    if timeseries_on:
        with open(os.path.join(path, "timeseries.csv"), "w") as f:
            f.write(",".join(columns) + "\n")
            for row in rows:
                f.write(",".join(repr(float(v)) for v in row) + "\n")
    if not snapshots_on:
        return path
    os.makedirs(os.path.join(path, "snapshots"))
    index = []
    for k, (t, points, fields) in enumerate(snapshots):
        name = f"snapshots/snapshot_{k:06d}.hdf"
        n = points.shape[0]
        with h5py.File(os.path.join(path, name), "w") as h:
            v = h.create_group("VTKHDF")
            v.attrs["Version"] = np.array([1, 0], dtype=np.int64)
            v.attrs["Type"] = np.string_("UnstructuredGrid")
            for key in ("NumberOfPoints", "NumberOfCells", "NumberOfConnectivityIds"):
                v.create_dataset(key, data=np.array([n], dtype=np.int64))
            v.create_dataset("Points", data=points.astype(real))
            v.create_dataset("Connectivity", data=np.arange(n, dtype=np.int64))
            v.create_dataset("Offsets", data=np.arange(n + 1, dtype=np.int64))
            v.create_dataset("Types", data=np.ones(n, dtype=np.uint8))
            pd = v.create_group("PointData")
            for key, value in fields.items():
                pd.create_dataset(key, data=value if value.dtype == np.int32 else value.astype(real))
            s = h.create_group("sphsolid")
            s.attrs["time"] = t
            s.attrs["snapshot_index"] = np.int64(k)
        index.append({"name": name, "time": t})
    with open(os.path.join(path, "snapshots.hdf.series"), "w") as f:
        json.dump({"file-series-version": "1.0", "files": index}, f)
    return path


def table_row(out, name):
    """(max |a-b|, rel) of a field or column in the report."""
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 4 and parts[0] == name:
            return float(parts[1]), float(parts[2])
    return None


tmp = tempfile.mkdtemp(prefix="sphsolid-compare-")
try:
    base = base_data()
    run_a = write_run(os.path.join(tmp, "a"), base)
    run_same = write_run(os.path.join(tmp, "same"), copy_data(base))

    # identical runs pass, every field and column listed
    code, out, err = compare(run_a, run_same)
    check(code == 0, f"identical: exit status {code} ({err.strip()})")
    check("compare: PASS" in out, f"identical: PASS line\n{out}")
    for name in ["Points", "velocity", "density", "particle_id", "kinetic_energy", "tip_y"]:
        row = table_row(out, name)
        check(row == (0.0, 0.0), f"identical: {name} listed with zero difference: {row}")
    check("time series (timeseries.csv): 21 rows compared" in out, f"identical: row count\n{out}")
    check("snapshots: 3 pairs compared" in out, f"identical: snapshot count\n{out}")

    # velocity of particle 17, component 1, in the second snapshot, off by 1e-6 relative
    data = copy_data(base)
    data[0][1][2]["velocity"][17, 1] *= 1.0 + 1e-6
    run_b = write_run(os.path.join(tmp, "vel6"), data)
    code, out, err = compare(run_a, run_b)
    final = out.strip().splitlines()[-1] if out.strip() else ""
    check(code == 3, f"velocity 1e-6: exit status {code}, expected 3 ({err.strip()})")
    check(final.startswith("compare: FAIL: velocity differs by"), f"velocity 1e-6: {final}")
    check("particle 17," in final and "component 1," in final and "t = 0.1 s" in final,
          f"velocity 1e-6: names particle 17, component 1, t = 0.1: {final}")
    expected = abs(data[0][1][2]["velocity"][17, 1] - base[0][1][2]["velocity"][17, 1])
    row = table_row(out, "velocity")
    check(row is not None and abs(row[0] - expected) <= 1e-6 * expected,
          f"velocity 1e-6: max |a-b| {row} vs {expected}")

    # 1e-12 relative: within the default rtol, beyond --rtol 1e-14
    data = copy_data(base)
    data[0][1][2]["velocity"][17, 1] *= 1.0 + 1e-12
    run_b = write_run(os.path.join(tmp, "vel12"), data)
    code, out, err = compare(run_a, run_b)
    check(code == 0 and "compare: PASS" in out, f"velocity 1e-12, default rtol: {code}\n{out}")
    code, out, err = compare(run_a, run_b, "--rtol", "1e-14")
    check(code == 3 and "FAIL: velocity" in out and "particle 17," in out,
          f"velocity 1e-12, --rtol 1e-14: {code}\n{out}")
    code, out, err = compare(run_a, run_b, "--rtol", "0", "--atol", "1e-9")
    check(code == 0, f"velocity 1e-12, --atol 1e-9: {code}\n{out}")

    # a time-series column off in one row
    data = copy_data(base)
    col = CSV_COLUMNS.index("strain_energy")
    data[1][7, col] *= 1.0 + 1e-6
    run_b = write_run(os.path.join(tmp, "csv"), data)
    code, out, err = compare(run_a, run_b)
    final = out.strip().splitlines()[-1] if out.strip() else ""
    check(code == 3, f"csv column: exit status {code} ({err.strip()})")
    check(final.startswith("compare: FAIL: strain_energy differs by"), f"csv column: {final}")
    check(f"t = {data[1][7, 0]:.9g} s" in final, f"csv column: names the row's time: {final}")

    # different particle counts
    small = base_data(N - 1)
    small = (small[0], base[1].copy())
    run_b = write_run(os.path.join(tmp, "small"), small)
    code, out, err = compare(run_a, run_b)
    check(code == 3, f"particle counts: exit status {code} ({err.strip()})")
    check(f"{N} particles in run A, {N - 1} in run B" in out, f"particle counts:\n{out}")

    # fewer time-series rows
    data = copy_data(base)
    data = (data[0], data[1][:-2])
    run_b = write_run(os.path.join(tmp, "short"), data)
    code, out, err = compare(run_a, run_b)
    check(code == 3 and "run A has 21 rows, run B has 19" in out, f"row counts: {code}\n{out}")

    # a column in one run only is reported, not a failure
    data = copy_data(base)
    data = (data[0], np.column_stack([data[1], np.ones(data[1].shape[0])]))
    run_b = write_run(os.path.join(tmp, "extra"), data, columns=CSV_COLUMNS + ["extra_col"])
    code, out, err = compare(run_a, run_b)
    check(code == 0 and "extra_col is only in run B" in out, f"extra column: {code}\n{out}")

    # float32 storage of the same values: the difference is the float32 rounding
    run_b = write_run(os.path.join(tmp, "single"), copy_data(base), real=np.float32)
    code, out, err = compare(run_a, run_b)
    check(code == 3, f"float32: exit status {code}, expected 3 ({err.strip()})")
    for name in ["velocity", "Points", "density", "von_mises"]:
        if name == "Points":
            values = [s[1] for s in base[0]]
        else:
            values = [s[2][name] for s in base[0]]
        expected = max(float(np.max(np.abs(v - v.astype(np.float32).astype(np.float64))))
                       for v in values)
        row = table_row(out, name)
        check(row is not None and abs(row[0] - expected) <= 1e-6 * expected,
              f"float32: {name} max |a-b| {row} vs float32 rounding {expected}")
    code, out, err = compare(run_a, run_b, "--rtol", "1e-7")
    check(code == 0, f"float32 within --rtol 1e-7: {code}\n{out}")

    # --fields restricts the point data
    code, out, err = compare(run_a, run_b, "--fields", "velocity,density", "--rtol", "1e-7")
    check(code == 0 and table_row(out, "velocity") and table_row(out, "density") and
          not table_row(out, "Points") and not table_row(out, "pressure"),
          f"--fields velocity,density: {code}\n{out}")
    code, out, err = compare(run_a, run_same, "--fields", "temperature")
    check(code == 2 and "temperature" in err, f"--fields temperature: {code} {err.strip()}")

    # only time series in both runs; nothing in common
    ts_a = write_run(os.path.join(tmp, "ts_a"), base, snapshots_on=False)
    ts_b = write_run(os.path.join(tmp, "ts_b"), copy_data(base), snapshots_on=False)
    code, out, err = compare(ts_a, ts_b)
    check(code == 0 and "compare: PASS" in out, f"time series only: {code}\n{out}")
    snap_only = write_run(os.path.join(tmp, "snap_only"), base, timeseries_on=False)
    code, out, err = compare(ts_a, snap_only)
    check(code == 2 and "nothing to compare" in err, f"nothing in common: {code} {err.strip()}")

    # an unreadable snapshot is a runtime error naming the file
    broken = write_run(os.path.join(tmp, "broken"), copy_data(base))
    bad_file = os.path.join(broken, "snapshots", "snapshot_000001.hdf")
    with open(bad_file, "w") as f:
        f.write("not HDF5\n")
    code, out, err = compare(run_a, broken)
    check(code == 1 and "snapshot_000001.hdf" in err, f"unreadable snapshot: {code} {err.strip()}")

    # bad flags and missing or empty run directories
    empty = os.path.join(tmp, "empty")
    os.makedirs(empty)
    for args, needle in [
        ([run_a, run_same, "--frobnicate"], "--frobnicate"),
        ([run_a, run_same, "--rtol", "abc"], "--rtol"),
        ([run_a, run_same, "--rtol", "-1"], "--rtol"),
        ([run_a, run_same, "--atol"], "--atol"),
        ([run_a, run_same, "--fields", "velocity,,density"], "--fields"),
        ([run_a], "two run directories"),
        ([run_a, run_same, run_same], "unexpected argument"),
        ([run_a, os.path.join(tmp, "missing")], os.path.join(tmp, "missing")),
        ([os.path.join(tmp, "missing"), run_a], os.path.join(tmp, "missing")),
        ([run_a, empty], empty),
    ]:
        code, out, err = compare(*args)
        check(code == 2, f"{args}: exit status {code}, expected 2 ({err.strip()})")
        check(needle in err, f"{args}: message names {needle}: {err.strip()}")

    # --- issue #34, 9: quantities zero in theory against the physical scale ----------------
    # a spinning plate's linear momentum is round-off, |p| ~ 1e-11, different in each run,
    # against sum m |v| ~ 2e4: within the default rtol of that scale, not of its own size
    rng = np.random.default_rng(7)
    spin_scales = {"total_mass": 1100.0, "momentum": 2.0e4, "angular_momentum": 9.0e3,
                   "energy": 2.0e5}
    p_cols = [CSV_COLUMNS.index("momentum_x"), CSV_COLUMNS.index("momentum_y")]

    def spin_data():
        data = copy_data(base)
        data[1][:, p_cols] = rng.uniform(-2e-11, 2e-11, (data[1].shape[0], 2))
        return data

    spin_a = write_run(os.path.join(tmp, "spin_a"), spin_data(),
                       summary={"status": "completed", "scales": spin_scales})
    spin_b_data = spin_data()
    spin_b = write_run(os.path.join(tmp, "spin_b"), spin_b_data,
                       summary={"status": "completed", "scales": spin_scales})
    code, out, err = compare(spin_a, spin_b)
    check(code == 0 and "compare: PASS" in out,
          f"momentum round-off against summary.json scales: exit {code}\n{out}{err}")
    check("momentum          2.000000e+04  for momentum_*" in out,
          f"the report states the momentum scale it used:\n{out}")
    row = table_row(out, "momentum_x")
    check(row is not None and row[1] < 1e-14,
          f"momentum_x relative to 2e4, not to its own 2e-11: {row}")
    # without the scales (a directory of another tool) each column is its own scale: fails
    spin_c = write_run(os.path.join(tmp, "spin_c"), copy_data(spin_b_data))
    code, out, err = compare(spin_a, spin_c)
    check(code == 0, f"the scale of one run is enough (same scene): exit {code}\n{out}")
    spin_d = write_run(os.path.join(tmp, "spin_d"), spin_data())
    code, out, err = compare(spin_c, spin_d)
    check(code == 3 and "neither run's summary.json states" in out,
          f"no scales in either run: relative to the column, fails: exit {code}\n{out}")
    # a real difference of 1e-6 of the scale still fails, naming the column
    data = copy_data(spin_b_data)
    data[1][5, p_cols[0]] += 1e-6 * spin_scales["momentum"]
    spin_e = write_run(os.path.join(tmp, "spin_e"), data,
                       summary={"status": "completed", "scales": spin_scales})
    code, out, err = compare(spin_a, spin_e)
    final = out.strip().splitlines()[-1] if out.strip() else ""
    check(code == 3 and final.startswith("compare: FAIL: momentum_x differs by"),
          f"momentum off by 1e-6 of sum m|v|: exit {code}: {final}")

    # the native and the OpenCL spinning plate (pocl here, when it is installed)
    devices = subprocess.run([BIN, "devices"], capture_output=True, text=True, timeout=120)
    if "OpenCL device 0" in devices.stdout:
        scene = os.path.join(SRC, "cases", "spinning_plate_2d", "scene.cfg")
        plates = {}
        for backend in ("cpu", "opencl"):
            plates[backend] = os.path.join(tmp, f"plate_{backend}")
            p = subprocess.run([BIN, "run", scene, "--backend", backend, "--quiet", "--out",
                                plates[backend], "--set", "resolution.dp=0.1", "--set",
                                "time.end=0.05", "--set", "output.snapshot_interval=0.05"],
                               capture_output=True, text=True, timeout=600)
            check(p.returncode == 0, f"spinning plate on {backend}: {p.stderr.strip()}")
        code, out, err = compare(plates["cpu"], plates["opencl"])
        check(code == 0 and "compare: PASS" in out,
              f"native vs OpenCL spinning plate, default tolerance: exit {code}\n{out}{err}")
        check(re.search(r"momentum +[0-9.e+]+ +for momentum_\*", out) is not None,
              f"native vs OpenCL: the momentum scale is stated:\n{out}")
        # 1e-6 of the speeds in one snapshot velocity, and of the kinetic energy: both fail
        bad = os.path.join(tmp, "plate_bad_velocity")
        shutil.copytree(plates["opencl"], bad)
        with h5py.File(os.path.join(bad, "snapshots", "snapshot_000001.hdf"), "r+") as f:
            v = f["VTKHDF/PointData/velocity"]
            row = v[7]
            row[0] += 1e-6 * float(np.max(np.abs(v[()])))
            v[7] = row
        code, out, err = compare(plates["cpu"], bad)
        check(code == 3 and "FAIL: velocity" in out and "particle 7," in out,
              f"native vs OpenCL, velocity +1e-6: exit {code}\n{out}")
        bad = os.path.join(tmp, "plate_bad_energy")
        shutil.copytree(plates["opencl"], bad)
        ts = os.path.join(bad, "timeseries.csv")
        lines = open(ts).read().splitlines()
        cells = lines[3].split(",")
        cells[1] = repr(float(cells[1]) * (1 + 1e-6))
        lines[3] = ",".join(cells)
        open(ts, "w").write("\n".join(lines) + "\n")
        code, out, err = compare(plates["cpu"], bad)
        check(code == 3 and "FAIL: kinetic_energy" in out,
              f"native vs OpenCL, kinetic energy x (1 + 1e-6): exit {code}\n{out}")
    else:
        print("test_compare: no OpenCL device: the native vs OpenCL spinning plate is skipped")

    # --- issue #34, 10: an incomplete run fails unless --common-prefix ---------------------
    # a killed run: no summary.json, timeseries.csv.partial ending in a row cut short (which
    # still parses: the last number lost digits), the snapshots written before the kill
    killed = write_run(os.path.join(tmp, "killed"), copy_data(base))
    os.remove(os.path.join(killed, "summary.json"))
    os.remove(os.path.join(killed, "timeseries.csv"))
    with open(os.path.join(killed, "timeseries.csv.partial"), "w") as f:
        f.write(",".join(CSV_COLUMNS) + "\n")
        for r in base[1][:11]:
            f.write(",".join(repr(float(v)) for v in r) + "\n")
        f.write(",".join(repr(float(v)) for v in base[1][11])[:-4])
    os.remove(os.path.join(killed, "snapshots", "snapshot_000002.hdf"))
    with open(os.path.join(killed, "snapshots.hdf.series"), "w") as f:
        json.dump({"file-series-version": "1.0", "files": [
            {"name": f"snapshots/snapshot_{k:06d}.hdf", "time": t}
            for k, t in enumerate(SNAPSHOT_TIMES[:2])]}, f)
    for a, b, label in [(run_a, killed, "B"), (killed, run_a, "A")]:
        code, out, err = compare(a, b)
        final = out.strip().splitlines()[-1] if out.strip() else ""
        check(code == 3, f"killed run {label}: exit {code}, expected 3 ({err.strip()})\n{out}")
        check(final.startswith(f"compare: FAIL: run {label} ({killed}) is incomplete: no "
                               "summary.json and only timeseries.csv.partial"),
              f"killed run {label}: the last line names the incomplete run: {final}")
        check("--common-prefix" in out, f"killed run {label}: the report names the flag")
    code, out, err = compare(run_a, killed, "--common-prefix")
    check(code == 0 and "compare: PASS" in out and
          "time series (timeseries.csv): 11 rows compared" in out and
          "snapshots: 2 pairs compared" in out,
          f"killed run, --common-prefix: the 11 whole rows and 2 snapshots: {code}\n{out}{err}")
    # the common prefix still has to agree
    data = copy_data(base)
    data[0][1][2]["velocity"][17, 1] *= 1.0 + 1e-6
    killed_bad = write_run(os.path.join(tmp, "killed_bad"), data)
    os.remove(os.path.join(killed_bad, "summary.json"))
    code, out, err = compare(run_a, killed_bad, "--common-prefix")
    check(code == 3 and "FAIL: velocity" in out,
          f"killed run, --common-prefix, velocity 1e-6: {code}\n{out}")
    # stopped by the instability monitor: a finished run with results up to the stop, noted;
    # one that stopped earlier than the other fails on its row count, not on its status
    unstable = write_run(os.path.join(tmp, "unstable"), copy_data(base),
                         summary={"status": "unstable", "instability": {"time": 0.2}})
    code, out, err = compare(run_a, unstable)
    check(code == 0 and 'note: run B (' + unstable + '): summary.json status "unstable": '
          'stopped by the instability monitor at t = 0.2 s' in out,
          f"unstable run, same rows: exit {code}\n{out}")
    data = copy_data(base)
    unstable = write_run(os.path.join(tmp, "unstable_early"), (data[0][:2], data[1][:11]),
                         summary={"status": "unstable", "instability": {"time": 0.1}})
    code, out, err = compare(run_a, unstable)
    check(code == 3 and "run A has 21 rows, run B has 11" in out,
          f"unstable run stopped earlier: exit {code}\n{out}")
    code, out, err = compare(run_a, unstable, "--common-prefix")
    check(code == 0, f"unstable run stopped earlier, --common-prefix: exit {code}\n{out}")
    # a status this compare does not know is no finished run
    odd = write_run(os.path.join(tmp, "odd_status"), copy_data(base),
                    summary={"status": "running"})
    code, out, err = compare(run_a, odd)
    check(code == 3 and 'is incomplete: summary.json status "running"' in out,
          f"unknown status: exit {code}\n{out}")
    # complete runs of different lengths: --common-prefix compares the shorter's rows
    code, out, err = compare(run_a, os.path.join(tmp, "short"), "--common-prefix")
    check(code == 0 and "19 rows compared" in out, f"row counts, --common-prefix: {code}\n{out}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish("test_compare")
