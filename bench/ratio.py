#!/usr/bin/env python3
"""Engine throughput as a ratio to the raw-Embree baseline measured in the same run.

    ./build/bench/sciray_bench --benchmark_filter=frame/ --benchmark_repetitions=5 \
        --benchmark_report_aggregates_only=true --benchmark_out=frame.json
    python3 bench/ratio.py frame.json

Prints Markdown tables: for each scene, each engine benchmark's median rays/s and its
ratio to frame/raw_embree/intersect16/<scene>; for spheres, sciray's own intersector
against Embree's native spheres (frame/spheres/<isa>/native/<scene>) of the same ISA;
for BVH builds (bench_build.cpp), the engine's build rate over raw Embree's on the same
mesh; for unstructured volumes (bench_unstructured.cpp), the 1M-tetrahedron frame's speed,
sampled and exact, over the grid of equal memory's; for volume samples
(bench_volume_types.cpp), each type's samples/s per ISA over its scalar path; for renderers (bench_renderers.cpp), what each configuration costs a pixel sample as a
multiple of primary rays, renderer/<isa>/<scene>/scivis, of the same ISA and scene:

    ./build/bench/sciray_bench --benchmark_filter=renderer/ --benchmark_min_time=0.2 \
        --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
        --benchmark_out=renderers.json --benchmark_out_format=json
    python3 bench/ratio.py renderers.json

Given the JSON lines of bench/peers/side_by_side.sh (sciray and OSPRay 3.1 through the
same C API client), prints per case the medians over rounds of frame time, time to first
image and peak memory, and sciray's ratio to OSPRay for each (speed: OSPRay's time over
sciray's, so above 1 is faster; memory: sciray's over OSPRay's, so below 1 is smaller).
"""
import json
import re
import statistics
import sys


def medians(path):
    with open(path) as f:
        report = json.load(f)
    out = {}
    for b in report["benchmarks"]:
        if b.get("aggregate_name", "median") == "median":
            out[b["run_name"].removesuffix("/process_time").removesuffix("/real_time")] = b["items_per_second"]
    return out


def main(path):
    rates = medians(path)
    if any(name.startswith(("frame/scivis/", "frame/raw_embree/")) for name in rates):
        print("| benchmark | Mrays/s | ratio to raw Embree |")
        print("|---|---:|---:|")
    for name, rate in sorted(rates.items()):
        match = re.match(r"frame/scivis/[^/]+/(torus_\w+?)_(plain|normals_colors)", name)
        if not match:
            continue
        baseline = rates.get(f"frame/raw_embree/intersect16/{match.group(1)}")
        ratio = f"{rate / baseline:.2f}" if baseline else "n/a"
        print(f"| `{name}` | {rate / 1e6:.1f} | {ratio} |")
    for name, rate in sorted(rates.items()):
        if name.startswith("frame/raw_embree"):
            print(f"| `{name}` (baseline) | {rate / 1e6:.1f} | 1.00 |")

    ratio_table(rates, "frame/spheres/", ("Mrays/s", "own / native"), lambda n: n.replace("/own/", "/native/"))
    for name, rate in sorted(rates.items()):
        if name.startswith("frame/curves/"):
            print(f"| `{name}` | {rate / 1e6:.1f} | |")
    ratio_table(rates, "build/sciray/", ("Mtriangles/s", "speed × raw Embree"),
                lambda n: n.replace("/sciray/", "/raw_embree/"), digits=2)
    ratio_table(rates, "frame/unstructured/", ("Mpixels/s", "speed × grid of equal memory"),
                lambda n: re.sub(r"/tetrahedra_1M(_exact)?$", "/grid_of_equal_memory", n), digits=3)
    ratio_table(rates, "samples/", ("Msamples/s", "speed × scalar"), lambda n: re.sub(r"/[^/]+$", "/scalar", n))
    renderer_costs(rates)


def ratio_table(rates, prefix, columns, counterpart, digits=1):
    """A table of the benchmarks named `prefix`...: each one's rate (in millions) and its
    ratio to the rate of counterpart(name) in the same run (1.00 for the counterparts)."""
    names = sorted(name for name in rates if name.startswith(prefix))
    if not names:
        return
    print(f"\n| benchmark | {columns[0]} | {columns[1]} |")
    print("|---|---:|---:|")
    for name in names:
        baseline = rates.get(counterpart(name))
        ratio = f"{rates[name] / baseline:.2f}" if baseline else "n/a"
        print(f"| `{name}` | {rates[name] / 1e6:.{digits}f} | {ratio} |")


RENDERER_CONFIGS = ["scivis_shadows", "scivis_ao4", "ao1", "ao4", "pathtracer_pl8"]


def renderer_costs(rates):
    """Per scene and ISA: primary-ray Msamples/s and each configuration's cost per sample
    as a multiple of it (baseline rate / configuration rate)."""
    rows = {}
    for name, rate in rates.items():
        match = re.match(r"renderer/([^/]+)/([^/]+)/(\w+)$", name)
        if match:
            rows.setdefault((match.group(2), match.group(1)), {})[match.group(3)] = rate
    if not rows:
        return
    order = {"avx512": 0, "avx2": 1, "sse4.2": 2, "scalar": 3}
    print("\n| scene | ISA | primary Msamples/s | " + " | ".join(RENDERER_CONFIGS) + " |")
    print("|---|---|---:|" + "---:|" * len(RENDERER_CONFIGS))
    for (scene, isa), configs in sorted(rows.items(), key=lambda kv: (kv[0][0], order.get(kv[0][1], 9))):
        base = configs.get("scivis")
        cells = [f"{base / configs[c]:.2f}" if base and c in configs else "n/a" for c in RENDERER_CONFIGS]
        primary = f"{base / 1e6:.2f}" if base else "n/a"
        print(f"| {scene} | {isa} | {primary} | " + " | ".join(cells) + " |")
    print("\nMsamples per CPU second:\n")
    print("| scene | ISA | scivis | " + " | ".join(RENDERER_CONFIGS) + " |")
    print("|---|---|---:|" + "---:|" * len(RENDERER_CONFIGS))
    for (scene, isa), configs in sorted(rows.items(), key=lambda kv: (kv[0][0], order.get(kv[0][1], 9))):
        cells = [f"{configs[c] / 1e6:.2f}" if c in configs else "n/a" for c in ["scivis", *RENDERER_CONFIGS]]
        print(f"| {scene} | {isa} | " + " | ".join(cells) + " |")


def side_by_side(path):
    runs = {}
    with open(path) as f:
        for line in f:
            if line.strip():
                run = json.loads(line)
                runs.setdefault(run["case"], {}).setdefault(run["engine"], []).append(run)
    print("| case | sciray ms | OSPRay ms | speed × OSPRay | first image s (sciray / OSPRay) | × | "
          "peak MB (sciray / OSPRay) | memory × |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for case, engines in runs.items():
        if not {"sciray", "ospray"} <= engines.keys():
            continue

        def median(engine, key):
            return statistics.median(run[key] for run in engines[engine])

        frame = {e: median(e, "frame_ms_median") for e in ("sciray", "ospray")}
        first = {e: median(e, "time_to_first_image_ms") / 1e3 for e in ("sciray", "ospray")}
        peak = {e: median(e, "peak_kb") / 1024 for e in ("sciray", "ospray")}
        print(f"| {case} | {frame['sciray']:.1f} | {frame['ospray']:.1f} | **{frame['ospray'] / frame['sciray']:.2f}** | "
              f"{first['sciray']:.2f} / {first['ospray']:.2f} | {first['ospray'] / first['sciray']:.2f} | "
              f"{peak['sciray']:.0f} / {peak['ospray']:.0f} | {peak['sciray'] / peak['ospray']:.2f} |")


if __name__ == "__main__":
    if sys.argv[1].endswith(".jsonl"):
        side_by_side(sys.argv[1])
    else:
        main(sys.argv[1])
