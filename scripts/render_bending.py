#!/usr/bin/env python3
"""Renders stages/bending.json (written by `kerfab run --dump`) to an SVG picture: the quad
mesh in flat-shaded orthographic view, bendable edges in red, like the paper's Fig. 1b.
Standard library only. Usage: render_bending.py bending.json out.svg [--azimuth DEG]
[--elevation DEG]"""
import argparse
import json

from plotting import View


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
    view = View(d["vertices"], a.up, a.azimuth, a.elevation, a.width)
    bend = {tuple(sorted(e["v"])) for e in d["edges"] if e["bendable"]}
    faces = []
    for q in d["quads"]:
        seen = view.face(q)
        if seen:
            faces.append((seen[0], q, seen[1]))
    faces.sort(key=lambda f: -f[0])                     # far to near
    out = [view.svg_header()]
    for _, q, shade in faces:
        g = int(90 + 160 * shade)
        poly = " ".join(f"{x:.1f},{y:.1f}" for x, y in (view.screen(i) for i in q))
        out.append(f'<polygon points="{poly}" fill="rgb({g},{g},{int(g*0.97)})" '
                   f'stroke="#555" stroke-width="0.4"/>')
        for k in range(4):
            e = tuple(sorted((q[k], q[(k + 1) % 4])))
            if e in bend:
                (x1, y1), (x2, y2) = view.screen(e[0]), view.screen(e[1])
                out.append(f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" '
                           f'stroke="#d01010" stroke-width="2"/>')
    out.append("</svg>")
    open(a.out_svg, "w").write("\n".join(out))


if __name__ == "__main__":
    main()
