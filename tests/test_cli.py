#!/usr/bin/python3
"""test_cli.py — the command line contract: exit status 2 with a message naming
file, line and key for bad scenes and flags, no result files after a failed
run, and a complete run directory after a good one."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, PLATE, SRC, check, finish  # noqa: E402


def run(args, cwd):
    p = subprocess.run([BIN] + args, cwd=cwd, capture_output=True, text=True, timeout=600)
    return p.returncode, p.stderr


def scene_with(tmp, old, new, name="bad.cfg"):
    text = open(PLATE).read()
    assert old in text, old
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(text.replace(old, new))
    return path


def line_of(path, needle):
    for k, line in enumerate(open(path), 1):
        if needle in line:
            return k
    return -1


tmp = tempfile.mkdtemp(prefix="sphsolid-cli-")
try:
    # each malformed scene: (old text, new text, line marker, expected key in message)
    cases = [
        ("youngs_modulus = 2.0e6;", "youngs_modulus = -2.0e6;", "youngs_modulus",
         "materials.plate.youngs_modulus"),
        ("poisson_ratio = 0.3975;", "poisson_ratio = 0.5;", "poisson_ratio",
         "materials.plate.poisson_ratio"),
        ("ratio = 10.0;", "ratio = 0.0;", "ratio = 0.0", "resolution.ratio"),
        ("youngs_modulus = 2.0e6;", "youngs_modulous = 2.0e6;", "youngs_modulous",
         "youngs_modulus"),
        ("end = 1.0;", "end = = 1.0;", "end = = 1.0", "syntax error"),
    ]
    for old, new, marker, key in cases:
        path = scene_with(tmp, old, new)
        out = os.path.join(tmp, "out-bad")
        code, err = run(["run", path, "--backend", "cpu", "--quiet", "--out", out], tmp)
        line = line_of(path, marker)
        check(code == 2, f"{new!r}: exit status {code}, expected 2 ({err.strip()})")
        check("bad.cfg" in err, f"{new!r}: message names the file: {err.strip()}")
        check(f":{line}:" in err, f"{new!r}: message names line {line}: {err.strip()}")
        check(key in err, f"{new!r}: message names {key}: {err.strip()}")
        check(not os.path.exists(os.path.join(out, "summary.json")) and
              not os.path.exists(os.path.join(out, "timeseries.csv")),
              f"{new!r}: no result files")

    # dp <= 0 given directly
    path = scene_with(tmp, "reference_length = 0.02;   # H\n  ratio = 10.0;", "dp = -0.002;")
    code, err = run(["run", path, "--backend", "cpu", "--quiet", "--out", os.path.join(tmp, "o")], tmp)
    check(code == 2 and "resolution.dp" in err, f"dp <= 0: {code} {err.strip()}")

    # bad flags and overrides
    for args, needle in [
        (["run", PLATE, "--backend", "gpu"], "--backend"),
        (["run", PLATE, "--precision", "half"], "--precision"),
        (["run", PLATE, "--frobnicate"], "--frobnicate"),
        (["run"], "scene"),
        (["run", PLATE, "--set", "time.end"], "--set"),
        (["run", PLATE, "--set", "materials.plate.poisson_ratio=0.7"], "--set"),
        (["run", os.path.join(tmp, "missing.cfg")], "missing.cfg"),
        (["launch"], "launch"),
    ]:
        code, err = run(args + ["--quiet"] if args[0] == "run" and len(args) > 1 else args, tmp)
        check(code == 2, f"{args}: exit status {code}, expected 2 ({err.strip()})")
        check(needle in err, f"{args}: message names {needle}: {err.strip()}")

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

    # devices lists the native backend
    p = subprocess.run([BIN, "devices"], capture_output=True, text=True)
    check(p.returncode == 0 and "native CPU backend" in p.stdout, "sphsolid devices")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish("test_cli")
