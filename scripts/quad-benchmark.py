#!/usr/bin/env python3
"""kerfab's quad meshes against Blender's QuadriFlow at equal quad counts (issue 15): writes
docs/quad-benchmark.md.

  scripts/quad-benchmark.py [--counts 400 1500] [--models spot bob ...] [--from-runs]

For every model and count: kerfab makes its own quad mesh (`--quads N`) and runs the whole
pipeline; QuadriFlow (Debian `blender`, headless, scripts/quadriflow_remesh.py) is asked for as
many faces as kerfab's mesh has (up to four tries, to within 5 %) and its mesh runs the same
pipeline with `--quad`. The meshes are measured here, from the written OBJ files (irregular
vertices, corner angles in 3D), the rest read from each run's report.json. Without Blender the
QuadriFlow columns are left out and the doc says so: Blender is never a kerfab dependency.
"""
import argparse
import datetime
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from benchmarks import fmt  # noqa: E402
from meshfile import read_mesh  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
KERFAB = ROOT / "build" / "kerfab"
SHARED = ROOT.parent / "shared" / "data" / "meshes"
WORK = ROOT / "build" / "quad-benchmark"
MODELS = {
    "spot": ROOT / "examples" / "spot" / "spot_triangulated.obj",
    "bob": SHARED / "bob_tri.obj",
    "bunny": SHARED / "bunny_closed_odedstein.obj",
    "fertility": SHARED / "fertility.off",
    "rocker-arm": SHARED / "rocker-arm.obj",
}


def log(*a):
    print("quad-benchmark:", *a, file=sys.stderr, flush=True)


def mesh_metrics(path):
    """All-quad?, irregular vertices (inner valence != 4, border valence != 3), corner angles:
    mean |angle - 90 deg| and the share of corners outside 45..135 deg, measured in 3D."""
    verts, faces = read_mesh(path)
    edge_faces = {}
    for f in faces:
        for i in range(len(f)):
            e = tuple(sorted((f[i], f[(i + 1) % len(f)])))
            edge_faces[e] = edge_faces.get(e, 0) + 1
    valence, border = {}, set()
    for (a, b), n in edge_faces.items():
        valence[a] = valence.get(a, 0) + 1
        valence[b] = valence.get(b, 0) + 1
        if n == 1:
            border.update((a, b))
    irregular = sum(1 for v, k in valence.items() if k != (3 if v in border else 4))
    deviations, bad = [], 0
    for f in faces:
        n = len(f)
        for i in range(n):
            p, c, q = verts[f[i - 1]], verts[f[i]], verts[f[(i + 1) % n]]
            u = [p[k] - c[k] for k in range(3)]
            w = [q[k] - c[k] for k in range(3)]
            nu, nw = math.sqrt(sum(x * x for x in u)), math.sqrt(sum(x * x for x in w))
            if nu == 0 or nw == 0:
                angle = 0.0
            else:
                cos = sum(u[k] * w[k] for k in range(3)) / (nu * nw)
                angle = math.degrees(math.acos(max(-1.0, min(1.0, cos))))
            deviations.append(abs(angle - 90))
            bad += angle < 45 or angle > 135
    return {"faces": len(faces), "all_quads": all(len(f) == 4 for f in faces),
            "vertices": len(valence), "irregular": irregular,
            "angle_dev": sum(deviations) / max(1, len(deviations)),
            "bad_corners": 100.0 * bad / max(1, len(deviations))}


def draw_quads(path, svg, view=(1.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), width=420):
    """An orthographic view of the quad mesh at `path` seen from +view with `up` up (back
    faces culled, far faces first), irregular vertices marked: valence 3 blue, 5 red, others
    magenta."""
    verts, faces = read_mesh(path)
    nb = {}
    for f in faces:
        for i in range(len(f)):
            a, b = f[i], f[(i + 1) % len(f)]
            nb.setdefault(a, set()).add(b)
            nb.setdefault(b, set()).add(a)
    border = set()
    count = {}
    for f in faces:
        for i in range(len(f)):
            e = tuple(sorted((f[i], f[(i + 1) % len(f)])))
            count[e] = count.get(e, 0) + 1
    for e, n in count.items():
        if n == 1:
            border.update(e)

    def cross(a, b):
        return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])

    def dot(a, b):
        return sum(x * y for x, y in zip(a, b))

    d = view
    r = cross(up, d)
    u = cross(d, r)
    P = [(dot(v, r), -dot(v, u), dot(v, d)) for v in verts]
    xs, ys = [p[0] for p in P], [p[1] for p in P]
    x0, y0 = min(xs), min(ys)
    scale = (width - 20) / max(max(xs) - x0, max(ys) - y0)
    height = (max(ys) - y0) * scale + 20

    def xy(i):
        return f"{(P[i][0] - x0) * scale + 10:.1f},{(P[i][1] - y0) * scale + 10:.1f}"

    shown = []
    for f in faces:
        c = [verts[i] for i in f]
        n = [0.0, 0.0, 0.0]
        for i in range(len(c)):
            a, b = c[i], c[(i + 1) % len(c)]
            n[0] += (a[1] - b[1]) * (a[2] + b[2])
            n[1] += (a[2] - b[2]) * (a[0] + b[0])
            n[2] += (a[0] - b[0]) * (a[1] + b[1])
        if dot(n, d) > 0:
            shown.append((sum(P[i][2] for i in f) / len(f), f))
    shown.sort()
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height:.0f}">',
           '<rect width="100%" height="100%" fill="white"/>']
    marks = set()
    for _, f in shown:
        out.append(f'<polygon points="{" ".join(xy(i) for i in f)}" fill="#e4e6ef" '
                   'stroke="#333" stroke-width="0.6"/>')
        marks.update(f)
    for i in sorted(marks):
        k = len(nb[i])
        if k != (3 if i in border else 4):
            colour = {3: "#1f4fd6", 5: "#d61f1f"}.get(k, "#c41fd6")
            x, y = xy(i).split(",")
            out.append(f'<circle cx="{x}" cy="{y}" r="3" fill="{colour}"/>')
    out.append("</svg>")
    Path(svg).write_text("\n".join(out) + "\n")


def kerfab_run(name, args, timeout):
    out = WORK / name
    if out.exists():
        shutil.rmtree(out)
    cmd = [str(KERFAB)] + args + ["--size", "250", "--out", str(out)]
    log("run", name, " ".join(args))
    start = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"failed": f"not finished after {timeout:.0f} s"}
    wall = time.monotonic() - start
    report = out / "report.json"
    if p.returncode != 0 or not report.exists():
        tail = " | ".join(p.stderr.strip().splitlines()[-2:])
        log(f"{name}: exit {p.returncode}: {tail}")
        return {"failed": f"exit {p.returncode}: {tail}"}
    r = json.loads(report.read_text())
    res = r["resolve"]
    return {
        "out": str(out), "wall": wall, "status": r["status"],
        "quads_s": r["timings_s"].get("quads"),
        "patches": r["strips"]["patches"],
        "critical_before": res.get("critical_before"),
        "critical_after": r["kerf"]["critical_regions"],
        "parts": len(r["layout"]["parts"]),
        "unplaced": len(r["layout"]["unplaced"]) + len(r["layout"].get("empty", [])),
        "hausdorff": 100 * r["quality"]["hausdorff_rel"],
        "mean": 100 * r["quality"]["mean_distance_rel"],
        "minutes": r["cutting"]["estimated_minutes"],
        "no_joint": r["joints"].get("borders_without_joint"),
        "borders": r["joints"].get("border_pieces"),
        "total_s": r["timings_s"]["total"],
    }


def quadriflow(target, faces, out):
    """QuadriFlow asked for `faces` faces; (seconds of the remesh alone, faces made) or None."""
    cmd = ["blender", "-b", "--factory-startup", "--python",
           str(ROOT / "scripts" / "quadriflow_remesh.py"), "--", str(target), str(out),
           "--faces", str(faces), "--seed", "0"]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    seconds = None
    for line in p.stdout.splitlines():
        if line.startswith("quadriflow_seconds "):
            seconds = float(line.split()[1])
    if p.returncode != 0 or seconds is None or not Path(out).exists():
        log(f"QuadriFlow failed on {target}: " + " | ".join(p.stdout.strip().splitlines()[-3:]))
        return None
    return seconds, mesh_metrics(out)["faces"]


def machine():
    cpu = "unknown CPU"
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip() or "unknown"
    blender = "absent"
    if shutil.which("blender"):
        v = subprocess.run(["blender", "--version"], capture_output=True, text=True).stdout
        blender = v.splitlines()[0] if v else "present"
    return (f"{os.cpu_count()} hardware threads, {cpu}; {platform.system()} {platform.release()}; "
            f"kerfab {commit}; {blender}; "
            f"{datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}")


def write_doc(path, rows, where, have_blender):
    L = ["# Quad meshes: kerfab's own against QuadriFlow", "",
         "Written by `scripts/quad-benchmark.py` (one command; about 10 minutes) on " + where +
         ". Every model at 250 mm, 3 mm MDF, the default 600 × 450 mm sheet. For each model and "
         "requested count, kerfab makes its quad mesh (`--quads N`) and QuadriFlow (Blender's, "
         "headless, `scripts/quadriflow_remesh.py`, seed 0) is asked for as many faces as "
         "kerfab's mesh has; both meshes then run the whole pipeline (the QuadriFlow one with "
         "`--quad`).", "",
         "Mesh columns are measured by the script from the written OBJ files: irregular vertices "
         "(inner valence ≠ 4), angle distortion (mean |corner − 90°| in 3D) and the share of "
         "corners outside 45–135°. Time is the meshing alone (kerfab's `quads` stage; "
         "QuadriFlow's operator). The rest is read from each run's report: parts (the strips "
         "stage's patches after the resolve stage), critical regions before and after the resolve "
         "stage, parts not on a sheet (unplaced or empty), Hausdorff and mean distance of the strips to the target "
         "(% of the diagonal), estimated cut time, borders without a joint, whole-run time.", ""]
    pictures = [row for row in rows if row["model"] == "spot" and row["asked"] == 400
                and row.get("QuadriFlow") and "failed" not in row["QuadriFlow"]
                and "failed" not in row["kerfab"]]
    if pictures:
        row = pictures[0]
        images = Path(path).parent / "images"
        images.mkdir(parents=True, exist_ok=True)
        draw_quads(Path(row["kerfab"]["run"]["out"]) / "model" / "quads.obj",
                   images / "quads-spot-kerfab.svg")
        draw_quads(WORK / "spot_400_qf.obj", images / "quads-spot-quadriflow.svg")
        g, q = row["kerfab"]["mesh"], row["QuadriFlow"]["mesh"]
        L += [f"![kerfab's quad mesh of Spot, {g['faces']} quads](images/quads-spot-kerfab.svg) "
              f"![QuadriFlow's quad mesh of Spot, {q['faces']} quads]"
              "(images/quads-spot-quadriflow.svg)", "",
              f"*Spot asked for about 400 quads, seen from the side: kerfab's mesh ({g['faces']} "
              f"quads, {g['irregular']} irregular vertices) left, QuadriFlow's ({q['faces']} "
              f"quads, {q['irregular']}) right; valence 3 blue, 5 red, others magenta. Both "
              "whole runs are in the table below.*", ""]
    if not have_blender:
        L += ["Blender was absent on this machine, so the QuadriFlow rows are missing "
              "(`apt-get install blender` adds them; it is never a kerfab dependency).", ""]
    L.append("| model | asked | mesher | quads | irregular | angle dev. ° | corners off % | "
             "mesh s | parts | critical before → after | not on sheet | Hausdorff % | "
             "mean % | cut min | no joint | run s |")
    L.append("|" + "---|" * 16)
    for row in rows:
        for mesher in ("kerfab", "QuadriFlow"):
            m = row.get(mesher)
            if m is None:
                continue
            cells = [row["model"], str(row["asked"]), mesher]
            if "failed" in m:
                cells += [m["failed"]] + [""] * 13
                L.append("| " + " | ".join(cells) + " |")
                continue
            g, r = m["mesh"], m["run"]
            cells += [str(g["faces"]) + ("" if g["all_quads"] else " (not all quads)"),
                      str(g["irregular"]), fmt(g["angle_dev"]), fmt(g["bad_corners"]),
                      fmt(m["mesh_s"])]
            if "failed" in r:
                cells += [r["failed"]] + [""] * 7
            else:
                cells += [str(r["parts"]),
                          f"{fmt(r['critical_before'])} → {fmt(r['critical_after'])}",
                          str(r["unplaced"]), fmt(r["hausdorff"], 2),
                          fmt(r["mean"], 3), fmt(r["minutes"], 0),
                          f"{fmt(r['no_joint'])} of {fmt(r['borders'])}", fmt(r["total_s"], 0)]
            L.append("| " + " | ".join(cells) + " |")
    # Totals over the rows where both ran.
    both = [row for row in rows if row.get("QuadriFlow") and "failed" not in row["QuadriFlow"]
            and "failed" not in row["QuadriFlow"]["run"] and "failed" not in row["kerfab"]
            and "failed" not in row["kerfab"]["run"]]
    if both:
        L += ["", f"Over the {len(both)} model/count pairs where both ran:", ""]
        L.append("| | kerfab | QuadriFlow |")
        L.append("|---|---|---|")

        def total(key, source):
            return sum(row[m][source][key] for row in both for m in ("kerfab",)), \
                sum(row["QuadriFlow"][source][key] for row in both)

        for label, key, source, digits in [
                ("quads", "faces", "mesh", 0), ("irregular vertices", "irregular", "mesh", 0),
                ("critical regions before resolve", "critical_before", "run", 0),
                ("critical regions after resolve", "critical_after", "run", 0),
                ("parts", "parts", "run", 0), ("not on a sheet", "unplaced", "run", 0)]:
            a, b = total(key, source)
            L.append(f"| {label} | {fmt(int(a)) if digits == 0 else fmt(a)} | "
                     f"{fmt(int(b)) if digits == 0 else fmt(b)} |")
        closer = sum(1 for row in both
                     if row["kerfab"]["run"]["hausdorff"] <= row["QuadriFlow"]["run"]["hausdorff"])
        L.append(f"| strips at least as close to the target (Hausdorff) | {closer} of "
                 f"{len(both)} | {len(both) - closer} of {len(both)} |")
    Path(path).write_text("\n".join(L) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--counts", type=int, nargs="+", default=[400, 1500])
    ap.add_argument("--models", nargs="+", default=list(MODELS))
    ap.add_argument("--limit", type=float, default=900, help="stop a run after this long [s]")
    ap.add_argument("--out-doc", default=str(ROOT / "docs" / "quad-benchmark.md"))
    ap.add_argument("--from-runs", action="store_true",
                    help="write the doc again from build/quad-benchmark/runs.json")
    args = ap.parse_args()
    if args.from_runs:
        runs = json.loads((WORK / "runs.json").read_text())
        write_doc(args.out_doc, runs["rows"], runs["machine"], runs["blender"])
        return
    if not KERFAB.exists():
        sys.exit("quad-benchmark: build/kerfab is missing; run scripts/build.sh first")
    have_blender = shutil.which("blender") is not None
    if not have_blender:
        log("blender is absent: the QuadriFlow column is left out")
    WORK.mkdir(parents=True, exist_ok=True)
    where = machine()
    rows = []
    for model in args.models:
        target = MODELS[model]
        if not target.exists():
            log(f"{model}: {target} is missing, skipped")
            continue
        for asked in args.counts:
            row = {"model": model, "asked": asked}
            name = f"{model}_{asked}"
            k = kerfab_run(f"{name}_kerfab", ["run", "--target", str(target), "--quads",
                                               str(asked)], args.limit)
            if "failed" in k:
                row["kerfab"] = {"failed": k["failed"]}
                rows.append(row)
                continue
            kmesh = mesh_metrics(Path(k["out"]) / "model" / "quads.obj")
            row["kerfab"] = {"mesh": kmesh, "mesh_s": k["quads_s"], "run": k}
            if have_blender:
                want, qf_path, made = kmesh["faces"], WORK / f"{name}_qf.obj", None
                ask = want
                for _ in range(4):  # QuadriFlow makes fewer faces than asked: aim again
                    made = quadriflow(target, ask, qf_path)
                    if made is None or abs(made[1] - want) <= 0.05 * want:
                        break
                    ask = max(4, round(ask * want / max(1, made[1])))
                if made is None:
                    row["QuadriFlow"] = {"failed": "QuadriFlow failed"}
                else:
                    q = kerfab_run(f"{name}_qf", ["run", "--target", str(target), "--quad",
                                                  str(qf_path)], args.limit)
                    row["QuadriFlow"] = {"mesh": mesh_metrics(qf_path), "mesh_s": made[0],
                                         "run": q}
            rows.append(row)
            (WORK / "runs.json").write_text(json.dumps(
                {"rows": rows, "machine": where, "blender": have_blender}))
            write_doc(args.out_doc, rows, where, have_blender)
    (WORK / "runs.json").write_text(json.dumps(
        {"rows": rows, "machine": where, "blender": have_blender}))
    write_doc(args.out_doc, rows, where, have_blender)


if __name__ == "__main__":
    main()
