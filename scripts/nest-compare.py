#!/usr/bin/python3
"""kerfab's nesting against a true-shape nester on the same parts (issue 18): writes
docs/nest-compare.md.

  scripts/nest-compare.py RUN_DIR[=LABEL] ...

Each RUN_DIR is a finished `kerfab run --out RUN_DIR`. Its parts' outlines (the laser paths, teeth
included) are read back from its written SVG sheets, and its sheet size, margin and spacing from
its report.json. The same outlines are then nested by libnest2d (Debian `python3-pynest2d`, the
no-fit-polygon nester Cura uses): quarter turns, bottom-left, the same spacing between parts, on
the sheet's usable area (inside its margins). Both sheet counts are put side by side with the area
bound (the parts' area over the usable area, rounded up) and each nester's time.

libnest2d is never a kerfab dependency: without it the script says so and stops. It runs with
Debian's /usr/bin/python3 (the module is built for it).
"""
import glob
import json
import math
import re
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from benchmarks import machine  # noqa: E402  (the machine named as in docs/benchmarks.md)
UNITS = 100  # libnest2d works in integers: 0.01 mm


def outlines(run):
    """Per part on the written sheets: its outline, the largest loop of its "outline" path [mm]."""
    parts = []
    for sheet in sorted(glob.glob(str(run / "cut" / "sheet-*.svg"))):
        text = Path(sheet).read_text()
        for m in re.finditer(r'<path class="outline"[^>]* d="([^"]*)"', text):
            loops, cur = [], []
            for tok in re.findall(r"[MLZ]|-?\d+\.?\d*(?:e-?\d+)?", m.group(1)):
                if tok == "M" or tok == "Z":
                    if cur:
                        loops.append(cur)
                    cur = []
                elif tok != "L":
                    cur.append(float(tok))
            if cur:
                loops.append(cur)
            best = None
            for loop in loops:
                pts = list(zip(loop[0::2], loop[1::2]))
                area = 0.5 * sum(pts[i][0] * pts[(i + 1) % len(pts)][1] -
                                 pts[(i + 1) % len(pts)][0] * pts[i][1] for i in range(len(pts)))
                if best is None or abs(area) > abs(best[0]):
                    best = (area, pts)
            if best:
                parts.append(best)
    return parts


def libnest2d_sheets(parts, usable_w, usable_h, spacing):
    import pynest2d as n2d
    items = []
    for area, pts in parts:
        # libnest2d takes outer contours clockwise (its area() is positive then).
        if area > 0:
            pts = pts[::-1]
        items.append(n2d.Item([n2d.Point(round(x * UNITS), round(y * UNITS)) for x, y in pts]))
    cfg = n2d.NfpConfig()
    cfg.alignment = n2d.NfpConfig.Alignment.BOTTOM_LEFT
    cfg.starting_point = n2d.NfpConfig.Alignment.BOTTOM_LEFT
    cfg.rotations = [k * math.pi / 2 for k in range(4)]
    # Parts keep the spacing apart; each takes half of it on every side, so the bin grows by it.
    box = n2d.Box(round((usable_w + spacing) * UNITS), round((usable_h + spacing) * UNITS))
    start = time.monotonic()
    sheets = n2d.nest(items, box, round(spacing * UNITS), cfg)
    return sheets, time.monotonic() - start


def main():
    try:
        import pynest2d  # noqa: F401
    except ImportError:
        print("nest-compare: libnest2d is not installed (apt-get install python3-pynest2d); "
              "nothing compared", file=sys.stderr)
        return 2
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    rows = []
    for arg in sys.argv[1:]:
        path, _, label = arg.partition("=")
        run = Path(path)
        report = json.loads((run / "report.json").read_text())
        lay = report["layout"]
        w, h = lay["sheet_mm"]
        margin, spacing = lay["margin_mm"], lay["spacing_mm"]
        uw, uh = w - 2 * margin, h - 2 * margin
        parts = outlines(run)
        area = sum(abs(a) for a, _ in parts)
        sheets, seconds = libnest2d_sheets(parts, uw, uh, spacing)
        rows.append((label or run.name, len(parts), f"{w:g} x {h:g}",
                     math.ceil(area / (uw * uh) - 1e-9), lay["sheets"],
                     report["timings_s"]["layout"], sheets, seconds))
        print(f"{rows[-1][0]}: kerfab {lay['sheets']} sheets, libnest2d {sheets} "
              f"({seconds:.1f} s)", file=sys.stderr)
    lines = [
        "# Nesting against a true-shape nester",
        "",
        f"Written by `scripts/nest-compare.py` (issue 18): {machine()}. The same parts (the "
        "laser paths read back from each run's sheets) nested by kerfab's layout stage and by "
        "libnest2d (Debian `python3-pynest2d`, its no-fit-polygon placer: quarter turns, "
        "bottom-left, the run's spacing between parts, on the sheet's "
        "usable area inside its margins). Area bound: the parts' area over the usable area, "
        "rounded up. kerfab's time is its whole layout stage (labels included); libnest2d's is "
        "its nest() call alone, single runs on a machine that may have been busy.",
        "",
        "| job | parts | sheet mm | area bound | kerfab sheets | kerfab s | libnest2d sheets "
        "| libnest2d s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for label, n, sheet, bound, ours, ours_s, theirs, theirs_s in rows:
        lines.append(f"| {label} | {n} | {sheet} | {bound} | {ours} | {ours_s:.2f} | {theirs} "
                     f"| {theirs_s:.1f} |")
    (ROOT / "docs" / "nest-compare.md").write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
