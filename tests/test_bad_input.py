#!/usr/bin/python3
"""test_bad_input.py — every class of bad input, one row of a table each.

A row says how the bad input is made (an edit of the oscillating plate's
scene text, command-line arguments, environment, a process limit, a small
or read-only filesystem), the exit status it must give and fragments its
message must contain.  Conventions checked on every row:

- a scene error (exit 2) names the file, the line and the full key path:
  "bad.cfg:LINE: KEY: what is wrong" (a syntax error has no key yet:
  "bad.cfg:LINE: syntax error"; a value from an override names the override
  instead: "--set KEY=VALUE: KEY: ..."; a missing top-level key has no line,
  docs/scene-format.md "Errors");
- a runtime failure (exit 1) is one sentence on one line;
- afterwards nothing under the row's directories looks like a complete
  result: no summary.json, timeseries.csv, snapshots/*.hdf (only .partial)
  or checkpoint.h5.

Two controls follow the table: bodies that touch (without overlapping) run,
and a run stopped by a full disk keeps its checkpoint and restarts from it to
the uninterrupted run's results.

Full disks are real where this process may mount a tmpfs (as root): a
256 KiB tmpfs with a filler file that leaves the chosen room.  Where it may
not, the same rows run through the fault injection SPHSOLID_TEST_DISK_FULL
(host/io/hdf5_file.c), and the output says which path ran.
"""
import importlib.util
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, PLATE, SRC, check, finish  # noqa: E402

# tools/plot_run.py needs matplotlib: where it is missing, that check is skipped (and said)
HAVE_MATPLOTLIB = importlib.util.find_spec("matplotlib") is not None

PLATE_TEXT = open(PLATE).read()
# the plate's initial velocity group, which the expression rows replace
CANTILEVER = PLATE_TEXT[PLATE_TEXT.index("initial_velocity = {"):
                        PLATE_TEXT.index("};", PLATE_TEXT.index("initial_velocity = {")) + 2]
FAST = ["--set", "resolution.ratio=4", "--set", "time.end=0.01"]
# a fluid scene of the eulerian formulations (seed 004 §3.1; docs/scene-format.md, "Fluids"): a
# weakly compressible fluid, periodic along x and y; the fluid rows edit it (GAS: the ideal gas)
FLUID_TEXT = """dimension = 2;
resolution = { dp = 0.1; };
method = { formulation = "eulerian-wc"; };
time = { end = 0.01; output_interval = 0.01; };
materials = {
  water = { density = 1.0; sound_speed = 10.0; viscosity = 0.01; };
};
shapes = {
  box = { type = "box"; lower = [0.0, 0.0]; upper = [1.0, 1.0]; };
};
bodies = (
  { name = "water"; material = "water"; shape = "box"; }
);
boundary = { periodic = ["x", "y"]; lower = [0.0, 0.0]; upper = [1.0, 1.0]; };
"""
GAS_TEXT = (FLUID_TEXT.replace('"eulerian-wc"', '"eulerian-compressible"')
            .replace("sound_speed = 10.0; viscosity = 0.01;", "gamma = 1.4;")
            .replace('shape = "box"; }', 'shape = "box"; initial_pressure = 71.43; }'))
SCENE = "bad.cfg"  # scenes are written into the row's directory under this name
RESULTS = ("summary.json", "timeseries.csv", "checkpoint.h5")
# the disk-full rows fill the disk during the run: past the estimate of the
# output volume, which refuses a run the free space cannot hold beforehand
NO_LIMIT = ["--no-work-limit"]


class Row:
    """One bad input.  `edits` are (old, new) replacements of the plate's
    scene text (or `text` is the whole scene); `args` follow
    `run bad.cfg --backend cpu --quiet --out OUT` (or `argv` is the whole
    command line); `marker` is the text whose line the message must name
    ({line}), with `offset` added (`marker_b`, `offset_b`: {line_b}).
    Fragments may use {file}, {line}, {line_b}, {out}, {dir} (the row's
    directory).  `data_limit`: RLIMIT_DATA of the run, bytes; `fs`:
    "below-file" (--out below a regular file), "read-only" (a read-only
    tmpfs) or ("full", free bytes, the SPHSOLID_TEST_DISK_FULL fallback)."""

    def __init__(self, what, code, fragments, edits=(), text=None, args=(), argv=None, env=None,
                 marker=None, offset=0, marker_b=None, offset_b=0, data_limit=None, fs=None,
                 located=None):
        self.what, self.code, self.fragments = what, code, list(fragments)
        self.edits, self.text, self.args, self.argv = list(edits), text, list(args), argv
        self.env, self.marker, self.offset = env or {}, marker, offset
        self.marker_b, self.offset_b = marker_b, offset_b
        self.data_limit, self.fs = data_limit, fs
        # scene rows (an edited scene, no argv of their own) must give
        # "bad.cfg:LINE: KEY:" unless told otherwise
        self.located = located if located is not None else (
            code == 2 and argv is None and (bool(edits) or text is not None))


def ed(old, new):
    return (old, new)


def within(seconds, row):
    """A row whose run must end within `seconds` (default 300): what it
    refuses ran for hours before."""
    row.timeout = seconds
    return row


# ---------------------------------------------------------------- the table
ROWS = [
    # --- syntax
    Row("syntax error", 2, ["{file}:{line}: syntax error"],
        [ed("end = 1.0;", "end = = 1.0;")], marker="end = = 1.0"),
    Row("syntax error: integer in an array of decimals", 2,
        ["{file}:{line}: syntax error: mismatched element type in array", "as a decimal"],
        [ed("upper = [0.2, 0.01]", "upper = [0.2, 0]")], marker="upper = [0.2, 0]"),
    Row("syntax error: a malformed number", 2, ["{file}:{line}: syntax error"],
        [ed("ratio = 10.0;", "ratio = 10..0;")], marker="ratio = 10..0"),
    Row("syntax error: an unquoted string", 2, ["{file}:{line}: syntax error"],
        [ed('kernel = "wendland-c2";', "kernel = wendland-c2;")], marker="kernel = wendland"),
    Row("empty scene file", 2, ["{file}: dimension: missing required key"], text="",
        located=False),
    # --- unknown keys, with the nearest valid name
    Row("unknown key: a typo in a material", 2,
        ["{file}:{line}: materials.plate.youngs_modulous: unknown key 'youngs_modulous' "
         "(did you mean 'youngs_modulus'?)"],
        [ed("youngs_modulus = 2.0e6;", "youngs_modulous = 2.0e6;")], marker="youngs_modulous"),
    Row("unknown key: top level", 2,
        ["{file}:{line}: dimensoin: unknown key 'dimensoin' (did you mean 'dimension'?)"],
        [ed("dimension = 2;", "dimensoin = 2;")], marker="dimensoin"),
    Row("unknown key: time", 2,
        ["{file}:{line}: time.cfl_acustic: unknown key 'cfl_acustic' "
         "(did you mean 'cfl_acoustic'?)"],
        [ed("cfl_acoustic = 0.4;", "cfl_acustic = 0.4;")], marker="cfl_acustic"),
    Row("unknown key: a body", 2,
        ["{file}:{line}: bodies.plate.materail: unknown key 'materail' (did you mean 'material'?)"],
        [ed('material = "plate";', 'materail = "plate";')], marker="materail"),
    Row("unknown key: nothing close, the valid keys listed", 2,
        ["{file}:{line}: resolution.spacing: unknown key 'spacing' (valid keys here: dp, "
         "reference_length, ratio)"],
        [ed("ratio = 10.0;", "ratio = 10.0; spacing = 0.002;")], marker="spacing"),
    # --- wrong types
    Row("wrong type: a string for a number", 2,
        ["{file}:{line}: materials.plate.density: expected a number, got a string"],
        [ed("density = 1000.0;", 'density = "1000";')], marker='density = "1000"'),
    Row("wrong type: a number for a string", 2,
        ["{file}:{line}: method.formulation: expected a string, got an integer"],
        [ed('formulation = "enog-a";', "formulation = 3;")], marker="formulation = 3"),
    Row("wrong type: a decimal for an integer", 2,
        ["{file}:{line}: dimension: expected an integer, got a number"],
        [ed("dimension = 2;", "dimension = 2.0;")], marker="dimension = 2.0"),
    Row("wrong type: a number for a group", 2,
        ["{file}:{line}: resolution: expected a group {{ ... }}, got a number"],
        [ed("resolution = {\n  reference_length = 0.02;   # H\n  ratio = 10.0;              # H / dp\n};",
            "resolution = 0.002;")], marker="resolution = 0.002"),
    Row("wrong type: an integer for a boolean", 2,
        ["{file}:{line}: time.acceleration_criterion: expected a boolean (true or false), "
         "got an integer"],
        [ed('stepping = "dual";', 'stepping = "dual"; acceleration_criterion = 1;')],
        marker="acceleration_criterion"),
    Row("wrong type: a vector of the wrong length", 2,
        ["{file}:{line}: observers.tip.position: expected a vector of 2 numbers, got 1 element"],
        [ed("position = [0.2, 0.0]", "position = [0.2]")], marker="position = [0.2]"),
    Row("wrong type: a string for a vector", 2,
        ["{file}:{line}: shapes.beam.lower: expected a vector of 2 numbers [ ... ], got a string"],
        [ed("lower = [-0.06, -0.01]; upper = [0.2, 0.01]", 'lower = "origin"; upper = [0.2, 0.01]')],
        marker='lower = "origin"'),
    # --- material ranges
    Row("E < 0", 2, ["{file}:{line}: materials.plate.youngs_modulus: must be > 0, got -2e+06"],
        [ed("youngs_modulus = 2.0e6;", "youngs_modulus = -2.0e6;")], marker="youngs_modulus"),
    Row("E = 0", 2, ["{file}:{line}: materials.plate.youngs_modulus: must be > 0, got 0"],
        [ed("youngs_modulus = 2.0e6;", "youngs_modulus = 0.0;")], marker="youngs_modulus"),
    Row("nu < 0", 2,
        ["{file}:{line}: materials.plate.poisson_ratio: must be in [0, 0.5), got -0.1"],
        [ed("poisson_ratio = 0.3975;", "poisson_ratio = -0.1;")], marker="poisson_ratio"),
    Row("nu = 0.5", 2,
        ["{file}:{line}: materials.plate.poisson_ratio: must be in [0, 0.5), got 0.5"],
        [ed("poisson_ratio = 0.3975;", "poisson_ratio = 0.5;")], marker="poisson_ratio"),
    Row("nu > 0.5", 2,
        ["{file}:{line}: materials.plate.poisson_ratio: must be in [0, 0.5), got 0.7"],
        [ed("poisson_ratio = 0.3975;", "poisson_ratio = 0.7;")], marker="poisson_ratio"),
    Row("density = 0", 2, ["{file}:{line}: materials.plate.density: must be > 0, got 0"],
        [ed("density = 1000.0;", "density = 0.0;")], marker="density"),
    Row("density < 0", 2, ["{file}:{line}: materials.plate.density: must be > 0, got -1000"],
        [ed("density = 1000.0;", "density = -1000.0;")], marker="density"),
    Row("yield stress <= 0", 2,
        ["{file}:{line}: materials.plate.yield_stress: must be > 0, got 0"],
        [ed("poisson_ratio = 0.3975;", "poisson_ratio = 0.3975; yield_stress = 0.0;")],
        marker="yield_stress"),
    # --- resolution
    Row("dp < 0", 2, ["{file}:{line}: resolution.dp: must be > 0, got -0.002"],
        [ed("reference_length = 0.02;   # H\n  ratio = 10.0;", "dp = -0.002;")],
        marker="dp = -0.002;"),
    Row("dp = 0", 2, ["{file}:{line}: resolution.dp: must be > 0, got 0"],
        [ed("reference_length = 0.02;   # H\n  ratio = 10.0;", "dp = 0.0;")],
        marker="dp = 0.0;"),
    Row("resolution ratio = 0", 2, ["{file}:{line}: resolution.ratio: must be > 0, got 0"],
        [ed("ratio = 10.0;", "ratio = 0.0;")], marker="ratio = 0.0"),
    Row("resolution ratio < 0", 2, ["{file}:{line}: resolution.ratio: must be > 0, got -10"],
        [ed("ratio = 10.0;", "ratio = -10.0;")], marker="ratio = -10.0"),
    Row("reference length = 0", 2,
        ["{file}:{line}: resolution.reference_length: must be > 0, got 0"],
        [ed("reference_length = 0.02;", "reference_length = 0.0;")], marker="reference_length"),
    Row("both dp and ratio", 2,
        ["{file}:{line}: resolution: give either dp or reference_length and ratio"],
        [ed("ratio = 10.0;", "ratio = 10.0; dp = 0.002;")], marker="resolution = {"),
    Row("neither dp nor ratio", 2,
        ["{file}:{line}: resolution: missing required key: dp, or reference_length and ratio"],
        [ed("reference_length = 0.02;   # H\n  ratio = 10.0;", "")], marker="resolution = {"),
    Row("smoothing ratio out of range", 2,
        ["{file}:{line}: method.smoothing_ratio: must be in [1, 2], got 3"],
        [ed("smoothing_ratio = 1.3;", "smoothing_ratio = 3.0;")], marker="smoothing_ratio"),
    # --- time
    Row("time.end = 0", 2, ["{file}:{line}: time.end: must be > 0, got 0"],
        [ed("end = 1.0;", "end = 0.0;")], marker="end = 0.0"),
    Row("time.end < 0", 2, ["{file}:{line}: time.end: must be > 0, got -1"],
        [ed("end = 1.0;", "end = -1.0;")], marker="end = -1.0"),
    Row("output_interval = 0", 2, ["{file}:{line}: time.output_interval: must be > 0, got 0"],
        [ed("output_interval = 0.01;", "output_interval = 0.0;")], marker="output_interval"),
    Row("output_interval < 0", 2,
        ["{file}:{line}: time.output_interval: must be > 0, got -0.01"],
        [ed("output_interval = 0.01;", "output_interval = -0.01;")], marker="output_interval"),
    Row("output_interval > end", 2,
        ["{file}:{line}: time.output_interval: must not exceed time.end (1), got 2"],
        [ed("output_interval = 0.01;", "output_interval = 2.0;")], marker="output_interval"),
    Row("cfl out of range", 2, ["{file}:{line}: time.cfl_acoustic: must be in (0, 1], got 1.5"],
        [ed("cfl_acoustic = 0.4;", "cfl_acoustic = 1.5;")], marker="cfl_acoustic"),
    # --- shapes
    Row("box upper < lower", 2,
        ["{file}:{line}: shapes.beam.upper: must exceed lower in every component (padding "
         "included), got upper.x = -0.1 <= lower.x = -0.06"],
        [ed("upper = [0.2, 0.01]", "upper = [-0.1, 0.01]")], marker="upper = [-0.1, 0.01]"),
    Row("box of zero size (upper = lower)", 2,
        ["{file}:{line}: shapes.beam.upper: must exceed lower",
         "upper.y = -0.01 <= lower.y = -0.01"],
        [ed("upper = [0.2, 0.01]", "upper = [0.2, -0.01]")], marker="upper = [0.2, -0.01]"),
    Row("negative padding", 2,
        ["{file}:{line}: shapes.base.lower_pad_dp.[0]: padding must be >= 0, got -4"],
        [ed("lower_pad_dp = [4.0, 4.0]", "lower_pad_dp = [-4.0, 4.0]")], marker="lower_pad_dp"),
    Row("unknown shape type", 2,
        ['{file}:{line}: shapes.plate.type: must be one of "box", "union", "difference", '
         '"disc", "ball", "annulus", "hollow_sphere", "cylinder", "mesh", got "unoin"'],
        [ed('plate = { type = "union";', 'plate = { type = "unoin";')], marker='"unoin"'),
    Row("annulus with inner radius >= outer radius", 2,
        ["{file}:{line}: shapes.ring.outer_radius: must exceed inner_radius = 0.02, got 0.01"],
        [ed('plate = { type = "union";',
            'ring = { type = "annulus"; centre = [0.0, 0.0];\n'
            '          inner_radius = 0.02; outer_radius = 0.01; };\n'
            '  plate = { type = "union";')], marker="outer_radius = 0.01"),
    Row("disc of negative radius", 2,
        ["{file}:{line}: shapes.blob.radius: must be > 0, got -0.01"],
        [ed('plate = { type = "union";',
            'blob = { type = "disc"; centre = [0.0, 0.0]; radius = -0.01; };\n'
            '  plate = { type = "union";')], marker="radius = -0.01"),
    Row("a 3D shape in 2D", 2,
        ['{file}:{line}: shapes.blob.type: "ball" is a 3D shape; in 2D use "disc"'],
        [ed('plate = { type = "union";',
            'blob = { type = "ball"; centre = [0.0, 0.0]; radius = 0.01; };\n'
            '  plate = { type = "union";')], marker='"ball"'),
    Row("unknown shape name in a union", 2,
        ["{file}:{line}: shapes.plate.parts.[1]: unknown shape 'bsae' (did you mean 'base'?)"],
        [ed('parts = ["beam", "base"]', 'parts = ["beam", "bsae"]')], marker='"bsae"'),
    Row("a shape that contains itself", 2,
        ["{file}:{line}: shapes.plate.parts: shapes refer to each other in a cycle"],
        [ed('parts = ["beam", "base"]', 'parts = ["beam", "plate"]')], marker='"plate"]'),
    # --- names
    Row("unknown material name", 2,
        ["{file}:{line}: bodies.plate.material: unknown material 'plat' (did you mean 'plate'?)"],
        [ed('material = "plate";', 'material = "plat";')], marker='material = "plat"'),
    Row("unknown material name, nothing close", 2,
        ["{file}:{line}: bodies.plate.material: unknown material 'steel' "
         "(defined materials: plate)"],
        [ed('material = "plate";', 'material = "steel";')], marker='material = "steel"'),
    Row("unknown shape name of a body", 2,
        ["{file}:{line}: bodies.plate.shape: unknown shape 'plates' (did you mean 'plate'?)"],
        [ed('shape = "plate";', 'shape = "plates";')], marker='shape = "plates"'),
    Row("unknown constraint region", 2,
        ["{file}:{line}: bodies.plate.constraints.[0].region: unknown shape 'clmap' "
         "(did you mean 'clamp'?)"],
        [ed('region = "clamp"', 'region = "clmap"')], marker="clmap"),
    Row("unknown formulation", 2,
        ['{file}:{line}: method.formulation: must be one of "enog", "enog-a"', 'got "enog-b"'],
        [ed('formulation = "enog-a";', 'formulation = "enog-b";')], marker='"enog-b"'),
    Row("unknown kernel", 2,
        ['{file}:{line}: method.kernel: must be one of "wendland-c2"', 'got "wendland"'],
        [ed('kernel = "wendland-c2";', 'kernel = "wendland";')], marker='"wendland"'),
    Row("unknown observer in the analysis", 2,
        ["{file}:{line}: analysis.period.observer: unknown observer 'top' (did you mean 'tip'?)"],
        [ed('observer = "tip"', 'observer = "top"')], marker='"top"'),
    Row("duplicate body name", 2,
        ["{file}:{line}: bodies.[1].name: duplicate body name 'plate' (bodies.[0] has it too)"],
        [ed('    constraints = ( { type = "fixed"; region = "clamp"; } );\n  }\n',
            '    constraints = ( { type = "fixed"; region = "clamp"; } );\n  },\n'
            '  { name = "plate"; material = "plate"; shape = "beam"; }\n')],
        marker='{ name = "plate"; material'),
    Row("a formulation that does not fit the material", 2,
        ['{file}:{line}: method.formulation: formulation "enog-a" is for elastic materials'],
        [ed("poisson_ratio = 0.3975;", "poisson_ratio = 0.3975; yield_stress = 1.0e5;")],
        marker="formulation ="),
    # --- TLSPH's hyperelastic laws and pairwise damping (device/tl_step.cl)
    Row("a hyperelastic model with an updated-Lagrangian formulation", 2,
        ["{file}:{line}: method.formulation: material 'plate' has a hyperelastic model",
         'formulation "enog-a" is hypoelastic'],
        [ed("poisson_ratio = 0.3975;", 'poisson_ratio = 0.3975; model = "neo-hookean";')],
        marker="formulation ="),
    Row("an unknown elastic model", 2,
        ['{file}:{line}: materials.plate.model: must be one of "saint-venant-kirchhoff", '
         '"neo-hookean", "exponential", got "mooney-rivlin"'],
        [ed("poisson_ratio = 0.3975;", 'poisson_ratio = 0.3975; model = "mooney-rivlin";')],
        marker="mooney-rivlin"),
    Row("exponential_b without the exponential model", 2,
        ['{file}:{line}: materials.plate.exponential_b: is the stiffening exponent of model '
         '"exponential"; material \'plate\' has model "neo-hookean"'],
        [ed("poisson_ratio = 0.3975;",
            'poisson_ratio = 0.3975; model = "neo-hookean"; exponential_b = 2.0;')],
        marker="exponential_b"),
    Row("exponential_b <= 0", 2,
        ["{file}:{line}: materials.plate.exponential_b: must be in (0, 100], got 0"],
        [ed("poisson_ratio = 0.3975;",
            'poisson_ratio = 0.3975; model = "exponential"; exponential_b = 0.0;')],
        marker="exponential_b"),
    Row("a hyperelastic model on a plastic material", 2,
        ["{file}:{line}: materials.plate.model: material 'plate' is J2-plastic",
         'model "neo-hookean" is for elastic materials'],
        [ed("poisson_ratio = 0.3975;",
            'poisson_ratio = 0.3975; yield_stress = 1.0e5; model = "neo-hookean";')],
        marker="yield_stress"),
    Row("pairwise damping outside TLSPH", 2,
        ['{file}:{line}: method.pairwise_damping: is the pairwise damping of "tlsph"',
         'formulation "enog-a" has none'],
        [ed('kernel = "wendland-c2";', 'kernel = "wendland-c2"; pairwise_damping = 0.25;')],
        marker="pairwise_damping"),
    # --- several materials: regions of a body (docs/scene-format.md, "Materials and regions")
    Row("a region of an undefined material", 2,
        ["{file}:{line}: bodies.plate.regions.[0].material: unknown material 'rubber'",
         "defined materials"],
        [ed('shape = "plate";',
            'shape = "plate"; regions = ( { shape = "base"; material = "rubber"; } );')],
        marker="rubber"),
    Row("a region that gives its material to no particle", 2,
        ["{file}:{line}: bodies.plate.regions.[0]: region 'far'",
         "gives material 'soft' to none of the", "particles of body 'plate'"],
        [ed("materials = {",
            "materials = {\n  soft = { density = 900.0; youngs_modulus = 1.0e6; "
            "poisson_ratio = 0.45; };"),
         ed("shapes = {",
            'shapes = {\n  far = { type = "box"; lower = [1.0, 1.0]; upper = [1.1, 1.1]; };'),
         ed('shape = "plate";',
            'shape = "plate"; regions = ( { shape = "far"; material = "soft"; } );')],
        marker="regions"),
    Row("several materials with TLSPH", 2,
        ["{file}:{line}: method.formulation: the bodies and regions of this scene use 2 "
         "materials ('plate', 'soft', ...)", 'formulation "tlsph" runs one material'],
        [ed('formulation = "enog-a";', 'formulation = "tlsph";'),
         ed('rotation = "averaged";', 'rotation = "none";'),
         ed("materials = {",
            "materials = {\n  soft = { density = 900.0; youngs_modulus = 1.0e6; "
            "poisson_ratio = 0.45; };"),
         ed('shape = "plate";',
            'shape = "plate"; regions = ( { shape = "base"; material = "soft"; } );')],
        marker='formulation = "tlsph"'),
    Row("a traction observer without its plane", 2,
        ["{file}:{line}: observers.tip.normal: "],
        [ed('{ name = "tip"; position = [0.2, 0.0]; }',
            '{ name = "tip"; position = [0.2, 0.0]; quantity = "traction"; }')],
        marker='quantity = "traction"'),
    Row("the wave analysis on a position observer", 2,
        ["{file}:{line}: analysis.wave.incident: observer 'tip' reports a position"],
        [ed('{ name = "tip"; position = [0.2, 0.0]; }',
            '{ name = "tip"; position = [0.2, 0.0]; },\n'
            '  { name = "mid"; position = [0.1, 0.0]; quantity = "traction"; '
            'normal = [1.0, 0.0]; }'),
         ed("analysis = {", 'analysis = {\n  wave = { incident = "tip"; transmitted = "mid"; };')],
        marker='incident = "tip"'),
    # --- fluids: the eulerian formulations (docs/scene-format.md, "Fluids")
    Row("fluid: an unphysical gamma below 1", 2,
        ["{file}:{line}: materials.water.gamma: an ideal gas has 1 < gamma <= 5/3", "got 0.9"],
        [ed("gamma = 1.4;", "gamma = 0.9;")], text=GAS_TEXT, marker="gamma = 0.9"),
    Row("fluid: an unphysical gamma above 5/3", 2,
        ["{file}:{line}: materials.water.gamma: an ideal gas has 1 < gamma <= 5/3", "got 2"],
        [ed("gamma = 1.4;", "gamma = 2.0;")], text=GAS_TEXT, marker="gamma = 2.0"),
    Row("fluid: a period that is not a whole number of dp", 2,
        ["{file}:{line}: boundary.upper: the period along x, upper - lower = 1.05, must be a "
         "whole number of particle spacings (dp = 0.1), got 10.5 dp"],
        [ed('"y"]; lower = [0.0, 0.0]; upper = [1.0, 1.0]',
            '"y"]; lower = [0.0, 0.0]; upper = [1.05, 1.0]')], text=FLUID_TEXT,
        marker="boundary = {"),
    Row("fluid: a period shorter than two cut-off radii", 2,
        ["{file}:{line}: boundary.upper: the period along y (0.5) is shorter than two cut-off "
         "radii (2 x 2.6 dp = 0.52): a particle would meet a neighbour through two images"],
        [ed('"y"]; lower = [0.0, 0.0]; upper = [1.0, 1.0]',
            '"y"]; lower = [0.0, 0.0]; upper = [1.0, 0.5]')], text=FLUID_TEXT,
        marker="boundary = {"),
    Row("fluid: the ideal gas without initial_pressure", 2,
        ["{file}:{line}: bodies.water.initial_pressure: missing required key: the ideal gas of "
         'formulation "eulerian-compressible" starts from a pressure'],
        [ed(" initial_pressure = 71.43;", "")], text=GAS_TEXT, marker='{ name = "water"'),
    Row("fluid: a negative initial density expression", 2,
        ['{file}:{line}: bodies.water.initial_density: the expression "1 - 2 * x" gives -0.1 at '
         "the particle at (0.55, 0.05) of body 'water': initial densities must be finite and > 0"],
        [ed('shape = "box"; }', 'shape = "box"; initial_density = "1 - 2 * x"; }')],
        text=FLUID_TEXT, marker="initial_density"),
    Row("fluid: a fluid material with a solid formulation", 2,
        ['{file}:{line}: materials.plate: a material without youngs_modulus is a fluid, which '
         'needs method.formulation "eulerian-wc" or "eulerian-compressible", got "enog-a"'],
        [ed("plate = { density = 1000.0; youngs_modulus = 2.0e6; poisson_ratio = 0.3975; };",
            "plate = { density = 1000.0; sound_speed = 1500.0; };")],
        marker="sound_speed = 1500.0"),
    # --- fluids: wall bodies, the far field, forces (the flow around a cylinder, seed 004 §4.3)
    Row("fluid: a wall body in a solid scene", 2,
        ['{file}:{line}: bodies.plate.role: is for the bodies of fluid scenes (formulations '
         '"eulerian-wc" and "eulerian-compressible"): a body there is matter or a wall; '
         'formulation "enog-a"'],
        [ed('    name = "plate";\n', '    name = "plate"; role = "wall";\n')],
        marker='role = "wall"'),
    Row("fluid: a supersonic far field of the gas", 2,
        ["{file}:{line}: boundary.far_field.velocity: the far field is a subsonic treatment: the "
         "free stream's Mach number |U_inf| / c_inf = 12 / 10.0001 = 1.19999 must be below 1"],
        [ed('boundary = { periodic = ["x", "y"];',
            'boundary = { periodic = ["x"];\n'
            '  far_field = { velocity = [12.0, 0.0]; pressure = 71.43; };')],
        text=GAS_TEXT, marker="far_field ="),
    Row("fluid: forces without a wall body", 2,
        ["{file}:{line}: forces: the forces are those the fluid exerts on the wall bodies, and "
         'the scene has none: give a body role = "wall"'],
        [ed("boundary = {", "forces = { reference_length = 1.0; reference_speed = 1.0; };\n"
            "boundary = {")], text=FLUID_TEXT, marker="forces ="),
    Row("fluid: a wall's spacing out of range", 2,
        ["{file}:{line}: bodies.cyl.spacing: the body's particle spacing over dp must be in "
         "(0, 1], got 1.5"],
        [ed('shape = "box"; }\n', 'shape = "box"; },\n'
            '  { name = "cyl"; role = "wall"; shape = "disc";\n    spacing = 1.5; }\n'),
         ed("};\nbodies", '  disc = { type = "disc"; centre = [0.5, 0.5]; radius = 0.2; };\n'
            "};\nbodies")],
        text=FLUID_TEXT, marker="spacing = 1.5"),
    Row("fluid: a relaxed fluid whose shape reaches into a wall body", 2,
        ["{file}:{line}: bodies.water: the body is relaxed (placement = \"relaxed\") within its "
         "shape 'box', which reaches into wall body 'cyl' ({file}:{line_b}: bodies.cyl) at "
         "(0.45, 0.35): the relaxation would move its particles into the wall; give the body its "
         "shape without the wall's"],
        [ed('shape = "box"; }\n', 'shape = "box"; placement = "relaxed"; },\n'
            '  { name = "cyl"; role = "wall"; shape = "disc"; }\n'),
         ed("};\nbodies", '  disc = { type = "disc"; centre = [0.5, 0.5]; radius = 0.2; };\n'
            "};\nbodies"),
         ed('periodic = ["x", "y"];', 'far_field = { velocity = [1.0, 0.0]; };')],
        text=FLUID_TEXT, marker='name = "water"', marker_b='name = "cyl"'),
    # --- missing required keys
    Row("missing required key: a material's density", 2,
        ["{file}:{line}: materials.plate.density: missing required key"],
        [ed("density = 1000.0; ", "")], marker="plate = { youngs_modulus"),
    Row("missing required key: a body's shape", 2,
        ["{file}:{line}: bodies.plate.shape: missing required key"],
        [ed('    shape = "plate";\n', "")], marker='name = "plate";', offset=-1),
    Row("missing required key: time.end", 2, ["{file}:{line}: time.end: missing required key"],
        [ed("  end = 1.0;\n", "")], marker="time = {"),
    Row("missing required key: method.formulation", 2,
        ["{file}:{line}: method.formulation: missing required key"],
        [ed('  formulation = "enog-a";    # "enog" | "enog-a"\n', "")], marker="method = {"),
    Row("missing required top-level key (no line to name)", 2,
        ["{file}: dimension: missing required key"], [ed("dimension = 2;", "")], located=False),
    # --- geometry checked when the particles are placed
    Row("observer outside every body, inside the domain", 2,
        ["{file}:{line}: observers.tip.position: (0.1, 0.028) is outside every body",
         "place the observer inside a body"],
        [ed("position = [0.2, 0.0]", "position = [0.1, 0.028]")], marker="position = [0.1"),
    Row("observer outside the domain", 2,
        ["{file}:{line}: observers.tip.position: (5, 5) is outside every body"],
        [ed("position = [0.2, 0.0]", "position = [5.0, 5.0]")], marker="position = [5.0"),
    Row("overlapping bodies", 2,
        ["{file}:{line}: bodies.plate: overlaps body 'b' ({file}:{line_b}: bodies.b)",
         "shape 'plate' and shape 'base' both contain the point",
         "bodies may touch but must not overlap"],
        [ed("bodies = (\n  {\n",
            'bodies = (\n  { name = "b"; material = "plate"; shape = "base"; },\n  {\n')],
        marker='{ name = "b"', offset=1, marker_b='{ name = "b"'),
    Row("overlapping bodies: one inside the other", 2,
        ["{file}:{line}: bodies.inner: overlaps body 'plate' ({file}:{line_b}: bodies.plate)",
         "shape 'beam' and shape 'plate' both contain the point"],
        [ed('    constraints = ( { type = "fixed"; region = "clamp"; } );\n  }\n',
            '    constraints = ( { type = "fixed"; region = "clamp"; } );\n  },\n'
            '  { name = "inner"; material = "plate"; shape = "beam"; }\n')],
        marker='{ name = "inner"', marker_b="bodies = (", offset_b=1),
    Row("a body without particles (thinner than dp)", 2,
        ["{file}:{line}: bodies.sliver: the body has no particles"],
        [ed("  clamp = {", '  sliver = { type = "box"; lower = [0.5, 0.0]; upper = [0.5001, 0.01]; };'
            "\n  clamp = {"),
         ed('    constraints = ( { type = "fixed"; region = "clamp"; } );\n  }\n',
            '    constraints = ( { type = "fixed"; region = "clamp"; } );\n  },\n'
            '  { name = "sliver"; material = "plate"; shape = "sliver"; }\n')],
        marker='{ name = "sliver"'),
    # --- rigid walls (device/sph_wall.h)
    Row("a wall that cuts a body", 2,
        ["{file}:{line}: walls.floor: wall 'floor' cuts body 'plate' ({file}:{line_b}: "
         "bodies.plate)", "less than dp/2 = 0.001 in front of it",
         "a body may touch a wall but not cross it"],
        [ed("analysis = {", 'walls = ( { name = "floor"; point = [0.0, 0.0]; '
            'normal = [0.0, 1.0]; } );\nanalysis = {')],
        marker='walls = (', marker_b='name = "plate";', offset_b=-1),
    Row("a wall with a zero normal", 2,
        ["{file}:{line}: walls.floor.normal: must be a non-zero vector"],
        [ed("analysis = {", 'walls = ( { name = "floor"; point = [0.0, -0.5]; '
            'normal = [0.0, 0.0]; } );\nanalysis = {')], marker='walls = ('),
    Row("torque projection with a formulation that has none", 2,
        ['{file}:{line}: method.torque_projection: only formulation "enog-a" with rotation '
         '"averaged" has it, got formulation "gnog-a" with rotation "averaged"'],
        [ed('  formulation = "enog-a";', '  formulation = "gnog-a";'),
         ed('  rotation = "averaged";', '  rotation = "averaged";\n  torque_projection = true;')],
        marker="torque_projection"),
    Row("torque projection on a clamped body", 2,
        ["{file}: method.torque_projection keeps the net torque of free bodies; this scene "
         "constrains", "particles (clamp, rollers or a driven region), so leave it false"],
        [ed('  rotation = "averaged";', '  rotation = "averaged";\n  torque_projection = true;')],
        located=False),
    Row("wrong type: a string for the torque projection", 2,
        ['{file}:{line}: method.torque_projection: expected a boolean (true or false), '
         'got a string'],
        [ed('  rotation = "averaged";', '  rotation = "averaged";\n  torque_projection = "yes";')],
        marker="torque_projection"),
    Row("walls with TLSPH", 2,
        ["{file}:{line}: method.formulation: \"tlsph\" has no wall contact"],
        [ed('  formulation = "enog-a";', '  formulation = "tlsph";'),
         ed('  rotation = "averaged";', '  rotation = "none";'),
         ed("analysis = {", 'walls = ( { name = "floor"; point = [0.0, -0.5]; '
            'normal = [0.0, 1.0]; } );\nanalysis = {')], marker='formulation = "tlsph"'),
    Row("--set: a 3D velocity field in 2D", 2,
        ['--set bodies.plate.initial_velocity.type="plate_mode": '
         'bodies.plate.initial_velocity.type: "plate_mode" is a 3D velocity field'],
        argv=["run", PLATE, "--quiet", "--set",
              'bodies.plate.initial_velocity.type="plate_mode"']),
    # --- overrides: the message names the override
    Row("--set: a value out of range", 2,
        ["--set materials.plate.poisson_ratio=0.7: materials.plate.poisson_ratio: "
         "must be in [0, 0.5), got 0.7"],
        argv=["run", PLATE, "--quiet", "--set", "materials.plate.poisson_ratio=0.7"]),
    Row("--set: a string for a number", 2,
        ["--set time.end=abc: time.end: expected a number, got a string"],
        argv=["run", PLATE, "--quiet", "--set", "time.end=abc"]),
    Row("--set: an unknown key", 2,
        ["--set time.ende=1: time.ende: unknown key 'ende' (did you mean 'end'?)"],
        argv=["run", PLATE, "--quiet", "--set", "time.ende=1"]),
    Row("--set: a missing parent", 2,
        ["--set solver.threads=4: solver: no such setting in the scene"],
        argv=["run", PLATE, "--quiet", "--set", "solver.threads=4"]),
    Row("--set: no '='", 2, ["--set time.end: expected key=value"],
        argv=["run", PLATE, "--quiet", "--set", "time.end"]),
    Row("--set: empty key", 2, ["--set =1: expected key=value, the key is empty"],
        argv=["run", PLATE, "--quiet", "--set", "=1"]),
    Row("--set: empty path component", 2, ["--set time..end=1: the key has an empty component"],
        argv=["run", PLATE, "--quiet", "--set", "time..end=1"]),
    Row("--set: a value that does not parse", 2,
        ["--set gravity=[0.0, : cannot parse the value"],
        argv=["run", PLATE, "--quiet", "--set", "gravity=[0.0, "]),
    Row("--set: an unknown output field", 2,
        ["output.fields.[1]: unknown output field 'presure' (did you mean 'pressure'?)"],
        argv=["run", PLATE, "--quiet", "--set", 'output.fields=["velocity", "presure"]']),
    Row("--set: an observer moved outside every body", 2,
        ["--set observers.tip.position=[0.5, 0.3]: observers.tip.position: (0.5, 0.3) is "
         "outside every body"],
        argv=["run", PLATE, "--quiet", "--set", "observers.tip.position=[0.5, 0.3]"]),
    # --- command line (exit 2: bad input)
    Row("unknown flag", 2, ["unknown option --frobnicate"],
        argv=["run", PLATE, "--quiet", "--frobnicate"]),
    Row("flag missing its value", 2, ["--out needs a value"], argv=["run", PLATE, "--out"]),
    Row("--set missing its value", 2, ["--set needs a value"], argv=["run", PLATE, "--set"]),
    Row("bad numeric value: not a number", 2,
        ["--checkpoint-every abc: expected a positive number of seconds"],
        argv=["run", PLATE, "--checkpoint-every", "abc"]),
    Row("bad numeric value: negative", 2,
        ["--checkpoint-wall -5: expected a positive number of seconds"],
        argv=["run", PLATE, "--checkpoint-wall", "-5"]),
    Row("bad numeric value: zero", 2,
        ["--progress-interval 0: expected a positive number of seconds"],
        argv=["run", PLATE, "--progress-interval", "0"]),
    Row("bad numeric value: device", 2, ["--device x: expected a device number"],
        argv=["run", PLATE, "--device", "x"]),
    Row("bad backend name", 2, ["--backend gpu: expected opencl or cpu"],
        argv=["run", PLATE, "--backend", "gpu"]),
    Row("bad precision", 2, ["--precision half: expected double, single or mixed"],
        argv=["run", PLATE, "--precision", "half"]),
    Row("bad pair geometry", 2,
        ["--pair-geometry cached: expected auto, stored or recomputed"],
        argv=["run", PLATE, "--pair-geometry", "cached"]),
    Row("--device with --backend cpu", 2, ["--device selects an OpenCL device"],
        argv=["run", PLATE, "--backend", "cpu", "--device", "0"]),
    Row("missing scene file", 2, ["missing.cfg: cannot read scene file: No such file or directory"],
        argv=["run", "missing.cfg", "--quiet"]),
    Row("scene file is a directory", 2, ["{dir}: cannot read scene file: Is a directory"],
        argv=["run", "{dir}", "--quiet"]),
    Row("no scene file", 2, ["run needs a scene file"], argv=["run"]),
    Row("two scene files", 2, ["unexpected argument"], argv=["run", PLATE, PLATE]),
    Row("unknown command", 2, ["unknown command 'launch'"], argv=["launch"]),
    Row("no command", 2, ["usage: sphsolid run SCENE"], argv=[]),
    Row("--restart with a scene file", 2, ["give no scene file"],
        argv=["run", PLATE, "--restart", "{dir}"]),
    Row("--restart of a directory without a checkpoint", 2,
        ["cannot read {dir}/checkpoint/checkpoint.h5: No such file or directory"],
        argv=["run", "--restart", "{dir}", "--quiet"]),
    Row("--restart changing the physics", 2, ["a restart may change only time.end and output.*"],
        argv=["run", "--restart", "{dir}", "--set", "method.formulation=og"]),
    Row("compare: missing run directories", 2, ["run directory nope_a: No such file or directory"],
        argv=["compare", "nope_a", "nope_b"]),
    # --- runtime failures (exit 1): devices, memory, output
    Row("--backend opencl without an OpenCL device", 1, ["no OpenCL device found"],
        args=FAST + ["--backend", "opencl"],
        env={"OCL_ICD_VENDORS": "{dir}/no-vendors", "OPENCL_VENDOR_PATH": "{dir}/no-vendors"}),
    Row("particle count beyond the memory (resolution.ratio = 1e5)", 1,
        ["at dp = 2e-07 the shape of body 'plate' spans about 1.3e+11 lattice points",
         "need at least", "TiB of memory", "physical memory", "lower the resolution"],
        args=["--set", "resolution.ratio=1e5"]),
    Row("particle arrays beyond the process's memory limit", 1,
        ["particles at dp = ", "need", "for their initial arrays alone, but this process may "
         "use 64.0 MiB (its data-size limit, ulimit -d", "lower the resolution"],
        args=["--set", "resolution.ratio=600"], data_limit=64 << 20),
    Row("native backend beyond the process's memory limit", 1,
        ["the native backend needs", "of neighbour lists",
         "but this process may use 512.0 MiB (its data-size limit, ulimit -d"],
        args=["--set", "resolution.ratio=300"], data_limit=512 << 20),
    Row("output directory below a regular file", 1,
        ["cannot create output directory {dir}/file/out: Not a directory"],
        args=FAST, fs="below-file"),
    # --- relaxed placement (bodies[i].placement = "relaxed", docs/scene-format.md)
    Row("unknown key: a relaxation setting", 2,
        ["{file}:{line}: bodies.plate.relaxation.stpes: unknown key 'stpes' "
         "(did you mean 'steps'?)"],
        [ed('material = "plate";',
            'material = "plate"; placement = "relaxed"; relaxation = { stpes = 10; };')],
        marker="stpes"),
    Row("relaxation file in a missing directory", 1,
        ["{file}:{line}: bodies.plate: saving the relaxed particles: cannot write",
         "no-such-dir/plate.h5.partial: No such file or directory"],
        [ed('material = "plate";', 'material = "plate"; placement = "relaxed"; '
            'relaxation = { steps = 2; file = "no-such-dir/plate.h5"; };')],
        marker="name = \"plate\"", offset=-1, args=FAST),
    Row("output directory on a read-only filesystem", 1,
        ["cannot create output directory {out}: Read-only file system"], args=FAST,
        fs="read-only"),
    Row("disk full: the time series", 1,
        ["cannot write {out}/timeseries.csv.partial: No space left on device"],
        args=FAST + NO_LIMIT, fs=("full", 0, "timeseries.csv")),
    Row("disk full: the first snapshot", 1,
        ["cannot write {out}/snapshots/snapshot_000000.hdf.partial: No space left on device"],
        args=FAST + NO_LIMIT, fs=("full", 8192, "snapshot_000000")),
    Row("disk full: a later snapshot (the completed one is marked .partial)", 1,
        ["cannot write {out}/snapshots/snapshot_000001.hdf.partial: No space left on device"],
        args=FAST + NO_LIMIT, fs=("full", "one-snapshot", "snapshot_000001")),
    Row("disk full: summary.json (timeseries.csv is marked .partial again)", 1,
        ["cannot write {out}/summary.json.partial: No space left on device"],
        args=FAST + ["--set", "output.snapshot_interval=0"], fs=("full", 4096, "summary.json")),
    # --- issue 34, runaway work: checkpoints, progress, predicted work and output volume
    #     (refused before the run, host/setup/work_estimate.h; the old binary ran these for
    #     hours, hence within(); checkpoint intervals below the step:
    #     tests/test_restart.py; progress inside a long advection step and
    #     --no-work-limit: tests/test_output.py)
    within(20, Row("acoustic CFL 1e-300: about 1e302 substeps", 2,
                   ["--set time.cfl_acoustic=1e-300: time.cfl_acoustic: the run would take about "
                    "9.2e+301 acoustic substeps of", "for 0.01 s of simulated time, beyond 1e+09 "
                    "substeps", "or run it anyway with --no-work-limit"],
                   args=FAST + ["--set", "time.cfl_acoustic=1e-300", "--progress-interval", "3"])),
    within(20, Row("end time 1e6 s: 2e10 substeps of an ordinary scene", 2,
                   ["--set time.end=1e6: time.end: the run would take about 2.3e+10 acoustic "
                    "substeps of 4.35e-05 s"],
                   args=FAST + ["--set", "time.end=1e6", "--set", "time.output_interval=1e4",
                                "--set", "output.snapshot_interval=0"])),
    within(20, Row("outputs every 1e-9 s for 1e6 s: exabytes against the free disk", 2,
                   ["--set time.output_interval=1e-9: time.output_interval: the run would write "
                    "about 4.8 EiB (1e+14 snapshots of about 52.8 KiB every 1e-08 s, and a row "
                    "of timeseries.csv at each of 1e+15 output times 1e-09 s apart) to {out}, "
                    "whose filesystem has",
                    "write less often (time.output_interval, output.snapshot_interval)"],
                   args=FAST + ["--set", "time.end=1e6", "--set", "time.output_interval=1e-9"])),
    Row("snapshots beyond the free disk (SPHSOLID_TEST_FREE_BYTES = 1e6)", 2,
        ["--set output.snapshot_interval=1e-4: output.snapshot_interval: the run would write "
         "about 5.2 MiB (101 snapshots of about 52.8 KiB every 0.0001 s, and a row of "
         "timeseries.csv at each of 100 output times 0.0001 s apart) to {out}, whose filesystem "
         "has 976.6 KiB free"],
        args=FAST + ["--set", "time.output_interval=1e-4", "--set",
                     "output.snapshot_interval=1e-4"],
        env={"SPHSOLID_TEST_FREE_BYTES": "1e6"}),
    within(20, Row("Poisson's ratio 0.49999999999: c0 = 5.8e6 m/s", 2,
                   ["{file}:{line}: materials.plate.poisson_ratio: density 1000, youngs_modulus "
                    "2e+06 and poisson_ratio 0.49999999999 give the sound speed c0 = sqrt(E / "
                    "(3 (1 - 2 nu) rho0)) = 5.774e+06 m/s", "beyond 1e+05 m/s, faster than sound "
                    "in any solid", "about 2.33e+07 acoustic substeps"],
                   [ed("poisson_ratio = 0.3975", "poisson_ratio = 0.49999999999")],
                   marker="poisson_ratio", args=FAST)),
    within(20, Row("Young's modulus 1e300: c0 = 4e148 m/s", 2,
                   ["{file}:{line}: materials.plate.youngs_modulus: density 1000, youngs_modulus "
                    "1e+300 and poisson_ratio 0.3975 give the sound speed", "= 4.032e+148 m/s",
                    "about 1.63e+149 acoustic substeps"],
                   [ed("youngs_modulus = 2.0e6", "youngs_modulus = 1e300")],
                   marker="youngs_modulus", args=FAST)),
    within(20, Row("density 1e-300: c0 = 2e153 m/s", 2,
                   ["--set materials.plate.density=1e-300: materials.plate.density: density "
                    "1e-300,", "= 1.803e+153 m/s", "acoustic substeps"],
                   args=FAST + ["--set", "materials.plate.density=1e-300"])),
    # --- issue 34, names in CSV and JSON: names are a letter, then letters,
    #     digits, '_' or '-' (docs/scene-format.md, "Names"); free text
    #     (title, scene path, overrides) of any bytes: free_text_bytes_run
    Row("observer name with a comma (a timeseries.csv column)", 2,
        ["{file}:{line}: observers.[0].name: a name cannot contain ','"],
        [ed('name = "tip"', 'name = "ti,p"'), ed('observer = "tip"', 'observer = "ti,p"')],
        marker='name = "ti,p"'),
    Row("observer name with a newline", 2,
        ["{file}:{line}: observers.[0].name: a name cannot contain \\x0A"],
        [ed('name = "tip"', 'name = "ti\\np"'), ed('observer = "tip"', 'observer = "ti\\np"')],
        marker='name = "ti'),
    Row("observer name with a quote", 2,
        ["{file}:{line}: observers.[0].name: a name cannot contain '\"'"],
        [ed('name = "tip"', 'name = "ti\\"p"'), ed('observer = "tip"', 'observer = "ti\\"p"')],
        marker='name = "ti'),
    Row("observer name whose columns repeat momentum_x, momentum_y", 2,
        ["{file}:{line}: observers.momentum.name: 'momentum' is reserved"],
        [ed('name = "tip"', 'name = "momentum"'), ed('observer = "tip"', 'observer = "momentum"')],
        marker='name = "momentum"'),
    Row("observer name with a byte that is not UTF-8", 2,
        ["{file}:{line}: observers.[0].name: a name cannot contain \\xFF"],
        [ed('name = "tip"', 'name = "ti\\xffp"'), ed('observer = "tip"', 'observer = "ti\\xffp"')],
        marker='name = "ti'),
    Row("body name with a byte that is not UTF-8", 2,
        ["{file}:{line}: bodies.[0].name: a name cannot contain \\xC3"],
        [ed('name = "plate"', 'name = "pl\\xc3\\x28te"')], marker='name = "pl'),
    Row("body name with a space", 2,
        ["{file}:{line}: bodies.[0].name: a name cannot contain \\x20"],
        [ed('name = "plate"', 'name = "the plate"')], marker='name = "the plate"'),
    Row("body name starting with a digit", 2,
        ["{file}:{line}: bodies.1plate.name: a name cannot start with '1'"],
        [ed('name = "plate"', 'name = "1plate"')], marker='name = "1plate"'),
    # --- issue 34, scene values: empty constraint regions, 64-bit integers, monitor domain,
    #     absurd materials
    Row("a constraint region that holds no particle", 2,
        ["{file}:{line}: bodies.plate.constraints.[0].region: region 'clamp' (within (1, 1) to "
         "(2, 2)) holds none of the 352 particles of body 'plate'",
         "so the constraint would do nothing"],
        [ed('clamp = { type = "difference"; parts = ["base", "beam"]; };',
            'clamp = { type = "box"; lower = [1.0, 1.0]; upper = [2.0, 2.0]; };')],
        marker='region = "clamp"', args=FAST),
    Row("a constraint region that holds no particle, relaxed placement", 2,
        ["{file}:{line}: bodies.plate.constraints.[0].region: region 'clamp'",
         "holds none of the 352 particles of body 'plate'"],
        [ed('clamp = { type = "difference"; parts = ["base", "beam"]; };',
            'clamp = { type = "box"; lower = [1.0, 1.0]; upper = [2.0, 2.0]; };'),
         ed('material = "plate";',
            'material = "plate"; placement = "relaxed"; relaxation = { steps = 20; };')],
        marker='region = "clamp"', args=FAST),
    Row("a driven region that holds no particle", 2,
        ["{file}:{line}: bodies.plate.constraints.[1].region: region 'grip' (within (0.3, -0.01) "
         "to (0.4, 0.01)) holds none of the 352 particles of body 'plate'"],
        [ed("  clamp = {", '  grip = { type = "box"; lower = [0.3, -0.01]; upper = [0.4, 0.01]; };'
            "\n  clamp = {"),
         ed('constraints = ( { type = "fixed"; region = "clamp"; } );',
            'constraints = ( { type = "fixed"; region = "clamp"; },\n'
            '      { type = "velocity"; region = "grip"; velocity = [0.0, 1.0]; } );')],
        marker='region = "grip"', args=FAST),
    Row("a constraint whose particles all take an earlier one", 2,
        ["{file}:{line}: bodies.plate.constraints.[1].region: every one of the 144 particles of "
         "body 'plate' in region 'clamp' takes an earlier constraint",
         "constraint [0], region 'clamp'"],
        [ed('constraints = ( { type = "fixed"; region = "clamp"; } );',
            'constraints = ( { type = "fixed"; region = "clamp"; },\n'
            '      { type = "fixed_axes"; region = "clamp"; axes = ["y"]; } );')],
        marker='type = "fixed_axes"', args=FAST),
    Row("an integer beyond 32 bits: dimension", 2,
        ["{file}:{line}: dimension: must be 1, 2 or 3, got 4294967298"],
        [ed("dimension = 2;", "dimension = 4294967298;")], marker="dimension =", args=FAST),
    Row("--set: an integer beyond 32 bits", 2,
        ["--set dimension=4294967298: dimension: must be 1, 2 or 3, got 4294967298"],
        argv=["run", PLATE, "--backend", "cpu", "--quiet", "--out", "{dir}/out"] + FAST +
        ["--set", "dimension=4294967298"]),
    Row("an integer beyond 32 bits: relaxation steps", 2,
        ["{file}:{line}: bodies.plate.relaxation.steps: must be in [0, 1000000], got 4294967297"],
        [ed('material = "plate";', 'material = "plate"; placement = "relaxed";\n'
            '    relaxation = { steps = 4294967297; };')], marker="steps = 4294967297", args=FAST),
    Row("an integer below -2^31: relaxation seed", 2,
        ["{file}:{line}: bodies.plate.relaxation.seed: must be >= 0, got -2147483649"],
        [ed('material = "plate";', 'material = "plate"; placement = "relaxed";\n'
            '    relaxation = { steps = 20; seed = -2147483649; };')], marker="seed =", args=FAST),
    Row("an integer beyond 64 bits: relaxation seed", 2,
        ["{file}:{line}: bodies.plate.relaxation.seed: expected a 64-bit integer "
         "(-9223372036854775808 to 18446744073709551615), got 1.8446744073709552e+19"],
        [ed('material = "plate";', 'material = "plate"; placement = "relaxed";\n'
            '    relaxation = { steps = 20; seed = 18446744073709551616; };')],
        marker="seed =", args=FAST),
    Row("an integer beyond 32 bits where a number is expected", 2,
        ["{file}:{line}: materials.plate.poisson_ratio: must be in [0, 0.5), got 4.29497e+09"],
        [ed("poisson_ratio = 0.3975;", "poisson_ratio = 4294967296;")], marker="poisson_ratio",
        args=FAST),
    Row("--set: a list index beyond 32 bits", 2,
        ["--set bodies.[4294967296].material=plate: bodies.[4294967296]: no such setting"],
        argv=["run", PLATE, "--backend", "cpu", "--quiet", "--out", "{dir}/out"] + FAST +
        ["--set", "bodies.[4294967296].material=plate"]),
    Row("monitor.domain that does not contain the body", 2,
        ["{file}:{line}: monitor.domain: 80 of the 352 particles of body 'plate' ({file}:{line_b}: "
         "bodies.plate) start outside the domain (-0.1, -0.1) to (0.1, 0.1)",
         "the body's particles span (-0.0775, -0.0275) to (0.1975, 0.0275)"],
        [ed("analysis = {", "monitor = {\n  domain = { lower = [-0.1, -0.1]; upper = [0.1, 0.1]; };"
            "\n};\nanalysis = {")],
        marker="domain = {", marker_b='name = "plate";', offset_b=-1, args=FAST),
    # --- issue 34, restart and the output directory
    #     (two runs into one --out: busy_output_directory below; an end before
    #     the checkpoint, checkpoints after a restart: tests/test_restart.py)
    # --- initial fields as expressions (host/setup/expression.c, issue 30 item 4)
    Row("expression: unknown variable", 2,
        ["{file}:{line}: bodies.plate.initial_velocity.y: the expression \"0.1 * q\": unknown "
         "variable 'q' (variables: x, y)"],
        [ed(CANTILEVER, 'initial_velocity = { type = "expression";\n'
            '      y = "0.1 * q"; };')], marker='y = "0.1 * q"', args=FAST),
    Row("expression: syntax error", 2,
        ["{file}:{line}: bodies.plate.initial_velocity.y: the expression \"0.1 * sin(x\": "
         "Missing parenthesis"],
        [ed(CANTILEVER, 'initial_velocity = { type = "expression";\n'
            '      y = "0.1 * sin(x"; };')], marker='y = "0.1 * sin(x"', args=FAST),
    Row("expression: not finite at a particle", 2,
        ["{file}:{line}: bodies.plate.initial_velocity.y: the expression "
         "\"x > 0.19 ? 1 / (x - x) : 0\" gives inf at the particle at (0.1925, -0.0075)",
         "of body 'plate': initial velocities must be finite"],
        [ed(CANTILEVER, 'initial_velocity = { type = "expression";\n'
            '      y = "x > 0.19 ? 1 / (x - x) : 0"; };')], marker='y = "x > 0.19', args=FAST),
    Row("constants: the name of a function", 2,
        ["{file}:{line}: constants.exp: 'exp' is a function or constant of the expressions "
         "already"],
        [ed("dimension = 2;", "dimension = 2;\nconstants = { exp = 1.0; };")],
        marker="constants = {", args=FAST),
    Row("--set: an expression that does not parse", 2,
        # (braces doubled: fragments and argv go through str.format)
        ['--set bodies.plate.initial_velocity={{ type = "expression"; y = "sin("; }}: '
         'bodies.plate.initial_velocity.y: the expression "sin(": Unexpected end of expression'],
        argv=["run", PLATE, "--backend", "cpu", "--quiet", "--out", "{dir}/out"] + FAST +
        ["--set", 'bodies.plate.initial_velocity={{ type = "expression"; y = "sin("; }}']),
]


# ---------------------------------------------------------------- machinery
def line_of(text, needle):
    for k, line in enumerate(text.splitlines(), 1):
        if needle in line:
            return k
    raise AssertionError("marker %r not in the scene" % needle)


def complete_looking(root):
    """Files under root that look like a complete result."""
    found = []
    for d, _, files in os.walk(root):
        for f in files:
            if f in RESULTS or (os.path.basename(d) == "snapshots" and f.endswith(".hdf")):
                found.append(os.path.join(d, f))
    return found


class Mount:
    """A tmpfs of `size` bytes at `path` (read-only, or with `free` bytes
    left); `ok` is False where this process may not mount."""

    def __init__(self, path, size, free=None, ro=False):
        self.path, self.ok = path, False
        os.makedirs(path)
        opts = "size=%d" % size + (",ro" if ro else "")
        try:
            p = subprocess.run(["mount", "-t", "tmpfs", "-o", opts, "tmpfs", path],
                               capture_output=True, text=True)
            self.ok = p.returncode == 0
        except OSError:  # no mount(8)
            self.ok = False
        if self.ok and free is not None:
            with open(os.path.join(path, "filler"), "wb") as f:
                f.write(b"\0" * (size - free))

    def close(self):
        if self.ok:
            subprocess.run(["umount", self.path], check=False)
            self.ok = False


SNAPSHOT_BYTES = []  # size of the plate's first snapshot at FAST settings


def snapshot_bytes(tmp):
    if not SNAPSHOT_BYTES:
        out = os.path.join(tmp, "measure")
        p = subprocess.run([BIN, "run", PLATE, "--backend", "cpu", "--quiet", "--out", out] + FAST,
                           capture_output=True, text=True, timeout=300)
        assert p.returncode == 0, p.stderr
        SNAPSHOT_BYTES.append(os.path.getsize(os.path.join(out, "snapshots",
                                                           "snapshot_000000.hdf")))
        shutil.rmtree(out)
    return SNAPSHOT_BYTES[0]


# AddressSanitizer reserves terabytes of shadow memory at start: a process
# under a data-size limit cannot even start (the release build runs those rows)
with open(BIN, "rb") as f:
    SANITIZED = b"__asan_init" in f.read()


def run_row(k, row, tmp, paths_used):
    if row.data_limit and SANITIZED:
        print("  %-66s (skipped under AddressSanitizer)" % row.what[:66])
        return
    d = os.path.join(tmp, "row%03d" % k)
    os.makedirs(d)
    out = os.path.join(d, "out")
    mount = None
    env = dict(os.environ)
    for key, value in row.env.items():
        env[key] = value.format(dir=d)
        if "no-vendors" in value:
            os.makedirs(env[key], exist_ok=True)
    if row.fs == "below-file":
        open(os.path.join(d, "file"), "w").close()
        out = os.path.join(d, "file", "out")
    elif row.fs == "read-only":
        mount = Mount(os.path.join(d, "ro"), 65536, ro=True)
        if not mount.ok:
            print("  (skipped: this process may not mount a read-only tmpfs; the row 'below a "
                  "regular file' covers an unwritable output directory)")
            return
        out = os.path.join(d, "ro", "out")
    elif isinstance(row.fs, tuple):
        _, free, inject = row.fs
        if free == "one-snapshot":
            # the time series, the first snapshot and its index fit, the second does not
            free = 4096 * (3 + (snapshot_bytes(tmp) + 4095) // 4096)
        mount = Mount(os.path.join(d, "small"), 262144, free=free)
        if mount.ok:
            out = os.path.join(d, "small", "out")
            paths_used.add("tmpfs")
        else:
            env["SPHSOLID_TEST_DISK_FULL"] = inject
            paths_used.add("fault injection")

    text = None
    if row.text is not None or row.edits:
        text = row.text if row.text is not None else PLATE_TEXT
        for old, new in row.edits:
            assert old in text, (row.what, old)
            text = text.replace(old, new, 1)
        with open(os.path.join(d, SCENE), "w") as f:
            f.write(text)
    if row.argv is not None:
        argv = [a.format(dir=d) for a in row.argv]
    else:
        argv = ["run", SCENE if text is not None else PLATE, "--backend", "cpu", "--quiet",
                "--out", out] + [a.format(dir=d) for a in row.args]
        if "--backend" in row.args:  # the row chooses the backend
            argv = argv[:2] + argv[4:]

    def limit():
        if row.data_limit:
            resource.setrlimit(resource.RLIMIT_DATA, (row.data_limit, row.data_limit))

    try:
        # errors="replace": a message may quote bytes of the scene that are not UTF-8
        seconds = getattr(row, "timeout", 300)
        try:
            p = subprocess.run([BIN] + argv, cwd=d, env=env, capture_output=True, text=True,
                               errors="replace", timeout=seconds,
                               preexec_fn=limit if row.data_limit else None)
        except subprocess.TimeoutExpired:
            check(False, "%s: still running after %d s" % (row.what, seconds))
            return
        err = p.stderr.strip()
        what = "%s: %s" % (row.what, err or "(no message)")
        fmt = {"file": SCENE, "out": out, "dir": d}
        if text is not None and row.marker:
            fmt["line"] = line_of(text, row.marker) + row.offset
        if text is not None and row.marker_b:
            fmt["line_b"] = line_of(text, row.marker_b) + row.offset_b
        check(p.returncode == row.code,
              "%s: exit status %d, expected %d" % (what, p.returncode, row.code))
        for frag in row.fragments:
            frag = frag.format(**fmt)
            check(frag in err, "%s\n    expected: %s" % (what, frag))
        first = err.splitlines()[0] if err else ""
        if row.located:
            check(re.match(r"sphsolid: %s:\d+: (syntax error|[\w.\[\]-]+: )" % re.escape(SCENE),
                           first),
                  "%s: the message names no file, line and key" % what)
        if row.code == 1:
            check(len(err.splitlines()) == 1 and first.startswith("sphsolid: "),
                  "%s: not one line" % what)
        roots = [d] + ([out] if not out.startswith(d) else [])
        for r in roots:
            left = complete_looking(r)
            check(not left, "%s: complete-looking results left: %s" % (row.what, left))
        if row.fs and isinstance(row.fs, tuple) and row.fs[1] == "one-snapshot":
            check(os.path.exists(os.path.join(out, "snapshots", "snapshot_000000.hdf.partial")),
                  "%s: the completed snapshot is kept as .partial" % row.what)
        print("  %-66s %d  %s" % (row.what[:66], p.returncode, first[:110]))
    finally:
        if mount:
            mount.close()


def touching_bodies_run(tmp):
    """Control: two bodies that touch (not overlap) are accepted and run."""
    text = PLATE_TEXT.replace(
        '  plate = { type = "union"; parts = ["beam", "base"]; };',
        '  plate = { type = "union"; parts = ["beam", "base"]; };\n'
        '  free_part = { type = "box"; lower = [0.2, -0.01]; upper = [0.24, 0.01]; };')
    text = text.replace(
        '    constraints = ( { type = "fixed"; region = "clamp"; } );\n  }\n',
        '    constraints = ( { type = "fixed"; region = "clamp"; } );\n  },\n'
        '  { name = "extension"; material = "plate"; shape = "free_part"; }\n')
    d = os.path.join(tmp, "touching")
    os.makedirs(d)
    with open(os.path.join(d, SCENE), "w") as f:
        f.write(text)
    # the extension starts at rest next to the moving plate: the zigzag
    # monitor would stop that at once, and this is about the geometry
    p = subprocess.run([BIN, "run", SCENE, "--backend", "cpu", "--quiet", "--out", "out",
                        "--set", "monitor.action=off"] + FAST,
                       cwd=d, capture_output=True, text=True, timeout=300)
    check(p.returncode == 0, "two touching bodies run: exit %d: %s" % (p.returncode, p.stderr))
    check(os.path.exists(os.path.join(d, "out", "summary.json")), "touching bodies: summary")


def strict_utf8_json(path):
    """The file's JSON, or None when it is not valid UTF-8 JSON (the check
    counts that as a failure, so an old binary fails instead of crashing)."""
    try:
        with open(path, "rb") as f:
            return json.loads(f.read().decode("utf-8", "strict"))
    except (OSError, ValueError) as e:  # UnicodeDecodeError is a ValueError
        print("  %s: %s" % (path, e))
        return None


def free_text_bytes_run(tmp):
    """Issue 34, item 5: bytes that are not UTF-8 (a stray byte, a surrogate,
    a cut sequence, an overlong '/') in the title, the scene path and an
    override: the run completes, summary.json is valid UTF-8 JSON with each
    ill-formed subsequence as U+FFFD (what bytes.decode("utf-8", "replace")
    gives, docs/output-format.md), and `sphsolid compare` reads the run."""
    d = os.path.join(tmp, "free-text")
    os.makedirs(d)
    title = b"bad \xff\xfe title, \xed\xa0\x80 surrogate, \xe2\x82 cut, \xc0\xaf, \xc3\xa9 fine"
    text = PLATE_TEXT.encode().replace(b'title = "2D oscillating plate";',
                                       b'title = "' + title + b'";')
    scene = b"scene \xff\xc3.cfg"
    with open(os.path.join(os.fsencode(d), scene), "wb") as f:
        f.write(text)
    override = b'title="over \xf4\x90\x80\x80 ride"'  # beyond U+10FFFF
    runs = [("title", [], title), ("override", [b"--set", override], override[7:-1])]
    for name, extra, expected_title in runs:
        argv = [os.fsencode(BIN), b"run", scene, b"--backend", b"cpu", b"--quiet", b"--out",
                name.encode()] + [a.encode() for a in FAST] + extra
        p = subprocess.run(argv, cwd=d, capture_output=True, timeout=300)
        check(p.returncode == 0, "bytes that are not UTF-8 in the %s: exit %d: %s" %
              (name, p.returncode, p.stderr.decode(errors="replace")))
        summary = strict_utf8_json(os.path.join(d, name, "summary.json"))
        check(summary is not None, "%s: summary.json is valid UTF-8 JSON" % name)
        if summary is None:
            continue
        sc = summary["scene"]
        check(sc["title"] == expected_title.decode("utf-8", "replace"),
              "%s: the title, ill-formed bytes as U+FFFD: %r" % (name, sc["title"]))
        check(sc["path"] == scene.decode("utf-8", "replace"),
              "%s: the scene path, ill-formed bytes as U+FFFD: %r" % (name, sc["path"]))
        overrides = FAST[1::2] + [x.decode("utf-8", "replace") for x in extra[1::2]]
        check(sc["overrides"] == overrides, "%s: the overrides: %r" % (name, sc["overrides"]))
        p = subprocess.run([BIN, "compare", name, name], cwd=d, capture_output=True, text=True,
                           timeout=300)
        check(p.returncode == 0, "%s: sphsolid compare reads the run: %s" % (name, p.stderr))
        if name == "title" and not HAVE_MATPLOTLIB:
            print("  (tools/plot_run.py on that run skipped: no matplotlib)")
        elif name == "title":
            p = subprocess.run([sys.executable, os.path.join(SRC, "tools", "plot_run.py"), name,
                                "--snapshots", "0"], cwd=d, capture_output=True, text=True,
                               timeout=300)
            check(p.returncode == 0 and os.path.exists(os.path.join(d, name, "plots",
                                                                    "timeseries.png")),
                  "%s: tools/plot_run.py reads the run: %s" % (name, p.stderr[-300:]))
        print("  %-66s %d  title %r" % ("bytes that are not UTF-8 in the " + name, 0,
                                        sc["title"][:40]))


def restart_after_disk_full(tmp):
    """A run that a full disk stops keeps its checkpoint (a restart point,
    not a result); its snapshots are marked .partial, and a restart, with
    room again, renames those the checkpoint lists back and ends like the
    uninterrupted run."""
    d = os.path.join(tmp, "restart")
    os.makedirs(d)
    args = ["--backend", "cpu", "--quiet", "--set", "resolution.ratio=4", "--set",
            "time.end=0.03", "--set", "output.snapshot_interval=0.01"]
    env = dict(os.environ, SPHSOLID_TEST_DISK_FULL="snapshot_000002")
    p = subprocess.run([BIN, "run", PLATE, "--out", "a", "--checkpoint-every", "0.01"] + args,
                       cwd=d, env=env, capture_output=True, text=True, timeout=300)
    check(p.returncode == 1 and "snapshot_000002.hdf.partial: No space left on device" in p.stderr,
          "disk full with checkpoints: exit %d: %s" % (p.returncode, p.stderr))
    a = os.path.join(d, "a")
    check(not complete_looking(os.path.join(a, "snapshots")) and
          os.path.exists(os.path.join(a, "snapshots", "snapshot_000001.hdf.partial")) and
          os.path.exists(os.path.join(a, "checkpoint", "checkpoint.h5")),
          "disk full with checkpoints: snapshots .partial, checkpoint kept")
    p = subprocess.run([BIN, "run", "--restart", "a", "--backend", "cpu", "--quiet"], cwd=d,
                       capture_output=True, text=True, timeout=300)
    check(p.returncode == 0, "restart after a full disk: exit %d: %s" % (p.returncode, p.stderr))
    p = subprocess.run([BIN, "run", PLATE, "--out", "b"] + args, cwd=d, capture_output=True,
                       text=True, timeout=300)
    p = subprocess.run([BIN, "compare", "a", "b", "--rtol", "0"], cwd=d, capture_output=True,
                       text=True, timeout=300)
    check(p.returncode == 0 and len(os.listdir(os.path.join(a, "snapshots"))) == 4,
          "restart after a full disk equals the uninterrupted run: %s" % p.stdout[-300:])


def wait_for(path, proc, limit=120):
    t0 = time.time()
    while not os.path.exists(path) and proc.poll() is None and time.time() - t0 < limit:
        time.sleep(0.01)
    return os.path.exists(path) and proc.poll() is None


def busy_output_directory(tmp):
    """Two processes in one output directory: while a run holds it (here
    inside its checkpoint write, SPHSOLID_TEST_CHECKPOINT_DELAY), a second
    run, a restart in place and `relax --out` into it are refused (exit 1,
    one sentence naming the directory and the holder's pid) and change
    nothing: the first run ends with the results it would have had alone.
    A run killed with SIGKILL leaves no lock (the kernel drops it) and no
    .partial checkpoint after the next run."""
    d = os.path.join(tmp, "busy")
    os.makedirs(d)
    plain = ["--backend", "cpu", "--quiet"] + FAST
    args = plain + ["--checkpoint-every", "0.01"]
    p = subprocess.run([BIN, "run", PLATE, "--out", "alone"] + args, cwd=d, capture_output=True,
                       text=True, timeout=300)
    check(p.returncode == 0, "busy directory: the reference run: %s" % p.stderr)
    out = os.path.join(d, "out")
    env = dict(os.environ, SPHSOLID_TEST_CHECKPOINT_DELAY="4")
    first = subprocess.Popen([BIN, "run", PLATE, "--out", out] + args, cwd=d, env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        held = wait_for(os.path.join(out, "checkpoint", "checkpoint.h5.partial"), first)
        check(held, "busy directory: the first run is inside its checkpoint write")
        busy = "is in use by another sphsolid process (pid %d)" % first.pid
        for what, argv, fragment in [
            ("a second run", ["run", PLATE, "--out", out] + args, "output directory " + out),
            ("a restart in place", ["run", "--restart", out, "--backend", "cpu", "--quiet"],
             "output directory " + out),
            ("relax --out", ["relax", PLATE, "--out", os.path.join(out, "plate.h5"), "--set",
                             "bodies.plate.placement=relaxed", "--set",
                             "bodies.plate.relaxation.steps=2"] + FAST[:2],
             "--out %s: directory %s" % (os.path.join(out, "plate.h5"), out)),
        ]:
            q = subprocess.run([BIN] + argv, cwd=d, capture_output=True, text=True, timeout=300)
            err = q.stderr.strip()
            check(held and q.returncode == 1 and fragment + " " + busy in err and
                  len(err.splitlines()) == 1,
                  "busy directory: %s: exit 1 naming the directory and pid %d, got %d: %s"
                  % (what, first.pid, q.returncode, err))
            print("  %-66s %d  %s" % (("busy --out: " + what)[:66], q.returncode, err[:110]))
    finally:
        first.wait(timeout=300)
    check(first.returncode == 0, "busy directory: the first run: %s" % first.stderr.read())
    first.stderr.close()
    def content(path):
        return open(path, "rb").read() if os.path.exists(path) else None

    same = all(content(os.path.join(out, f)) is not None and
               content(os.path.join(out, f)) == content(os.path.join(d, "alone", f))
               for f in ("timeseries.csv", "snapshots.hdf.series", "snapshots/snapshot_000001.hdf"))
    check(same and not os.path.exists(os.path.join(out, "plate.h5")),
          "busy directory: the first run's results are those of a run alone")
    # SIGKILL inside a checkpoint write: the next run gets the directory
    killed = subprocess.Popen([BIN, "run", PLATE, "--out", out] + args, cwd=d,
                              env=dict(os.environ, SPHSOLID_TEST_CHECKPOINT_DELAY="120"),
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wait_for(os.path.join(out, "checkpoint", "checkpoint.h5.partial"), killed)
    killed.kill()
    killed.wait()
    p = subprocess.run([BIN, "run", PLATE, "--out", out] + plain, cwd=d, capture_output=True,
                       text=True, timeout=300)
    check(p.returncode == 0 and not os.path.exists(
        os.path.join(out, "checkpoint", "checkpoint.h5.partial")),
        "busy directory: after a killed run, a run without checkpoints gets the directory and "
        "leaves no checkpoint.h5.partial: exit %d: %s" % (p.returncode, p.stderr.strip()))


def opencl_memory_row():
    """With an OpenCL device: a particle count its buffers cannot hold,
    refused before anything is allocated on it (skipped when the device is
    so large that the host would need GBs for the particle arrays)."""
    p = subprocess.run([BIN, "devices"], capture_output=True, text=True)
    m = re.search(r"OpenCL device 0: .*?, ([0-9.]+) GiB, double precision: yes", p.stdout)
    if not m:
        return None
    gib = float(m.group(1))
    particles = 1.3 * gib * 2**30 / 1400.0  # 2D double: about 1.5 KiB of buffers each
    if particles > 6e6:
        return None
    ratio = (particles / 13.0) ** 0.5  # the plate has about 13 ratio^2 particles
    return Row("OpenCL: particles beyond the device's memory", 1,
               ["OpenCL device 0 (", "GiB of global memory, but", "particles need",
                "of buffers", "lower the resolution or use --backend cpu"],
               args=["--backend", "opencl", "--set", "resolution.ratio=%.0f" % ratio])


tmp = tempfile.mkdtemp(prefix="sphsolid-bad-input-")
paths_used = set()
try:
    rows = list(ROWS)
    ocl = opencl_memory_row()
    if ocl:
        rows.append(ocl)
    else:
        print("(no OpenCL device with double precision and a few GiB: the OpenCL memory row "
              "is skipped)")
    for k, row in enumerate(rows):
        run_row(k, row, tmp, paths_used)
    touching_bodies_run(tmp)
    free_text_bytes_run(tmp)
    restart_after_disk_full(tmp)
    busy_output_directory(tmp)
    print("disk-full rows ran on: %s" % (", ".join(sorted(paths_used)) or "none"))
finally:
    for d, _, _ in os.walk(tmp, topdown=False):
        if os.path.ismount(d):
            subprocess.run(["umount", d], check=False)
    shutil.rmtree(tmp, ignore_errors=True)

finish("test_bad_input")
