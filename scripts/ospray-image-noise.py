#!/usr/bin/env python3
"""Tells Monte Carlo noise from a different image among the image failures of OSPRay's suite.

OSPRay passes its own path-traced tests because it replays the random numbers its references
were made with; an engine with other random numbers differs pixel by pixel even where both
converge to the same image. The suite's metric cannot tell the two apart, so this compares
the images averaged over 16x16-pixel blocks as well: averaging shrinks independent noise
about 16 times and a coherent difference not at all. A test is called noise when the mean
difference (8-bit units, over pixels and RGB) shrinks at least 3 times from pixels to
blocks and the block means agree to within 0.65 (99% of them to within 8); otherwise the
images differ.

usage: ospray-image-noise.py OUTDIR    (the OUTDIR of shared/conformance/ospray-3.1/run.sh)
Prints one line per failed image test: test, the suite's mean error, the per-pixel and the
block-mean differences, and the verdict; last the count of each verdict.
"""
import csv
import os
import sys

import matplotlib.image as mpimg
import numpy as np

BLOCK = 16
NOISE_MEAN, NOISE_P99, NOISE_SHRINK = 0.65, 8.0, 3.0


def block_means(img):
    h, w = img.shape[0] // BLOCK * BLOCK, img.shape[1] // BLOCK * BLOCK
    return img[:h, :w].reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK, -1).mean(axis=(1, 3))


def main(out):
    verdicts = {}
    with open(os.path.join(out, "results.tsv")) as f:
        rows = [r for r in csv.reader(f, delimiter="\t") if r and r[0] == "FAIL"]
    for status, test, why in (r + [""] * (3 - len(r)) for r in rows):
        # The suite's failed-image names: the test's name parts reordered, as run.sh keeps them.
        suite, _, case = test.partition(".")
        prefix, _, fixture = suite.rpartition("/")
        name, _, index = case.partition("/")
        stem = "_".join(p for p in (fixture, prefix.replace("/", "_"), name, index) if p)
        paths = [os.path.join(out, "failed", f"{stem}_{k}.png") for k in ("baseline", "rendered")]
        if not all(os.path.exists(p) for p in paths):
            print(f"{test}\t(no images)")
            continue
        baseline, rendered = (mpimg.imread(p)[..., :3].astype(np.float64) * 255 for p in paths)
        pixel = np.abs(baseline - rendered).mean()
        blocks = np.abs(block_means(baseline) - block_means(rendered))
        mean, p99 = blocks.mean(), np.percentile(blocks, 99)
        noise = mean <= NOISE_MEAN and p99 <= NOISE_P99 and pixel >= NOISE_SHRINK * mean
        verdict = "noise" if noise else "differs"
        verdicts[verdict] = verdicts.get(verdict, 0) + 1
        suite_error = why.rsplit("/", 1)[-1] if "STATISTIC" in why else "?"
        print(f"{test}\t{suite_error}\tpixel {pixel:.2f}\tblocks {mean:.2f} (99%: {p99:.1f})\t{verdict}")
    print(", ".join(f"{n} {v}" for v, n in sorted(verdicts.items())))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
