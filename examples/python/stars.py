#!/usr/bin/env python3
"""The HYG star catalogue (../shared/data/points/stars.vtp: 107,857 stars) as spheres sized
by luminosity and coloured by colour index, from the arrays sciray.read_vtp returns.

    python3 examples/python/stars.py [--data DIR] [--out DIR]

A star's radius grows as the fourth root of its luminosity (a compressive scale: the
catalogue's luminosities span ten orders of magnitude), clamped so that the brightest do
not swallow their neighbours.
"""
import argparse
import os
import pathlib
import time

import numpy as np

import sciray


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    default_data = os.environ.get("SCIRAY_DATA_DIR", pathlib.Path(__file__).resolve().parents[3] / "shared" / "data")
    parser.add_argument("--data", default=default_data, help="the shared data folder")
    parser.add_argument("--out", default=".", help="folder for stars.png")
    args = parser.parse_args()

    start = time.perf_counter()
    stars = sciray.read_vtp(str(pathlib.Path(args.data) / "points" / "stars.vtp"))
    centers, luminosity, color_index = stars["vertices"], stars["point_data"]["lum"], stars["point_data"]["ci"]
    extent = np.percentile(np.linalg.norm(centers, axis=1), 90)
    base = 2e-3 * extent
    radius = np.clip(base * (luminosity / np.median(luminosity)) ** 0.25, 0.3 * base, 6 * base).astype(np.float32)
    # Colour index B−V: blue-white (−0.4) through white and yellow to red (2.0).
    colormap = [[0.55, 0.7, 1.0], [1.0, 1.0, 1.0], [1.0, 0.85, 0.4], [1.0, 0.45, 0.2]]
    scene = sciray.Scene()
    scene.add_spheres(centers, radius, scalars=color_index, scalar_range=(-0.4, 2.0), colormap=colormap)
    scene.add_light(sciray.Light("ambient", intensity=1.0))
    camera = sciray.Camera(position=(0.0, 0.0, 3.2 * extent), look_at=(0.0, 0.0, 0.0), fovy=40)
    renderer = sciray.Renderer("scivis", backgroundColor=(0.0, 0.0, 0.005))
    image = sciray.render(scene, camera, renderer, size=(640, 480), frames=4)
    seconds = time.perf_counter() - start
    lit = (np.asarray(image)[..., :3].max(axis=-1) > 40).mean()
    out = pathlib.Path(args.out) / "stars.png"
    image.save(out)
    print(f"{len(centers)} stars, radii {radius.min():.3g} to {radius.max():.3g}: read, built and 4 frames in "
          f"{seconds:.2f} s; {100 * lit:.1f} % of the pixels lit -> {out}")
    if lit < 0.005:
        raise SystemExit("no stars in the picture")


if __name__ == "__main__":
    main()
