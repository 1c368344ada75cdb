#!/usr/bin/env python3
"""Runs the speed and accuracy sweeps and draws the charts in docs/images.

    /usr/bin/python3 bench/charts.py [--build build] [--out docs/images] [--smoke]
                                     [--sweeps renderers,ao_samples,bounces] [--redraw]

Sweeps (each measured in one run on this machine):
  * accumulation: RMSE of the bunny against a 4x-longer converged rendering, against the
    time spent, for 1..64 accumulated frames, per ISA (pixel sampling, which every
    renderer shares);
  * throughput: primary-ray frames per ISA and the raw-Embree baseline (Google Benchmark,
    process CPU time, 1M-triangle torus);
  * threads: speed-up of a frame with 1..N threads;
  * memory: bytes per triangle of mesh data and BVH;
  * volume: RMSE of a direct volume rendering (neghip) against one at 8x the highest
    sampling rate, against the sampling rate and the frame time: midpoint sampling with
    and without empty-space skipping, pre-integrated, and with adaptive step lengths;
  * renderers: RMSE against time on the Cornell box (128x128, one sample per pixel a
    frame, accumulated; one thread's CPU time) of the path tracer (MIS, light sampling
    only, BSDF sampling only), scivis with shadows and AO, and ao, each against its
    own converged reference (16x the sweep's longest run, rendered here; the three path
    tracers share the MIS reference: each alone is unbiased);
  * ao_samples: the ao renderer with aoSamples 1..16 a frame, against one reference
    (aoSamples 16, 4x the sweep's longest run);
  * bounces: the path tracer at maxPathLength 1..8 against the maxPathLength-20
    reference of `renderers`: RMSE, light missing and time per frame;
  * volume_lights: RMSE against time of the path tracer in a scattering volume (neghip,
    albedo 0.8, anisotropy 0.5, a sphere light with size, maxPathLength 8) with MIS,
    light sampling only and phase-function sampling only, against one MIS reference at
    16x the sweep's longest run; and how much light single scattering (maxPathLength 1)
    misses.
The renderer sweeps run bench/render_sweep.cpp (build/bench/sciray_render_sweep).
--smoke runs each sweep tiny (the test suite does, so that the pipeline cannot rot) and
checks the results make sense. --sweeps picks sweeps (comma-separated; charts.json keeps
the other sweeps' figures, and only the picked sweeps' charts are drawn). Writes
charts.json with every figure next to the PNGs.
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


# Renderer convergence on the Cornell box: its quad light (plus an ambient light of 0.3
# for scivis, whose AO darkens only ambient light), AO rays 200 mm long (a third of the
# box; unbounded AO rays in a closed box would all be blocked).
CORNELL_AO = ["--ao-distance", "200"]
RENDERER_CURVES = [
    ("pathtracer (MIS)", "pathtracer", ["--renderer", "pathtracer", "--light-sampling", "mis"]),
    ("pathtracer, light sampling only", "pathtracer", ["--renderer", "pathtracer", "--light-sampling", "lights_only"]),
    ("pathtracer, BSDF sampling only", "pathtracer", ["--renderer", "pathtracer", "--light-sampling", "bsdf_only"]),
    ("scivis, shadows + AO", "scivis",
     ["--renderer", "scivis", "--shadows", "--ao-samples", "1", "--ambient", "0.3", *CORNELL_AO]),
    ("ao (aoSamples 1)", "ao", ["--renderer", "ao", "--ao-samples", "1", *CORNELL_AO]),
]


def render_sweep(build, tmp, tag, args, frames, size):
    """Runs sciray_render_sweep; returns its checkpoints, each with the image loaded."""
    # One thread: its CPU time is the work alone, whatever else runs on the machine (two
    # threads' CPU time also counts a worker waiting for the other's last tile).
    out = subprocess.run([os.path.join(build, "bench", "sciray_render_sweep"), "--scene", "cornell_box", "--size",
                          size, "--threads", "1", "--checkpoints", ",".join(map(str, frames)), "--out",
                          os.path.join(tmp, tag + "_"), *args], check=True, capture_output=True, text=True).stdout
    report = json.loads(out)
    for c in report["checkpoints"]:
        c["isa"] = report["isa"]
        c["image"] = read_pfm(c.pop("file"))
        os.remove(os.path.join(tmp, f"{tag}_{c['frames']}.pfm"))
    return report["checkpoints"]


def errors(image, reference):
    """RMSE of the linear RGB image clamped to [0, 1] (what a display shows; the light's
    own pixels would otherwise dominate), and unclamped."""
    clamped = np.sqrt(np.mean((np.clip(image, 0, 1) - np.clip(reference, 0, 1)) ** 2))
    return float(clamped), float(np.sqrt(np.mean((image - reference) ** 2)))


def convergence(build, tmp, tag, args, frames, reference, size):
    points = []
    for c in render_sweep(build, tmp, tag, args, frames, size):
        rmse, rmse_unclamped = errors(c["image"], reference)
        points.append({"frames": c["frames"], "cpu_s": c["cpu_s"], "wall_s": c["wall_s"], "rmse": rmse,
                       "rmse_unclamped": rmse_unclamped})
    return points


def at_time(points, seconds):
    """RMSE at `seconds` of render time, interpolated log-log between checkpoints (None
    outside the measured range)."""
    for a, b in zip(points, points[1:]):
        if a["cpu_s"] <= seconds <= b["cpu_s"]:
            f = np.log(seconds / a["cpu_s"]) / np.log(b["cpu_s"] / a["cpu_s"])
            return float(np.exp(np.log(a["rmse"]) + f * (np.log(b["rmse"]) - np.log(a["rmse"]))))
    return None


def renderers_sweep(build, tmp, smoke):
    size = "32x32" if smoke else "128x128"
    frames = [1, 16, 256] if smoke else [2 ** k for k in range(11)]
    reference_frames = 16 * frames[-1]
    references, reference_info = {}, {}
    for _, kind, args in RENDERER_CURVES:
        if kind not in references:
            ref = render_sweep(build, tmp, "ref_" + kind, args, [reference_frames], size)[0]
            references[kind] = ref["image"]
            reference_info[kind] = {"frames": reference_frames, "cpu_s": ref["cpu_s"]}
            isa = ref["isa"]
    curves = {}
    for label, kind, args in RENDERER_CURVES:
        points = convergence(build, tmp, "curve", args, frames, references[kind], size)
        curves[label] = {"reference": kind, "points": points, "rmse_at_1s": at_time(points, 1.0)}
    return {"size": size, "isa": isa, "references": reference_info, "curves": curves,
            "pathtracer_reference": references["pathtracer"]}


def ao_samples_sweep(build, tmp, smoke):
    size = "32x32" if smoke else "128x128"
    counts = [1, 4] if smoke else [1, 2, 4, 8, 16]
    frames = [1, 4, 16] if smoke else [2 ** k for k in range(11)]
    reference_frames = 4 * frames[-1]  # of aoSamples 16: 64x the AO rays of the aoSamples-1 curve's last point
    ao = ["--renderer", "ao", *CORNELL_AO]
    reference = render_sweep(build, tmp, "ao_ref", [*ao, "--ao-samples", str(counts[-1])], [reference_frames],
                             size)[0]
    curves = {}
    for n in counts:
        points = convergence(build, tmp, "ao", [*ao, "--ao-samples", str(n)], frames, reference["image"], size)
        curves[str(n)] = {"points": points, "rmse_at_1s": at_time(points, 1.0),
                          "ms_per_frame": 1000 * points[-1]["cpu_s"] / points[-1]["frames"]}
    return {"size": size, "isa": reference["isa"], "curves": curves,
            "reference": {"ao_samples": counts[-1], "frames": reference_frames, "cpu_s": reference["cpu_s"]}}


def bounces_sweep(build, tmp, smoke, reference):
    """maxPathLength 1..8 against the renderers sweep's maxPathLength-20 MIS reference."""
    size = "32x32" if smoke else "128x128"
    lengths = [1, 2, 4] if smoke else list(range(1, 9))
    frames = 16 if smoke else 1024
    points = []
    for n in lengths:
        c = render_sweep(build, tmp, "bounces", ["--renderer", "pathtracer", "--max-path-length", str(n)], [frames],
                         size)[0]
        rmse, rmse_unclamped = errors(c["image"], reference)
        points.append({"max_path_length": n, "frames": frames, "rmse": rmse, "rmse_unclamped": rmse_unclamped,
                       "light_missing": float(1 - c["image"].mean() / reference.mean()),
                       "ms_per_frame": 1000 * c["cpu_s"] / frames})
    return {"size": size, "reference_max_path_length": 20, "points": points}


# A scattering volume lit by a sphere light with size (the scene of the test
# `pathtracer: light sampling, phase sampling and MIS converge to the same volume image`):
# neghip, a grey transfer function of albedo 0.8 whose extinction rises to 0.15 per voxel,
# forward scattering (g = 0.5); the lamp (radius 35 voxels) lies above, right and in
# front of the 65-voxel volume, outside the view.
VOLUME_SCENE = ["--renderer", "pathtracer", "--volume", os.path.join(DATA, "volumes", "neghip_66x66x66_uint8.raw"),
                "--albedo", "0.8", "--extinction", "0.15", "--anisotropy", "0.5",
                "--sphere-light", "80,-20,70,35,2e4", "--max-path-length", "8"]
VOLUME_CURVES = [("MIS", "mis"), ("light sampling only", "lights_only"), ("phase sampling only", "bsdf_only")]


def slope(points):
    """Least-squares slope of log RMSE against log time (-0.5 for plain Monte Carlo)."""
    return float(np.polyfit(np.log([p["cpu_s"] for p in points]), np.log([p["rmse"] for p in points]), 1)[0])


def volume_lights_sweep(build, tmp, smoke):
    size = "16x16" if smoke else "96x96"
    frames = [1, 16, 64] if smoke else [2 ** k for k in range(10)]
    reference_frames = 16 * frames[-1]
    ref = render_sweep(build, tmp, "vol_ref", [*VOLUME_SCENE, "--light-sampling", "mis"], [reference_frames], size)[0]
    reference = ref["image"]
    curves = {}
    for label, strategy in VOLUME_CURVES:
        points = []
        for c in render_sweep(build, tmp, "vol", [*VOLUME_SCENE, "--light-sampling", strategy], frames, size):
            rmse, rmse_unclamped = errors(c["image"], reference)
            # The mean against the reference's: an unbiased estimator tends to 1.
            points.append({"frames": c["frames"], "cpu_s": c["cpu_s"], "wall_s": c["wall_s"], "rmse": rmse,
                           "rmse_unclamped": rmse_unclamped, "mean_ratio": float(c["image"].mean() / reference.mean())})
        curves[label] = {"points": points, "rmse_at_1s": at_time(points, 1.0), "slope": slope(points),
                         "ms_per_frame": 1000 * points[-1]["cpu_s"] / points[-1]["frames"]}
    # Single scattering: the same estimator stopped after the first collision.
    c = render_sweep(build, tmp, "vol_single", [*VOLUME_SCENE, "--light-sampling", "mis", "--max-path-length", "1"],
                     [frames[-1]], size)[0]
    rmse, _ = errors(c["image"], reference)
    single = {"max_path_length": 1, "frames": frames[-1], "rmse": rmse,
              "light_missing": float(1 - c["image"].mean() / reference.mean()),
              "ms_per_frame": 1000 * c["cpu_s"] / frames[-1]}
    return {"size": size, "isa": ref["isa"], "scene": VOLUME_SCENE[2:],
            "reference": {"light_sampling": "mis", "frames": reference_frames, "cpu_s": ref["cpu_s"]},
            "curves": curves, "single_scattering": single}


def draw_renderers(results, out):
    if "renderers" in results:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for label, curve in results["renderers"]["curves"].items():
            points = curve["points"]
            # MIS and light sampling alone coincide on the diffuse box: draw MIS wide beneath.
            style = {"lw": 4, "alpha": 0.5} if "MIS" in label else {"ls": "--"} if "light sampling" in label else {}
            ax.loglog([p["cpu_s"] for p in points], [p["rmse"] for p in points], marker="o", ms=3, label=label,
                      **style)
        ax.set_xlabel("render time (s, one thread, summed over frames)")
        ax.set_ylabel("RMSE against own converged reference")
        ax.set_title(f"Renderers: error against time (Cornell box, {results['renderers']['size']}, "
                     f"{results['renderers']['isa']})")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "accuracy_renderers.png"), dpi=100)
        plt.close(fig)
    if "ao_samples" in results:
        fig, ax = plt.subplots(figsize=(6, 4))
        for n, curve in results["ao_samples"]["curves"].items():
            points = curve["points"]
            ax.loglog([p["cpu_s"] for p in points], [p["rmse"] for p in points], "o-", ms=3, label=f"aoSamples {n}")
        ax.set_xlabel("render time (s, one thread, summed over frames)")
        ax.set_ylabel("RMSE against converged AO")
        ax.set_title(f"ao renderer: AO rays per sample (Cornell box, {results['ao_samples']['size']}, "
                     f"{results['ao_samples']['isa']})")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "accuracy_ao_samples.png"), dpi=100)
        plt.close(fig)
    if "bounces" in results:
        points = results["bounces"]["points"]
        fig, (err, cost) = plt.subplots(1, 2, figsize=(10, 4))
        lengths = [p["max_path_length"] for p in points]
        err.semilogy(lengths, [p["rmse"] for p in points], "o-", label="RMSE")
        err.semilogy(lengths, [max(p["light_missing"], 1e-5) for p in points], "s--", label="light missing (mean)")
        err.set_xlabel("maxPathLength")
        err.set_ylabel("against maxPathLength 20")
        err.grid(True, which="both", alpha=0.3)
        err.legend()
        cost.plot(lengths, [p["ms_per_frame"] for p in points], "o-")
        cost.set_xlabel("maxPathLength")
        cost.set_ylabel("ms per frame, one thread (1 sample a pixel)")
        cost.set_ylim(bottom=0)
        cost.grid(True, alpha=0.3)
        fig.suptitle(f"Path tracer: bounces (Cornell box, {results['bounces']['size']}, "
                     f"{points[0]['frames']} frames each)")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "accuracy_bounces.png"), dpi=100)
        plt.close(fig)
    if "volume_lights" in results:
        v = results["volume_lights"]
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for label, curve in v["curves"].items():
            points = curve["points"]
            ax.loglog([p["cpu_s"] for p in points], [p["rmse"] for p in points], marker="o", ms=3,
                      label=f"{label} (slope {curve['slope']:.2f})")
        ax.set_xlabel("render time (s, one thread, summed over frames)")
        ax.set_ylabel("RMSE against converged MIS")
        ax.set_title(f"Path-traced volume: light sampling (neghip, albedo 0.8, g 0.5, {v['size']}, {v['isa']})",
                     fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "accuracy_volume_lights.png"), dpi=100)
        plt.close(fig)


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


def check_renderers(results):
    problems = []
    for label, curve in results.get("renderers", {}).get("curves", {}).items():
        points = curve["points"]
        if not points[-1]["rmse"] < 0.7 * points[0]["rmse"]:
            problems.append(f"renderers, {label}: error does not fall with more frames: {points}")
        if not all(b["cpu_s"] > a["cpu_s"] for a, b in zip(points, points[1:])):
            problems.append(f"renderers, {label}: time does not grow with frames: {points}")
    for n, curve in results.get("ao_samples", {}).get("curves", {}).items():
        points = curve["points"]
        if not points[-1]["rmse"] < 0.7 * points[0]["rmse"]:
            problems.append(f"ao_samples {n}: error does not fall with more frames: {points}")
    ao = results.get("ao_samples", {}).get("curves", {})
    if ao:
        first = [curve["points"][0]["rmse"] for curve in ao.values()]
        if not first[-1] < first[0]:
            problems.append(f"ao_samples: one frame of more AO rays is not more accurate: {first}")
    for label, curve in results.get("volume_lights", {}).get("curves", {}).items():
        points = curve["points"]
        if not points[-1]["rmse"] < 0.7 * points[0]["rmse"]:
            problems.append(f"volume_lights, {label}: error does not fall with more frames: {points}")
        if not abs(points[-1]["mean_ratio"] - 1) < 0.2:  # wide for the smoke run's few samples
            problems.append(f"volume_lights, {label}: converges away from the MIS reference: {points[-1]}")
    single = results.get("volume_lights", {}).get("single_scattering")
    if single and not single["light_missing"] > 0:
        problems.append(f"volume_lights: single scattering is not darker than multiple: {single}")
    points = results.get("bounces", {}).get("points", [])
    if points:
        if not points[-1]["light_missing"] < points[0]["light_missing"]:
            problems.append(f"bounces: more bounces do not bring more light: {points}")
        if not points[0]["light_missing"] > 0:
            problems.append(f"bounces: direct light alone is not darker than the reference: {points}")
    return problems


def check_smoke(results):
    """Checks the sweeps that ran."""
    problems = check_renderers(results)
    for label, points in results.get("volume", {}).get("curves", {}).items():
        if not points[-1]["rmse"] < points[0]["rmse"]:
            problems.append(f"volume, {label}: error does not fall with the sampling rate: {points}")
    for isa, points in results.get("accumulation", {}).get("curves", {}).items():
        if not points[-1]["rmse"] < points[0]["rmse"]:
            problems.append(f"{isa}: error does not fall with more frames: {points}")
    if "throughput" in results and (not all(rate > 0 for rate in results["throughput"].values())
                                    or len(results["throughput"]) < 2):
        problems.append(f"throughput: {results['throughput']}")
    if any(m["bvh_bytes_per_triangle"] <= 0 for m in results.get("memory", [])):
        problems.append(f"memory: {results['memory']}")
    return problems


SWEEPS = {
    "accumulation": accumulation_sweep,
    "throughput": throughput_sweep,
    "threads": thread_sweep,
    "memory": memory_sweep,
    "volume": volume_sweep,
    "renderers": renderers_sweep,
    "ao_samples": ao_samples_sweep,
    "bounces": None,  # bounces_sweep, given the renderers sweep's path-traced reference
    "volume_lights": volume_lights_sweep,
}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(HERE, "..", "build"))
    parser.add_argument("--out", default=os.path.join(HERE, "..", "docs", "images"))
    parser.add_argument("--smoke", action="store_true")
    parser.add_argument("--redraw", action="store_true",
                        help="draw the renderer charts again from OUT/charts.json, running nothing")
    parser.add_argument("--sweeps", default=",".join(SWEEPS),
                        help="comma-separated sweeps to run (default: all): " + ", ".join(SWEEPS))
    args = parser.parse_args()
    chosen = args.sweeps.split(",")
    unknown = [s for s in chosen if s not in SWEEPS]
    if unknown:
        parser.error(f"unknown sweeps {unknown}; expected some of {list(SWEEPS)}")
    if "bounces" in chosen and "renderers" not in chosen:
        chosen.append("renderers")  # the bounces sweep compares with its reference
    os.makedirs(args.out, exist_ok=True)
    if args.redraw:
        with open(os.path.join(args.out, "charts.json")) as f:
            draw_renderers(json.load(f), args.out)
        return 0
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in SWEEPS:
            if name == "bounces" and name in chosen:
                results[name] = bounces_sweep(args.build, tmp, args.smoke, results["renderers"]["pathtracer_reference"])
            elif name in chosen:
                results[name] = SWEEPS[name](args.build, tmp, args.smoke)
    if "renderers" in results:
        results["renderers"].pop("pathtracer_reference")
    if all(name in results for name in ["accumulation", "throughput", "threads", "memory"]):
        draw(results, args.out)
    if "volume" in results:
        draw_volume(results, args.out)
    draw_renderers(results, args.out)
    # Keep the figures of the sweeps not run this time.
    path = os.path.join(args.out, "charts.json")
    stored = {}
    if os.path.exists(path) and not args.smoke:
        with open(path) as f:
            stored = json.load(f)
    stored.update(results)
    with open(path, "w") as f:
        json.dump(stored, f, indent=1)
    problems = check_smoke(results)
    for p in problems:
        print("charts: " + p, file=sys.stderr)
    print(f"charts written to {args.out}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
