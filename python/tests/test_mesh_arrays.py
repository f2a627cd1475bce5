"""vdbmesh.mesh on numpy arrays: geometry, sample types, memory layouts, spacing and affine."""

import numpy as np
import pytest

import vdbmesh
from volumes import ball, ellipsoid_field, sphere_field

SAMPLE_TYPES = ["uint8", "int8", "uint16", "int16", "uint32", "int32", "float32", "float64"]


def test_sphere_is_closed_clean_and_has_the_sphere_volume():
    radius = 20.0
    vertices, faces = vdbmesh.mesh(sphere_field(64, radius), 0.0)
    figures = vdbmesh.check(vertices, faces)
    assert figures["clean"] and figures["closed"] and figures["outward"]
    assert figures["boundary_edges"] == 0 and figures["nonmanifold_edges"] == 0
    assert figures["components"] == 1 and figures["genus"] == 0
    # The vertices interpolate a signed distance linearly along voxel edges (error about
    # l^2 / 8r = 0.006 voxel for l = 1) and the flat triangles cut below the sphere by their
    # sagitta (at most (sqrt 2)^2 / 8r = 0.0125 voxel): the volume is short by about
    # 3 * depth / r < 3 * 0.0125 / 20 = 0.19%. 0.3% allows that bound, not a wrong mesh.
    exact = 4 / 3 * np.pi * radius**3
    assert figures["volume"] == pytest.approx(exact, rel=3e-3)
    assert figures["volume"] < exact  # inscribed
    assert figures["area"] == pytest.approx(4 * np.pi * radius**2, rel=3e-3)


def test_vertices_and_area_match_skimage_marching_cubes_with_spacing():
    measure = pytest.importorskip("skimage.measure")
    volume = ellipsoid_field((40, 50, 60), (18.2, 24.6, 29.4), (12, 17, 25))
    spacing = (0.5, 1.0, 2.0)
    vertices, faces = vdbmesh.mesh(volume, 0.0, spacing=spacing, method="mc")  # dc's error 0 is the dual mesh
    sk_vertices, sk_faces, _, _ = measure.marching_cubes(volume, 0.0, spacing=spacing)
    # Both put a vertex where the linear interpolation crosses iso on each voxel edge, in
    # array axis order times spacing: the same points, up to float32 rounding of the
    # interpolation (measured: 0.0009, on 7 of 17526 coordinates; 0.002 is 0.001 voxel
    # along the axis of spacing 2).
    assert len(vertices) == len(sk_vertices)
    np.testing.assert_allclose(np.unique(vertices, axis=0), np.unique(sk_vertices.astype(np.float32), axis=0),
                               atol=2e-3)
    # Only the triangulation of the cells may differ: a few triangles split along the other
    # diagonal change the area by far less than 0.1%.
    area = vdbmesh.check(vertices, faces)["area"]
    sk_area = measure.mesh_surface_area(sk_vertices, sk_faces)
    assert area == pytest.approx(sk_area, rel=1e-3)


@pytest.mark.parametrize("dtype", SAMPLE_TYPES)
def test_every_sample_type_gives_the_float_mesh(dtype):
    volume = ball((20, 22, 24), 100)
    expected = vdbmesh.mesh(volume.astype(np.float32), 50)
    vertices, faces = vdbmesh.mesh(volume.astype(dtype), 50)
    assert vertices.dtype == np.float32 and faces.dtype == np.int32
    assert vertices.shape[1] == 3 and faces.shape[1] == 3 and len(faces) > 0
    np.testing.assert_array_equal(vertices, expected[0])
    np.testing.assert_array_equal(faces, expected[1])


def test_booleans_are_meshed_as_zero_and_one():
    mask = ball((20, 22, 24), 1) > 0
    np.testing.assert_array_equal(vdbmesh.mesh(mask, 0.5)[1], vdbmesh.mesh(mask.astype(np.uint8), 0.5)[1])


def _layouts(volume):
    """The same values in other memory layouts, none of them C-contiguous."""
    return {
        "fortran": np.asfortranarray(volume),
        "strided view": np.repeat(volume, 2, axis=2)[:, ::1, ::2],
        "transposed view": np.ascontiguousarray(volume.transpose(2, 0, 1)).transpose(1, 2, 0),
        "big endian": volume.astype(">i2"),
    }


@pytest.mark.parametrize("layout", ["fortran", "strided view", "transposed view", "big endian"])
def test_memory_layout_does_not_change_the_mesh(layout):
    volume = ball((30, 26, 22), 1000).astype(np.int16)
    other = _layouts(volume)[layout]
    assert not other.flags.c_contiguous or layout == "big endian"
    expected = vdbmesh.mesh(volume, 500)
    actual = vdbmesh.mesh(other, 500)
    np.testing.assert_array_equal(actual[0], expected[0])
    np.testing.assert_array_equal(actual[1], expected[1])


def test_a_reversed_axis_is_read_through_negative_strides():
    volume = ball((30, 26, 22), 1000).astype(np.int16)
    flipped = volume[:, :, ::-1]
    assert flipped.strides[2] < 0
    expected = vdbmesh.mesh(np.ascontiguousarray(flipped), 500)
    actual = vdbmesh.mesh(flipped, 500)
    np.testing.assert_array_equal(actual[0], expected[0])
    np.testing.assert_array_equal(actual[1], expected[1])


def test_spacing_scales_each_array_axis():
    volume = ball((20, 22, 24), 1)
    unit_vertices, unit_faces = vdbmesh.mesh(volume, 0.5)
    vertices, faces = vdbmesh.mesh(volume, 0.5, spacing=(2.0, 3.0, 0.5))
    np.testing.assert_allclose(vertices, unit_vertices * np.float32([2.0, 3.0, 0.5]), rtol=1e-6)
    np.testing.assert_array_equal(faces, unit_faces)


def _rotation(axis, degrees):
    axis = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    angle = np.radians(degrees)
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def test_affine_maps_array_indices_to_the_world():
    volume = ball((20, 22, 24), 1)
    unit_vertices, unit_faces = vdbmesh.mesh(volume, 0.5)
    affine = np.eye(4)
    affine[:3, :3] = _rotation((1, 2, 3), 30) @ np.diag([0.8, 1.1, 1.3])
    affine[:3, 3] = (10.0, -5.0, 2.5)
    vertices, faces = vdbmesh.mesh(volume, 0.5, affine=affine)
    expected = unit_vertices.astype(np.float64) @ affine[:3, :3].T + affine[:3, 3]
    np.testing.assert_allclose(vertices, expected, atol=1e-4)
    np.testing.assert_array_equal(faces, unit_faces)
    assert vdbmesh.check(vertices, faces)["clean"]


def test_a_mirroring_affine_keeps_the_normals_pointing_out():
    volume = ball((20, 22, 24), 1)
    unit_vertices, unit_faces = vdbmesh.mesh(volume, 0.5)
    vertices, faces = vdbmesh.mesh(volume, 0.5, affine=np.diag([-1.0, 1.0, 1.0, 1.0]))
    np.testing.assert_allclose(vertices, unit_vertices * np.float32([-1, 1, 1]))
    np.testing.assert_array_equal(faces, unit_faces[:, [0, 2, 1]])
    figures = vdbmesh.check(vertices, faces)
    assert figures["outward"] and figures["volume"] > 0


def test_inside_below_on_the_negated_volume_gives_the_same_mesh():
    volume = sphere_field(32, 10.0)
    expected = vdbmesh.mesh(volume, 0.5)
    actual = vdbmesh.mesh(-volume, -0.5, inside="below")
    np.testing.assert_array_equal(actual[0], expected[0])
    np.testing.assert_array_equal(actual[1], expected[1])


def test_the_surface_is_closed_where_the_object_meets_the_border():
    volume = np.ones((10, 12, 14), dtype=np.uint8)  # all object: the box's faces are the surface
    volume[5, 6, 7] = 0  # and a cavity, so that the level lies within the data range
    # The default (the dual mesh at error 0) closes it too; Marching Cubes, whose volume is
    # exact here, is checked below.
    assert vdbmesh.check(*vdbmesh.mesh(volume, 0.5, inside="above"))["clean"]
    vertices, faces = vdbmesh.mesh(volume, 0.5, inside="above", method="mc")  # "auto" would mesh the cavity
    assert vdbmesh.check(vertices, faces)["clean"]
    # Outside the array is outside the object, crossed at the middle of each edge leaving the
    # array: the surface is the box of the voxels' faces, -0.5 to n - 0.5 along each axis,
    # with its 12 edges cut at 45 degrees through those midpoints (0.125 voxel^3 per voxel of
    # edge length) and 1/12 voxel^3 given back at each of the 8 corners, where cuts overlap;
    # less the cavity, the octahedron |x| + |y| + |z| < 0.5 round the zero (1/6 voxel^3).
    np.testing.assert_array_equal(vertices.min(axis=0), [-0.5] * 3)
    np.testing.assert_array_equal(vertices.max(axis=0), np.array(volume.shape) - 0.5)
    edge_length = 4 * sum(volume.shape)
    expected = np.prod(volume.shape) - 0.125 * edge_length + 8 / 12 - 1 / 6
    assert vdbmesh.check(vertices, faces)["volume"] == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("method, options", [("dc", {"error": 0.25}), ("dmc", {"error": 0.25}), ("openvdb", {"adaptivity": 0.5})])
def test_adaptive_meshes_are_clean_and_smaller(method, options):
    volume = sphere_field(64, 20.0)
    full = vdbmesh.mesh(volume, 0.0, method=method)
    adaptive = vdbmesh.mesh(volume, 0.0, method=method, **options)
    assert len(adaptive[1]) < 0.8 * len(full[1])
    assert vdbmesh.check(*adaptive)["clean"]


def test_dmc_at_error_zero_has_the_marching_cubes_surface():
    volume = sphere_field(40, 12.0)
    dmc = vdbmesh.check(*vdbmesh.mesh(volume, 0.0, method="dmc"))
    mc = vdbmesh.check(*vdbmesh.mesh(volume, 0.0, method="mc"))
    assert (dmc["triangles"], dmc["vertices"]) == (mc["triangles"], mc["vertices"])
    assert dmc["area"] == pytest.approx(mc["area"], rel=1e-9)
