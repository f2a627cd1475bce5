"""Errors raise Python exceptions that carry vdbmesh's messages."""

import numpy as np
import pytest

import vdbmesh
from volumes import ball


@pytest.fixture
def volume():
    return ball((12, 12, 12), 1).astype(np.float32)


@pytest.mark.parametrize("dtype, value", [(np.float32, np.inf), (np.float64, -np.inf), (np.float64, 1e300)])
def test_an_infinite_sample_or_one_beyond_the_float_range_is_a_format_error(volume, dtype, value):
    volume = volume.astype(dtype)
    volume[11, 0, 7] = value
    with pytest.raises(vdbmesh.FormatError, match=r"array: sample \[11, 0, 7\]: expected a finite number, got infinity"):
        vdbmesh.mesh(volume, 0.5)


def test_format_errors_are_value_errors_and_vdbmesh_errors():
    assert issubclass(vdbmesh.FormatError, ValueError)
    assert issubclass(vdbmesh.FormatError, vdbmesh.Error)
    assert issubclass(vdbmesh.Error, RuntimeError)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"method": "marching"}, 'method: expected "dc", "dmc", "mc" or "openvdb", got "marching"'),
        ({"inside": "outside"}, 'inside: expected "auto", "above" or "below", got \'outside\''),
        ({"error": -1}, "error: expected a finite number >= 0"),
        ({"adaptivity": 2, "method": "openvdb"}, r"adaptivity: expected a number in \[0, 1\]"),
        ({"spacing": (1, 0, 1)}, "spacing: expected three positive numbers"),
        ({"spacing": (1, 1, 1), "affine": np.eye(4)}, "spacing, affine: give one of them"),
        ({"affine": np.ones((4, 4))}, "affine: expected a last row of 0, 0, 0, 1"),
    ],
)
def test_bad_options_raise_value_errors(volume, options, message):
    with pytest.raises(ValueError, match=message):
        vdbmesh.mesh(volume, 0.5, **options)


def test_a_singular_affine_is_refused(volume):
    with pytest.raises(ValueError, match="orientation: expected an invertible index-to-world affine"):
        vdbmesh.mesh(volume, 0.5, affine=np.diag([1.0, 1.0, 0.0, 1.0]))


def test_an_unsupported_array_is_refused():
    with pytest.raises(ValueError, match="expected a 3D array, got 2D"):
        vdbmesh.mesh(np.zeros((4, 4), dtype=np.float32), 0.5)
    with pytest.raises(ValueError, match="expected a 3D array of uint8, .* got complex64"):
        vdbmesh.mesh(np.zeros((4, 4, 4), dtype=np.complex64), 0.5)
    with pytest.raises(ValueError, match=r"volume: expected at least one sample along each axis, got shape \(0, 4, 4\)"):
        vdbmesh.mesh(np.zeros((0, 4, 4), dtype=np.float32), 0.5)


def test_missing_files_raise_file_not_found(tmp_path):
    for call in (vdbmesh.read_volume, vdbmesh.read_mesh, lambda p: vdbmesh.mesh(p, 0.5)):
        with pytest.raises(FileNotFoundError, match="nothing.nii"):
            call(tmp_path / "nothing.nii")


def test_a_file_of_the_wrong_format_names_the_file(tmp_path):
    path = tmp_path / "broken.nii"
    path.write_bytes(b"not a nifti header")
    with pytest.raises(vdbmesh.FormatError, match="broken.nii"):
        vdbmesh.read_volume(path)


def test_mesh_arrays_are_validated(tmp_path):
    vertices = np.zeros((3, 3), dtype=np.float32)
    with pytest.raises(ValueError, match=r"faces: expected vertex indices in \[0, 3\), got 3 in face 0"):
        vdbmesh.check(vertices, [[0, 1, 3]])
    with pytest.raises(ValueError, match="vertices: expected an N x 3 numeric array"):
        vdbmesh.check(np.zeros((3, 2)), [[0, 1, 2]])
    with pytest.raises(ValueError, match="mesh.xyz"):
        vdbmesh.write_mesh(tmp_path / "mesh.xyz", vertices, [[0, 1, 2]])


def test_an_unwritable_output_is_a_vdbmesh_error(tmp_path, volume):
    with pytest.raises(vdbmesh.Error, match="does not exist"):
        vdbmesh.to_vdb(volume, 0.5, tmp_path / "no" / "such" / "folder.vdb")
