#!/usr/bin/python3
"""test_bandwidth.py — `sphsolid bandwidth BACKEND`: exit 0, a positive finite
GB/s in the text line and in the JSON object (with the fields tools/bench.py
reads), equal to 2 x buffer bytes / best seconds; bad flags exit 2 with a
message.  Small buffers (8 MiB) and few runs: this checks the command, not the
machine's bandwidth."""
import json
import math
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, check, finish  # noqa: E402

backend = sys.argv[1] if len(sys.argv) > 1 else "cpu"


def bandwidth(*args):
    p = subprocess.run([BIN, "bandwidth", *args], capture_output=True, text=True, timeout=300)
    return p.returncode, p.stdout, p.stderr


small = ["--backend", backend, "--size-mb", "8", "--repeat", "3"]
code, out, err = bandwidth(*small)
check(code == 0, f"text: exit status {code} ({err.strip()})")
m = re.search(r"best of 3: ([0-9.eE+-]+) GB/s \(median ([0-9.eE+-]+) GB/s", out)
check(m is not None, f"text line format: {out.strip()!r}")
if m:
    best, median = float(m.group(1)), float(m.group(2))
    check(math.isfinite(best) and best > 0 and best >= median > 0, f"text GB/s {best}, {median}")

code, out, err = bandwidth(*small, "--json")
check(code == 0, f"json: exit status {code} ({err.strip()})")
try:
    r = json.loads(out)
except ValueError:
    r = {}
    check(False, f"json: not a JSON object: {out!r}")
for key in ("backend", "device", "device_index", "opencl_version", "driver_version",
            "buffer_bytes", "repeats", "best_seconds", "median_seconds", "best_gbs",
            "median_gbs"):
    check(key in r, f"json key {key}")
if r:
    check(r["backend"] == backend, f"json backend {r['backend']}")
    check(r["repeats"] == 3 and r["buffer_bytes"] == 8 * 1048576, "json size and repeats")
    check(math.isfinite(r["best_gbs"]) and r["best_gbs"] > 0, f"json best GB/s {r['best_gbs']}")
    check(r["best_seconds"] <= r["median_seconds"], "best <= median time")
    check(abs(r["best_gbs"] - 2 * r["buffer_bytes"] / r["best_seconds"] / 1e9)
          <= 1e-9 * r["best_gbs"], "GB/s = 2 x bytes / best seconds")
    if backend == "opencl":
        check(r["device_index"] >= 0 and r["opencl_version"].startswith("OpenCL"),
              f"json OpenCL device and version: {r['device_index']}, {r['opencl_version']!r}")
    else:
        check(r["device_index"] == -1 and r["threads"] >= 1, "json native threads")

for args, what in ((["--backend", "gpu"], "expected opencl or cpu"),
                   (["--size-mb", "0"], "--size-mb 0"),
                   (["--repeat", "x"], "--repeat x"),
                   (["--backend", "cpu", "--device", "0"], "does not go with --backend cpu"),
                   (["--frobnicate"], "unknown option --frobnicate")):
    code, out, err = bandwidth(*args)
    check(code == 2 and what in err, f"{args}: exit {code}, message {err.strip()!r}")

finish(f"test_bandwidth_{backend}")
