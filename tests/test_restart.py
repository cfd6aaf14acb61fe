#!/usr/bin/python3
"""test_restart.py BACKEND — checkpoint and restart.

A run killed with SIGKILL and restarted from its last checkpoint equals the
uninterrupted run bit for bit (snapshots, time series, step counts) on the
same backend and precision; a run killed while it writes a checkpoint keeps
the previous checkpoint, which still restarts to the same bits; restarts
refuse a scene file or a change of physics; `sphsolid compare` passes on the
identical runs and fails on a perturbed copy, naming the field and particle.
A restart goes on writing checkpoints at the interval stored in the checkpoint
and leaves no .partial checkpoint; one to an end before the checkpoint is
refused; a run that ended between output times, extended, goes on with the
output grid; a damaged or edited checkpoint (a NaN, counters that disagree, ids
that are not the scene's particles, a wall particle turned into fluid) is an
input error naming the file and the value, with nothing written.  A fluid run
(the Taylor-Green vortex) to 0.3 s extended to 0.4 s equals
the run to 0.4 s bit for bit (an end on the output grid is the grid's own time).
Under the sanitizers (sphtest.SANITIZED) the plate runs end at 0.1 s instead of 0.2 s: the
same checkpoints at 0.04 and 0.08 s, and a shorter tail after them.
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import h5py

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, PLATE, SANITIZED, SRC, check, finish  # noqa: E402

BACKEND = sys.argv[1] if len(sys.argv) > 1 else "cpu"
END = "0.1" if SANITIZED else "0.2"
COMMON = ["--backend", BACKEND, "--quiet", "--set", "time.end=" + END,
          "--set", "output.snapshot_interval=0.05"]


def run(args, env=None):
    return subprocess.run([BIN] + args, capture_output=True, text=True, timeout=900, env=env)


def checkpoint_time(d):
    with h5py.File(os.path.join(d, "checkpoint", "checkpoint.h5"), "r") as f:
        return float(f.attrs["time"])


def start_and_kill(args, ready, env=None, limit=600):
    """Start sphsolid, wait until ready() is true, then SIGKILL it.  Returns
    True when it was killed (False: it finished first)."""
    p = subprocess.Popen([BIN] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         env=env)
    t0 = time.time()
    while p.poll() is None and not ready() and time.time() - t0 < limit:
        time.sleep(0.01)
    killed = p.poll() is None
    if killed:
        p.send_signal(signal.SIGKILL)
    p.wait()
    return killed


def same_results(a, b, what):
    c = run(["compare", a, b, "--rtol", "0", "--atol", "0"])
    check(c.returncode == 0, "%s: compare --rtol 0 exit %d\n%s%s" % (what, c.returncode, c.stdout,
                                                                     c.stderr))
    ta = open(os.path.join(a, "timeseries.csv")).read()
    tb = open(os.path.join(b, "timeseries.csv")).read()
    check(ta == tb, "%s: timeseries.csv byte-identical" % what)
    sa = json.load(open(os.path.join(a, "summary.json")))
    sb = json.load(open(os.path.join(b, "summary.json")))
    for k in ("acoustic_steps", "advection_steps", "snapshots"):
        check(sa[k] == sb[k], "%s: %s %s == %s" % (what, k, sa[k], sb[k]))
    check(sa["metrics"]["first_period"] == sb["metrics"]["first_period"] or
          (sa["metrics"]["first_period"] is None and sb["metrics"]["first_period"] is None),
          "%s: same metrics" % what)
    return sb


tmp = tempfile.mkdtemp(prefix="sphsolid-restart-")
try:
    # the uninterrupted run, without checkpoints: checkpoints must not change it
    ref = os.path.join(tmp, "ref")
    p = run(["run", PLATE, "--out", ref] + COMMON)
    check(p.returncode == 0, "reference run: %s" % p.stderr)

    # killed after its first checkpoint, then restarted in place
    a = os.path.join(tmp, "killed")
    ck = os.path.join(a, "checkpoint", "checkpoint.h5")
    killed = start_and_kill(["run", PLATE, "--out", a, "--checkpoint-every", "0.04"] + COMMON,
                            lambda: os.path.exists(ck))
    check(killed, "the run was killed before it finished")
    check(not os.path.exists(os.path.join(a, "summary.json")) and
          not os.path.exists(os.path.join(a, "timeseries.csv")),
          "a killed run leaves no summary.json or timeseries.csv")
    t_ck = checkpoint_time(a)
    check(0 < t_ck < float(END), "checkpoint at t = %g inside the run" % t_ck)
    p = run(["run", "--restart", a, "--backend", BACKEND, "--quiet", "--checkpoint-every", "0.04"])
    check(p.returncode == 0, "restart: %s" % p.stderr)
    sb = same_results(ref, a, "kill -9 and restart")
    check(abs(sb.get("restarted_from", {}).get("time", -1) - t_ck) < 1e-15,
          "summary records the restart time")
    check(abs(checkpoint_time(a) - float(END)) < 1e-15, "a final checkpoint at the end time")

    # killed while writing a checkpoint: the previous one survives and restarts
    b = os.path.join(tmp, "killed_in_write")
    ckb = os.path.join(b, "checkpoint", "checkpoint.h5")
    killed = start_and_kill(["run", PLATE, "--out", b, "--checkpoint-every", "0.04"] + COMMON,
                            lambda: os.path.exists(ckb))
    t_before = checkpoint_time(b)
    env = dict(os.environ, SPHSOLID_TEST_CHECKPOINT_DELAY="120")
    killed_in_write = start_and_kill(
        ["run", "--restart", b, "--backend", BACKEND, "--quiet", "--checkpoint-every", "0.04"],
        lambda: os.path.exists(ckb + ".partial"), env=env)
    check(killed and killed_in_write, "killed twice, the second time inside a checkpoint write")
    check(os.path.exists(ckb + ".partial"), "the interrupted checkpoint is left as .partial only")
    check(checkpoint_time(b) == t_before,
          "the previous checkpoint (t = %g) is intact, got %g" % (t_before, checkpoint_time(b)))
    p = run(["run", "--restart", b, "--backend", BACKEND, "--quiet"])
    check(p.returncode == 0, "restart after a kill during a write: %s" % p.stderr)
    same_results(ref, b, "kill during a checkpoint write and restart")
    # that restart had no --checkpoint-every: it goes on with the run's own
    # (0.04 s, stored in the checkpoint) to a final checkpoint at the end
    # time, and the interrupted write's 0-byte .partial is gone
    check(abs(checkpoint_time(b) - float(END)) < 1e-15,
          "a restart continues the stored checkpoint interval: final checkpoint at %s, got %g"
          % (END, checkpoint_time(b)))
    check(not os.path.exists(ckb + ".partial"), "a restarted run leaves no checkpoint.h5.partial")

    # restart into another directory, extending the end time
    c = os.path.join(tmp, "extended")
    p = run(["run", "--restart", a, "--out", c, "--backend", BACKEND, "--quiet", "--set",
             "time.end=0.25"])
    check(p.returncode == 0, "restart with a later end time into another directory: %s" % p.stderr)
    series = json.load(open(os.path.join(c, "snapshots.hdf.series")))
    check([f["time"] for f in series["files"]] == [0.0, 0.05, 0.1, 0.15, 0.2, 0.25],
          "the continued run lists the copied and the new snapshots")
    check(all(os.path.exists(os.path.join(c, f["name"])) for f in series["files"]),
          "every listed snapshot is in the new directory")

    # restarts that cannot be honoured: exit 2 with the reason
    for args, needle in [
        (["run", PLATE, "--restart", a], "give no scene file"),
        (["run", "--restart", a, "--set", "method.formulation=enog"], "only time.end and output"),
        (["run", "--restart", os.path.join(tmp, "nowhere")], "checkpoint.h5"),
        (["run", "--restart", ref], "checkpoint.h5"),
    ]:
        p = run(args)
        check(p.returncode == 2 and needle in p.stderr,
              "%s: exit 2 mentioning %r, got %d: %s" % (args, needle, p.returncode, p.stderr.strip()))

    # an end before the checkpoint: refused, naming time.end and the
    # checkpoint's time, before anything in the directory changes
    t_a = checkpoint_time(a)
    p = run(["run", "--restart", a, "--backend", BACKEND, "--quiet", "--set", "time.end=0.05"])
    check(p.returncode == 2 and "time.end = 0.05 s is before" in p.stderr and
          "t = %.9g s" % t_a in p.stderr and os.path.exists(os.path.join(a, "summary.json")) and
          checkpoint_time(a) == t_a,
          "restart to an end before the checkpoint (t = %g): exit 2 naming time.end and the "
          "checkpoint's time, got %d: %s" % (t_a, p.returncode, p.stderr.strip()))

    # TLSPH: the restart rebuilds the reference configuration from the
    # initial particles, then restores the fields, and never rebuilds again
    tl = ["--backend", BACKEND, "--quiet", "--set", "time.end=0.1", "--set",
          "output.snapshot_interval=0.05", "--set", "method.formulation=tlsph", "--set",
          "method.rotation=none", "--set", "monitor.action=off"]
    tref = os.path.join(tmp, "tl_ref")
    p = run(["run", PLATE, "--out", tref] + tl)
    check(p.returncode == 0, "TLSPH reference run: %s" % p.stderr)
    e = os.path.join(tmp, "tl_killed")
    cke = os.path.join(e, "checkpoint", "checkpoint.h5")
    killed = start_and_kill(["run", PLATE, "--out", e, "--checkpoint-every", "0.02"] + tl,
                            lambda: os.path.exists(cke))
    check(killed, "the TLSPH run was killed before it finished")
    p = run(["run", "--restart", e, "--backend", BACKEND, "--quiet"])
    check(p.returncode == 0, "TLSPH restart: %s" % p.stderr)
    same_results(tref, e, "TLSPH kill -9 and restart")

    # issue 34: a checkpoint interval below the steps (the old scheduling
    # added it to the next checkpoint time until past t: 1e-12 s took 30 s
    # of additions, 1e-300 was lost to rounding and never ended) checkpoints
    # after every advection step, with a note, and leaves the results those
    # of the run without checkpoints
    fast = ["--backend", BACKEND, "--set", "resolution.ratio=4", "--set", "time.end=0.01"]
    f0 = os.path.join(tmp, "ck_none")
    p = run(["run", PLATE, "--out", f0, "--quiet"] + fast)
    check(p.returncode == 0, "run without checkpoints: %s" % p.stderr)
    for every in ("1e-12", "1e-300"):
        f = os.path.join(tmp, "ck_" + every)
        t0 = time.time()
        try:
            p = subprocess.run([BIN, "run", PLATE, "--out", f, "--checkpoint-every", every] + fast,
                               capture_output=True, text=True, timeout=30)
        except subprocess.TimeoutExpired:
            check(False, "--checkpoint-every %s: still running after 30 s" % every)
            continue
        wall = time.time() - t0
        check(p.returncode == 0 and wall < 10 and
              "a checkpoint is written after every advection step" in p.stderr,
              "--checkpoint-every %s: exit %d in %.1f s (expected 0, within 10 s, with a note): %s"
              % (every, p.returncode, wall, p.stderr.strip()[-300:]))
        if p.returncode == 0:
            check(checkpoint_time(f) == 0.01,
                  "--checkpoint-every %s: a checkpoint at the end" % every)
            same_results(f0, f, "--checkpoint-every %s against no checkpoints" % every)

    # a fluid (fixed particles, the two-stage update), a first run to 0.3 s extended to 0.4 s:
    # with outputs every 0.05 s the end 0.3 is not the sixth output's 6 * 0.05 =
    # 0.30000000000000004, where the run to 0.4 s passes; the scene takes the grid's time for
    # it, so the first run ends where the longer one passes (before, its last step was 6e-17 s
    # shorter and the states differed in round-off).  The snapshots' vorticity, which no
    # checkpoint stores, is formed again after the restart.
    tgv = os.path.join(SRC, "cases", "taylor_green_2d", "scene.cfg")
    fluid = ["--backend", BACKEND, "--quiet", "--set", "resolution.dp=0.05",
             "--set", "time.output_interval=0.05", "--set", "output.snapshot_interval=0.05"]
    f_ref, f_ext = os.path.join(tmp, "fluid_ref"), os.path.join(tmp, "fluid_extended")
    p = run(["run", tgv, "--out", f_ref, "--set", "time.end=0.4"] + fluid)
    check(p.returncode == 0, "fluid reference run: %s" % p.stderr)
    p = run(["run", tgv, "--out", f_ext, "--set", "time.end=0.3", "--checkpoint-every", "0.1"]
            + fluid)
    check(p.returncode == 0, "fluid run to 0.3 s: %s" % p.stderr)
    with h5py.File(os.path.join(f_ext, "checkpoint", "checkpoint.h5"), "r") as f:
        check("vorticity" not in f["fields"], "the checkpoint leaves out the derived vorticity")
    p = run(["run", "--restart", f_ext, "--backend", BACKEND, "--quiet", "--set", "time.end=0.4"])
    check(p.returncode == 0, "fluid restart to 0.4 s: %s" % p.stderr)
    c = run(["compare", f_ref, f_ext, "--rtol", "0", "--atol", "0"])
    check(c.returncode == 0, "fluid run extended from 0.3 s to 0.4 s: compare --rtol 0 exit %d\n%s"
          % (c.returncode, c.stdout[-2000:]))

    # a run whose end falls between output times (0.55 s, outputs every 0.1 s), extended to
    # 0.8 s, goes on with the output grid: 0.6 s next, not 0.7 s (before, the end's output
    # took the grid time after it); its series keeps the end's row, and a second extension
    # from the checkpoint that follows restarts as well
    off = os.path.join(tmp, "off_grid")
    offgrid = ["--backend", BACKEND, "--quiet", "--set", "resolution.dp=0.1",
               "--set", "time.output_interval=0.1"]
    p = run(["run", tgv, "--out", off, "--set", "time.end=0.55", "--checkpoint-every", "0.55"]
            + offgrid)
    check(p.returncode == 0, "fluid run to 0.55 s: %s" % p.stderr)
    for end in ("0.8", "1.0"):
        p = run(["run", "--restart", off, "--backend", BACKEND, "--quiet", "--set",
                 "time.end=" + end])
        check(p.returncode == 0, "off-grid run extended to %s s: %s" % (end, p.stderr))
    with open(os.path.join(off, "timeseries.csv")) as f:
        times = [round(float(line.split(",")[0]), 9) for line in f.readlines()[1:]]
    expected = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.55, 0.6, 0.7, 0.8, 0.9, 1.0]
    check(times == expected, "off-grid end extended: output times %s, expected %s"
          % (times, expected))

    # a damaged or edited checkpoint is an input error naming the file and the value, with
    # nothing written: before the checks, a NaN time ran to exit 0, negative step counts and a
    # huge snapshot count hung, and an id out of range crashed the restart
    def damage(source, name, edit, expected):
        d, out = os.path.join(tmp, "damaged-" + name), os.path.join(tmp, "damaged-out-" + name)
        shutil.copytree(source, d)
        path = os.path.join(d, "checkpoint", "checkpoint.h5")
        with h5py.File(path, "r+") as f:
            edit(f)
        p = run(["run", "--restart", d, "--out", out, "--backend", BACKEND, "--quiet",
                 "--set", "time.end=0.5"])
        check(p.returncode == 2 and path in p.stderr and expected in p.stderr and
              "no run writes such a checkpoint" in p.stderr,
              "damaged checkpoint (%s): exit %d, expected 2 naming %s and '%s': %s"
              % (name, p.returncode, path, expected, p.stderr.strip()[-400:]))
        written = os.listdir(out) if os.path.isdir(out) else []
        check(not any(n in written for n in ("summary.json", "timeseries.csv", "snapshots")),
              "damaged checkpoint (%s): nothing written to --out (%s)" % (name, written))

    def set_attr(key, value):
        return lambda f: f.attrs.__setitem__(key, value)

    def set_value(dataset, index, value):
        return lambda f: f[dataset].__setitem__(index, value)

    nan = float("nan")
    for name, edit, expected in (
            ("time", set_attr("time", nan), "attribute 'time' is nan"),
            ("steps", set_attr("acoustic_steps", -3), "'acoustic_steps' -3"),
            ("snapshots", set_attr("snapshot_count", 10 ** 9), "'snapshot_count' 1000000000"),
            ("outputs", set_attr("output_index", 10 ** 12), "'output_index' 1000000000000"),
            ("series", set_value("series_time", 2, nan), "dataset 'series_time'[2] is nan"),
            ("carried", set_value("carried", 0, nan), "dataset 'carried'[0] is nan"),
            ("position", set_value("fields/pos", 3, nan), "fields/pos[3] is nan"),
            ("mass", set_value("fields/mass", 3, 0.0), "fields/mass[3] is 0"),
            ("id_range", set_value("fields/id", 3, 100000), "fields/id[3] is 100000"),
            ("id_twice", set_value("fields/id", 3, 4), "the ids are the scene's particles")):
        damage(f_ext, name, edit, expected)
    # a wall particle turned into fluid: the kinds must be those the scene places
    cyl, cyl_run = os.path.join(SRC, "cases", "cylinder_flow_2d", "small.cfg"), \
        os.path.join(tmp, "cylinder")
    p = run(["run", cyl, "--out", cyl_run, "--backend", BACKEND, "--quiet", "--set", "time.end=0.2",
             "--set", "time.output_interval=0.1", "--checkpoint-every", "0.1"])
    check(p.returncode == 0, "small cylinder to 0.2 s with a checkpoint: %s" % p.stderr)
    if p.returncode == 0:
        with h5py.File(os.path.join(cyl_run, "checkpoint", "checkpoint.h5"), "r") as f:
            wall = int(list(f["fields/kind"][...]).index(1))
        damage(cyl_run, "kind", set_value("fields/kind", wall, 0), "fields/kind[%d] is 0" % wall)

    # compare fails on a perturbed copy, naming the field and the particle
    d = os.path.join(tmp, "perturbed")
    shutil.copytree(ref, d)
    with h5py.File(os.path.join(d, "snapshots", "snapshot_000002.hdf"), "r+") as f:
        v = f["VTKHDF/PointData/velocity"]
        row = v[1234]
        row[1] += 1e-6  # m/s: about 1e-6 of the largest speed
        v[1234] = row
    p = run(["compare", ref, d])
    check(p.returncode == 3 and "velocity" in p.stdout and "particle 1234" in p.stdout,
          "compare names the perturbed field and particle, exit %d:\n%s" % (p.returncode, p.stdout))
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish("test_restart (%s)" % BACKEND)
