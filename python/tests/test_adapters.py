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
