#!/usr/bin/env python3
"""Engine throughput as a ratio to the raw-Embree baseline measured in the same run.

    ./build/bench/sciray_bench --benchmark_filter=frame/ --benchmark_repetitions=5 \
        --benchmark_report_aggregates_only=true --benchmark_out=frame.json
    python3 bench/ratio.py frame.json

Prints Markdown tables: for each scene, each engine benchmark's median rays/s and its
ratio to frame/raw_embree/intersect16/<scene>; for spheres, sciray's own intersector
against Embree's native spheres (frame/spheres/<isa>/native/<scene>) of the same ISA.
"""
import json
import re
import sys


def medians(path):
    with open(path) as f:
        report = json.load(f)
    out = {}
    for b in report["benchmarks"]:
        if b.get("aggregate_name", "median") == "median":
            out[b["run_name"].removesuffix("/process_time")] = b["items_per_second"]
    return out


def main(path):
    rates = medians(path)
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

    spheres = sorted(name for name in rates if name.startswith("frame/spheres/"))
    if spheres:
        print("\n| benchmark | Mrays/s | own / native |")
        print("|---|---:|---:|")
        for name in spheres:
            native = rates.get(name.replace("/own/", "/native/"))
            ratio = f"{rates[name] / native:.2f}" if "/own/" in name and native else "1.00" if "/native/" in name else "n/a"
            print(f"| `{name}` | {rates[name] / 1e6:.1f} | {ratio} |")
    for name, rate in sorted(rates.items()):
        if name.startswith("frame/curves/"):
            print(f"| `{name}` | {rate / 1e6:.1f} | |")


if __name__ == "__main__":
    main(sys.argv[1])
