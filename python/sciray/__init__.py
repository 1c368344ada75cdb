"""sciray: CPU ray tracing for scientific visualization, over numpy arrays.

    import sciray
    scene = sciray.Scene()
    scene.add_mesh(vertices, indices, scalars=temperature)
    image = sciray.render(scene, size=(800, 600))   # (600, 800, 4) uint8, shows in Jupyter

See docs/python.md.
"""
from ._sciray import (Camera, Error, Light, Material, Renderer, Scene, Session, TransferFunction, isas, read_obj,
                      read_pdb, read_ply, read_points, read_volume, read_vti, read_vtp, read_vtu, wavy_torus)
from .adapters import grid_arrays, image_arrays, mesh_arrays, molecule_arrays, shareable
from .image import Image

Error.__module__ = "sciray"  # an engine error: a ValueError naming what is wrong

__all__ = ["Camera", "Error", "Image", "Light", "Material", "Renderer", "Scene", "Session", "TransferFunction",
           "builtin_scene", "grid_arrays", "image_arrays", "isas", "mesh_arrays", "molecule_arrays", "read_obj", "read_pdb",
           "read_ply", "read_points", "read_volume", "read_vti", "read_vtp", "read_vtu", "render", "shareable",
           "wavy_torus"]


def render(scene, camera=None, renderer=None, size=(640, 480), frames=1, dtype="uint8", channels=(), callback=None,
           error_target=0.0, threads=0):
    """Renders `scene` and returns the image, (height, width, 4) top row first: uint8 sRGB or
    float32 linear. With `channels` (depth, normal, albedo, primitive_id, geometry_id,
    instance_id) it returns a dict of arrays by name, the image as "color".

    renderer: a Renderer or its type name ("scivis", "ao", "pathtracer"); camera: a Camera,
    or None to frame the whole scene; callback(session) after each frame may return False
    to stop. The GIL is released while frames render.
    """
    if isinstance(renderer, str):
        renderer = Renderer(renderer)
    session = Session(scene, camera, renderer, tuple(size), dtype, list(channels), threads)
    session.render(frames, callback, error_target)
    image = Image(session.color())
    if not channels:
        return image
    out = session.channels()
    out["color"] = image
    return out


def builtin_scene(triangles=400_000):
    """The sciray tool's default scene: a wavy torus coloured along its waves."""
    scene = Scene()
    scene.add_mesh(**wavy_torus(triangles))
    return scene
