"""sphtest.py — what the Python tests share: the paths ctest passes in the
environment (SPHSOLID_BIN, SPHSOLID_SOURCE_DIR) and a check counter that
reports every failed check and sets the exit status."""
import os
import sys

SRC = os.environ.get("SPHSOLID_SOURCE_DIR") or \
    os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("SPHSOLID_BIN", os.path.join(SRC, "build", "sphsolid"))
PLATE = os.path.join(SRC, "cases", "oscillating_plate_2d", "scene.cfg")

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
