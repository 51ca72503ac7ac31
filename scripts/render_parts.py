#!/usr/bin/env python3
"""Draws parts with their box joints and kerf cuts from stages/parts.json (written by
`kerfab run --dump`): the kerf-compensated cut outline in red, kerf cuts dark grey, tooth
regions shaded, each part rotated so its longest
extent is horizontal, all at one scale. Standard library only.
Usage: render_parts.py parts.json out.svg [--first N] [--count N] [--width PX] [--zoom PART]"""
import argparse
import json

from plotting import principal_frame


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("parts_json")
    ap.add_argument("out_svg")
    ap.add_argument("--first", type=int, default=0, help="first part number")
    ap.add_argument("--count", type=int, default=6, help="how many parts")
    ap.add_argument("--width", type=int, default=1000, help="picture width [px]")
    ap.add_argument("--zoom", type=float, default=1.0,
                    help="magnify: show only the first 1/zoom of each part's length")
    a = ap.parse_args()
    d = json.load(open(a.parts_json))
    parts = d["parts"][a.first:a.first + a.count]
    shapes = []
    for p in parts:
        pts = p["cut"]
        tr = principal_frame(pts)
        cut = [tr(q) for q in pts]
        teeth = [[tr(q) for q in tooth] for tooth in p["teeth"]]
        kerf = [(tr(k[:2]), tr(k[2:])) for k in p.get("kerf", [])]
        xs, ys = [q[0] for q in cut], [q[1] for q in cut]
        shapes.append((p["part"], cut, teeth, kerf, min(xs), max(xs), min(ys), max(ys)))
    widest = max((s[5] - s[4]) / a.zoom for s in shapes)
    scale = (a.width - 80) / widest
    y = 20.0
    out = []
    for name, cut, teeth, kerf, x0, x1, y0, y1 in shapes:
        def P(q):
            return 60 + scale * (q[0] - x0), y + scale * (y1 - q[1])
        for tooth in teeth:
            pts = " ".join(f"{u:.2f},{v:.2f}" for u, v in map(P, tooth))
            out.append(f'<polygon points="{pts}" fill="#9bc5f0" stroke="none"/>')
        for k0, k1 in kerf:
            (u0, v0), (u1, v1) = P(k0), P(k1)
            out.append(f'<line x1="{u0:.2f}" y1="{v0:.2f}" x2="{u1:.2f}" y2="{v1:.2f}" '
                       f'stroke="#303030" stroke-width="0.5"/>')
        pts = " ".join(f"{u:.2f},{v:.2f}" for u, v in map(P, cut))
        out.append(f'<polygon points="{pts}" fill="none" stroke="#d00000" stroke-width="0.8"/>')
        out.append(f'<text x="6" y="{y + scale * (y1 - y0) / 2 + 5:.1f}" '
                   f'font-family="sans-serif" font-size="14">{name:03d}</text>')
        y += scale * (y1 - y0) + 16
    h = int(y + 10)
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{a.width}" height="{h}" '
           f'viewBox="0 0 {a.width} {h}"><rect width="100%" height="100%" fill="white"/>']
    open(a.out_svg, "w").write("\n".join(svg + out + ["</svg>"]))


if __name__ == "__main__":
    main()
