"""Renderers, progressive frames with callbacks and cancellation, the GIL, channels, pick,
pictures, and agreement with the sciray tool."""
import os
import pathlib
import struct
import subprocess
import threading
import time

import numpy as np
import pytest

import sciray
from conftest import covered, cube, fixed_camera


def cube_scene():
    vertices, indices = cube()
    scene = sciray.Scene()
    scene.add_mesh(vertices, indices, material=sciray.Material("obj", kd=(0.8, 0.5, 0.3)))
    return scene


@pytest.mark.parametrize("renderer", ["scivis", "ao", "pathtracer"])
def test_every_renderer_shows_the_cube(renderer):
    scene = cube_scene()
    scene.add_light(sciray.Light("ambient", intensity=0.4))
    scene.add_light(sciray.Light("distant", direction=(-1, -2, -1.5), intensity=2.5))
    image = sciray.render(scene, fixed_camera(), renderer, size=(96, 72), frames=4)
    mask = covered(image)
    assert 0.1 < mask.mean() < 0.9
    inside = np.asarray(image)[mask].astype(np.float32)
    assert inside[:, 0].mean() > inside[:, 2].mean() + 10  # the material's orange, lit


def test_renderers_differ_and_parameters_take_effect():
    scene = cube_scene()
    camera = fixed_camera()
    ao = np.asarray(sciray.render(scene, camera, sciray.Renderer("ao", aoSamples=4), size=(64, 48)), np.int32)
    scivis = np.asarray(sciray.render(scene, camera, "scivis", size=(64, 48)), np.int32)
    white = np.asarray(sciray.render(scene, camera, sciray.Renderer("scivis", backgroundColor=(1, 1, 1)),
                                     size=(64, 48)))
    assert np.abs(ao - scivis).mean() > 2
    assert tuple(white[0, 0, :3]) == (255, 255, 255)


def test_renderer_parameters_are_checked():
    with pytest.raises(TypeError, match=r"Renderer\('scivis'\): unknown parameter 'aoSample' \(known: .*aoSamples"):
        sciray.Renderer("scivis", aoSample=4)
    with pytest.raises(TypeError, match=r"'pixelSamples' must be an int, got str"):
        sciray.Renderer("pathtracer", pixelSamples="4")
    with pytest.raises(ValueError, match="type: expected scivis, ao or pathtracer, got 'raster'"):
        sciray.Renderer("raster")
    with pytest.raises(ValueError, match="pixelFilter: expected point, box, .* got 'cubic'"):
        sciray.Renderer("scivis", pixelFilter="cubic")
    with pytest.raises(ValueError, match=r"Material\('obj'\): \"kd\" must be a number"):
        sciray.Material("obj", kd="red")


def test_a_closed_renderer_refuses_to_render():
    renderer = sciray.Renderer("scivis")
    renderer.close()
    with pytest.raises(ValueError, match=r"Renderer\('scivis'\) is closed"):
        sciray.render(cube_scene(), renderer=renderer, size=(8, 8))
    with sciray.Renderer("ao") as ao:
        pass
    assert ao.closed


def test_progressive_frames_call_back_and_stop_when_asked():
    session = sciray.Session(cube_scene(), fixed_camera(), sciray.Renderer("pathtracer"), size=(48, 36))
    seen = []

    def callback(s):
        seen.append((s.frames, s.error))
        return s.frames < 5

    assert session.render(frames=50, callback=callback) == 5
    assert [f for f, _ in seen] == [1, 2, 3, 4, 5] and session.frames == 5
    errors = [e for _, e in seen if e is not None]
    assert errors and errors[-1] < errors[0]


def test_cancel_from_another_thread_stops_a_long_render():
    session = sciray.Session(sciray.builtin_scene(50_000), None, sciray.Renderer("pathtracer", pixelSamples=16),
                             size=(256, 192))
    timer = threading.Timer(0.3, session.cancel)
    start = time.perf_counter()
    timer.start()
    rendered = session.render(frames=1000)
    elapsed = time.perf_counter() - start
    timer.join()
    assert rendered < 1000 and elapsed < 20


def test_the_gil_is_released_while_rendering():
    scene = sciray.builtin_scene(50_000)
    counter = [0]
    running = threading.Event()
    stop = threading.Event()

    def count():
        running.set()
        while not stop.is_set():
            counter[0] += 1

    thread = threading.Thread(target=count)
    thread.start()
    running.wait()
    session = sciray.Session(scene, None, sciray.Renderer("pathtracer", pixelSamples=4), size=(192, 144), threads=1)
    session.render_frame()  # commits first
    before = counter[0]
    start = time.perf_counter()
    session.render(frames=3)
    rendering = time.perf_counter() - start
    during = counter[0] - before
    stop.set()
    thread.join()
    # The counting thread ran on while frames rendered (with the GIL held it would not).
    assert rendering > 0.05 and during > 1000


def test_channels_and_pick_agree():
    scene = cube_scene()
    spheres = scene.add_spheres([[0.5, 0.5, 2.0]], radius=0.3)
    out = sciray.render(scene, fixed_camera(), size=(96, 72),
                        channels=["depth", "normal", "albedo", "primitive_id", "geometry_id"])
    assert set(out) == {"color", "depth", "normal", "albedo", "primitive_id", "geometry_id"}
    ids, depth, normal = out["geometry_id"], out["depth"], out["normal"]
    hit = ids != 0xFFFFFFFF
    assert set(np.unique(ids[hit])) == {0, spheres}
    assert np.all(np.isfinite(depth[hit])) and np.allclose(np.linalg.norm(normal[hit], axis=-1), 1, atol=0.02)
    session = sciray.Session(scene, fixed_camera(), None, size=(96, 72))
    rows, cols = np.nonzero(ids == spheres)
    picked = session.pick(cols[len(cols) // 2], rows[len(rows) // 2])
    assert picked["geometry"] == spheres
    assert np.linalg.norm(np.subtract(picked["position"], (0.5, 0.5, 2.0))) == pytest.approx(0.3, abs=1e-3)
    assert picked["distance"] == pytest.approx(depth[rows[len(rows) // 2], cols[len(cols) // 2]], rel=0.02)
    assert session.pick(0, 0) is None
    with pytest.raises(IndexError, match="outside the 96x72 image"):
        session.pick(96, 0)


def test_images_show_in_jupyter_as_png():
    image = sciray.render(cube_scene(), fixed_camera(), size=(40, 30))
    png = image._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", png[16:24])
    assert (width, height) == (40, 30)
    float_png = sciray.render(cube_scene(), fixed_camera(), size=(40, 30), dtype="float32")._repr_png_()
    assert float_png[:4] == b"\x89PNG"


def test_the_module_renders_what_the_tool_renders(tmp_path):
    """The built-in scene through the module and through `sciray render`: the same image
    (RMSE of 8-bit channels below 0.5: same camera, lights, background and renderer)."""
    tool = pathlib.Path(os.environ.get("SCIRAY_TOOL", pathlib.Path(sciray.__file__).parents[2] / "examples" / "sciray"))
    if not tool.exists():
        pytest.skip(f"the sciray tool is not built at {tool}")
    out = tmp_path / "tool.png"
    subprocess.run([str(tool), "render", "--size", "160x120", "-o", str(out), "--quiet"], check=True)
    from sciray.image import Image
    module = np.asarray(sciray.render(sciray.builtin_scene(), size=(160, 120)), dtype=np.float64)
    import matplotlib.image
    tool_image = matplotlib.image.imread(out) * 255.0
    rmse = np.sqrt(np.mean((module - tool_image) ** 2))
    assert rmse < 0.5, rmse


def test_image_sizes_are_limited():
    scene = cube_scene()
    with pytest.raises(ValueError, match=r"size: width and height are limited to 32768"):
        sciray.Session(scene, size=(40000, 8))
    with pytest.raises(ValueError, match=r"size: expected \(width, height\) of at least 1 pixel, got \(0, 8\)"):
        sciray.Session(scene, size=(0, 8))
    with pytest.raises(ValueError, match="dtype: expected 'uint8' \\(sRGB\\) or 'float32' \\(linear\\), got 'float16'"):
        sciray.Session(scene, dtype="float16")
    with pytest.raises(ValueError, match="channels: unknown channel 'ids'"):
        sciray.Session(scene, channels=["ids"])


def test_commits_racing_frames_from_another_thread():
    """Frames keep the world they started with while another thread commits a new one
    (arrays copied afresh each commit, and their old copies freed only after the swap)."""
    vertices, indices = cube()
    moving = vertices.astype(np.float64)  # copied at every commit
    scene = sciray.Scene()
    scene.add_mesh(moving, indices)
    camera = fixed_camera()
    states = []
    for dx in (0.0, 0.5):
        moving[:] = vertices + [dx, 0, 0]
        scene.commit()
        states.append(np.asarray(sciray.render(scene, camera, size=(48, 36))))
    assert not np.array_equal(states[0], states[1])
    stop = threading.Event()

    def commit_in_a_loop():
        k = 0
        while not stop.is_set():
            moving[:] = vertices + [0.5 * (k % 2), 0, 0]
            scene.commit()
            k += 1

    committer = threading.Thread(target=commit_in_a_loop)
    committer.start()
    session = sciray.Session(scene, camera, None, size=(48, 36))
    unknown = 0
    try:
        for _ in range(40):
            session.reset()
            session.render_frame()
            image = session.color()
            unknown += not any(np.array_equal(image, s) for s in states)
    finally:
        stop.set()
        committer.join()
    assert unknown == 0
