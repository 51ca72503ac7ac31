"""Blender's QuadriFlow (Huang et al. 2018) on one triangle mesh, for scripts/quad-benchmark.py.

Run by Blender, headless (Debian's `blender`, never a kerfab dependency):
  blender -b --factory-startup --python scripts/quadriflow_remesh.py -- TARGET OUT.obj
      --faces N [--seed S] [--preserve-sharp]

TARGET (.obj or .off) is read here, not by Blender's importers, so that its frame and units are
kept exactly; OUT.obj gets `v` and `f` lines only. Prints `quadriflow_seconds T` (the remesh
alone) on stdout.
"""
import argparse
import os
import sys
import time

import bpy  # noqa: E402  (only inside Blender)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from meshfile import read_mesh  # noqa: E402


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="quadriflow_remesh.py")
    ap.add_argument("target")
    ap.add_argument("out")
    ap.add_argument("--faces", type=int, required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--preserve-sharp", action="store_true")
    args = ap.parse_args(argv)

    verts, faces = read_mesh(args.target)
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    mesh = bpy.data.meshes.new("target")
    mesh.from_pydata(verts, [], faces)
    mesh.validate()
    obj = bpy.data.objects.new("target", mesh)
    bpy.context.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)

    start = time.monotonic()
    result = bpy.ops.object.quadriflow_remesh(
        mode="FACES", target_faces=args.faces, seed=args.seed,
        use_preserve_sharp=args.preserve_sharp, use_preserve_boundary=True,
        use_mesh_symmetry=False, smooth_normals=False)
    seconds = time.monotonic() - start
    if "FINISHED" not in result:
        sys.exit(f"quadriflow_remesh.py: QuadriFlow failed on {args.target}: {result}")
    out_mesh = obj.data
    if len(out_mesh.polygons) == 0 or out_mesh is mesh and len(out_mesh.polygons) == len(faces):
        sys.exit(f"quadriflow_remesh.py: QuadriFlow left {args.target} unchanged")
    with open(args.out, "w") as f:
        f.write(f"# QuadriFlow (Blender {bpy.app.version_string}) of {args.target}: "
                f"{args.faces} faces, seed {args.seed}"
                f"{', preserve sharp' if args.preserve_sharp else ''}\n")
        for v in out_mesh.vertices:
            f.write(f"v {v.co.x:.6f} {v.co.y:.6f} {v.co.z:.6f}\n")
        for p in out_mesh.polygons:
            f.write("f " + " ".join(str(i + 1) for i in p.vertices) + "\n")
    print(f"quadriflow_seconds {seconds:.3f}")


main()
