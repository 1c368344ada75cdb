"""Arrays from pyvista and VTK objects, and from sciray's readers, ready for a Scene's add_*
methods: `scene.add_mesh(**sciray.mesh_arrays(poly))`. Nothing here imports VTK or pyvista
unless handed one of their objects."""
import numpy as np


def shareable(array, dtype=None):
    """A copy of `array` with 16 readable bytes after its end, which Embree needs of the
    vertex and index arrays it reads in place: meshes given such arrays share them (no copy
    at commit, and changes show after Scene.commit())."""
    array = np.asarray(array, dtype=dtype)
    buffer = np.empty(array.nbytes + 16, dtype=np.uint8)
    out = buffer[:array.nbytes].view(array.dtype).reshape(array.shape)
    out[...] = array
    return out


def _triangles_of_cells(cells):
    """VTK's cell list [n, i0, ..., n, ...] (pyvista's `faces`) as triangles (polygons fanned)."""
    cells = np.asarray(cells, dtype=np.int64)
    if cells.size == 0:
        return np.empty((0, 3), dtype=np.uint32)
    if cells.size % 4 == 0 and np.all(cells[::4] == 3):
        return cells.reshape(-1, 4)[:, 1:].astype(np.uint32)
    triangles = []
    at = 0
    while at < cells.size:
        n = int(cells[at])
        polygon = cells[at + 1:at + 1 + n]
        if n < 3 or polygon.size != n:
            raise ValueError(f"faces: cell at {at} has {n} points; polygons need at least 3")
        for k in range(1, n - 1):
            triangles.append((polygon[0], polygon[k], polygon[k + 1]))
        at += n + 1
    return np.asarray(triangles, dtype=np.uint32)


def _vtk_to_numpy(vtk_array):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    return vtk_to_numpy(vtk_array)


def _point_array(obj, name):
    if hasattr(obj, "point_data"):  # pyvista
        return np.asarray(obj.point_data[name] if name else obj.active_scalars)
    data = obj.GetPointData()
    array = data.GetArray(name) if name else data.GetScalars()
    if array is None:
        raise ValueError(f"point array {name!r} not found" if name else "the object has no active point scalars")
    return _vtk_to_numpy(array)


def mesh_arrays(obj, scalars=None):
    """vertices and indices (and, with `scalars`, a point array by name, or True for the
    active scalars) of a pyvista.PolyData, a vtkPolyData, or a dict from read_ply/read_vtp.
    Polygons are fanned into triangles; magnitudes are taken of vector arrays."""
    if isinstance(obj, dict):
        out = {k: obj[k] for k in ("vertices", "indices", "normals", "colors", "texcoords") if k in obj}
        if scalars is not None:
            out["scalars"] = _magnitude(obj["point_data"][scalars])
        return out
    if hasattr(obj, "faces") and hasattr(obj, "points"):  # pyvista.PolyData
        vertices, cells = np.asarray(obj.points), np.asarray(obj.faces)
    elif hasattr(obj, "GetPoints"):  # vtkPolyData
        from vtkmodules.vtkCommonCore import vtkIdTypeArray
        vertices = _vtk_to_numpy(obj.GetPoints().GetData())
        legacy = vtkIdTypeArray()
        obj.GetPolys().ExportLegacyFormat(legacy)
        cells = _vtk_to_numpy(legacy)
    else:
        raise TypeError(f"mesh_arrays: expected a pyvista.PolyData, a vtkPolyData or a dict, got {type(obj).__name__}")
    out = {"vertices": vertices, "indices": _triangles_of_cells(cells)}
    normals = _point_normals(obj)
    if normals is not None:
        out["normals"] = normals
    if scalars is not None:
        out["scalars"] = _magnitude(_point_array(obj, None if scalars is True else scalars))
    return out


def _point_normals(obj):
    if hasattr(obj, "point_data"):  # pyvista
        return np.asarray(obj.point_data["Normals"]) if "Normals" in obj.point_data else None
    normals = obj.GetPointData().GetNormals()
    return None if normals is None else _vtk_to_numpy(normals)


def _magnitude(values):
    values = np.asarray(values)
    return np.linalg.norm(values, axis=1) if values.ndim == 2 else values


def image_arrays(obj, field=None):
    """values (a 3-D array, x fastest), spacing and origin of a pyvista.ImageData or a
    vtkImageData (a point array by name, default the active scalars), for Scene.add_volume
    and add_isosurface. The values are the object's own memory where VTK's layout allows."""
    # The first point's position: the origin moved by where the extent starts.
    if hasattr(obj, "dimensions") and hasattr(obj, "spacing"):  # pyvista.ImageData
        dims, spacing, first = obj.dimensions, obj.spacing, obj.bounds[0::2]
    elif hasattr(obj, "GetDimensions"):  # vtkImageData
        dims, spacing, first = obj.GetDimensions(), obj.GetSpacing(), obj.GetBounds()[0::2]
    else:
        raise TypeError(f"image_arrays: expected a pyvista.ImageData or a vtkImageData, got {type(obj).__name__}")
    values = _point_array(obj, field)
    if values.ndim != 1:
        raise ValueError(f"image_arrays: {field or 'the active scalars'} has {values.shape[1]} components; "
                         "give a scalar field")
    # VTK stores x fastest: Fortran order over (x, y, z).
    return {"values": values.reshape(tuple(dims), order="F"), "spacing": tuple(spacing), "origin": tuple(first)}


def grid_arrays(obj, field=None):
    """points, connectivity, cell_types, offsets and values (point data) or cell_values of a
    pyvista.UnstructuredGrid, a vtkUnstructuredGrid or a read_vtu dict, for
    Scene.add_unstructured. `field` names the array (default: the active scalars, or for a
    dict the first point array, else the first cell array); vectors by magnitude."""
    if isinstance(obj, dict):  # read_vtu
        points, connectivity, types, ends = obj["points"], obj["connectivity"], obj["cell_types"], obj["offsets"]
        point_data, cell_data = obj["point_data"], obj["cell_data"]
    elif hasattr(obj, "celltypes"):  # pyvista.UnstructuredGrid
        points, connectivity, types = obj.points, obj.cell_connectivity, obj.celltypes
        ends, point_data, cell_data = np.asarray(obj.offset)[1:], obj.point_data, obj.cell_data
    elif hasattr(obj, "GetCells"):  # vtkUnstructuredGrid
        cells = obj.GetCells()
        points = _vtk_to_numpy(obj.GetPoints().GetData())
        connectivity = _vtk_to_numpy(cells.GetConnectivityArray())
        ends = _vtk_to_numpy(cells.GetOffsetsArray())[1:]
        types = _vtk_to_numpy(obj.GetCellTypesArray())
        point_data, cell_data = _vtk_arrays(obj.GetPointData()), _vtk_arrays(obj.GetCellData())
    else:
        raise TypeError(f"grid_arrays: expected a pyvista.UnstructuredGrid, a vtkUnstructuredGrid or a dict, "
                        f"got {type(obj).__name__}")
    out = {"points": points, "connectivity": connectivity, "cell_types": types, "offsets": ends}
    names = [field] if field else list(point_data.keys()) + list(cell_data.keys())
    for name in names:
        if name in point_data:
            out["values"] = _magnitude(point_data[name])
            return out
        if name in cell_data:
            out["cell_values"] = _magnitude(cell_data[name])
            return out
    raise ValueError(f"grid_arrays: no point or cell array {field!r}" if field else "grid_arrays: the grid has no arrays")


def _vtk_arrays(data):
    """A vtkDataSetAttributes' arrays by name, active scalars first."""
    arrays = {}
    scalars = data.GetScalars()
    if scalars is not None and scalars.GetName():
        arrays[scalars.GetName()] = _vtk_to_numpy(scalars)
    for i in range(data.GetNumberOfArrays()):
        array = data.GetArray(i)
        if array is not None and array.GetName() not in arrays:
            arrays[array.GetName()] = _vtk_to_numpy(array)
    return arrays


def molecule_arrays(molecule, bond_radius=0.2):
    """Atoms (spheres) and bonds (two-vertex tubes) of a read_pdb result:
    `scene.add_spheres(**atoms)`, `scene.add_curves(**bonds)`."""
    atoms = {k: molecule[k] for k in ("centers", "radius", "colors")}
    bonds = molecule["bonds"]
    vertices = molecule["centers"][bonds.reshape(-1)]
    colors = molecule["colors"][bonds.reshape(-1)]
    starts = np.arange(0, len(vertices), 2, dtype=np.uint32)
    return atoms, {"vertices": vertices, "radius": bond_radius, "indices": starts, "colors": colors}
