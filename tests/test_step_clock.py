#!/usr/bin/python3
"""test_step_clock.py [opencl|cpu] — the acoustic step clock on the device, and on the
native backend's thread team.

OpenCL: with `--step-clock device` (the default where the device has double
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
pass), the ideal-gas Taylor-Green vortex with SSP-RK3 (a fluid's stage
passes), a blow-up the monitor stops at a substep between outputs (the
device halts the clock there), and the same blow-up with monitor.action =
"report", which goes on past the warning to the end time.  And the point of
it: with --profile, the host waits once per advection step instead of once
per substep.

The native backend (argument `cpu`): by default an advection step's substeps run in one
parallel region, thread 0 advancing the clock between them and the team synchronising on
its own spinning barrier (host/backend/cpu/cpu_team.h); `--step-clock host` forks the team
once per substep and advances the clock on the host.  The same runs must match bit for bit,
and so must runs on one thread and on two, with OMP_WAIT_POLICY passive or active (the team
size and the barrier change no sum).  With --profile, the "acoustic substep" phase is then
one call per advection step against one per substep.
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
TGV_GAS = os.path.join(SRC, "cases", "taylor_green_2d", "public_code.cfg")
CYLINDER_SMALL = os.path.join(SRC, "cases", "cylinder_flow_2d", "small.cfg")
BACKEND = sys.argv[1] if len(sys.argv) > 1 else "opencl"
NATIVE = BACKEND == "cpu"
tmp = tempfile.mkdtemp(prefix="sphsolid-clock-")


def run(name, scene, mode, sets, options=(), env=None):
    out = os.path.join(tmp, f"{name}-{mode}")
    saved = dict(os.environ)
    os.environ.update(env or {})
    try:
        code, err = run_sphsolid(scene, BACKEND, out, sets,
                                 options=["--step-clock", mode] + list(options))
    finally:
        os.environ.clear()
        os.environ.update(saved)
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
    marks = ("step_clock=host", "step_clock=team") if NATIVE else \
        ("-DSPH_STEP_CLOCK=0", "-DSPH_STEP_CLOCK=1")
    check(marks[0] in host["build_options"] and marks[1] in dev["build_options"],
          f"{name}: the runs say which clock they used: "
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
    # a fluid with SSP-RK3 and outputs every 0.05 s: the device clock's batches overran an
    # output time, and the stage rates of the no-op substeps past it changed the vorticity
    # written there (8e-4 at t = 0.5) until eulerian_rates, too, stopped at a halted clock (the
    # vorticity has since left the stage rates: it is formed for the snapshots)
    same_run("fluid-rk3", TGV_GAS, ["resolution.dp=0.04", "time.end=1",
                                    "time.output_interval=0.05", 'time.integrator="ssp-rk3"'])
    # with a wall body: the wall force, which SSP-RK3's stage rates weight over the step and
    # the time series' drag and lift columns read, the same under both clocks (the small
    # cylinder; the vorticity is no longer the rates' but formed for the snapshots)
    same_run("fluid-rk3-walls", CYLINDER_SMALL, ["time.end=2", "time.output_interval=0.1",
                                                 'time.integrator="ssp-rk3"'])

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

    # the native team: one thread and two, passive and active waits, the same bits
    if NATIVE:
        outs = []
        for env in ({"OMP_NUM_THREADS": "1", "OMP_WAIT_POLICY": "passive"},
                    {"OMP_NUM_THREADS": "2", "OMP_WAIT_POLICY": "passive"},
                    {"OMP_NUM_THREADS": "2", "OMP_WAIT_POLICY": "active"}):
            tag = f"threads{env['OMP_NUM_THREADS']}-{env['OMP_WAIT_POLICY']}"
            out, code, err = run(tag, PLATE, "auto",
                                 ["resolution.ratio=10", "time.end=0.01",
                                  "method.formulation=gnog-a", "method.rotation=per-particle"],
                                 env=env)
            check(code == 0, f"{tag}: exit {code} ({err})")
            threads = summary(out)["device"] if code == 0 else ""
            check(f"{env['OMP_NUM_THREADS']} OpenMP thread" in threads,
                  f"{tag}: the plate's 1612 particles run on the threads given: {threads}")
            outs.append(out)
        for other in outs[1:]:
            p = subprocess.run([BIN, "compare", outs[0], other, "--rtol", "0"],
                               capture_output=True, text=True, timeout=300)
            check(p.returncode == 0, f"{os.path.basename(other)} against one thread: "
                  f"bit-identical:\n{p.stdout}{p.stderr}")

    # the host's waits inside the acoustic loop, counted by --profile: one
    # read of the clock per advection step with the device clock (measured on
    # this plate, H/dp = 10 to 0.05 s: 262 reads for 262 advection steps; a
    # mispredicted step length costs one more), one read of max |v| per
    # substep with the host clock (2852)
    reads = {}
    phases = (("device", "acoustic substep"), ("host", "acoustic substep")) if NATIVE else \
        (("device", "step clock read"), ("host", "max speed read"))
    for mode, phase in phases:
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
