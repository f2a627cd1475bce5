"""Files in and out: meshes, .vdb grids and scans give back what went in."""

import numpy as np
import pytest

import vdbmesh
from shared_data import testdata
from volumes import sphere_field


@pytest.fixture(scope="module")
def sphere_mesh():
    return vdbmesh.mesh(sphere_field(32, 10.0), 0.0, spacing=(0.5, 0.7, 0.9))


@pytest.mark.parametrize("name, options", [("m.ply", {}), ("m.ply", {"ascii": True}), ("m.obj", {}),
                                           ("m.ply", {"normals": True})])
def test_ply_and_obj_give_back_the_same_arrays(tmp_path, sphere_mesh, name, options):
    vdbmesh.write_mesh(tmp_path / name, *sphere_mesh, **options)
    vertices, faces = vdbmesh.read_mesh(tmp_path / name)
    np.testing.assert_array_equal(vertices, sphere_mesh[0])
    np.testing.assert_array_equal(faces, sphere_mesh[1])


@pytest.mark.parametrize("ascii", [False, True])
def test_stl_gives_back_the_same_triangles(tmp_path, sphere_mesh, ascii):
    # STL stores corners, not indices: reading welds bit-identical ones, in order of first use.
    vdbmesh.write_mesh(tmp_path / "m.stl", *sphere_mesh, ascii=ascii)
    vertices, faces = vdbmesh.read_mesh(tmp_path / "m.stl")
    np.testing.assert_array_equal(vertices[faces], sphere_mesh[0][sphere_mesh[1]])
    assert len(vertices) == len(sphere_mesh[0])


def test_a_vdb_written_from_an_array_meshes_like_the_array(tmp_path):
    volume = sphere_field(40, 12.0)
    affine = np.array([[0, 0.5, 0, 3], [0.7, 0, 0, -2], [0, 0, 0.9, 1], [0, 0, 0, 1]])
    vdbmesh.to_vdb(volume, 0.0, tmp_path / "sphere.vdb", affine=affine)
    expected = vdbmesh.mesh(volume, 0.0, affine=affine)
    actual = vdbmesh.mesh(tmp_path / "sphere.vdb", 0.0)
    np.testing.assert_array_equal(actual[0], expected[0])
    np.testing.assert_array_equal(actual[1], expected[1])


@pytest.mark.parametrize("name", ["sphere_phantom.nii.gz", "read/metaimage_rotated.mhd", "read/nifti_qform_u16.nii"])
def test_a_scan_read_into_an_array_meshes_like_the_file(name):
    path = testdata(name)
    array, spacing, affine = vdbmesh.read_volume(path)
    iso = float(np.percentile(array, 60))
    expected = vdbmesh.mesh(path, iso)
    actual = vdbmesh.mesh(array, iso, affine=affine)
    assert len(expected[1]) > 0
    np.testing.assert_array_equal(actual[0], expected[0])
    np.testing.assert_array_equal(actual[1], expected[1])
    np.testing.assert_allclose(spacing, np.linalg.norm(affine[:3, :3], axis=0))


def test_read_volume_returns_slices_first_with_spacing_per_array_axis():
    # sphere_phantom.nii.gz: a 48^3 u8 sphere of radius 15 voxels, density x 255 with
    # scl_slope 1/255 (testdata/README.md), unit spacing.
    array, spacing, affine = vdbmesh.read_volume(testdata("sphere_phantom.nii.gz"))
    assert array.shape == (48, 48, 48) and array.dtype == np.float32 and array.flags.c_contiguous
    assert 0 <= array.min() and array.max() <= 1
    assert affine.shape == (4, 4) and np.array_equal(affine[3], [0, 0, 0, 1])
    figures = vdbmesh.check(*vdbmesh.mesh(array, 0.5, spacing=spacing))
    assert figures["clean"]
    assert figures["volume"] == pytest.approx(4 / 3 * np.pi * 15**3 * np.prod(spacing), rel=0.01)
