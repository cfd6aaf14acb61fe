"""sphtest.py — what the Python tests share: the paths ctest passes in the
environment (SPHSOLID_BIN, SPHSOLID_SOURCE_DIR) and a check counter that
reports every failed check and sets the exit status."""
import os
import sys

SRC = os.environ.get("SPHSOLID_SOURCE_DIR") or \
    os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("SPHSOLID_BIN", os.path.join(SRC, "build", "sphsolid"))
PLATE = os.path.join(SRC, "cases", "oscillating_plate_2d", "scene.cfg")
# under the sanitizers (tests/CMakeLists.txt) the longest physics runs are cut short: the same
# code paths for fewer steps; the bounds that need the whole run are left to the release build
SANITIZED = os.environ.get("SPHSOLID_SANITIZED", "0") not in ("", "0")

_counts = {"passed": 0, "failed": 0}


def check(cond, what):
    if cond:
        _counts["passed"] += 1
    else:
        _counts["failed"] += 1
        print("FAILED:", what, file=sys.stderr)


def finish(name):
    """Print the tally and exit 1 if any check failed."""
    print("%s: %d passed, %d failed" % (name, _counts["passed"], _counts["failed"]))
    sys.exit(1 if _counts["failed"] else 0)


def run_sphsolid(scene, backend, out, sets=(), timeout=900, options=()):
    """`sphsolid run SCENE --backend BACKEND --quiet --out OUT [OPTIONS] --set S ...`:
    (exit status, stderr stripped)."""
    import subprocess
    cmd = [BIN, "run", scene, "--backend", backend, "--quiet", "--out", out] + list(options)
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stderr.strip()


def run_quiet(scene, backend, out, sets=(), timeout=900, options=()):
    """Run a scene that must complete with the instability monitor quiet: checks the exit
    status and the summary's status, and returns (summary, time series), or (None, None)
    when the run failed."""
    code, err = run_sphsolid(scene, backend, out, sets, timeout=timeout, options=options)
    check(code == 0, f"exit {code} ({err})")
    if code != 0:
        return None, None
    summ, ts = run_results(out)
    check(summ["status"] == "completed" and "instability" not in summ,
          f"monitor quiet ({summ.get('instability')})")
    return summ, ts


def run_results(out):
    """A run directory's summary.json (a dict) and timeseries.csv (a numpy
    structured array, columns by name)."""
    import json
    import numpy as np
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return summary, np.genfromtxt(os.path.join(out, "timeseries.csv"), delimiter=",", names=True)


def snapshot_paths(out):
    """The run's snapshot files, in time order (snapshots.hdf.series)."""
    import json
    with open(os.path.join(out, "snapshots.hdf.series")) as f:
        return [os.path.join(out, s["name"]) for s in json.load(f)["files"]]


def plastic_work(out, mass, sigma_y, kappa=0.0):
    """The J2 plastic work sum V (sigma_Y eps_p + kappa eps_p^2 / 2) of a run's last snapshot,
    V = m / rho for particles of equal mass m (the snapshot needs plastic_strain and density)."""
    import h5py
    import numpy as np
    with h5py.File(snapshot_paths(out)[-1], "r") as f:
        pd = f["VTKHDF/PointData"]
        eps, rho = pd["plastic_strain"][:], pd["density"][:]
    return float(np.sum(mass / rho * (sigma_y * eps + 0.5 * kappa * eps ** 2)))
