#!/usr/bin/python3
"""make_ball_stl.py [--level N] [--out ball.stl] — the ball of cases/mesh_ball_3d as a binary
STL: an icosphere (an icosahedron whose faces are split in four N times, the new vertices
pushed onto the sphere), radius 1, centred at the origin (the scene scales and moves it),
scaled so that the mesh encloses exactly the unit ball's volume 4 pi / 3 (at level 4 its
vertices lie 0.072 % outside the sphere, its face centres 0.018 % to 0.042 % inside).  Faces counter-
clockwise seen from outside, each with its outward normal.  Level 4: 5 120 triangles."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from stl_file import write_binary_stl  # noqa: E402


def icosphere(level):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        mid = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = [(x + y) / 2 for x, y in zip(v[a], v[b])]
                n = math.sqrt(sum(x * x for x in p))
                v.append(tuple(x / n for x in p))
                mid[key] = len(v) - 1
            return mid[key]
        g = []
        for a, b, c in f:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = g
    return v, f


def volume(v, f):
    return sum(v[a][0] * (v[b][1] * v[c][2] - v[b][2] * v[c][1]) -
               v[a][1] * (v[b][0] * v[c][2] - v[b][2] * v[c][0]) +
               v[a][2] * (v[b][0] * v[c][1] - v[b][1] * v[c][0]) for a, b, c in f) / 6


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--level", type=int, default=4)
    ap.add_argument("--out", default="ball.stl")
    a = ap.parse_args()
    v, f = icosphere(a.level)
    s = (4 * math.pi / 3 / volume(v, f)) ** (1 / 3)
    v = [tuple(s * x for x in p) for p in v]
    write_binary_stl(a.out, "sphsolid cases/mesh_ball_3d: equal-volume icosphere",
                     [[v[k] for k in tri] for tri in f])
    print(f"{a.out}: {len(f)} triangles, {len(v)} vertices, scale {s:.6f}, volume "
          f"{volume(v, f):.9f} (4 pi / 3 = {4 * math.pi / 3:.9f})")


if __name__ == "__main__":
    main()
