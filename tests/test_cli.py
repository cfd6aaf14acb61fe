#!/usr/bin/python3
"""test_cli.py — the command line contract for good input: a complete run
directory after a good run, and `sphsolid devices`.  Bad scenes, flags,
overrides and runtime failures (exit status, message, no result left) are
the table of tests/test_bad_input.py."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, PLATE, check, finish  # noqa: E402


def run(args, cwd):
    p = subprocess.run([BIN] + args, cwd=cwd, capture_output=True, text=True, timeout=600)
    return p.returncode, p.stderr


tmp = tempfile.mkdtemp(prefix="sphsolid-cli-")
try:
    # a good short run: exit 0, complete files
    out = os.path.join(tmp, "good")
    code, err = run(["run", PLATE, "--backend", "cpu", "--quiet", "--out", out,
                     "--set", "time.end=0.02"], tmp)
    check(code == 0, f"good run: exit status {code} ({err.strip()})")
    summary = json.load(open(os.path.join(out, "summary.json")))
    check(summary["particle_count"] == 1612, "summary particle count")
    check(summary["backend"] == "cpu" and summary["precision"] == "double", "summary backend")
    check(abs(summary["metrics"]["initial_kinetic_energy"] - 4.0647984104106447) < 4e-6,
          "summary initial kinetic energy")
    rows = open(os.path.join(out, "timeseries.csv")).read().strip().splitlines()
    check(rows[0].startswith("time,kinetic_energy,strain_energy,total_energy"), "csv header")
    check(len(rows) == 1 + 3, f"csv rows for t = 0, 0.01, 0.02: {len(rows) - 1}")
    check(not os.path.exists(os.path.join(out, "timeseries.csv.partial")), "no partial file left")

    # sphsolid relax: relax ahead of a run, save, reuse (the plate at 50 steps)
    plate = os.path.join(tmp, "plate.cfg")
    shutil.copy(PLATE, plate)
    relaxed = ["--set", "bodies.plate.placement=relaxed",
               "--set", "bodies.plate.relaxation.steps=50"]
    p = subprocess.run([BIN, "relax", plate] + relaxed + ["--out", "plate_relaxed.h5"], cwd=tmp,
                       capture_output=True, text=True, timeout=600)
    check(p.returncode == 0 and "body 'plate': 1612 relaxed particles, 50 steps" in p.stdout
          and "saved to plate_relaxed.h5 (no file yet)" in p.stdout,
          f"relax --out: exit {p.returncode}: {p.stdout.strip()} {p.stderr.strip()}")
    check(os.path.exists(os.path.join(tmp, "plate_relaxed.h5"))
          and not os.path.exists(os.path.join(tmp, "plate_relaxed.h5.partial")), "relax: the file")
    p = subprocess.run([BIN, "relax", plate] + relaxed + ["--out", "plate_relaxed.h5"], cwd=tmp,
                       capture_output=True, text=True, timeout=600)
    check(p.returncode == 0 and "reused from plate_relaxed.h5" in p.stdout,
          f"relax again: reused: {p.stdout.strip()}")
    p = subprocess.run([BIN, "relax", plate] + relaxed + ["--out", "plate_relaxed.h5", "--force"],
                       cwd=tmp, capture_output=True, text=True, timeout=600)
    check(p.returncode == 0 and "regeneration forced" in p.stdout,
          f"relax --force: {p.stdout.strip()}")
    # a run with the file named in the scene (relative to the scene file) reuses it
    out = os.path.join(tmp, "relaxed-run")
    code, err = run(["run", plate, "--backend", "cpu", "--out", out, "--set", "time.end=0.01"]
                    + relaxed + ["--set", "bodies.plate.relaxation.file=\"plate_relaxed.h5\""],
                    "/")
    check(code == 0 and "reused from " + os.path.join(tmp, "plate_relaxed.h5") in err,
          f"run with the relaxed file: exit {code}: {err.strip()[:400]}")
    if code == 0:
        rb = json.load(open(os.path.join(out, "summary.json")))["relaxed_bodies"]
        check(len(rb) == 1 and rb[0]["body"] == "plate" and rb[0]["reused"]
              and rb[0]["steps"] == 50 and 0 < rb[0]["residual_mean"] < rb[0]["residual_start_mean"],
              f"summary.json relaxed_bodies: {rb}")
    p = subprocess.run([BIN, "relax", PLATE], capture_output=True, text=True)
    check(p.returncode == 2 and "no body has placement = \"relaxed\"" in p.stderr,
          f"relax without a relaxed body: exit {p.returncode}: {p.stderr.strip()}")
    p = subprocess.run([BIN, "relax", plate, "--frobnicate"], capture_output=True, text=True)
    check(p.returncode == 2 and "unknown option --frobnicate" in p.stderr, "relax: bad option")

    # devices lists the native backend
    p = subprocess.run([BIN, "devices"], capture_output=True, text=True)
    check(p.returncode == 0 and "native CPU backend" in p.stdout, "sphsolid devices")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish("test_cli")
