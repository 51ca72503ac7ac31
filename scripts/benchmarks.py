#!/usr/bin/env python3
"""kerfab's benchmark (issue 18): runs the kerfab binary on the bundled and shared models and
writes docs/benchmarks.md with its plots (docs/images/bench-*.svg, drawn by gnuplot).

Every number in that file comes from one run of this script on the machine it names. Models
from ../shared/data/meshes are skipped (and listed as skipped) when that folder is absent.

  scripts/benchmarks.py [--quick] [--out-doc docs/benchmarks.md] [--limit S] [--from-runs]

--quick: two models and the scaling series to 2 Catmull-Clark steps (~2,900 quads); the extra
comparisons are left out; for trying the script, not for the docs.
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

ROOT = Path(__file__).resolve().parent.parent
KERFAB = ROOT / "build" / "kerfab"
SHARED = ROOT.parent / "shared" / "data" / "meshes"
EXAMPLES = ROOT / "examples"
WORK = ROOT / "build" / "benchmarks"
IMAGES = ROOT / "docs" / "images"
STAGES = ["load", "prepare", "quads", "bending", "strips", "flatten", "resolve", "joints",
          "kerf", "layout", "assembly", "quality"]


def log(*a):
    print("benchmarks:", *a, file=sys.stderr, flush=True)


def run(name, args, timeout=None):
    """One kerfab run into WORK/name: its report, wall time and peak memory (GNU time). A run
    still going after `timeout` seconds is stopped and recorded as such."""
    out = WORK / name
    if out.exists():
        shutil.rmtree(out)
    cmd = ["/usr/bin/time", "-f", "KERFAB_BENCH %M %e", str(KERFAB)] + args + ["--out", str(out)]
    log("run", name, " ".join(args))
    start = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        log(f"{name}: stopped after {timeout} s")
        return {"name": name, "args": args, "failed": "timeout", "wall": timeout}
    wall = time.monotonic() - start
    peak_kb = None
    for line in p.stderr.splitlines():
        if line.startswith("KERFAB_BENCH "):
            peak_kb = int(line.split()[1])
    report_path = out / "report.json"
    if p.returncode != 0 or not report_path.exists():
        tail = p.stderr.strip().splitlines()[-3:]
        log(f"{name}: exit {p.returncode}: " + " | ".join(tail))
        return {"name": name, "args": args, "failed": p.returncode, "wall": wall}
    report = json.loads(report_path.read_text())
    return {"name": name, "args": args, "report": report, "wall": wall,
            "peak_mb": peak_kb / 1024 if peak_kb else float("nan"), "failed": 0}


def shared(mesh):
    path = SHARED / mesh
    return str(path) if path.exists() else None


def fmt(x, digits=1):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "–"
    if isinstance(x, int):
        return str(x)
    return f"{x:.{digits}f}"


def failure(r, limit):
    """A table cell saying why run r has no report."""
    if r["failed"] == "timeout":
        return f"not finished after {fmt(limit, 0)} s"
    return f"run failed (exit {r['failed']})"


def header(L, *columns):
    """A markdown table's header row and its separator, one column per argument."""
    L.append("| " + " | ".join(columns) + " |")
    L.append("|" + "---|" * len(columns))


def gnuplot(script):
    subprocess.run(["gnuplot"], input=script, text=True, check=True)


def machine():
    cpu = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = ""
    try:
        kb = int(Path("/proc/meminfo").read_text().split()[1])
        mem = f", {kb / 1024 / 1024:.1f} GB RAM"
    except (OSError, ValueError, IndexError):
        pass
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip() or "unknown"
    return (f"{os.cpu_count()} hardware threads, {cpu}{mem}; {platform.system()} "
            f"{platform.release()}; kerfab {commit}; "
            f"{datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}")


def model_row(r):
    rep = r["report"]
    lay, q, cut, res = rep["layout"], rep["quality"], rep["cutting"], rep["resolve"]
    return {
        "quads": rep["input"]["quads"],
        "parts": len(lay["parts"]),
        "sheets": lay["sheets"],
        "lb": lay.get("sheets_lower_bound"),
        "lb_spaced": lay.get("sheets_lower_bound_spaced"),
        "util": lay["utilization"],
        "last": (lay.get("sheet_utilization") or [None])[-1],
        "unplaced": len(lay["unplaced"]),
        "critical": rep["kerf"]["critical_regions"],
        "critical_before": res.get("critical_before"),
        "hausdorff": 100 * q["hausdorff_rel"],
        "cut_m": cut["total_cut_length_mm"] / 1000,
        "minutes": cut["estimated_minutes"],
        "total_s": rep["timings_s"]["total"],
        "peak_mb": r["peak_mb"],
        "no_joint": rep["joints"].get("borders_without_joint"),
        "borders": rep["joints"].get("border_pieces"),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out-doc", default=str(ROOT / "docs" / "benchmarks.md"))
    ap.add_argument("--from-runs", action="store_true",
                    help="write the doc again from build/benchmarks/runs.json, running nothing")
    ap.add_argument("--limit", type=float, default=600,
                    help="stop a whole scaling run after this many seconds, a --no-resolve one "
                         "after twice that [s]")
    args = ap.parse_args()
    if args.from_runs:  # the doc again from the last run's results (no kerfab runs)
        runs = json.loads((WORK / "runs.json").read_text())
        write_doc(Path(args.out_doc), runs["model_runs"], runs["multi"],
                  [tuple(d) for d in runs["density"]], runs["scaling"], runs["whole"],
                  runs["skipped"], runs["quick"], runs["limit"], runs["machine"])
        return
    if not KERFAB.exists():
        sys.exit("benchmarks: build/kerfab is missing; run scripts/build.sh first")
    WORK.mkdir(parents=True, exist_ok=True)
    IMAGES.mkdir(parents=True, exist_ok=True)
    skipped = []

    # 1. Models at 250 mm on the default 600 x 450 mm sheet, 3 mm MDF.
    spot = str(EXAMPLES / "spot" / "spot_triangulated.obj")
    spot_quad = str(EXAMPLES / "spot" / "spot_control_mesh.obj")
    models = [
        ("spot (control mesh, 1 CC step)", "spot", ["run", "--target", spot, "--quad", spot_quad,
                                                      "--subdivide", "1"]),
        ("spot from its triangle mesh", "spot_tri", ["run", "--target", spot]),
        ("quad sphere (1 CC step)", "sphere", ["run", "--target", shared("quad-sphere.off"),
                                                "--subdivide", "1"]
         if shared("quad-sphere.off") else None),
        ("Amo (QuadriFlow quads)", "amo", ["run", "--target", shared("amo_quad.off")]
         if shared("amo_quad.off") else None),
        ("open surface (inspired, smooth quads)", "open",
         ["run", "--target", shared("inspired_mesh_quads_Smooth.off")]
         if shared("inspired_mesh_quads_Smooth.off") else None),
        ("bunny from its triangle mesh", "bunny", ["run", "--target",
                                                   shared("bunny_closed_odedstein.obj")]
         if shared("bunny_closed_odedstein.obj") else None),
    ]
    if args.quick:
        models = models[:2]
    model_runs = []
    for label, name, cmd in models:
        if cmd is None:
            skipped.append(label)
            continue
        r = run(name, cmd + ["--size", "250"])
        r["label"] = label
        model_runs.append(r)

    # 2. Multi-sheet jobs: the same parts on smaller sheets, and spot at twice the size.
    multi = []
    if not args.quick:
        jobs = [("spot, 500 mm, 600 x 450 sheets", "spot500",
                 ["run", "--target", spot, "--quad", spot_quad, "--subdivide", "1", "--size",
                  "500"]),
                ("spot, 250 mm, 300 x 300 sheets", "spot_300",
                 ["run", "--target", spot, "--quad", spot_quad, "--subdivide", "1", "--size",
                  "250", "--sheet", "300x300"])]
        if shared("quad-sphere.off"):
            jobs.append(("quad sphere, 250 mm, 300 x 300 sheets", "sphere_300",
                         ["run", "--target", shared("quad-sphere.off"), "--subdivide", "1",
                          "--size", "250", "--sheet", "300x300"]))
        if shared("amo_quad.off"):
            jobs.append(("Amo, 250 mm, 300 x 250 sheets", "amo_300",
                         ["run", "--target", shared("amo_quad.off"), "--size", "250", "--sheet",
                          "300x250"]))
        for label, name, cmd in jobs:
            r = run(name, cmd)
            r["label"] = label
            multi.append(r)

    # 3. Adaptive kerf density against the just-sufficient constant one: every quad gets as
    # many cuts as the adaptive run's most demanding quad (report kerf.max_cuts_per_quad).
    density = []
    if not args.quick:
        for r in model_runs:
            if r["failed"] or r["name"] not in ("spot", "sphere", "amo"):
                continue
            n = r["report"]["kerf"]["max_cuts_per_quad"]
            c = run(r["name"] + "_constant",
                    r["args"] + ["--constant-density", str(n)])
            density.append((r, c, n))

    # 4. Scaling: spot's control mesh with 1 to 4 Catmull-Clark steps (732 to 46,848 quads),
    # 500 mm so that the finest strips stay buildable: every stage without the resolve step
    # (--no-resolve) and on the mesh as given (--no-coarsen: each stage at that quad count),
    # then whole runs as a user makes them (coarsened, resolved), each stopped after `limit` s.
    steps = [1, 2] if args.quick else [1, 2, 3, 4]
    scaling = []
    for s in steps:
        r = run(f"scale_{s}_no_resolve",
                ["run", "--target", spot, "--quad", spot_quad, "--subdivide", str(s), "--size",
                 "500", "--no-resolve", "--no-coarsen"], timeout=2 * args.limit)
        r["steps"] = s
        scaling.append(r)
    whole = []
    for s in steps:
        r = run(f"scale_{s}", ["run", "--target", spot, "--quad", spot_quad, "--subdivide", str(s),
                               "--size", "500"], timeout=args.limit)
        r["steps"] = s
        whole.append(r)
        if r["failed"]:
            break  # finer meshes take longer still

    runs = {"model_runs": model_runs, "multi": multi, "density": density, "scaling": scaling,
            "whole": whole, "skipped": skipped, "quick": args.quick, "limit": args.limit,
            "machine": machine()}
    (WORK / "runs.json").write_text(json.dumps(runs))
    write_doc(Path(args.out_doc), model_runs, multi, density, scaling, whole, skipped,
              args.quick, args.limit, runs["machine"])


def write_doc(path, model_runs, multi, density, scaling, whole, skipped, quick, limit, where):
    L = []
    L.append("# Benchmarks")
    L.append("")
    L.append("Written by `scripts/benchmarks.sh` (README); every number below comes from the run "
             "named here, not by hand. Machine: " + where + ".")
    L.append("")
    L.append("All runs: 3 mm MDF, default options (600 x 450 mm sheets, 10 mm margins, 3 mm "
             "spacing, ILP time limit 60 s), `--size` as given. Times are wall-clock seconds from "
             "the report (`timings_s`); peak memory is the maximum resident set (GNU time). "
             "'Stages s' is the report's sum over the pipeline's stages; 'wall s' adds reading the "
             "files and writing every output (sheets, previews, pictures, guide). "
             "The machine is shared, so compare ratios rather than single seconds.")
    if skipped:
        L.append("")
        L.append("Skipped (mesh not found beside the repository): " + ", ".join(skipped) + ".")
    if quick:
        L.append("")
        L.append("**--quick run**: a subset only.")

    # The goals of issue 18, checked against this run.
    L.append("")
    L.append("## Goals against this run")
    L.append("")
    header(L, "goal", "measured", "met")
    demo = next((r for r in model_runs if r["name"] == "spot" and not r["failed"]), None)
    if demo:
        t = demo["report"]["timings_s"]
        L.append(f"| demo end to end under 2 s | {fmt(demo['wall'])} s wall, {fmt(t['total'])} s "
                 f"in the stages | {'yes' if demo['wall'] < 2 else 'no'} |")
        over = [f"{s} {100 * t[s] / t['total']:.0f} %" for s in STAGES
                if s != "bending" and t.get(s, 0.0) > 0.25 * t["total"]]
        L.append(f"| no stage above 25 % of the demo (bending excepted) | "
                 f"{', '.join(over) or 'none'} | {'no' if over else 'yes'} |")
    big = next((r for r in scaling if r["steps"] == 4), None)
    if big:
        if big["failed"]:
            L.append(f"| 47k quads under 60 s and 2 GB | {failure(big, 2 * limit)} "
                     f"(`--no-resolve`) | no |")
        else:
            ok = big["wall"] < 60 and big["peak_mb"] < 2048
            L.append(f"| 47k quads under 60 s and 2 GB | {fmt(big['wall'])} s, "
                     f"{fmt(big['peak_mb'], 0)} MB (`--no-resolve --no-coarsen`: every stage "
                     f"at 47k quads) | {'yes' if ok else 'no'} |")
    bigw = next((r for r in whole if r["steps"] == 4), None)
    if bigw and not bigw["failed"]:
        ok = bigw["wall"] < 60 and bigw["peak_mb"] < 2048
        q = bigw["report"].get("quads", {})
        L.append(f"| 47k quads under 60 s and 2 GB | {fmt(bigw['wall'])} s, "
                 f"{fmt(bigw['peak_mb'], 0)} MB (whole run as a user makes it: "
                 f"{q.get('given_quads', '?')} quads coarsened to {q.get('quads', '?')}, "
                 f"resolved) | {'yes' if ok else 'no'} |")
    timed = [r for r in model_runs + multi + scaling + whole if not r["failed"]]
    within = [r for r in timed if r["report"]["timings_s"].get("bending", 0.0)
              <= 1.1 * r["report"]["options"]["ilp_time_limit_s"]]
    L.append(f"| bending stage within its time limit + 10 % | {len(within)} of {len(timed)} runs "
             f"| {'yes' if len(within) == len(timed) else 'no'} |")
    def lay(r):
        return r["report"]["layout"]
    jobs = [r for r in model_runs + multi + scaling if not r["failed"] and lay(r)["sheets"] > 1]
    by_area = [r for r in jobs if lay(r)["sheets"] <= lay(r)["sheets_lower_bound"] + 1]
    by_spaced = [r for r in jobs if lay(r)["sheets"] <= lay(r)["sheets_lower_bound_spaced"] + 1]
    # The spaced bound is a lower bound too: where it is over the area bound + 1, no nesting
    # at this spacing meets the goal; where it equals it, only one at the spaced bound does.
    missed = [r for r in jobs if lay(r)["sheets"] > lay(r)["sheets_lower_bound"] + 1]
    beyond = [r for r in missed
              if lay(r)["sheets_lower_bound_spaced"] > lay(r)["sheets_lower_bound"] + 1]
    at_edge = [r for r in missed
               if lay(r)["sheets_lower_bound_spaced"] == lay(r)["sheets_lower_bound"] + 1]
    why = ""
    if beyond or at_edge:
        why = (f"; of the {len(missed)} others, {len(beyond)} cannot meet it at this spacing "
               f"(their spaced bound, itself a lower bound, is over the area bound + 1) and "
               f"{len(at_edge)} only with a nesting at their spaced bound")
    L.append(f"| multi-sheet jobs: sheets ≤ area bound + 1 | {len(by_area)} of {len(jobs)} "
             f"(≤ spaced bound + 1: {len(by_spaced)} of {len(jobs)}{why}) | "
             f"{'yes' if len(by_area) == len(jobs) else 'no'} |")

    # Models.
    L.append("")
    L.append("## Models at 250 mm")
    L.append("")
    header(L, "model", "quads", "parts", "critical regions before → after resolve",
           "Hausdorff % diag", "borders without joint", "cut length m", "cut time min", "sheets",
           "stages s", "wall s", "peak MB")
    for r in model_runs:
        if r["failed"]:
            L.append(f"| {r['label']} | run failed (exit {r['failed']}) |||||||||| ")
            continue
        m = model_row(r)
        L.append(f"| {r['label']} | {m['quads']} | {m['parts']} | {fmt(m['critical_before'])} → "
                 f"{m['critical']} | {fmt(m['hausdorff'], 2)} | {fmt(m['no_joint'])} of "
                 f"{fmt(m['borders'])} | {fmt(m['cut_m'])} | {fmt(m['minutes'])} | {m['sheets']} | "
                 f"{fmt(m['total_s'])} | {fmt(r['wall'])} | {fmt(m['peak_mb'], 0)} |")

    # Stage shares.
    L.append("")
    L.append("### Where the time goes")
    L.append("")
    L.append("Seconds per stage; **bold**: above 25 % of the run (the issue's limit, the bending "
             "program excepted where proven optimal).")
    L.append("")
    header(L, "model", *STAGES, "total")
    for r in model_runs:
        if r["failed"]:
            continue
        t = r["report"]["timings_s"]
        cells = []
        for s in STAGES:
            v = t.get(s, 0.0)
            c = fmt(v, 2)
            cells.append(f"**{c}**" if v > 0.25 * t["total"] else c)
        L.append(f"| {r['label']} | " + " | ".join(cells) + f" | {fmt(t['total'], 1)} |")

    # ILP time limit.
    L.append("")
    L.append("### The ILP time limit")
    L.append("")
    L.append("The bending stage (seams, rings, separation and CBC) against `--ilp-time-limit` "
             "(60 s): the promise is at most 10 % over.")
    L.append("")
    header(L, "run", "quads", "bending s", "ILP status", "within limit + 10 %")
    for r in model_runs + multi + scaling + whole:
        if r["failed"]:
            continue
        rep = r["report"]
        b = rep["timings_s"].get("bending", 0.0)
        ilp_limit = rep["options"]["ilp_time_limit_s"]
        label = r.get("label") or (f"spot, {r['steps']} CC steps, 500 mm"
                                   + (", --no-resolve" if "--no-resolve" in r["args"] else ""))
        L.append(f"| {label} | {rep['input']['quads']} | {fmt(b, 2)} | "
                 f"{rep['bending']['status']} | {'yes' if b <= 1.1 * ilp_limit else '**no**'} |")

    # Nesting.
    if multi or model_runs:
        L.append("")
        L.append("## Sheets against the lower bounds")
        L.append("")
        L.append("Area bound: the parts' area over one sheet's usable area (inside the margins), "
                 "rounded up — no nesting uses fewer sheets. Spaced bound: the same with every "
                 "part grown by half the spacing and the usable area alike (parts keep the "
                 "spacing apart, so the grown parts are disjoint); tighter, because box teeth give "
                 "parts long outlines. Utilisation: parts' area over the sheets' whole area; last "
                 "sheet: the same for the last sheet alone (it is filled last: what is left of it "
                 "is one offcut).")
        L.append("")
        header(L, "job", "parts", "sheets", "area bound", "spaced bound", "utilisation",
               "last sheet", "unplaced")
        for r in model_runs + multi:
            if r["failed"]:
                continue
            m = model_row(r)
            last = "" if m["last"] is None else f"{100 * m['last']:.0f} %"
            L.append(f"| {r['label']} | {m['parts']} | {m['sheets']} | {fmt(m['lb'])} | "
                     f"{fmt(m['lb_spaced'])} | {100 * m['util']:.0f} % | {last} | "
                     f"{m['unplaced']} |")

    # Density.
    if density:
        L.append("")
        L.append("## Adaptive kerf density against the just-sufficient constant density")
        L.append("")
        L.append("Constant: every quad gets the cut count of the adaptive run's most demanding "
                 "quad (`kerf.max_cuts_per_quad`), the least constant density that keeps every "
                 "beam within yield (the paper's baseline, Sec. 5).")
        L.append("")
        header(L, "model", "cuts per quad", "kerf cuts adaptive / constant",
               "cut length m adaptive / constant", "cut time min adaptive / constant",
               "critical regions after")
        for a, c, n in density:
            if c["failed"]:
                L.append(f"| {a['label']} | {n} | constant run failed (exit {c['failed']}) ||||")
                continue
            ka, kc = a["report"]["kerf"], c["report"]["kerf"]
            ca, cc = a["report"]["cutting"], c["report"]["cutting"]
            L.append(f"| {a['label']} | {n} | {ka['cuts']} / {kc['cuts']} | "
                     f"{fmt(ca['total_cut_length_mm'] / 1000)} / "
                     f"{fmt(cc['total_cut_length_mm'] / 1000)} | {fmt(ca['estimated_minutes'])} / "
                     f"{fmt(cc['estimated_minutes'])} | {ka['critical_regions']} / "
                     f"{kc['critical_regions']} |")

    # Scaling.
    ok = [r for r in scaling if not r["failed"]]
    if scaling:
        L.append("")
        L.append("## Scaling with the quad count")
        L.append("")
        L.append("Spot's control mesh with 1 to 4 Catmull-Clark steps, 500 mm. First every stage "
                 "of one pass through the pipeline on the mesh as given (`--no-resolve "
                 "--no-coarsen`: critical regions and small parts reported, not resolved):")
        L.append("")
        header(L, "CC steps", "quads", "parts", "sheets (spaced bound)", *STAGES, "stages s",
               "wall s", "peak MB")
        for r in scaling:
            if r["failed"]:
                L.append(f"| {r['steps']} | {failure(r, 2 * limit)} |")
                continue
            rep = r["report"]
            t = rep["timings_s"]
            lay = rep["layout"]
            L.append(f"| {r['steps']} | {rep['input']['quads']} | {len(lay['parts'])} | "
                     f"{lay['sheets']} ({fmt(lay.get('sheets_lower_bound_spaced'))}) | "
                     + " | ".join(fmt(t.get(s, 0.0), 2) for s in STAGES)
                     + f" | {fmt(t['total'])} | {fmt(r['wall'])} | {fmt(r['peak_mb'], 0)} |")
    if whole:
        L.append("")
        L.append("Then whole runs as a user makes them (the given mesh coarsened where its rows "
                 "are too narrow to bend, then the resolve step), each stopped "
                 f"after {fmt(limit, 0)} s; the next finer mesh is not tried once one stops:")
        L.append("")
        header(L, "CC steps", "quads given → used", "resolve rounds",
               "critical regions before → after", "parts", "quads s", "resolve s", "stages s",
               "wall s", "peak MB")
        for r in whole:
            if r["failed"]:
                L.append(f"| {r['steps']} | {failure(r, limit)} |")
                continue
            rep = r["report"]
            t, res = rep["timings_s"], rep["resolve"]
            given = rep.get("quads", {}).get("given_quads", rep["input"]["quads"])
            L.append(f"| {r['steps']} | {given} → {rep['input']['quads']} | {res['rounds']} | "
                     f"{res['critical_before']} → {res['critical_after']} | "
                     f"{len(rep['layout']['parts'])} | {fmt(t.get('quads', 0.0))} | "
                     f"{fmt(t.get('resolve', 0.0))} | "
                     f"{fmt(t['total'])} | {fmt(r['wall'])} | {fmt(r['peak_mb'], 0)} |")
    if ok:
        data = WORK / "scaling.dat"
        with data.open("w") as f:
            f.write("# quads total peak_mb " + " ".join(STAGES) + "\n")
            for r in ok:
                rep = r["report"]
                t = rep["timings_s"]
                f.write(f"{rep['input']['quads']} {t['total']} {r['peak_mb']} "
                        + " ".join(str(max(t.get(s, 0.0), 1e-3)) for s in STAGES) + "\n")
        if shutil.which("gnuplot") and len(ok) >= 2:
            plots = [f"'{data}' using 1:2 with linespoints lw 3 title 'total'"]
            for i, s in enumerate(STAGES):
                if any(r["report"]["timings_s"].get(s, 0.0) > 0.05 for r in ok):
                    plots.append(f"'{data}' using 1:{i + 4} with linespoints title '{s}'")
            gnuplot(f"""set terminal svg size 800,500 font 'sans,12' background rgb 'white'
set output '{IMAGES / 'bench-scaling-time.svg'}'
set logscale xy
set xlabel 'quads'
set ylabel 'seconds'
set key outside right
set grid
set title 'Time per stage against quad count (spot, 500 mm, --no-resolve)'
plot {', '.join(plots)}
""")
            gnuplot(f"""set terminal svg size 800,400 font 'sans,12' background rgb 'white'
set output '{IMAGES / 'bench-scaling-memory.svg'}'
set logscale x
set xlabel 'quads'
set ylabel 'peak resident memory [MB]'
set grid
set title 'Peak memory against quad count (spot, 500 mm, --no-resolve)'
plot '{data}' using 1:3 with linespoints lw 3 notitle
""")
            L.append("")
            L.append("![time per stage](images/bench-scaling-time.svg)")
            L.append("")
            L.append("![peak memory](images/bench-scaling-memory.svg)")
        elif not shutil.which("gnuplot"):
            L.append("")
            L.append("(gnuplot not found: no plots; `apt-get install gnuplot-nox`.)")

    path.write_text("\n".join(L) + "\n")
    log("wrote", path)


if __name__ == "__main__":
    main()
