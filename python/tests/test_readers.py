"""Readers return arrays the scene takes; bad files raise sciray.Error naming them."""
import numpy as np
import pytest

import sciray


def test_ply_mesh(data_dir):
    bunny = sciray.read_ply(str(data_dir / "meshes" / "bunny.ply"))
    assert bunny["vertices"].shape[1] == 3 and bunny["vertices"].dtype == np.float32
    assert bunny["indices"].shape[1] == 3 and bunny["indices"].max() < len(bunny["vertices"])
    scene = sciray.Scene()
    scene.add_mesh(**bunny)
    assert scene.contents[0]["shared"] is True  # the reader's arrays have Embree's slack


def test_pdb_molecule(data_dir):
    path = next((data_dir / "molecules").glob("*.pdb"))
    molecule = sciray.read_pdb(str(path))
    n = len(molecule["centers"])
    assert n > 100 and molecule["radius"].shape == (n,) and molecule["bonds"].max() < n
    atoms, bonds = sciray.molecule_arrays(molecule)
    scene = sciray.Scene()
    scene.add_spheres(**atoms)
    scene.add_curves(**bonds)
    image = sciray.render(scene, size=(64, 64))
    assert (np.asarray(image)[..., :3].std(axis=(0, 1)) > 5).all()


def test_volume_file_shares_the_readers_memory(data_dir):
    path = sorted((data_dir / "volumes").glob("*.raw"))[0]
    volume = sciray.read_volume(str(path))
    values = volume["values"]
    assert values.ndim == 3 and values.flags.c_contiguous
    scene = sciray.Scene()
    scene.add_volume(volume["values"], spacing=volume["spacing"], origin=volume["origin"])
    assert scene.contents[0]["shared"] is True


def test_vtk_files(data_dir):
    grid = sciray.read_vtu(str(data_dir / "unstructured" / "can.vtu"))
    assert len(grid["offsets"]) == len(grid["cell_types"]) and grid["connectivity"].max() < len(grid["points"])
    stars = sciray.read_vtp(str(data_dir / "points" / "stars.vtp"))
    assert len(stars["vertices"]) == 107_857 and len(stars["indices"]) == 0
    assert all(len(a) == 107_857 for a in stars["point_data"].values())


def test_obj_scene_with_materials(tmp_path):
    (tmp_path / "m.mtl").write_text("newmtl red\nKd 1 0 0\n")
    (tmp_path / "s.obj").write_text("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n")
    scene_file = sciray.read_obj(str(tmp_path / "s.obj"))
    (mesh,) = scene_file["meshes"]
    assert mesh["indices"].tolist() == [[0, 1, 2]] and mesh["material"].type == "obj"
    scene = sciray.Scene()
    scene.add_mesh(mesh["vertices"], mesh["indices"], material=mesh["material"])
    image = np.asarray(sciray.render(scene, size=(32, 32)), np.int32)
    assert (image[..., 0] - image[..., 1]).max() > 60  # red


def test_points(tmp_path):
    path = tmp_path / "p.xyzr"
    path.write_text("0 0 0 0.5\n1 0 0 0.25\n")
    points = sciray.read_points(str(path))
    assert points["centers"].shape == (2, 3) and points["radius"].tolist() == [0.5, 0.25]


@pytest.mark.parametrize("reader,text", [(sciray.read_ply, b"ply\nformat ascii 1.0\nelement vertex 3\n"),
                                         (sciray.read_volume, b"\x00\x01"),
                                         (sciray.read_vtu, b"<VTKFile type='UnstructuredGrid'>"),
                                         (sciray.read_pdb, b"")])
def test_truncated_or_mislabelled_files_are_named(tmp_path, reader, text):
    suffix = {sciray.read_ply: ".ply", sciray.read_volume: ".nrrd", sciray.read_vtu: ".vtu", sciray.read_pdb: ".pdb"}
    path = tmp_path / ("bad" + suffix[reader])
    path.write_bytes(text)
    with pytest.raises(sciray.Error, match="bad"):
        reader(str(path))
    with pytest.raises(sciray.Error):
        reader(str(tmp_path / "missing.ply"))


def test_unstructured_grid_renders_from_read_vtu_arrays(data_dir):
    grid = sciray.read_vtu(str(data_dir / "unstructured" / "kiefer_jaw.vtu"))
    (name, stress), = [(k, v) for k, v in grid["cell_data"].items() if "Stress" in k][:1]
    scene = sciray.Scene()
    scene.add_unstructured(grid["points"], grid["connectivity"], grid["cell_types"], cell_values=stress,
                           offsets=grid["offsets"], density=2.0)
    assert scene.contents == [{"kind": "unstructured", "index": 0, "shared": False}]
    image = np.asarray(sciray.render(scene, size=(96, 72)))
    assert (np.abs(image[..., :3].astype(int) - image[0, 0, :3]).max(axis=-1) > 8).mean() > 0.05
    # Quadratic tetrahedra (VTK type 24) need their offsets; linear cells do not.
    assert set(grid["cell_types"].tolist()) == {24}
    with pytest.raises(ValueError, match="offsets: needed for cell 0 of VTK type 24"):
        scene.add_unstructured(grid["points"], grid["connectivity"], grid["cell_types"], cell_values=stress)
    with pytest.raises(ValueError, match="cell 0 has VTK type 5, which is not a volume cell"):
        scene.add_unstructured(grid["points"], grid["connectivity"], np.full(len(stress), 5), cell_values=stress,
                               offsets=grid["offsets"])
    tets = sciray.Scene()
    corners = grid["connectivity"].reshape(-1, 10)[:, :4]  # a quadratic tetrahedron's corners come first
    tets.add_unstructured(grid["points"], corners.ravel(), np.full(len(stress), 10), cell_values=stress, density=2.0)
    assert np.array_equal(np.asarray(sciray.render(tets, size=(96, 72))), image)
    with pytest.raises(TypeError, match="give values \\(per point\\) or cell_values"):
        scene.add_unstructured(grid["points"], grid["connectivity"], grid["cell_types"])
    bad = grid["connectivity"].copy()
    bad[2] = len(grid["points"])
    with pytest.raises(ValueError, match="add_unstructured: cell 0 refers to vertex [0-9]+ but points has"):
        scene.add_unstructured(grid["points"], bad, grid["cell_types"], cell_values=stress, offsets=grid["offsets"])
