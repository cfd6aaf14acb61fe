#!/usr/bin/python3
"""make_gear_stl.py [--teeth N] [--out gear.stl] — the spur gear of cases/mesh_gear_3d as a
binary STL: N trapezoidal teeth (tip radius 0.5 m, root radius 0.4 m; each tooth 0.2 of the
pitch wide at its tip and 0.4 at its root) extruded 0.2 m along z, centred at the origin.
A shape no union of the built-in primitives gives (slanted flanks).  The outline is
star-shaped about the axis, so each end cap is a fan of triangles about its centre; the side
wall is a band of quads split in two.  Counter-clockwise seen from outside.  The exact
volume of the prism (the outline's area times the thickness) is printed."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from stl_file import write_binary_stl  # noqa: E402

R_TIP, R_ROOT, THICKNESS = 0.5, 0.4, 0.2


def outline(teeth):
    """The outline, counter-clockwise: per tooth, root corner, tip corner, tip corner, root
    corner (flanks slanted: 0.4 of the pitch at the root, 0.2 at the tip)."""
    pts = []
    pitch = 2 * math.pi / teeth
    for k in range(teeth):
        a = k * pitch
        for frac, r in ((0.0, R_ROOT), (0.1, R_TIP), (0.3, R_TIP), (0.4, R_ROOT)):
            pts.append((r * math.cos(a + frac * pitch), r * math.sin(a + frac * pitch)))
    return pts


def triangles(teeth):
    p = outline(teeth)
    n = len(p)
    z0, z1 = -THICKNESS / 2, THICKNESS / 2
    tris = []
    for k in range(n):
        a, b = p[k], p[(k + 1) % n]
        # the caps: fans about the axis (bottom seen from below is clockwise in x-y)
        tris.append(((0, 0, z1), (a[0], a[1], z1), (b[0], b[1], z1)))
        tris.append(((0, 0, z0), (b[0], b[1], z0), (a[0], a[1], z0)))
        # the side wall between a and b
        tris.append(((a[0], a[1], z0), (b[0], b[1], z0), (b[0], b[1], z1)))
        tris.append(((a[0], a[1], z0), (b[0], b[1], z1), (a[0], a[1], z1)))
    return tris


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--teeth", type=int, default=24)
    ap.add_argument("--out", default="gear.stl")
    a = ap.parse_args()
    tris = triangles(a.teeth)
    p = outline(a.teeth)
    area = 0.5 * sum(p[k][0] * p[(k + 1) % len(p)][1] - p[(k + 1) % len(p)][0] * p[k][1]
                     for k in range(len(p)))
    write_binary_stl(a.out, "sphsolid cases/mesh_gear_3d: spur gear", tris)
    print(f"{a.out}: {a.teeth} teeth, {len(tris)} triangles, outline area {area:.9f} m^2, "
          f"volume {area * THICKNESS:.9f} m^3")


if __name__ == "__main__":
    main()
