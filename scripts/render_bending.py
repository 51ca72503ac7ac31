#!/usr/bin/env python3
"""Renders stages/bending.json (written by `kerfab run --dump`) to an SVG picture: the quad
mesh in flat-shaded orthographic view, bendable edges in red, like the paper's Fig. 1b.
Standard library only. Usage: render_bending.py bending.json out.svg [--azimuth DEG]
[--elevation DEG]"""
import argparse
import json
import math


def rotate(p, az, el):
    x, y, z = p
    ca, sa = math.cos(az), math.sin(az)
    x, y = ca * x - sa * y, sa * x + ca * y          # about the vertical axis
    ce, se = math.cos(el), math.sin(el)
    y, z = ce * y - se * z, se * y + ce * z          # tilt towards the viewer
    return x, y, z


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("bending_json")
    ap.add_argument("out_svg")
    ap.add_argument("--azimuth", type=float, default=-60.0, help="view turn [deg]")
    ap.add_argument("--elevation", type=float, default=15.0, help="view tilt [deg]")
    ap.add_argument("--up", default="y", choices=["x", "y", "z"], help="model's up axis")
    ap.add_argument("--width", type=int, default=800, help="picture width [px]")
    a = ap.parse_args()
    d = json.load(open(a.bending_json))
    axis = "xyz".index(a.up)
    order = {0: (1, 2, 0), 1: (2, 0, 1), 2: (0, 1, 2)}[axis]   # make the up axis z
    verts = [tuple(v[i] for i in order) for v in d["vertices"]]
    az, el = math.radians(a.azimuth), math.radians(a.elevation)
    # Screen: x right, z up, y depth (larger = farther).
    pts = [rotate(p, az, el) for p in verts]
    xs = [p[0] for p in pts]
    zs = [p[2] for p in pts]
    span = max(max(xs) - min(xs), max(zs) - min(zs))
    s = 0.9 * a.width / span
    h = int(a.width * (max(zs) - min(zs)) / span) + int(0.1 * a.width)
    cx, cz = (max(xs) + min(xs)) / 2, (max(zs) + min(zs)) / 2

    def scr(p):
        return a.width / 2 + s * (p[0] - cx), h / 2 - s * (p[2] - cz)

    light = (-0.5, -0.6, 0.6)
    ln = math.sqrt(sum(c * c for c in light))
    light = tuple(c / ln for c in light)
    bend = {tuple(sorted(e["v"])) for e in d["edges"] if e["bendable"]}
    faces = []
    for q in d["quads"]:
        p = [pts[i] for i in q]
        u = [p[2][k] - p[0][k] for k in range(3)]
        v = [p[3][k] - p[1][k] for k in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        nn = math.sqrt(sum(c * c for c in n)) or 1.0
        n = tuple(c / nn for c in n)
        if n[1] > 0:      # facing away from the viewer (viewer looks along +y)
            continue
        depth = sum(c[1] for c in p) / 4
        shade = max(0.0, sum(n[k] * light[k] for k in range(3)))
        faces.append((depth, q, shade))
    faces.sort(key=lambda f: -f[0])                     # far to near
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{a.width}" height="{h}" '
           f'viewBox="0 0 {a.width} {h}"><rect width="100%" height="100%" fill="white"/>']
    for _, q, shade in faces:
        g = int(90 + 160 * shade)
        poly = " ".join(f"{x:.1f},{y:.1f}" for x, y in (scr(pts[i]) for i in q))
        out.append(f'<polygon points="{poly}" fill="rgb({g},{g},{int(g*0.97)})" '
                   f'stroke="#555" stroke-width="0.4"/>')
        for k in range(4):
            e = tuple(sorted((q[k], q[(k + 1) % 4])))
            if e in bend:
                (x1, y1), (x2, y2) = scr(pts[e[0]]), scr(pts[e[1]])
                out.append(f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" '
                           f'stroke="#d01010" stroke-width="2"/>')
    out.append("</svg>")
    open(a.out_svg, "w").write("\n".join(out))


if __name__ == "__main__":
    main()
