#!/usr/bin/env python3
"""Writes the generated triangle meshes the README's "Other shapes" runs use (OBJ, millimetres).

    python3 scripts/shapes.py DIR        # vase, terrain, ellipsoid, saddle, cone, vault, holed-block
    build/kerfab run --target DIR/vase.obj --size 250 --out out/vase

Each is a plain grid of triangles on an exact surface, so a run's distances can be read
against the shape itself:
  vase       open at the top, a disc at the bottom: r(z) = 50 + 25 sin(1.5 pi z/H) + 10 cos(3 pi z/H), H 200
  terrain    an open height field over 200 x 200: 25 sin(x/30) cos(y/40) + 10 exp(-(x^2 + y^2)/800)
  ellipsoid  semi-axes 150, 80, 60
  saddle     an open patch z = (x^2 - y^2)/200 over 160 x 160
  cone       base radius 80, height 150, with its base disc (the apex a point)
  vault      half a cylinder of radius 100 over 200, open (a barrel vault: its border's four
             corners turn by 90 degrees)
  holed-block  200 x 200 x 60 with a round hole of radius 50 through it (its top and bottom
             flat faces with a hole)
"""
import math
import os
import sys


def write(path, vertices, faces):
    with open(path, "w") as f:
        f.write("# written by kerfab's scripts/shapes.py\n")
        for v in vertices:
            f.write("v %.6f %.6f %.6f\n" % tuple(v))
        for t in faces:
            f.write("f " + " ".join(str(i + 1) for i in t) + "\n")


def ring_faces(nu, rows, index, outward, by_ring=False):
    """Two triangles per cell of a band of `rows` rings of `nu` vertices closed round, column by
    column (by_ring: ring by ring)."""
    faces = []
    cells = [(i, j) for j in range(rows) for i in range(nu)] if by_ring else \
        [(i, j) for i in range(nu) for j in range(rows)]
    for i, j in cells:
        a, b = index(i, j), index(i + 1, j)
        c, d = index(i + 1, j + 1), index(i, j + 1)
        faces += [(a, b, c), (a, c, d)] if outward else [(a, d, c), (a, c, b)]
    return faces


def grid(n, height, extent):
    """An open square patch of n x n cells over [-extent, extent]^2, z = height(x, y)."""
    vertices = []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = -extent + 2 * extent * i / n, -extent + 2 * extent * j / n
            vertices.append((x, y, height(x, y)))
    faces = []
    for i in range(n):
        for j in range(n):
            a, b = j * (n + 1) + i, j * (n + 1) + i + 1
            c, d = (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            faces += [(a, b, c), (a, c, d)]
    return vertices, faces


def vase():
    nu, nv, h = 64, 40, 200.0
    vertices = []
    for j in range(nv + 1):
        z = h * j / nv
        r = 50 + 25 * math.sin(1.5 * math.pi * z / h) + 10 * math.cos(3 * math.pi * z / h)
        for i in range(nu):
            a = 2 * math.pi * i / nu
            vertices.append((r * math.cos(a), r * math.sin(a), z))
    index = lambda i, j: j * nu + i % nu
    faces = ring_faces(nu, nv, index, True)
    centre = len(vertices)
    vertices.append((0, 0, 0))
    faces += [(centre, index(i + 1, 0), index(i, 0)) for i in range(nu)]
    return vertices, faces


def ellipsoid():
    nu, nv = 80, 40
    vertices = [(0, 0, -60)]
    for j in range(1, nv):
        t = math.pi * j / nv - math.pi / 2
        for i in range(nu):
            a = 2 * math.pi * i / nu
            vertices.append((150 * math.cos(t) * math.cos(a), 80 * math.cos(t) * math.sin(a),
                             60 * math.sin(t)))
    top = len(vertices)
    vertices.append((0, 0, 60))
    index = lambda i, j: 1 + (j - 1) * nu + i % nu
    faces = [(0, index(i + 1, 1), index(i, 1)) for i in range(nu)]
    faces += ring_faces(nu, nv - 2, lambda i, j: index(i, j + 1), True, by_ring=True)
    faces += [(top, index(i, nv - 1), index(i + 1, nv - 1)) for i in range(nu)]
    return vertices, faces


def cone():
    nu, nv, radius, h = 64, 30, 80.0, 150.0
    vertices = [(0, 0, h)]
    for j in range(1, nv + 1):
        r, z = radius * j / nv, h - h * j / nv
        for i in range(nu):
            a = 2 * math.pi * i / nu
            vertices.append((r * math.cos(a), r * math.sin(a), z))
    index = lambda i, j: 1 + (j - 1) * nu + i % nu
    faces = [(0, index(i, 1), index(i + 1, 1)) for i in range(nu)]
    faces += ring_faces(nu, nv - 1, lambda i, j: index(i, j + 1), False, by_ring=True)
    centre = len(vertices)
    vertices.append((0, 0, 0))
    faces += [(centre, index(i + 1, nv), index(i, nv)) for i in range(nu)]
    return vertices, faces


def vault():
    nu, nv = 40, 40
    vertices = []
    for j in range(nv + 1):
        for i in range(nu + 1):
            a = math.pi * i / nu
            vertices.append((100 * math.cos(a), 200 * j / nv, 100 * math.sin(a)))
    faces = []
    for j in range(nv):
        for i in range(nu):
            a = j * (nu + 1) + i
            b, c, d = a + 1, a + nu + 2, a + nu + 1
            faces += [(a, c, b), (a, d, c)]
    return vertices, faces


def holed_block():
    """200 x 200 x 60 with a round hole of radius 50 through it; each face of the square
    outline in 16 segments, joined to the hole's 64-gon by one row of quads (two triangles)."""
    n, half, r, h = 64, 100.0, 50.0, 60.0
    outer = []
    for side in range(4):
        for k in range(16):
            t = k / 16
            outer.append([(-half + 2 * half * t, -half), (half, -half + 2 * half * t),
                          (half - 2 * half * t, half), (-half, half - 2 * half * t)][side])
    hole = []
    for x, y in outer:
        a = math.atan2(y, x)
        hole.append((r * math.cos(a), r * math.sin(a)))
    vertices = []
    for z in (0.0, h):
        vertices += [(x, y, z) for x, y in outer] + [(x, y, z) for x, y in hole]
    index = lambda layer, ring, k: layer * 2 * n + ring * n + k % n
    faces = []
    for k in range(n):
        j = k + 1
        faces += [(index(0, 0, k), index(0, 0, j), index(1, 0, j)),
                  (index(0, 0, k), index(1, 0, j), index(1, 0, k)),   # outside
                  (index(0, 1, j), index(0, 1, k), index(1, 1, k)),
                  (index(0, 1, j), index(1, 1, k), index(1, 1, j)),   # the hole
                  (index(1, 0, k), index(1, 0, j), index(1, 1, j)),
                  (index(1, 0, k), index(1, 1, j), index(1, 1, k)),   # top
                  (index(0, 0, j), index(0, 0, k), index(0, 1, k)),
                  (index(0, 0, j), index(0, 1, k), index(0, 1, j))]   # bottom
    return vertices, faces


def main():
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):  # --help: the usage, no directory
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    shapes = {
        "vase": vase(),
        "terrain": grid(60, lambda x, y: 25 * math.sin(x / 30) * math.cos(y / 40) +
                        10 * math.exp(-(x * x + y * y) / 800), 100),
        "ellipsoid": ellipsoid(),
        "saddle": grid(50, lambda x, y: (x * x - y * y) / 200, 80),
        "cone": cone(),
        "vault": vault(),
        "holed-block": holed_block(),
    }
    for name, (vertices, faces) in shapes.items():
        write(os.path.join(out, name + ".obj"), vertices, faces)
        print("%s: %d vertices, %d triangles" % (name, len(vertices), len(faces)))


if __name__ == "__main__":
    main()
