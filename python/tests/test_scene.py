"""Arrays in: shapes, dtypes, sharing without copies, and bad input named."""
import numpy as np
import pytest

import sciray
from conftest import covered, cube, fixed_camera

SIZE = (96, 72)


def render(scene, **kw):
    return np.asarray(sciray.render(scene, camera=fixed_camera(), size=SIZE, **kw))


def test_builtin_scene_renders_into_a_numpy_array():
    image = sciray.render(sciray.builtin_scene(20_000), size=(160, 120))
    assert isinstance(image, np.ndarray) and image.shape == (120, 160, 4) and image.dtype == np.uint8
    assert 0.1 < covered(image).mean() < 0.9  # the torus, not the background alone


def test_float32_output_is_the_linear_image_of_the_uint8_one():
    scene = sciray.builtin_scene(20_000)
    srgb = np.asarray(sciray.render(scene, size=(80, 60)), dtype=np.int32)
    linear = sciray.render(scene, size=(80, 60), dtype="float32")
    assert linear.dtype == np.float32
    from sciray.image import to_srgb8
    assert np.abs(to_srgb8(linear).astype(np.int32) - srgb).max() <= 1


def test_shareable_mesh_arrays_are_read_in_place_and_recommit_sees_changes():
    vertices, indices = cube()
    scene = sciray.Scene()
    scene.add_mesh(vertices, indices)
    assert scene.contents == [{"kind": "mesh", "index": 0, "shared": True}]
    before = covered(render(scene))
    vertices[:, 0] += 0.6  # in place: the engine reads this memory
    scene.commit()
    after = covered(render(scene))
    assert before.sum() > 100 and after.sum() > 100
    columns = np.arange(SIZE[0])
    assert (after * columns).sum() / after.sum() > (before * columns).sum() / before.sum() + 3


def test_arrays_without_slack_or_in_other_dtypes_are_copied_and_render_the_same():
    vertices, indices = cube()
    shared = sciray.Scene()
    shared.add_mesh(vertices, indices)
    copied = sciray.Scene()
    copied.add_mesh(vertices.astype(np.float64), indices.astype(np.int64))
    plain = sciray.Scene()
    plain.add_mesh(np.array(vertices), np.array(indices))  # float32/uint32 but no bytes after the end
    assert copied.contents[0]["shared"] is False and plain.contents[0]["shared"] is False
    reference = render(shared)
    assert np.array_equal(render(copied), reference)
    assert np.array_equal(render(plain), reference)


def test_strided_rows_are_read_in_place():
    vertices, indices = cube()
    wide = sciray.shareable(np.hstack([vertices, np.zeros((8, 2), np.float32)]))
    scene = sciray.Scene()
    scene.add_mesh(wide[:, :3], indices)  # rows 20 bytes apart
    assert scene.contents[0]["shared"] is True
    reference = sciray.Scene()
    reference.add_mesh(vertices, indices)
    assert np.array_equal(render(scene), render(reference))


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.uint16, np.float32, np.float64, np.int32, np.int8])
def test_volumes_of_every_dtype_render_alike(dtype):
    z, y, x = np.mgrid[0:24, 0:20, 0:16]
    field = np.round(100 * np.exp(-((x - 8) ** 2 + (y - 10) ** 2 + (z - 12) ** 2) / 40.0)).astype(dtype)
    tf = sciray.TransferFunction([[0, 0, 1], [1, 1, 0]], [0, 1], value_range=(0, 100))
    scene = sciray.Scene()
    scene.add_volume(field, transfer_function=tf, density=0.2)
    reference = sciray.Scene()
    reference.add_volume(field.astype(np.float32), transfer_function=tf, density=0.2)
    camera = sciray.Camera(position=(40, 30, 60), look_at=(8, 10, 12))
    image = np.asarray(sciray.render(scene, camera=camera, size=SIZE), dtype=np.int32)
    expected = np.asarray(sciray.render(reference, camera=camera, size=SIZE), dtype=np.int32)
    assert covered(expected).mean() > 0.05
    assert np.abs(image - expected).max() <= 1
    assert scene.contents[0]["shared"] == (dtype in (np.uint8, np.int16, np.uint16, np.float32, np.float64))


def test_volume_axis_orders_c_and_fortran_are_the_same_volume():
    z, y, x = np.mgrid[0:10, 0:12, 0:14].astype(np.float32)
    zyx = np.ascontiguousarray(x + 2 * y + 3 * z)
    xyz = np.asfortranarray(zyx.transpose(2, 1, 0))  # pyvista's (x, y, z), x fastest
    camera = sciray.Camera(position=(30, 25, 40), look_at=(7, 6, 5))
    images = []
    for values in (zyx, xyz):
        scene = sciray.Scene()
        scene.add_isosurface(values, [20.0])
        assert scene.contents[0]["shared"] is True
        images.append(np.asarray(sciray.render(scene, camera=camera, size=SIZE)))
    assert covered(images[0]).mean() > 0.01 and np.array_equal(images[0], images[1])


def test_bad_shapes_and_dtypes_name_the_argument():
    scene = sciray.Scene()
    vertices, indices = cube()
    with pytest.raises(ValueError, match=r"vertices: expected shape \(N, 3\), got \(8, 2\)"):
        scene.add_mesh(vertices[:, :2], indices)
    with pytest.raises(TypeError, match="vertices: expected numbers"):
        scene.add_mesh(np.array([["a", "b", "c"]]), indices)
    with pytest.raises(TypeError, match="indices: expected integers, got dtype float64"):
        scene.add_mesh(vertices, indices.astype(np.float64))
    with pytest.raises(ValueError, match=r"indices\[0, 0\] = -1 is negative"):
        scene.add_mesh(vertices, np.where(indices == 0, -1, indices).astype(np.int64))
    with pytest.raises(ValueError, match="add_mesh: indices of face 0 refers to vertex 8"):
        scene.add_mesh(vertices, np.where(indices == 0, 8, indices).astype(np.uint32))
    bad = vertices.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="add_mesh: vertices 3 is not finite"):
        scene.add_mesh(bad, indices)
    with pytest.raises(ValueError, match="colors: expected shape \\(N, 4\\) or \\(N, 3\\)"):
        scene.add_mesh(vertices, indices, colors=np.ones((8, 5)))
    with pytest.raises(ValueError, match="add_mesh: colors has 7 elements but there are 8 vertices"):
        scene.add_mesh(vertices, indices, colors=np.ones((7, 3)))
    with pytest.raises(ValueError, match="values: expected a 3-D array, got shape \\(4, 4\\)"):
        scene.add_volume(np.zeros((4, 4)))
    with pytest.raises(ValueError, match="add_spheres: radius 1 must be positive"):
        scene.add_spheres(np.zeros((3, 3)), radius=np.array([1.0, -1.0, 1.0]))
    with pytest.raises(TypeError, match="centers: expected an array, got None"):
        scene.add_spheres(None)
    with pytest.raises(ValueError, match="indices: segment 0 starts at vertex 4"):
        scene.add_curves(np.zeros((5, 3)), indices=[4])
    assert scene.contents == []  # nothing half-added


def test_non_contiguous_arrays_are_copied():
    vertices, indices = cube()
    reversed_rows = vertices[::-1]
    remap = (7 - indices).astype(np.uint32)
    scene = sciray.Scene()
    scene.add_mesh(reversed_rows, remap)
    assert scene.contents[0]["shared"] is False
    reference = sciray.Scene()
    reference.add_mesh(vertices, indices)
    assert np.array_equal(render(scene), render(reference))


def test_scalars_colour_through_the_colormap():
    vertices, indices = cube()
    scene = sciray.Scene()
    scene.add_mesh(vertices, indices, scalars=vertices[:, 0], colormap=[[1, 0, 0], [0, 0, 1]])
    image = render(scene).astype(np.int32)
    mask = covered(image)
    reds, blues = image[..., 0][mask], image[..., 2][mask]
    assert reds.max() > 150 and blues.max() > 150  # both ends of the map show
    with pytest.raises(ValueError, match="scalars: has 3 values but there are 8 vertices"):
        scene.add_mesh(vertices, indices, scalars=[1, 2, 3])


def test_spheres_and_curves_with_per_item_radii_and_colours():
    scene = sciray.Scene()
    centers = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
    scene.add_spheres(centers, radius=np.array([0.3, 0.2, 0.1], np.float32), colors=np.eye(3, dtype=np.float32))
    assert scene.contents[0]["shared"] is False  # RGB colours get an alpha
    scene.add_curves(np.array([[0, 0, 0, 0.05], [1, 0, 0, 0.05], [0, 1, 0, 0.05]], np.float32))
    (lo, hi) = scene.bounds
    assert lo[0] == pytest.approx(-0.3) and hi[0] == pytest.approx(1.2)
    image = np.asarray(sciray.render(scene, size=SIZE)).astype(np.int32)
    mask = covered(image)
    for channel in range(3):  # the red, green and blue spheres each show
        others = [c for c in range(3) if c != channel]
        assert ((image[..., channel] > image[..., others].max(axis=-1) + 60) & mask).sum() > 5
