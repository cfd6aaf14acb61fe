#!/usr/bin/python3
"""test_kernel_bytes.py — the profile's byte counts (issue 33): every kernel in device/ carries
a declaration of its buffers directly above it ("/* buffers of NAME: reads ...; writes ...;
updates ... */", host/backend/kernel_bytes.c reads them from the embedded sources), and
`--profile` reports per phase the bytes one call moves by them.

(a) The declarations cannot drift from the signatures: each lists exactly the kernel's global
    pointer arguments, with the feature macros expanded to every alternative (a kernel with
    two definitions has one declaration each); "reads" only const arguments, "writes" and
    "updates" only non-const ones; a name without a shape is a field of host/model/fields.c,
    a shape is TYPE*FACTOR*... of the known types and factors, or small / host.
(b) On the 2D plate (a few advection steps, --profile), native double and mixed precision and
    OpenCL (pocl) double: bytes_per_call of rebuild_reduce and build_neighbours equal a count
    made here from n, the neighbour pairs counted here from the snapshot with numpy, the grid
    cells and the element sizes of the precision; gbs = bytes x calls / seconds; phases that
    are no declared kernel (host reads, the permutation) carry no bytes."""
import json
import os
import re
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import PLATE, SRC, check, finish, run_sphsolid, snapshot_paths  # noqa: E402

DEVICE = os.path.join(SRC, "device")
TYPES = {"int", "uint", "ulong", "u8", "real", "hreal", "double"}
FACTORS = {"n", "npad", "pairs", "cells", "d"}
DECL = re.compile(r"/\* buffers of (\w+):(.*?)\*/", re.S)
ARG = re.compile(r"(?:volatile\s+)?\b(?:GLOBAL|__global)\s+(const\s+)?(\w+)\s*\*\s*"
                 r"(?:restrict\s+)?(\w+)")
HEAD = re.compile(r"\b(?:KERNEL|__kernel)\b(?:\s+__attribute__\s*\(\(.*?\)\))?\s+void\s+"
                  r"(\w+)\s*\(")


# ---- (a) declarations against signatures ---------------------------------------------------
def device_files():
    out = {}
    for name in sorted(os.listdir(DEVICE)):
        if name.endswith((".cl", ".h")):
            with open(os.path.join(DEVICE, name)) as f:
                out[name] = f.read()
    return out


def macros(files):
    """Object-like macros {name: [every definition]} (the alternatives of the feature
    switches) and function-like ones {name: (parameters, body)}."""
    obj, fn = {}, {}
    for text in files.values():
        text = re.sub(r"\\\n", " ", text)
        for m in re.finditer(r"^[ \t]*#[ \t]*define[ \t]+(\w+)(\([^)]*\))?(.*)$", text, re.M):
            if m.group(2):
                fn[m.group(1)] = ([p.strip() for p in m.group(2)[1:-1].split(",")], m.group(3))
            else:
                obj.setdefault(m.group(1), []).append(m.group(3))
    return obj, fn


def expand(text, obj, fn):
    """Parameter text with the macros that hold global pointers expanded (every alternative
    at once) and the function-like ones substituted."""
    def call(m):
        params, body = fn[m.group(1)]
        for p, a in zip(params, [a.strip() for a in m.group(2).split(",")]):
            body = re.sub(r"\b%s\b" % re.escape(p), a, body)
        return body

    def obj_macro(m):
        bodies = obj.get(m.group(1))
        return " ".join(bodies) if bodies and "GLOBAL" in " ".join(bodies) else m.group(0)
    for _ in range(8):
        new = re.sub(r"\b(%s)\s*\(([^()]*)\)" % "|".join(map(re.escape, fn)), call, text)
        new = re.sub(r"\b(\w+)\b", obj_macro, new)
        if new == text:
            break
        text = new
    return re.sub(r"\s*##\s*", "", text)


def params_at(text, start):
    depth, k = 1, start
    while k < len(text) and depth:
        depth += {"(": 1, ")": -1}.get(text[k], 0)
        k += 1
    return text[start:k - 1]


def kernel_definitions():
    """[(file, offset of the definition's line, kernel, {argument: const in every
    alternative})]: KERNEL and __kernel functions, and the DEFINE_PERMUTE instances."""
    files = device_files()
    obj, fn = macros(files)
    found = []
    for fname, text in files.items():
        if not fname.endswith(".cl"):
            continue
        flat = re.sub(r"\\\n", "  ", text)  # the same length: offsets stay
        for m in HEAD.finditer(flat):
            line = flat.rfind("\n", 0, m.start()) + 1
            if flat[line:m.start()].lstrip().startswith("#"):
                continue  # the kernel inside DEFINE_PERMUTE's body
            found.append((fname, line, m.group(1), params_at(flat, m.end())))
        for m in re.finditer(r"^DEFINE_PERMUTE\((\w+),\s*(\w+)\)", flat, re.M):
            body = fn["DEFINE_PERMUTE"][1]
            p = params_at(body, HEAD.search(body).end())
            found.append((fname, m.start(), m.group(1), re.sub(r"\btype\b", m.group(2), p)))
    out = []
    for fname, off, name, params in found:
        args = {}
        for a in ARG.finditer(expand(params, obj, fn)):
            args[a.group(3)] = args.get(a.group(3), True) and bool(a.group(1))
        out.append((fname, off, name, args))
    return files, out


def field_names():
    with open(os.path.join(SRC, "host", "model", "fields.c")) as f:
        return set(re.findall(r"\]\s*=\s*\{\"(\w+)\",\s*FIELD_TYPE_", f.read()))


def parse_declaration(body):
    """{name: (access, shape or None)} of a declaration's text, or a message."""
    out, mode = {}, None
    for tok in re.split(r"[\s;,]+", body):
        if tok in ("", "*"):
            continue
        if tok in ("reads", "writes", "updates"):
            mode = tok
            continue
        if mode is None:
            return f"{tok!r} before reads/writes/updates"
        name, _, shape = tok.partition(":")
        if name in out:
            return f"{name} twice"
        out[name] = (mode, shape or None)
    return out


def check_declarations():
    files, defs = kernel_definitions()
    fields = field_names()
    check(len(fields) > 30, f"field names of fields.c: {len(fields)}")
    names = {k for _, _, k, _ in defs}
    for must in ("build_neighbours", "acoustic_pressure", "tl_update", "eulerian_rates",
                 "rebuild_reduce", "permute_real", "bitonic_global", "monitor_reduce"):
        check(must in names, f"kernel {must} found in device/")
    used = set()
    for fname, off, kernel, args in defs:
        text = files[fname]
        decl = None
        for m in DECL.finditer(text):
            if m.end() <= off and not text[m.end():off].strip():
                decl = m
        check(decl is not None, f"{fname}: {kernel} has a declaration directly above it")
        if decl is None:
            continue
        used.add((fname, decl.start()))
        check(decl.group(1) == kernel, f"{fname}: declaration of {decl.group(1)} above {kernel}")
        entries = parse_declaration(decl.group(2))
        if isinstance(entries, str):
            check(False, f"{fname}: {kernel}: {entries}")
            continue
        check(set(entries) == set(args),
              f"{fname}: {kernel} declares exactly its global pointer arguments: missing "
              f"{sorted(set(args) - set(entries))}, not arguments {sorted(set(entries) - set(args))}")
        for name, (access, shape) in entries.items():
            if name in args:
                check((access == "reads") == args[name],
                      f"{fname}: {kernel}: {name} {access} but is "
                      f"{'const' if args[name] else 'written'} in the signature")
            if shape is None:
                check(name in fields, f"{fname}: {kernel}: {name} has no shape and is no field")
            elif shape not in ("small", "host"):
                parts = shape.split("*")
                check(parts[0] in TYPES and len(parts) > 1 and
                      all(p in FACTORS or p.isdigit() for p in parts[1:]),
                      f"{fname}: {kernel}: shape {name}:{shape}")
    for fname, text in files.items():
        for m in DECL.finditer(text):
            check((fname, m.start()) in used, f"{fname}: declaration of {m.group(1)} above no kernel")


# ---- (b) the reported bytes ------------------------------------------------------------------
def pairs_in_snapshot(path, cutoff):
    """Ordered pairs (i, j), i != j, closer than the cut-off: the neighbour slots."""
    import h5py
    import numpy as np
    with h5py.File(path, "r") as f:
        x = np.asarray(f["VTKHDF/Points"][...], dtype=float)
    d2 = ((x[:, None, :] - x[None, :, :]) ** 2).sum(axis=2)
    return int(((d2 < cutoff * cutoff) & (d2 > 0)).sum())


def check_run(backend, precision, tmp):
    out = os.path.join(tmp, f"{backend}-{precision}")
    # OpenCL: the substep loop (device/substep_loop.cl), whose phase counts the passes it fuses
    loop = ("--substeps-per-launch", "64") if backend == "opencl" else ()
    code, err = run_sphsolid(PLATE, backend, out, sets=("time.end=0.01",),
                             options=("--profile", "--precision", precision) + loop)
    check(code == 0, f"{backend} {precision}: exit {code} ({err})")
    if code != 0:
        return
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    n, d = s["particle_count"], s["features"]["dimension"]
    real = 8 if precision == "double" else 4
    hreal = 4 if precision == "single" else 8
    nsym = d * (d + 1) // 2
    snaps = snapshot_paths(out)
    cutoff = s["resolved"]["cutoff"]
    pairs = pairs_in_snapshot(snaps[-1], cutoff)
    check(pairs == pairs_in_snapshot(snaps[0], cutoff), f"{backend}: the plate keeps its pairs")
    sizes = s.get("profile_sizes", {})
    check(sizes.get("pair_slots") == pairs,
          f"{backend} {precision}: pair slots {sizes.get('pair_slots')} == {pairs} counted here")
    cells = sizes.get("grid_cells", 0)
    check(cells > 0, f"{backend}: grid cells {cells}")
    records = {r["name"]: r["bytes"] for r in s["memory"]["buffers"]}
    # buffers of a few values: as the OpenCL backend allocated them; the native backend keeps
    # its reduction rows and overflow flag to itself (not counted)
    small = (lambda name: records[name]) if backend == "opencl" else (lambda name: 0)
    prof = {p["phase"]: p for p in s["profile"]}
    expect = {
        # reads x, v, m, rho and the dissipation acceleration (a vector); writes V = m / rho
        # and the group rows (device/reduction.cl)
        "rebuild_reduce": n * (d * hreal + d * real + real + hreal + d * real + real)
        + small("partials"),
        # reads x, v, V, the keys and the cell ranges; writes the counts, the pair slots
        # (j, e, dW, 1/r) and B (device/neighbour_build.cl; no TLSPH, contact or bodies here)
        "build_neighbours": n * (d * hreal + d * real + real + 8) + 2 * 4 * cells
        + n * 4 + pairs * (4 + d * real + real + real) + n * nsym * real + small("overflow"),
    }
    if backend == "opencl":
        args = {k.split("(")[0]: k.split("(", 1)[1] for k in s.get("program_kernels", [])}
        check("pair_pos" not in args.get("build_neighbours", "pair_pos"),
              "pocl stores the pair geometry (the count above assumes it)")
    for phase, want in expect.items():
        p = prof.get(phase, {})
        got = p.get("bytes_per_call")
        check(got == want, f"{backend} {precision}: {phase} bytes per call {got} == {want}")
        if got is not None and p["seconds"] > 0:
            gbs = got * p["calls"] / p["seconds"] / 1e9
            check(abs(p.get("gbs", -1) - gbs) <= 1e-12 * gbs, f"{backend}: {phase} GB/s")
    for phase in ("cell sort and permutation", "step clock read", "max speed read",
                  "permute_real", "fluid setup"):
        if phase in prof:
            check("bytes_per_call" not in prof[phase], f"{backend}: {phase} has no bytes")
    # the native substep phase, and OpenCL's substep loop, count the passes they fuse, per
    # substep
    sub = prof.get("acoustic substep" if backend == "cpu" else "acoustic_substep_loop", {})
    check(sub.get("bytes_of") == "acoustic_pressure + acoustic_velocity_terms + "
          "substep_reduce", f"{backend}: fused substep phase's kernels: {sub.get('bytes_of')}")
    if backend == "opencl":
        check(0 < sub.get("calls", 0) < s["acoustic_steps"] and sub.get("bytes_per_call", 0) > 0
              and "acoustic_pressure" not in prof,
              f"opencl: the loop's launches hold several substeps each: {sub}")


check_declarations()
tmp = tempfile.mkdtemp(prefix="sphsolid-kernel-bytes-")
try:
    for backend, precision in (("cpu", "double"), ("cpu", "mixed"), ("opencl", "double")):
        check_run(backend, precision, tmp)
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish("test_kernel_bytes")
