#!/usr/bin/env python3
"""Writes the seed corpus of the C API fuzz target (fuzz/fuzz_c_api.cpp): whole scenes in
its encoding of API calls, so that fuzzing starts from frames that render something. The
tables of parameter names, element types and object kinds are read from the target's
source, so that the two cannot disagree.

usage: make_c_api_seeds.py OUT_DIR"""
import pathlib
import re
import sys

source = (pathlib.Path(__file__).parent / "fuzz_c_api.cpp").read_text()
NAMES = re.findall(r'"([^"]*)"', re.search(r"names = std::to_array<const char\*>\(\{(.*?)\}\);", source, re.S).group(1))
TYPES = re.findall(r"\{(OSP_\w+), '(.)', (\d+)\}", source)
KINDS = re.findall(r'\{"(\w+)", \{([^}]*)\}\}', re.search(r"kinds = \{\{(.*?)\}\};", source, re.S).group(1))
KINDS = [(name, re.findall(r'"(\w+)"', subtypes)) for name, subtypes in KINDS]
OBJECT_TYPES = [t for t, component, _ in TYPES if component == "o"]


class Calls:
    """Encodes API calls as the target reads them; slots are handles in creation order."""

    def __init__(self):
        self.bytes = bytearray()
        self.slots = 0

    def _slot(self):
        self.slots += 1
        return self.slots - 1

    @staticmethod
    def component(kind, value):
        if kind in "fd":  # (b % 65 - 32) / 4
            return round(value * 4) + 32
        if kind == "o":
            return 255 if value is None else value
        return int(value)  # small integers are themselves

    def new(self, kind, subtype):
        k = [name for name, _ in KINDS].index(kind)
        self.bytes += bytes([0, k, KINDS[k][1].index(subtype)])
        return self._slot()

    def new_from(self, what, slot=None):
        which = ["geometricModel", "volumetricModel", "instance", "group", "world"].index(what)
        self.bytes += bytes([1, which, 255 if slot is None else slot])
        return self._slot()

    def type_of(self, type_name):
        return next(i for i, t in enumerate(TYPES) if t[0] == type_name)

    def set(self, slot, name, type_name, *values):
        t = self.type_of(type_name)
        kind = TYPES[t][1]
        self.bytes += bytes([2, slot, NAMES.index(name), t])
        if kind == "z":
            self.bytes += bytes([len(values[0])]) + values[0].encode()
        else:
            self.bytes += bytes(self.component(kind, v) for v in values)

    def data(self, type_name, items, copied=False):
        """A 1-D array of `items` (tuples of components, or handles' slots)."""
        t = self.type_of(type_name)
        kind = TYPES[t][1]
        self.bytes += bytes([3, t, len(items), 0, 0, 128 if copied else 0])
        for item in items:
            item = item if isinstance(item, tuple) else (item,)
            self.bytes += bytes(self.component(kind, v) for v in item)
        return self._slot()

    def commit(self, *slots):
        for slot in slots:
            self.bytes += bytes([4, slot])

    def render(self, renderer, camera, world, size=(8, 8), channels=0x1F3, frames=2, pick=False):
        self.bytes += bytes([9 if pick else 8, size[0] - 1, size[1] - 1, 3, channels & 255, channels >> 8,
                             renderer, camera, world, frames - 1, 0, 1])
        if pick:
            self.bytes += bytes([32, 32])  # the middle of the frame


def world_of(calls, geometries=(), volumes=(), light="ambient"):
    models = []
    for g in geometries:
        model = calls.new_from("geometricModel", g)
        material = calls.new("material", "obj")
        calls.set(material, "kd", "OSP_VEC3F", 0.75, 0.5, 0.25)
        calls.commit(material)
        calls.set(model, "material", "OSP_MATERIAL", material)
        calls.commit(model)
        models.append(("geometry", model))
    for v in volumes:
        tf = calls.new("transferFunction", "piecewiseLinear")
        calls.set(tf, "color", "OSP_DATA", calls.data("OSP_VEC3F", [(0, 0, 1), (1, 1, 1), (1, 0, 0)]))
        calls.set(tf, "opacity", "OSP_DATA", calls.data("OSP_FLOAT", [0, 0.5, 1]))
        calls.set(tf, "value", "OSP_BOX1F", 0, 1)
        calls.commit(tf)
        model = calls.new_from("volumetricModel", v)
        calls.set(model, "transferFunction", "OSP_TRANSFER_FUNCTION", tf)
        calls.commit(model)
        models.append(("volume", model))
    group = calls.new_from("group")
    for name, type_name in (("geometry", "OSP_GEOMETRIC_MODEL"), ("volume", "OSP_VOLUMETRIC_MODEL")):
        of_kind = [model for kind, model in models if kind == name]
        if of_kind:
            calls.set(group, name, "OSP_DATA", calls.data(type_name, of_kind))
    calls.commit(group)
    instance = calls.new_from("instance", group)
    calls.commit(instance)
    world = calls.new_from("world")
    calls.set(world, "instance", "OSP_DATA", calls.data("OSP_INSTANCE", [instance]))
    lamp = calls.new("light", light)
    calls.commit(lamp)
    calls.set(world, "light", "OSP_DATA", calls.data("OSP_LIGHT", [lamp]))
    calls.commit(world)
    return world


def view(calls, renderer_type, camera_type="perspective"):
    camera = calls.new("camera", camera_type)
    calls.set(camera, "position", "OSP_VEC3F", 0.5, 0.5, 4)
    calls.set(camera, "direction", "OSP_VEC3F", 0, 0, -1)
    renderer = calls.new("renderer", renderer_type)
    calls.set(renderer, "backgroundColor", "OSP_VEC4F", 0.25, 0.25, 0.25, 1)
    calls.commit(camera, renderer)
    return renderer, camera


def mesh():
    calls = Calls()
    g = calls.new("geometry", "mesh")
    calls.set(g, "vertex.position", "OSP_DATA", calls.data("OSP_VEC3F", [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)]))
    calls.set(g, "vertex.color", "OSP_DATA", calls.data("OSP_VEC4F", [(1, 0, 0, 1), (0, 1, 0, 1), (0, 0, 1, 1), (1, 1, 1, 1)]))
    calls.set(g, "index", "OSP_DATA", calls.data("OSP_VEC3UI", [(0, 1, 2), (1, 3, 2)], copied=True))
    calls.commit(g)
    world = world_of(calls, [g])
    for renderer_type in ("scivis", "ao", "pathtracer"):
        calls.render(*view(calls, renderer_type), world, pick=renderer_type == "scivis")
    return calls


def spheres_and_curves():
    calls = Calls()
    s = calls.new("geometry", "sphere")
    calls.set(s, "sphere.position", "OSP_DATA", calls.data("OSP_VEC3F", [(0, 0, 0), (1, 1, 0), (0.5, 0.5, 1)]))
    calls.set(s, "radius", "OSP_FLOAT", 0.5)
    calls.commit(s)
    c = calls.new("geometry", "curve")
    calls.set(c, "vertex.position_radius", "OSP_DATA",
              calls.data("OSP_VEC4F", [(0, 0, 0, 0.25), (1, 0, 0, 0.25), (1, 1, 0, 0.25), (0, 1, 0, 0.25)]))
    calls.set(c, "index", "OSP_DATA", calls.data("OSP_UINT", [0]))
    calls.set(c, "type", "OSP_UCHAR", 0)  # OSP_ROUND
    calls.set(c, "basis", "OSP_UCHAR", 1)  # OSP_BEZIER
    calls.commit(c)
    world = world_of(calls, [s, c], light="distant")
    calls.render(*view(calls, "scivis", "orthographic"), world, pick=True)
    return calls


def boxes_and_plane():
    calls = Calls()
    b = calls.new("geometry", "box")
    calls.set(b, "box", "OSP_DATA", calls.data("OSP_BOX3F", [(0, 0, 0, 1, 1, 1)]))
    calls.commit(b)
    p = calls.new("geometry", "plane")
    calls.set(p, "plane.coefficients", "OSP_DATA", calls.data("OSP_VEC4F", [(0, 1, 0, -0.5)]))
    calls.commit(p)
    calls.render(*view(calls, "ao"), world_of(calls, [b, p]))
    return calls


def structured_volume():
    calls = Calls()
    v = calls.new("volume", "structuredRegular")
    values = [((x + y + z) % 4) / 4 for z in range(3) for y in range(3) for x in range(3)]
    calls.bytes += bytes([3, calls.type_of("OSP_FLOAT"), 3, 2, 2, 0])  # a 3x3x3 array
    calls.bytes += bytes(calls.component("f", value) for value in values)
    data = calls._slot()
    calls.set(v, "data", "OSP_DATA", data)
    calls.set(v, "gridSpacing", "OSP_VEC3F", 0.5, 0.5, 0.5)
    calls.commit(v)
    iso = calls.new("geometry", "isosurface")
    calls.set(iso, "isovalue", "OSP_FLOAT", 0.5)
    calls.set(iso, "volume", "OSP_VOLUME", v)
    calls.commit(iso)
    world = world_of(calls, [iso], [v])
    calls.render(*view(calls, "scivis"), world, pick=True)
    calls.render(*view(calls, "pathtracer"), world, frames=1)
    return calls


def unstructured_and_particles():
    calls = Calls()
    u = calls.new("volume", "unstructured")
    calls.set(u, "vertex.position", "OSP_DATA", calls.data("OSP_VEC3F", [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]))
    calls.set(u, "vertex.data", "OSP_DATA", calls.data("OSP_FLOAT", [0, 0.25, 0.5, 1]))
    calls.set(u, "index", "OSP_DATA", calls.data("OSP_UINT", [0, 1, 2, 3]))
    calls.set(u, "cell.index", "OSP_DATA", calls.data("OSP_UINT", [0]))
    calls.set(u, "cell.type", "OSP_DATA", calls.data("OSP_UCHAR", [10]))  # OSP_TETRAHEDRON
    calls.commit(u)
    p = calls.new("volume", "particle")
    calls.set(p, "particle.position", "OSP_DATA", calls.data("OSP_VEC3F", [(0, 0, 0), (1, 1, 1)]))
    calls.set(p, "particle.radius", "OSP_DATA", calls.data("OSP_FLOAT", [0.5, 0.75]))
    calls.commit(p)
    calls.render(*view(calls, "scivis"), world_of(calls, [], [u, p]))
    return calls


out = pathlib.Path(sys.argv[1])
out.mkdir(parents=True, exist_ok=True)
for scene in (mesh, spheres_and_curves, boxes_and_plane, structured_volume, unstructured_and_particles):
    (out / f"{scene.__name__}.calls").write_bytes(bytes(scene().bytes))
