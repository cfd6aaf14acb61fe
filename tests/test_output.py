#!/usr/bin/python3
"""test_output.py — snapshots read back by VTK's own HDF reader (vtkHDFReader
of Debian's python3-vtk9, the reader ParaView uses for VTKHDF .hdf files), with
the particle count, field values and time values checked against the scene's
analytical initial state and against the run's own time series; the
output.fields / snapshot_interval contract; progress lines; --plot; the
angular-momentum metric (issue #34): reported only where the scene conserves angular
momentum, the "no spin" decision the same in every precision."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, PLATE, check, finish  # noqa: E402


def run(args, **kw):
    if args and args[0] != "compare":
        args = ["run"] + args
    return subprocess.run([BIN] + args, capture_output=True, text=True, timeout=600, **kw)


def read_vtkhdf(path):
    """The snapshot as VTK sees it: points and point-data arrays."""
    r = vtk.vtkHDFReader()
    r.SetFileName(path)
    r.Update()
    grid = r.GetOutput()
    pd = grid.GetPointData()
    arrays = {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)) for k in range(pd.GetNumberOfArrays())}
    return grid, vtk_to_numpy(grid.GetPoints().GetData()), arrays


def mode_shape(kl, ks):
    # 003 eq. 51, evaluated independently of the solver
    return (np.sin(kl) + np.sinh(kl)) * (np.cos(ks) - np.cosh(ks)) - \
        (np.cos(kl) + np.cosh(kl)) * (np.sin(ks) - np.sinh(ks))


tmp = tempfile.mkdtemp(prefix="sphsolid-output-")
try:
    out = os.path.join(tmp, "plate")
    p = run([PLATE, "--backend", "cpu", "--out", out, "--quiet", "--set", "time.end=0.1",
             "--set", "output.snapshot_interval=0.05", "--set",
             'output.fields=["velocity","displacement","density","pressure","von_mises",'
             '"shear_stress","body_id","particle_id"]'])
    check(p.returncode == 0, "plate run: exit %d: %s" % (p.returncode, p.stderr))
    summary = json.load(open(os.path.join(out, "summary.json")))
    n = summary["particle_count"]
    check(n == 1612, "particle count 1612 (H/dp = 10), got %d" % n)
    check(summary["snapshots"] == 3, "3 snapshots (0, 0.05, 0.1), got %s" % summary["snapshots"])

    # the ParaView index: times of the snapshots
    series = json.load(open(os.path.join(out, "snapshots.hdf.series")))
    times = [f["time"] for f in series["files"]]
    check(np.allclose(times, [0.0, 0.05, 0.1], rtol=0, atol=1e-15), "series times %s" % times)
    names = [os.path.join(out, f["name"]) for f in series["files"]]
    check(all(os.path.exists(x) for x in names), "every indexed snapshot exists")

    # --- snapshot 0 through VTK: the scene's analytical initial state
    grid, pts, arr = read_vtkhdf(names[0])
    check(grid.GetNumberOfPoints() == n and grid.GetNumberOfCells() == n,
          "VTK sees %d points and cells, got %d / %d" % (n, grid.GetNumberOfPoints(),
                                                         grid.GetNumberOfCells()))
    check(set(arr) == {"velocity", "displacement", "density", "pressure", "von_mises",
                       "shear_stress", "body_id", "particle_id"}, "point arrays %s" % sorted(arr))
    dp = 0.002
    rho0, E, nu = 1000.0, 2.0e6, 0.3975
    c0 = np.sqrt(E / (3 * (1 - 2 * nu) * rho0))
    check(np.all(pts[:, 2] == 0.0), "2D points have z = 0")
    # lattice: every coordinate is a cell centre of spacing dp
    frac = (pts[:, :2] / dp) - 0.5
    check(np.max(np.abs(frac - np.round(frac))) < 1e-9, "points on the dp lattice")
    check(np.array_equal(arr["particle_id"], np.arange(n)), "row k is particle k")
    check(np.all(arr["density"] == rho0), "initial density is rho0")
    check(np.all(arr["displacement"] == 0.0), "initial displacement is zero")
    # initial velocity: v_y = v_f c0 f(k s) / f(kL) for s = x > 0 (003 eqs. 50-51)
    kl, L, vf = 1.875, 0.2, 0.05
    s = pts[:, 0]
    vy = np.where(s > 0, vf * c0 * mode_shape(kl, kl * s / L) / mode_shape(kl, kl), 0.0)
    check(np.max(np.abs(arr["velocity"][:, 1] - vy)) < 1e-12 * vf * c0,
          "initial v_y is the cantilever mode, max error %g" % np.max(np.abs(arr["velocity"][:, 1] - vy)))
    check(np.all(arr["velocity"][:, 0] == 0.0), "initial v_x is zero")

    # --- the last snapshot: kinetic energy from VTK's arrays equals the time series'
    grid, pts, arr = read_vtkhdf(names[-1])
    mass = rho0 * dp * dp
    ke = 0.5 * mass * np.sum(arr["velocity"] ** 2)
    rows = np.genfromtxt(os.path.join(out, "timeseries.csv"), delimiter=",", names=True)
    last = rows[-1]
    check(abs(last["time"] - 0.1) < 1e-12, "the series ends at t = 0.1")
    check(abs(ke - last["kinetic_energy"]) < 1e-10 * last["kinetic_energy"],
          "snapshot kinetic energy %.12g equals the series' %.12g" % (ke, last["kinetic_energy"]))
    # displacement = position - initial position, by particle
    _, pts0, _ = read_vtkhdf(names[0])
    check(np.max(np.abs(arr["displacement"] - (pts - pts0))) < 1e-15,
          "displacement = x(t) - x(0)")
    check(np.max(np.abs(arr["displacement"][:, 1])) > 0.01, "the plate has moved by 0.1 s")
    # derived fields: pressure from the EOS p = c0^2 (rho - rho0); von Mises of tau - p I
    check(np.max(np.abs(arr["pressure"] - c0 * c0 * (arr["density"] - rho0))) <
          1e-9 * np.max(np.abs(arr["pressure"])), "pressure follows the EOS")
    tau = arr["shear_stress"]
    sxx, syy, sxy = tau[:, 0] - arr["pressure"], tau[:, 1] - arr["pressure"], tau[:, 3]
    vm = np.sqrt(np.maximum(sxx ** 2 + syy ** 2 - sxx * syy + 3 * sxy ** 2, 0))
    check(np.max(np.abs(vm - arr["von_mises"])) < 1e-9 * np.max(vm), "von Mises of tau - p I")
    check(np.all(tau[:, 2] == 0) and np.all(tau[:, 4] == 0) and np.all(tau[:, 5] == 0),
          "2D tau has no out-of-plane components")

    # --- HDF5 layout and provenance (h5py)
    with h5py.File(names[-1], "r") as f:
        v = f["VTKHDF"]
        check(list(v.attrs["Version"]) == [1, 0], "VTKHDF version 1.0")
        t = v.attrs["Type"]
        check((t.decode() if isinstance(t, bytes) else t) == "UnstructuredGrid", "Type attribute")
        check(v["Points"].compression == "gzip" and v["Points"].shuffle,
              "Points (%d values) chunked and compressed" % (3 * n))
        check(v["Points"].dtype == np.float64, "double run stores float64")
        a = f["sphsolid"].attrs
        def text(k):
            x = a[k]
            return x.decode() if isinstance(x, bytes) else str(x)
        check(abs(float(a["time"]) - 0.1) < 1e-15, "time attribute")
        check(text("formulation") == "enog-a" and text("backend") == "cpu" and
              text("precision") == "double", "provenance attributes")
        check("oscillating plate" in text("scene_text"), "scene text stored")
        check(json.loads(text("parameters"))["dp"] == summary["resolved"]["dp"],
              "parameters JSON stored")
        check(int(a["acoustic_steps"]) == summary["acoustic_steps"], "step count of the last snapshot")

    # --- single precision stores float32, default field set, no shear stress
    out32 = os.path.join(tmp, "single")
    p = run([PLATE, "--backend", "cpu", "--precision", "single", "--out", out32, "--quiet",
             "--set", "time.end=0.02", "--set", "time.output_interval=0.01"])
    check(p.returncode == 0, "single-precision run: %s" % p.stderr)
    with h5py.File(os.path.join(out32, "snapshots", "snapshot_000000.hdf"), "r") as f:
        check(f["VTKHDF/Points"].dtype == np.float32, "single run stores float32")
        check(sorted(f["VTKHDF/PointData"]) == ["body_id", "density", "displacement", "particle_id",
                                                "pressure", "velocity", "von_mises"],
              "default fields: %s" % sorted(f["VTKHDF/PointData"]))
    series = json.load(open(os.path.join(out32, "snapshots.hdf.series")))
    # default interval 10 x 0.01 > end: the start and the end time
    check([f["time"] for f in series["files"]] == [0.0, 0.02], "default snapshots: start and end")

    # --- bad output settings: exit 2 naming the key
    for sets, key in [
        (['output.fields=["velocity","strain"]'], "output.fields"),
        (['output.fields=["plastic_strain"]'], "plastic"),
        (["output.snapshot_interval=0.015"], "output.snapshot_interval"),
        (["output.snapshotinterval=0.1"], "snapshot_interval"),
    ]:
        args = [PLATE, "--backend", "cpu", "--out", os.path.join(tmp, "bad"), "--quiet"]
        for x in sets:
            args += ["--set", x]
        p = run(args)
        check(p.returncode == 2 and key in p.stderr,
              "%s: exit 2 naming %s, got %d: %s" % (sets, key, p.returncode, p.stderr.strip()))
    check(not os.path.exists(os.path.join(tmp, "bad", "snapshots.hdf.series")),
          "no snapshot index after a failed run")

    # snapshots off
    outoff = os.path.join(tmp, "off")
    p = run([PLATE, "--backend", "cpu", "--out", outoff, "--quiet", "--set", "time.end=0.01",
             "--set", "output.snapshot_interval=0"])
    check(p.returncode == 0 and not os.path.exists(os.path.join(outoff, "snapshots.hdf.series")),
          "output.snapshot_interval = 0: no snapshots")

    # --- progress: log lines when stderr is not a terminal, silence with --quiet
    p = run([PLATE, "--backend", "cpu", "--out", os.path.join(tmp, "prog"), "--set", "time.end=0.05",
             "--progress-interval", "0.2"])
    lines = [l for l in p.stderr.splitlines() if "particle-substeps/s" in l and "ETA" in l]
    check(p.returncode == 0 and len(lines) >= 2 and "\r" not in p.stderr,
          "progress log lines (%d) without carriage returns" % len(lines))
    check(any("(100%)" in l for l in lines), "a final 100% progress line")
    p = run([PLATE, "--backend", "cpu", "--out", os.path.join(tmp, "prog"), "--set", "time.end=0.05",
             "--quiet"])
    check(p.returncode == 0 and p.stderr == "", "--quiet prints nothing, got %r" % p.stderr)
    p = run([PLATE, "--progress-interval", "-1"])
    check(p.returncode == 2 and "--progress-interval" in p.stderr, "bad --progress-interval")
    # issue 34: progress inside one long advection step (an acoustic CFL of
    # 1e-6: 440 000 substeps, tens of seconds, before the first rebuild),
    # not only between advection steps: lines while "0 advection steps"
    slow = subprocess.Popen([BIN, "run", PLATE, "--backend", "cpu", "--out",
                             os.path.join(tmp, "slow"), "--set", "resolution.ratio=4", "--set",
                             "time.end=0.01", "--set", "time.cfl_acoustic=1e-6",
                             "--progress-interval", "0.3"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    time.sleep(2.5)
    slow.kill()
    inside = [line for line in slow.communicate()[1].splitlines()
              if "particle-substeps/s" in line and "/ 0 advection steps" in line]
    check(len(inside) >= 2, "progress every 0.3 s inside the first advection step: %d lines in "
          "2.5 s" % len(inside))
    # --no-work-limit: a run the estimate refuses (more output than the free
    # space, SPHSOLID_TEST_FREE_BYTES) goes on with the reason as a warning
    p = run([PLATE, "--backend", "cpu", "--out", os.path.join(tmp, "nolimit"), "--no-work-limit",
             "--set", "resolution.ratio=4", "--set", "time.end=0.01"],
            env=dict(os.environ, SPHSOLID_TEST_FREE_BYTES="1e5"))
    check(p.returncode == 0 and "sphsolid: warning: " in p.stderr and
          "whose filesystem has 97.7 KiB free" in p.stderr and
          "(--no-work-limit: running it anyway)" in p.stderr,
          "--no-work-limit: a warning, and the run: exit %d: %s" % (p.returncode, p.stderr))
    # on a terminal: one live line redrawn with carriage returns
    import pty
    pid, fd = pty.fork()
    if pid == 0:
        os.execv(BIN, [BIN, "run", PLATE, "--backend", "cpu", "--out", os.path.join(tmp, "tty"),
                       "--set", "time.end=0.1"])
    chunks = []
    while True:
        try:
            data = os.read(fd, 4096)
        except OSError:
            break
        if not data:
            break
        chunks.append(data)
    _, status = os.waitpid(pid, 0)
    tty_text = b"".join(chunks).decode(errors="replace")
    check(os.WEXITSTATUS(status) == 0 and "\rsphsolid: t = " in tty_text,
          "terminal progress redraws one line")

    # --- --plot: PNGs of the run
    p = run([PLATE, "--backend", "cpu", "--out", os.path.join(tmp, "plot"),
             "--set", "time.end=0.05", "--set", "output.snapshot_interval=0.05", "--plot"])
    pngs = sorted(os.listdir(os.path.join(tmp, "plot", "plots"))) if p.returncode == 0 else []
    check(p.returncode == 0 and "timeseries.png" in pngs and
          any(x.startswith("snapshot_") for x in pngs),
          "--plot writes the PNGs: %s %s" % (pngs, p.stderr))

    # --- the clamped plate does not conserve angular momentum: |L - L0| / |L0| swings
    # through 200 % with the motion, no error; summary.json, the printed line and the plot
    # say why instead of reporting it
    why = "constraint 'fixed' on region 'clamp' of body 'plate'"
    summ = json.load(open(os.path.join(tmp, "plot", "summary.json")))
    m = summ.get("metrics", {})
    check(m.get("max_angular_momentum_error", 0) is None and
          m.get("angular_momentum_not_conserved") == why,
          "clamped plate: no angular-momentum error, the reason instead: %s" % m)
    check("sphsolid: angular momentum not conserved (%s): no error reported" % why in p.stderr,
          "clamped plate: the printed line says why: %s" % p.stderr[-600:])
    ts_line = [x for x in p.stdout.splitlines() if "timeseries.png" in x]
    check(len(ts_line) == 1 and "angular momentum not conserved (%s)" % why in ts_line[0] and
          "|L - L0|/|L0| =" not in ts_line[0],
          "clamped plate: the plot shows |L| and says why: %s" % ts_line)

    # --- a free 3D block in the plate mode (2, 2): L(0) = 0 in theory, a round-off of 1e-8
    # of sum m |x| |v| on the device in single and mixed precision; the "no spin" decision
    # is taken in double on the host, so the error is null in every precision
    block = os.path.join(tmp, "block.cfg")
    with open(block, "w") as f:
        f.write("""title = "free 3D block in a plate mode"; dimension = 3;
resolution = { dp = 0.005; };
method = { formulation = "enog-a"; rotation = "averaged"; kernel = "wendland-c2";
           smoothing_ratio = 1.3; };
time = { end = 0.0002; output_interval = 0.0001; };
materials = { m = { density = 1000.0; youngs_modulus = 1.0e8; poisson_ratio = 0.3; }; };
shapes = { block = { type = "box"; lower = [0.0, 0.0, -0.01]; upper = [0.1, 0.1, 0.01]; }; };
bodies = ( { name = "block"; material = "m"; shape = "block";
             initial_velocity = { type = "plate_mode"; amplitude = 1.0; lower = [0.0, 0.0];
                                  size = [0.1, 0.1]; modes = [2, 2]; }; } );
output = { snapshot_interval = 0.0; };
""")
    for precision in ("double", "single"):
        out_p = os.path.join(tmp, "block_" + precision)
        p = run([block, "--backend", "cpu", "--quiet", "--precision", precision, "--out", out_p])
        m = json.load(open(os.path.join(out_p, "summary.json")))["metrics"] \
            if p.returncode == 0 else {}
        check(p.returncode == 0 and "max_angular_momentum_error" in m and
              m["max_angular_momentum_error"] is None and
              m.get("angular_momentum_not_conserved", 0) is None,
              "block without spin, %s: conserved, no error: %s %s" % (precision, m, p.stderr))
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish("test_output")
