#!/usr/bin/env python3
"""Draws parts with their box joints and kerf cuts from stages/parts.json (written by
`kerfab run --dump`): the kerf-compensated cut outline in red, kerf cuts dark grey, tooth
regions shaded, each part rotated so its longest
extent is horizontal, all at one scale. Standard library only.
Usage: render_parts.py parts.json out.svg [--first N] [--count N] [--width PX] [--zoom PART]"""
import argparse
import json

from plotting import principal_frame, stacked_svg


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
    def drawing(cut, teeth, kerf):
        def draw(P):
            out = []
            for tooth in teeth:
                pts = " ".join(f"{u:.2f},{v:.2f}" for u, v in map(P, tooth))
                out.append(f'<polygon points="{pts}" fill="#9bc5f0" stroke="none"/>')
            for k0, k1 in kerf:
                (u0, v0), (u1, v1) = P(k0), P(k1)
                out.append(f'<line x1="{u0:.2f}" y1="{v0:.2f}" x2="{u1:.2f}" y2="{v1:.2f}" '
                           f'stroke="#303030" stroke-width="0.5"/>')
            pts = " ".join(f"{u:.2f},{v:.2f}" for u, v in map(P, cut))
            out.append(f'<polygon points="{pts}" fill="none" stroke="#d00000" '
                       f'stroke-width="0.8"/>')
            return out
        return draw
    rows = [(f"{name:03d}", box, drawing(cut, teeth, kerf))
            for name, cut, teeth, kerf, *box in shapes]
    widest = max((s[5] - s[4]) / a.zoom for s in shapes)
    open(a.out_svg, "w").write(stacked_svg(rows, a.width, widest, label_x=6))

if __name__ == "__main__":
    main()
