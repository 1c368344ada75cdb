#!/usr/bin/env python3
"""Runs the speed and accuracy sweeps and draws the charts in docs/images.

    /usr/bin/python3 bench/charts.py [--build build] [--out docs/images] [--smoke]

Sweeps (each measured in one run on this machine):
  * accumulation: RMSE of the bunny against a 4x-longer converged rendering, against the
    time spent, for 1..64 accumulated frames, per ISA (the only approximate method the
    engine has so far: pixel sampling);
  * throughput: primary-ray frames per ISA and the raw-Embree baseline (Google Benchmark,
    process CPU time, 1M-triangle torus);
  * threads: speed-up of a frame with 1..N threads;
  * memory: bytes per triangle of mesh data and BVH;
  * volume: RMSE of a direct volume rendering (neghip) against one at 8x the highest
    sampling rate, against the sampling rate and the frame time: midpoint sampling with
    and without empty-space skipping, pre-integrated, and with adaptive step lengths.
--smoke runs each sweep tiny (the test suite does, so that the pipeline cannot rot) and
checks the results make sense. Writes charts.json with every figure next to the PNGs.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.environ.get("SCIRAY_DATA_DIR", os.path.join(HERE, "..", "..", "shared", "data"))


def read_pfm(path):
    with open(path, "rb") as f:
        magic = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if magic == b"PF" else 1
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, channels)


def tool(build, *args):
    out = subprocess.run([os.path.join(build, "examples", "sciray"), "render", *args, "--json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def supported_isas(build):
    info = subprocess.run([os.path.join(build, "examples", "sciray"), "info"], check=True, capture_output=True,
                          text=True).stdout
    return info.splitlines()[0].split(":")[1].split()


def accumulation_sweep(build, tmp, smoke):
    mesh = os.path.join(DATA, "meshes", "bunny.ply")
    size = "48x48" if smoke else "256x256"
    frame_counts = [1, 2, 4] if smoke else [1, 2, 4, 8, 16, 32, 64]
    reference_frames = 4 * frame_counts[-1]
    camera = os.path.join(tmp, "camera.json")
    with open(camera, "w") as f:
        json.dump({"position": [-0.02, 0.11, 0.25], "look_at": [-0.02, 0.11, 0.0], "up": [0, 1, 0], "fovy": 45}, f)
    reference_path = os.path.join(tmp, "reference.pfm")
    tool(build, mesh, "--camera", camera, "--size", size, "--frames", str(reference_frames), "-o", reference_path)
    reference = read_pfm(reference_path)
    results = {}
    for isa in supported_isas(build):
        points = []
        for frames in frame_counts:
            path = os.path.join(tmp, f"{isa}_{frames}.pfm")
            report = tool(build, mesh, "--camera", camera, "--size", size, "--frames", str(frames), "--isa", isa,
                          "-o", path)
            rmse = float(np.sqrt(np.mean((read_pfm(path) - reference) ** 2)))
            points.append({"frames": frames, "seconds": sum(report["frame_ms"]) / 1000, "rmse": rmse})
        results[isa] = points
    return {"size": size, "reference_frames": reference_frames, "curves": results}


def throughput_sweep(build, tmp, smoke):
    out = os.path.join(tmp, "bench.json")
    isas = "[^/]+" if not smoke else "scalar"
    pattern = f"frame/(raw_embree/intersect16/torus_1M/|scivis/{isas}/torus_1M_plain/color:1)"
    subprocess.run([os.path.join(build, "bench", "sciray_bench"), f"--benchmark_filter={pattern}",
                    "--benchmark_min_time=" + ("0.01" if smoke else "1"),
                    f"--benchmark_repetitions={1 if smoke else 3}", "--benchmark_report_aggregates_only=true",
                    f"--benchmark_out={out}", "--benchmark_out_format=json"], check=True, capture_output=True)
    with open(out) as f:
        report = json.load(f)
    rates = {}
    for b in report["benchmarks"]:
        if b.get("aggregate_name", "median") != "median":
            continue
        name = b["run_name"].removesuffix("/process_time")
        label = "raw Embree (16-wide)" if "raw_embree" in name else name.split("/")[2]
        rates[label] = b["items_per_second"] / 1e6
    return rates


def thread_sweep(build, tmp, smoke):
    threads = list(range(1, (os.cpu_count() or 1) + 1))
    size = "128x128" if smoke else "1024x1024"
    mesh = os.path.join(DATA, "meshes", "turbineblade.ply")
    points = []
    for t in threads:
        report = tool(build, mesh, "--size", size, "--frames", "3" if smoke else "10", "--threads", str(t),
                      "-o", os.path.join(tmp, "threads.png"))
        points.append({"threads": t, "ms": min(report["frame_ms"])})
    return points


def memory_sweep(build, tmp, smoke):
    points = []
    for name in (["footbones.ply"] if smoke else ["footbones.ply", "bunny.ply", "horse.ply", "turbineblade.ply"]):
        report = tool(build, os.path.join(DATA, "meshes", name), "--size", "8x8", "-o", os.path.join(tmp, "m.png"))
        triangles = report["triangles"]
        points.append({"mesh": name, "triangles": triangles,
                       "geometry_bytes_per_triangle": report["memory_bytes"]["geometry"] / triangles,
                       "bvh_bytes_per_triangle": report["memory_bytes"]["bvh"] / triangles})
    return points


def volume_sweep(build, tmp, smoke):
    volume = os.path.join(DATA, "volumes", "neghip_66x66x66_uint8.raw")
    size = "48x48" if smoke else "256x256"
    rates = [0.25, 0.5, 1.0] if smoke else [0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0]
    reference_rate = 8 * rates[-1]
    # A transfer function with narrow features, as isovalue-like highlighting makes them:
    # two opacity peaks 1/64 of the value range wide.
    tf = os.path.join(tmp, "tf.json")
    opacities = [0.0] * 65
    opacities[24], opacities[40] = 0.5, 1.0
    with open(tf, "w") as f:
        json.dump({"colors": [[0.2, 0.4, 1.0], [1.0, 0.9, 0.3], [1.0, 0.3, 0.1]], "opacities": opacities,
                   "range": [0, 255]}, f)
    common = ["--size", size, "--tf", tf, "--density", "2"]
    reference_path = os.path.join(tmp, "volume_reference.pfm")
    # The same 3 accumulated frames (pixel jitter) as the sweep, so only sampling differs.
    tool(build, volume, *common, "--sampling-rate", str(reference_rate), "--frames", "3", "-o", reference_path)
    reference = read_pfm(reference_path)
    curves = {}
    for label, extra in [("empty-space skipping", []), ("every sample", ["--no-empty-space-skipping"]),
                         ("pre-integrated", ["--preintegration"]), ("adaptive", ["--adaptive-sampling"])]:
        points = []
        for rate in rates:
            path = os.path.join(tmp, f"volume_{rate}.pfm")
            report = tool(build, volume, *common, "--sampling-rate", str(rate), "--frames", "3", "-o", path, *extra)
            rmse = float(np.sqrt(np.mean((read_pfm(path) - reference) ** 2)))
            points.append({"rate": rate, "ms": min(report["frame_ms"]), "rmse": rmse})
        curves[label] = points
    return {"size": size, "reference_rate": reference_rate, "curves": curves}


def draw(results, out):
    fig, ax = plt.subplots(figsize=(6, 4))
    for isa, points in results["accumulation"]["curves"].items():
        ax.loglog([p["seconds"] for p in points], [p["rmse"] for p in points], "o-", label=isa)
    ax.set_xlabel("render time (s, sum of frames)")
    ax.set_ylabel("RMSE against converged image")
    ax.set_title("Pixel sampling: error against time (bunny, scivis)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "accuracy_accumulation.png"), dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6, 3.5))
    labels = list(results["throughput"].keys())
    ax.bar(labels, [results["throughput"][k] for k in labels], color="#3b7dd8")
    ax.set_ylabel("Mrays/s (per CPU second)")
    ax.set_title("Primary-ray frames, 1M-triangle torus")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "performance_isa.png"), dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(5, 3.5))
    points = results["threads"]
    base = points[0]["ms"]
    ax.plot([p["threads"] for p in points], [base / p["ms"] for p in points], "o-", label="measured")
    ax.plot([p["threads"] for p in points], [p["threads"] for p in points], "--", label="linear")
    ax.set_xlabel("threads")
    ax.set_ylabel("speed-up")
    ax.set_title("Thread scaling (turbine blade, 1024²)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "performance_threads.png"), dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6, 3.5))
    mem = results["memory"]
    names = [m["mesh"].removesuffix(".ply") for m in mem]
    ax.bar(names, [m["geometry_bytes_per_triangle"] for m in mem], label="mesh data")
    ax.bar(names, [m["bvh_bytes_per_triangle"] for m in mem],
           bottom=[m["geometry_bytes_per_triangle"] for m in mem], label="BVH (Embree)")
    ax.set_ylabel("bytes per triangle")
    ax.set_title("Memory per primitive")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "performance_memory.png"), dpi=100)
    plt.close(fig)


def draw_volume(results, out):
    fig, (by_rate, by_time) = plt.subplots(1, 2, figsize=(10, 4))
    for label, points in results["volume"]["curves"].items():
        by_rate.loglog([p["rate"] for p in points], [p["rmse"] for p in points], "o-", label=label)
        by_time.loglog([p["ms"] for p in points], [p["rmse"] for p in points], "o-", label=label)
    by_rate.set_xlabel("volumeSamplingRate (samples per cell)")
    by_time.set_xlabel("frame time (ms, 2 threads)")
    for ax in (by_rate, by_time):
        ax.set_ylabel("RMSE against a converged rendering")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle("Direct volume rendering: error against sampling rate and time (neghip)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "accuracy_volume.png"), dpi=100)
    plt.close(fig)


def check_smoke(results):
    problems = []
    for label, points in results["volume"]["curves"].items():
        if not points[-1]["rmse"] < points[0]["rmse"]:
            problems.append(f"volume, {label}: error does not fall with the sampling rate: {points}")
    for isa, points in results["accumulation"]["curves"].items():
        if not points[-1]["rmse"] < points[0]["rmse"]:
            problems.append(f"{isa}: error does not fall with more frames: {points}")
    if not all(rate > 0 for rate in results["throughput"].values()) or len(results["throughput"]) < 2:
        problems.append(f"throughput: {results['throughput']}")
    if any(m["bvh_bytes_per_triangle"] <= 0 for m in results["memory"]):
        problems.append(f"memory: {results['memory']}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(HERE, "..", "build"))
    parser.add_argument("--out", default=os.path.join(HERE, "..", "docs", "images"))
    parser.add_argument("--smoke", action="store_true")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        results = {
            "accumulation": accumulation_sweep(args.build, tmp, args.smoke),
            "throughput": throughput_sweep(args.build, tmp, args.smoke),
            "threads": thread_sweep(args.build, tmp, args.smoke),
            "memory": memory_sweep(args.build, tmp, args.smoke),
            "volume": volume_sweep(args.build, tmp, args.smoke),
        }
    draw(results, args.out)
    draw_volume(results, args.out)
    with open(os.path.join(args.out, "charts.json"), "w") as f:
        json.dump(results, f, indent=1)
    problems = check_smoke(results)
    for p in problems:
        print("charts: " + p, file=sys.stderr)
    print(f"charts written to {args.out}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
