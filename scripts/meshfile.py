"""Vertices and faces of an OBJ (v/f lines) or OFF file, for the scripts of this folder
(quad-benchmark.py, and quadriflow_remesh.py inside Blender, which must not change the frame).
"""


def read_mesh(path):
    """(vertices as (x, y, z) tuples, faces as lists of 0-based vertex ids)."""
    verts, faces = [], []
    with open(path) as f:
        text = f.read()
    if str(path).lower().endswith(".off"):
        rows = [line.split("#")[0].split() for line in text.splitlines()]
        rows = [r for r in rows if r]
        head = rows[0]
        if head[0].upper().endswith("OFF") and len(head) > 1:  # "OFF nv nf ne" on one line
            counts, start = [int(x) for x in head[1:4]], 1
        else:
            counts, start = [int(x) for x in rows[1][:3]], 2
        nv, nf = counts[0], counts[1]
        for r in rows[start:start + nv]:
            verts.append(tuple(float(x) for x in r[:3]))
        for r in rows[start + nv:start + nv + nf]:
            n = int(r[0])
            faces.append([int(x) for x in r[1:1 + n]])
        return verts, faces
    for line in text.splitlines():
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            verts.append(tuple(float(x) for x in t[1:4]))
        elif t[0] == "f":
            idx = []
            for c in t[1:]:
                i = int(c.split("/")[0])
                idx.append(i - 1 if i > 0 else len(verts) + i)
            faces.append(idx)
    return verts, faces
