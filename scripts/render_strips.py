#!/usr/bin/env python3
"""Renders model/strips.ply or model/kerf_density.ply (written by `kerfab run`) to an SVG
picture: the subdivided strip mesh flat-shaded in the file's face colours, rulings as thin
lines, strip borders dark.
Standard library only. Usage: render_strips.py strips.ply out.svg [--azimuth DEG]
[--elevation DEG] [--up x|y|z] [--width PX]"""
import argparse
import math


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


def rotate(p, az, el):
    x, y, z = p
    ca, sa = math.cos(az), math.sin(az)
    x, y = ca * x - sa * y, sa * x + ca * y
    ce, se = math.cos(el), math.sin(el)
    y, z = ce * y - se * z, se * y + ce * z
    return x, y, z


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
    order = {0: (1, 2, 0), 1: (2, 0, 1), 2: (0, 1, 2)}["xyz".index(a.up)]
    verts = [tuple(v[i] for i in order) for v in verts]
    az, el = math.radians(a.azimuth), math.radians(a.elevation)
    pts = [rotate(p, az, el) for p in verts]
    used = sorted({i for f in faces for i in f[0]})
    xs = [pts[i][0] for i in used]
    zs = [pts[i][2] for i in used]
    span = max(max(xs) - min(xs), max(zs) - min(zs))
    s = 0.9 * a.width / span
    h = int(a.width * (max(zs) - min(zs)) / span) + int(0.1 * a.width)
    cx, cz = (max(xs) + min(xs)) / 2, (max(zs) + min(zs)) / 2

    def scr(p):
        return a.width / 2 + s * (p[0] - cx), h / 2 - s * (p[2] - cz)

    light = (-0.5, -0.6, 0.6)
    ln = math.sqrt(sum(c * c for c in light))
    light = tuple(c / ln for c in light)
    # Edges used by two faces of the same strip are inner; all others are strip borders.
    owner = {}
    for idx, strip, _ in faces:
        for k in range(len(idx)):
            e = tuple(sorted((idx[k], idx[(k + 1) % len(idx)])))
            owner.setdefault(e, []).append(strip)
    drawn = []
    for idx, strip, rgb in faces:
        p = [pts[i] for i in idx]
        u = [p[2][k] - p[0][k] for k in range(3)]
        v = [p[3][k] - p[1][k] for k in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        nn = math.sqrt(sum(c * c for c in n)) or 1.0
        n = tuple(c / nn for c in n)
        if n[1] > 0:
            continue
        depth = sum(c[1] for c in p) / len(p)
        shade = 0.35 + 0.65 * max(0.0, sum(n[k] * light[k] for k in range(3)))
        drawn.append((depth, idx, strip, tuple(int(c * shade) for c in rgb)))
    drawn.sort(key=lambda f: -f[0])
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{a.width}" height="{h}" '
           f'viewBox="0 0 {a.width} {h}"><rect width="100%" height="100%" fill="white"/>']
    for _, idx, strip, c in drawn:
        poly = " ".join(f"{x:.1f},{y:.1f}" for x, y in (scr(pts[i]) for i in idx))
        out.append(f'<polygon points="{poly}" fill="rgb{c}" stroke="rgb{c}" '
                   f'stroke-width="0.6"/>')
        for k in range(len(idx)):
            e = tuple(sorted((idx[k], idx[(k + 1) % len(idx)])))
            border = len(owner[e]) < 2 or owner[e][0] != owner[e][1]
            (x1, y1), (x2, y2) = scr(pts[e[0]]), scr(pts[e[1]])
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
