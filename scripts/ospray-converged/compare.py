#!/usr/bin/env python3
"""The OSPRay test suite's image metric between two PNGs, and the mean difference.

usage: compare.py A.png B.png
Prints the suite's mean error (per pixel the signed RGBA difference averaged over its 5x5
neighbourhood inside the image, absolute, summed over channels, in 8-bit units; pixels
above 13 add up; divided by 4 x pixels: a test passes at <= 0.1) and the mean absolute RGB
difference per pixel.
"""
import sys

import matplotlib.image as mpimg
import numpy as np

PIXEL_THRESHOLD = 13.0


def suite_error(a, b):
    d = b - a
    h, w = d.shape[:2]
    padded = np.pad(d, ((2, 2), (2, 2), (0, 0)))
    inside = np.pad(np.ones((h, w)), 2)
    total = sum(padded[i:i + h, j:j + w] for i in range(5) for j in range(5))
    count = sum(inside[i:i + h, j:j + w] for i in range(5) for j in range(5))
    error = np.abs(total / count[..., None]).sum(axis=2)
    return error[error > PIXEL_THRESHOLD].sum() / (4 * h * w)


def main(a_path, b_path):
    a, b = (np.round(mpimg.imread(p).astype(np.float64) * 255) for p in (a_path, b_path))
    print(f"suite error {suite_error(a, b):.3f}\tmean |difference| {np.abs(a - b)[..., :3].mean():.2f}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(*sys.argv[1:])
