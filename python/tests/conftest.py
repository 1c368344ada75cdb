import os
import pathlib

import numpy as np
import pytest

import sciray

DATA = pathlib.Path(os.environ.get("SCIRAY_DATA_DIR", pathlib.Path(__file__).parents[3] / "shared" / "data"))


@pytest.fixture(scope="session")
def data_dir():
    return DATA


def cube():
    """A unit cube of 12 triangles (float32 vertices, uint32 indices, both shareable)."""
    v = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=np.float32)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return sciray.shareable(v), sciray.shareable(np.array(tris, dtype=np.uint32))


def covered(image, background=None):
    """Pixels unlike the background (the top-left pixel)."""
    image = np.asarray(image, dtype=np.float32)
    background = image[0, 0] if background is None else background
    return np.abs(image[..., :3] - background[:3]).max(axis=-1) > 4


def fixed_camera():
    return sciray.Camera(position=(2.5, 2.0, 3.5), look_at=(0.5, 0.5, 0.5), fovy=45)
