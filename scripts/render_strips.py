#!/usr/bin/env python3
"""Renders model/strips.ply or model/kerf_density.ply (written by `kerfab run`) to an SVG
picture: the subdivided strip mesh flat-shaded in the file's face colours, rulings as thin
lines, strip borders dark.
Standard library only. Usage: render_strips.py strips.ply out.svg [--azimuth DEG]
[--elevation DEG] [--up x|y|z] [--width PX]"""
import argparse

from plotting import View


def read_ply(path):
    with open(path) as f:
        lines = f.read().split("\n")
    nv = nf = 0
    face_props = []  # names of the face properties after the vertex list
    element = None
    i = 0
    while lines[i] != "end_header":
        w = lines[i].split()
        if w[:1] == ["element"]:
            element = w[1]
            if w[1] == "vertex":
                nv = int(w[2])
            if w[1] == "face":
                nf = int(w[2])
        if w[:1] == ["property"] and element == "face" and w[1] != "list":
            face_props.append(w[-1])
        i += 1
    i += 1
    verts = [tuple(map(float, lines[i + k].split()[:3])) for k in range(nv)]
    faces = []
    for k in range(nf):
        w = lines[i + nv + k].split()
        n = int(w[0])
        idx = list(map(int, w[1:1 + n]))
        props = dict(zip(face_props, w[1 + n:]))
        rgb = (int(props["red"]), int(props["green"]), int(props["blue"]))
        faces.append((idx, int(props["strip"]), rgb))
    return verts, faces


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("strips_ply")
    ap.add_argument("out_svg")
    ap.add_argument("--azimuth", type=float, default=35.0, help="view turn [deg]")
    ap.add_argument("--elevation", type=float, default=10.0, help="view tilt [deg]")
    ap.add_argument("--up", default="y", choices=["x", "y", "z"], help="model's up axis")
    ap.add_argument("--width", type=int, default=800, help="picture width [px]")
    a = ap.parse_args()
    verts, faces = read_ply(a.strips_ply)
    view = View(verts, a.up, a.azimuth, a.elevation, a.width,
                fit=sorted({i for f in faces for i in f[0]}))
    # Edges used by two faces of the same strip are inner; all others are strip borders.
    owner = {}
    for idx, strip, _ in faces:
        for k in range(len(idx)):
            e = tuple(sorted((idx[k], idx[(k + 1) % len(idx)])))
            owner.setdefault(e, []).append(strip)
    drawn = []
    for idx, strip, rgb in faces:
        seen = view.face(idx)
        if not seen:
            continue
        shade = 0.35 + 0.65 * seen[1]
        drawn.append((seen[0], idx, strip, tuple(int(c * shade) for c in rgb)))
    drawn.sort(key=lambda f: -f[0])
    out = [view.svg_header()]
    for _, idx, strip, c in drawn:
        poly = " ".join(f"{x:.1f},{y:.1f}" for x, y in (view.screen(i) for i in idx))
        out.append(f'<polygon points="{poly}" fill="rgb{c}" stroke="rgb{c}" '
                   f'stroke-width="0.6"/>')
        for k in range(len(idx)):
            e = tuple(sorted((idx[k], idx[(k + 1) % len(idx)])))
            border = len(owner[e]) < 2 or owner[e][0] != owner[e][1]
            (x1, y1), (x2, y2) = view.screen(e[0]), view.screen(e[1])
            if border:
                out.append(f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" '
                           f'stroke="#202020" stroke-width="1.3"/>')
            else:
                out.append(f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" '
                           f'stroke="rgb(60,60,60)" stroke-opacity="0.35" '
                           f'stroke-width="0.4"/>')
    out.append("</svg>")
    with open(a.out_svg, "w") as f:
        f.write("\n".join(out))


if __name__ == "__main__":
    main()
