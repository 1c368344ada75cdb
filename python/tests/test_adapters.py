"""pyvista and VTK objects handed over in a line, without the module importing either."""
import numpy as np
import pytest

import sciray
from conftest import covered


class FakePolyData:
    """What sciray reads of a pyvista.PolyData: points, faces (VTK's cell list), point_data."""

    def __init__(self, points, faces, point_data=None):
        self.points, self.faces, self.point_data = points, faces, point_data or {}


def test_pyvista_like_faces_with_mixed_polygons_are_fanned():
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], np.float32)
    faces = np.array([4, 0, 1, 2, 3, 3, 1, 4, 2])
    arrays = sciray.mesh_arrays(FakePolyData(points, faces))
    assert arrays["indices"].tolist() == [[0, 1, 2], [0, 2, 3], [1, 4, 2]]
    with pytest.raises(ValueError, match="faces: cell at 0 has 2 points"):
        sciray.mesh_arrays(FakePolyData(points, np.array([2, 0, 1])))
    with pytest.raises(TypeError, match="expected a pyvista.PolyData"):
        sciray.mesh_arrays(42)


def test_vtk_objects_render_like_their_arrays():
    vtk = pytest.importorskip("vtk")
    source = vtk.vtkRTAnalyticSource()
    source.SetWholeExtent(-8, 8, -8, 8, -8, 8)
    source.Update()
    image = source.GetOutput()
    volume = sciray.image_arrays(image)
    assert volume["values"].shape == (17, 17, 17) and volume["origin"] == (-8.0, -8.0, -8.0)
    # x fastest, as VTK stores it: the value at (x, y, z) = (1, 0, 0) is the second in memory.
    assert volume["values"][1, 0, 0] == image.GetScalarComponentAsDouble(-7, -8, -8, 0)
    scene = sciray.Scene()
    scene.add_volume(**volume)
    assert scene.contents[0]["shared"] is True  # VTK's own memory
    contour = vtk.vtkContourFilter()
    contour.SetInputData(image)
    contour.SetValue(0, 150)
    contour.Update()
    mesh = sciray.mesh_arrays(contour.GetOutput())
    assert len(mesh["indices"]) == contour.GetOutput().GetNumberOfPolys() and "normals" in mesh
    surface = sciray.Scene()
    surface.add_mesh(**mesh)
    assert covered(sciray.render(surface, size=(64, 48))).mean() > 0.05


def test_unstructured_grids_from_vtk_and_read_vtu(data_dir):
    vtk = pytest.importorskip("vtk")
    source = vtk.vtkRTAnalyticSource()
    source.SetWholeExtent(-6, 6, -6, 6, -6, 6)
    source.Update()
    tetrahedra = vtk.vtkDataSetTriangleFilter()  # image cells cut into tetrahedra
    tetrahedra.SetInputData(source.GetOutput())
    tetrahedra.Update()
    grid = sciray.grid_arrays(tetrahedra.GetOutput())
    assert set(grid["cell_types"].tolist()) == {10} and len(grid["values"]) == 13 ** 3
    scene = sciray.Scene()
    scene.add_unstructured(**grid)
    structured = sciray.Scene()
    structured.add_volume(**sciray.image_arrays(source.GetOutput()))
    camera = sciray.Camera(position=(20, 15, 30), look_at=(0, 0, 0))
    a = np.asarray(sciray.render(scene, camera, size=(64, 48)), np.int32)
    b = np.asarray(sciray.render(structured, camera, size=(64, 48)), np.int32)
    assert covered(b).mean() > 0.05
    # Tetrahedra interpolate linearly where the grid is trilinear: nearly the same picture.
    assert np.abs(a - b).mean() < 0.5
    jaw = sciray.grid_arrays(sciray.read_vtu(str(data_dir / "unstructured" / "kiefer_jaw.vtu")))
    assert "cell_values" in jaw and len(jaw["offsets"]) == len(jaw["cell_types"])
