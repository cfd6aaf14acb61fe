"""stl_file.py — write a binary STL: what the cases' mesh generators share
(cases/mesh_ball_3d/make_ball_stl.py, cases/mesh_gear_3d/make_gear_stl.py)."""
import math
import struct


def write_binary_stl(path, header, triangles):
    """Triangles as three (x, y, z) corners each, counter-clockwise seen from outside; each is
    written with its unit normal, in float32, after an 80-byte header."""
    with open(path, "wb") as out:
        out.write(header.encode()[:80].ljust(80, b" "))
        out.write(struct.pack("<I", len(triangles)))
        for p in triangles:
            u = [p[1][k] - p[0][k] for k in range(3)]
            w = [p[2][k] - p[0][k] for k in range(3)]
            n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
            ln = math.sqrt(sum(x * x for x in n))
            out.write(struct.pack("<3f", *[x / ln for x in n]))
            for q in p:
                out.write(struct.pack("<3f", *q))
            out.write(struct.pack("<H", 0))
