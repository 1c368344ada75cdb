#!/usr/bin/env python3
"""Meshes of growing size: sciray's BVH layouts against each other, and sciray against
OSPRay 3.1, on the peers' perturbed-gyroid isosurfaces (1M to 20M triangles).

    bench/peers/side_by_side.sh build OUT          # builds the clients and the 5M mesh
    /usr/bin/python3 bench/peers/mesh_scaling.py OUT [--sizes 188,420,594,840] [--tool build/examples/sciray]

For each grid size N (triangles grow as N^2; 420 gives 5.1M) the mesh is generated into
OUT/scenes once (Debian's python3-vtk9), then
  * the sciray tool renders it with --bvh fast, compact and dynamic (--json: engine bytes,
    BVH build ms, frame ms; 5 frames at 1024x1024, median);
  * the OSPRay C API client (OUT/bench_ospray, OUT/bench_sciray) renders it with scivis,
    one engine after the other: frame median, time to first image, peak RSS (GNU time).
Writes OUT/mesh_scaling.json and draws docs/images/performance_bvh_layouts.png and
docs/images/performance_mesh_scaling.png.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LAYOUTS = ["fast", "compact", "dynamic"]


def run_json(cmd, env=None):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env).stdout
    return json.loads(out.strip().splitlines()[-1])


def mesh(out, n, shared):
    name = f"iso-{n}"
    ply = os.path.join(out, "scenes", name + ".ply")
    if not os.path.exists(ply):
        subprocess.run([sys.executable, os.path.join(shared, "peers", "gen_iso.py"), os.path.join(out, "scenes"), name,
                        str(n), "3"], check=True)
    return ply, os.path.join(out, "scenes", name + ".camera.json")


def client(out, engine, ply, camera):
    time_file = os.path.join(out, "time.txt")
    run = run_json(["/usr/bin/time", "-f", "peak_kb %M", "-o", time_file, os.path.join(out, "bench_" + engine), "mesh",
                    ply, camera, "1024", "1024", "10", "scivis"])
    with open(time_file) as f:
        run["peak_kb"] = int(next(line.split()[1] for line in f if line.startswith("peak_kb")))
    return run


def measure(args):
    shared = os.environ.get("SHARED_DIR", os.path.join(ROOT, "..", "shared"))
    results = []
    for n in args.sizes:
        ply, camera = mesh(args.out, n, shared)
        row = {"grid": n, "layouts": {}, "clients": {}}
        for layout in LAYOUTS:
            r = run_json([args.tool, "render", ply, "--camera", camera, "--size", "1024x1024", "--frames", "5", "--bvh",
                          layout, "--json", "-o", os.path.join(args.out, "layout.png")])
            row["triangles"] = r["triangles"]
            row["layouts"][layout] = {"bytes_per_triangle": r["memory_bytes"]["total"] / r["triangles"],
                                      "bvh_build_ms": r["bvh_build_ms"],
                                      "frame_ms": statistics.median(r["frame_ms"][1:] or r["frame_ms"])}
        for engine in ("ospray", "sciray"):
            row["clients"][engine] = client(args.out, engine, ply, camera)
        print(json.dumps(row), flush=True)
        results.append(row)
    with open(os.path.join(args.out, "mesh_scaling.json"), "w") as f:
        json.dump(results, f, indent=1)
    return results


def draw(results, images):
    mtri = [r["triangles"] / 1e6 for r in results]
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    for layout in LAYOUTS:
        for ax, key in zip(axes, ["bytes_per_triangle", "frame_ms", "bvh_build_ms"]):
            ax.plot(mtri, [r["layouts"][layout][key] for r in results], "o-", label=layout)
    for ax, title in zip(axes, ["engine bytes per triangle (mesh + BVH)", "scivis frame, ms (1024², 2 threads)",
                                "BVH build, ms"]):
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("million triangles")
        ax.grid(alpha=0.3)
    axes[0].legend(title="--bvh")
    fig.tight_layout()
    fig.savefig(os.path.join(images, "performance_bvh_layouts.png"), dpi=110)

    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    for engine, label in [("sciray", "sciray"), ("ospray", "OSPRay 3.1")]:
        c = [r["clients"][engine] for r in results]
        axes[0].plot(mtri, [x["frame_ms_median"] for x in c], "o-", label=label)
        axes[1].plot(mtri, [x["time_to_first_image_ms"] / 1e3 for x in c], "o-", label=label)
        axes[2].plot(mtri, [x["peak_kb"] / 1024 for x in c], "o-", label=label)
    for ax, title in zip(axes, ["scivis frame, ms", "time to first image, s", "peak memory of the client, MB"]):
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("million triangles")
        ax.grid(alpha=0.3)
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(images, "performance_mesh_scaling.png"), dpi=110)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("out")
    p.add_argument("--sizes", default="188,420,594,840")
    p.add_argument("--tool", default=os.path.join(ROOT, "build", "examples", "sciray"))
    p.add_argument("--images", default=os.path.join(ROOT, "docs", "images"))
    p.add_argument("--redraw", action="store_true", help="draw OUT/mesh_scaling.json again without measuring")
    args = p.parse_args()
    args.sizes = [int(s) for s in args.sizes.split(",")]
    if args.redraw:
        with open(os.path.join(args.out, "mesh_scaling.json")) as f:
            results = json.load(f)
    else:
        results = measure(args)
    draw(results, args.images)


if __name__ == "__main__":
    main()
