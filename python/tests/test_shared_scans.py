"""Real scans of ../shared/data (skipped when missing, failing under VDBMESH_REQUIRE_DATA=1)."""

import numpy as np
import pytest

import vdbmesh
from shared_data import shared_data


def test_the_walnut_ct_reads_as_slices_of_rows_and_meshes_closed():
    # OpenQVis, Resolution 128 96 114 (x y z), USHORT, SliceThickness 1 1 1 (SOURCES.md).
    path = shared_data("openqvis_walnut_ct/walnut.dat")
    array, spacing, affine = vdbmesh.read_volume(path)
    assert array.shape == (114, 96, 128)
    assert 0 <= array.min() and array.max() == 22526
    assert tuple(spacing) == (1, 1, 1)
    vertices, faces = vdbmesh.mesh(array, 8000.5, error=0.25)
    figures = vdbmesh.check(vertices, faces)
    assert figures["closed"] and figures["self_intersecting_pairs"] == 0


def test_an_oblique_nifti_meshes_from_its_array_like_from_its_file():
    # CT pitch phantom: the qform/sform rotates the acquisition by about 16.5 degrees.
    path = shared_data("nifti_ct_pitch_phantom/CT_pitch.nii.gz")
    array, spacing, affine = vdbmesh.read_volume(path)
    assert array.shape == (58, 248, 175)
    assert not np.allclose(affine[:3, :3], np.diag(np.diag(affine[:3, :3])))  # rotated
    iso = float(np.percentile(array, 80)) + 0.5
    expected = vdbmesh.mesh(path, iso)
    actual = vdbmesh.mesh(array, iso, affine=affine)
    np.testing.assert_array_equal(actual[0], expected[0])
    np.testing.assert_array_equal(actual[1], expected[1])
    assert vdbmesh.check(*actual)["closed"]
