#!/usr/bin/python3
"""test_step_clock.py — the acoustic step clock on the OpenCL device.

With `--step-clock device` (the default where the device has double
precision) the substeps plan their own size on the device
(device/sph_step_clock.h, substep_finalize in device/reduction.cl) and the
host enqueues an advection step's substeps without reading max |v| after
each; with `--step-clock host` it reads max |v| after every substep and
plans the next one itself, as the native backend does.  The arithmetic is the
same double-precision expression on both sides, so the two must give the
same runs bit for bit: the same number of acoustic and advection steps and
identical snapshots and time series (`sphsolid compare --rtol 0`).

Checked on the paths the clock touches: the ENOG-A plate (averaged rotation,
R-bar from the substep reduction), SPH-GNOG-A (the third pass), TLSPH (one
substep per advection step), single precision (a float program reading a
double clock), single-criterion stepping, two colliding bodies (the contact
pass), a blow-up the monitor stops at a substep between outputs (the
device halts the clock there), and the same blow-up with monitor.action =
"report", which goes on past the warning to the end time.  And the point of
it: with --profile, the host waits once per advection step instead of once
per substep.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, PLATE, SRC, check, finish, run_sphsolid  # noqa: E402

RINGS = os.path.join(SRC, "cases", "colliding_rings_2d", "scene.cfg")
tmp = tempfile.mkdtemp(prefix="sphsolid-clock-")


def run(name, scene, mode, sets, options=()):
    out = os.path.join(tmp, f"{name}-{mode}")
    code, err = run_sphsolid(scene, "opencl", out, sets,
                             options=["--step-clock", mode] + list(options))
    return out, code, err


def summary(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def same_run(name, scene, sets, options=(), expect_code=0):
    """Run with the host and the device clock; both must end alike and match bit for bit."""
    outs = {}
    for mode in ("host", "device"):
        out, code, err = run(name, scene, mode, sets, options)
        check(code == expect_code, f"{name} ({mode} clock): exit {code}, expected {expect_code}"
              f" ({err})")
        outs[mode] = out
    try:
        host, dev = summary(outs["host"]), summary(outs["device"])
    except OSError as e:
        check(False, f"{name}: summary.json: {e}")
        return None
    check("-DSPH_STEP_CLOCK=0" in host["build_options"] and
          "-DSPH_STEP_CLOCK=1" in dev["build_options"],
          f"{name}: the programs say which clock they were built for: "
          f"{host['build_options']} / {dev['build_options']}")
    for key in ("acoustic_steps", "advection_steps", "simulated_time", "status"):
        check(host[key] == dev[key], f"{name}: {key} {host[key]} (host) against {dev[key]} (device)")
    check(host.get("instability") == dev.get("instability"),
          f"{name}: same instability record: {host.get('instability')} / "
          f"{dev.get('instability')}")
    p = subprocess.run([BIN, "compare", outs["host"], outs["device"], "--rtol", "0"],
                       capture_output=True, text=True, timeout=300)
    check(p.returncode == 0, f"{name}: host and device clocks bit-identical:\n{p.stdout}{p.stderr}")
    print(f"{name}: {dev['acoustic_steps']} acoustic steps in {dev['advection_steps']} advection "
          f"steps, identical")
    return dev


try:
    plate = ["resolution.ratio=6", "time.end=0.05"]
    same_run("enog-a", PLATE, plate)
    same_run("gnog-a", PLATE, plate + ["method.formulation=gnog-a"])
    same_run("tlsph", PLATE, ["resolution.ratio=6", "time.end=0.01", "method.formulation=tlsph",
                              "method.rotation=none"])
    same_run("single", PLATE, plate, options=["--precision", "single"])
    same_run("single-stepping", PLATE, ["resolution.ratio=6", "time.end=0.01",
                                        "time.stepping=single"])
    same_run("rings", RINGS, ["resolution.dp=0.004", "time.end=0.002"])

    # the blow-up of test_monitor: the speed check trips at a substep
    # between two outputs, where the device clock halts
    blowup = ["resolution.ratio=4", "time.end=0.3", "time.cfl_acoustic=1.0"]
    dev = same_run("blowup", PLATE, blowup, expect_code=4)
    if dev:
        ins = dev.get("instability", {})
        check("maximum speed" in ins.get("quantity", "") and ins.get("time", 1) < 0.01,
              f"blowup: the speed check tripped before the first output: {ins}")
    # reported, not stopped: the substeps of the advection step go on after
    # the warning (the device clock resumes without the speed check)
    dev = same_run("blowup-report", PLATE, ["resolution.ratio=4", "time.end=0.01",
                                            "time.cfl_acoustic=1.0", "monitor.action=report"])
    if dev:
        ins = dev.get("instability", {})
        check(ins.get("stopped") is False and ins.get("time", 1) < 0.01,
              f"blowup-report: reported and gone on: {ins}")

    # the host's waits inside the acoustic loop, counted by --profile: one
    # read of the clock per advection step with the device clock (measured on
    # this plate, H/dp = 10 to 0.05 s: 262 reads for 262 advection steps; a
    # mispredicted step length costs one more), one read of max |v| per
    # substep with the host clock (2852)
    reads = {}
    for mode, phase in (("device", "step clock read"), ("host", "max speed read")):
        out, code, err = run("profile", PLATE, mode, ["time.end=0.05"], options=["--profile"])
        check(code == 0, f"profile ({mode} clock): exit {code} ({err})")
        if code == 0:
            s = summary(out)
            calls = [p["calls"] for p in s["profile"] if p["phase"] == phase]
            reads[mode] = (calls[0] if calls else 0, s["advection_steps"], s["acoustic_steps"])
    if len(reads) == 2:
        (dev_reads, adv, _), (host_reads, _, acoustic) = reads["device"], reads["host"]
        check(adv <= dev_reads <= 1.1 * adv,
              f"device clock: {dev_reads} reads for {adv} advection steps")
        check(host_reads == acoustic, f"host clock: {host_reads} reads for {acoustic} substeps")
        print(f"host reads: {dev_reads} with the device clock ({adv} advection steps), "
              f"{host_reads} with the host clock ({acoustic} substeps)")

    # a bad value names the flag
    p = subprocess.run([BIN, "run", PLATE, "--step-clock", "gpu"], capture_output=True, text=True,
                       timeout=60)
    check(p.returncode == 2 and "--step-clock gpu" in p.stderr,
          f"--step-clock gpu: exit {p.returncode}, {p.stderr.strip()}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish("test_step_clock")
