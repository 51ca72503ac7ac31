#!/usr/bin/env python3
"""Draws flattened patches (stages/patches/NNN_2d.obj, written by `kerfab run --dump`) side by
side at one common scale, each rotated so its longest extent is horizontal: outline dark, rulings
thin, patch number beside it. Standard library only.
Usage: render_patches.py PATCH_DIR out.svg [--first N] [--count N] [--width PX]"""
import argparse
import glob
import os

from plotting import principal_frame, stacked_svg


def read_obj(path):
    verts, faces = [], []
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            verts.append((float(w[1]), float(w[2])))
        elif w[0] == "f":
            faces.append([int(t.split("/")[0]) - 1 for t in w[1:]])
    return verts, faces


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("patch_dir")
    ap.add_argument("out_svg")
    ap.add_argument("--first", type=int, default=0, help="first patch number")
    ap.add_argument("--count", type=int, default=12, help="how many patches")
    ap.add_argument("--width", type=int, default=1000, help="picture width [px]")
    a = ap.parse_args()
    files = sorted(glob.glob(os.path.join(a.patch_dir, "*_2d.obj")))[a.first:a.first + a.count]
    shapes = []
    for f in files:
        v, faces = read_obj(f)
        tr = principal_frame(v)  # principal direction -> horizontal
        v = [tr(p) for p in v]
        xs, ys = [p[0] for p in v], [p[1] for p in v]
        shapes.append((os.path.basename(f)[:3], v, faces, min(xs), max(xs), min(ys), max(ys)))
    def drawing(v, faces):
        def draw(P):
            edges = {}
            for f in faces:
                for k in range(len(f)):
                    e = tuple(sorted((f[k], f[(k + 1) % len(f)])))
                    edges[e] = edges.get(e, 0) + 1
            out = []
            for (i, j), n in edges.items():
                (xa, ya), (xb, yb) = P(v[i]), P(v[j])
                style = 'stroke="#c00000" stroke-width="1.2"' if n == 1 else \
                    'stroke="#808080" stroke-width="0.4"'
                out.append(f'<line x1="{xa:.1f}" y1="{ya:.1f}" x2="{xb:.1f}" y2="{yb:.1f}" '
                           f'{style}/>')
            return out
        return draw
    rows = [(name, box, drawing(v, faces)) for name, v, faces, *box in shapes]
    widest = max(s[4] - s[3] for s in shapes)
    open(a.out_svg, "w").write(stacked_svg(rows, a.width, widest, label_x=8))

if __name__ == "__main__":
    main()
