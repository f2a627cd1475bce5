"""vdbmesh.marching_cubes as a drop-in for skimage.measure.marching_cubes: scikit-image's own
test cases (skimage/measure/tests/test_marching_cubes.py of 0.19, the version Debian 12
ships) with their tolerances, then its output compared with scikit-image's on the same input."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

import vdbmesh
from vdbmesh import marching_cubes

skimage_draw = pytest.importorskip("skimage.draw")
skimage_measure = pytest.importorskip("skimage.measure")
ellipsoid, ellipsoid_stats = skimage_draw.ellipsoid, skimage_draw.ellipsoid_stats
mesh_surface_area = skimage_measure.mesh_surface_area


# scikit-image's cases (their "_lorensen" method, an old implementation, is not offered).

@pytest.mark.parametrize("method", ["lewiner", "lorensen"])
def test_marching_cubes_isotropic(method):
    ellipsoid_isotropic = ellipsoid(6, 10, 16, levelset=True)
    _, surf = ellipsoid_stats(6, 10, 16)
    verts, faces = marching_cubes(ellipsoid_isotropic, 0.0, method=method)[:2]
    surf_calc = mesh_surface_area(verts, faces)
    # Test within 1% tolerance for isotropic. Will always underestimate.
    assert surf > surf_calc and surf_calc > surf * 0.99


@pytest.mark.parametrize("method", ["lewiner", "lorensen"])
def test_marching_cubes_anisotropic(method):
    # test spacing as numpy array (and not just tuple)
    spacing = np.array([1.0, 10 / 6.0, 16 / 6.0])
    ellipsoid_anisotropic = ellipsoid(6, 10, 16, spacing=spacing, levelset=True)
    _, surf = ellipsoid_stats(6, 10, 16)
    verts, faces = marching_cubes(ellipsoid_anisotropic, 0.0, spacing=spacing, method=method)[:2]
    surf_calc = mesh_surface_area(verts, faces)
    # Test within 1.5% tolerance for anisotropic. Will always underestimate.
    assert surf > surf_calc and surf_calc > surf * 0.985

    # Test marching cube with mask
    with pytest.raises(ValueError):
        marching_cubes(ellipsoid_anisotropic, 0.0, spacing=spacing, mask=np.array([]))
    # Test spacing together with allow_degenerate=False
    marching_cubes(ellipsoid_anisotropic, 0, spacing=spacing, allow_degenerate=False)


def test_invalid_input():
    with pytest.raises(ValueError):
        marching_cubes(np.zeros((2, 2, 1)), 0)
    with pytest.raises(ValueError):
        marching_cubes(np.zeros((2, 2, 1)), 1)
    with pytest.raises(ValueError):
        marching_cubes(np.ones((3, 3, 3)), 1, spacing=(1, 2))
    with pytest.raises(ValueError):
        marching_cubes(np.zeros((20, 20)), 0)


def _same_mesh(vertices1, faces1, vertices2, faces2, tol=1e-10):
    """Compare two meshes, using a certain tolerance and invariant to the order of the faces
    (scikit-image's helper)."""
    triangles1 = vertices1[np.array(faces1)]
    triangles2 = vertices2[np.array(faces2)]
    triang1 = [np.concatenate(sorted(t, key=lambda x: tuple(x))) for t in triangles1]
    triang2 = [np.concatenate(sorted(t, key=lambda x: tuple(x))) for t in triangles2]
    triang1 = np.array(sorted([tuple(x) for x in triang1]))
    triang2 = np.array(sorted([tuple(x) for x in triang2]))
    return triang1.shape == triang2.shape and np.allclose(triang1, triang2, 0, tol)


def test_both_algs_same_result_ellipse():
    sphere_small = ellipsoid(1, 1, 1, levelset=True)
    vertices2, faces2 = marching_cubes(sphere_small, 0, allow_degenerate=False)[:2]
    vertices3, faces3 = marching_cubes(sphere_small, 0, allow_degenerate=False, method="lorensen")[:2]
    assert _same_mesh(vertices2, faces2, vertices3, faces3)


def test_masked_marching_cubes():
    ellipsoid_scalar = ellipsoid(6, 10, 16, levelset=True)
    mask = np.ones_like(ellipsoid_scalar, dtype=bool)
    mask[:10, :, :] = False
    mask[:, :, 20:] = False
    ver, faces, _, _ = marching_cubes(ellipsoid_scalar, 0, mask=mask)
    area = mesh_surface_area(ver, faces)
    assert_allclose(area, 299.56878662109375, rtol=0.01)


def test_masked_marching_cubes_empty():
    ellipsoid_scalar = ellipsoid(6, 10, 16, levelset=True)
    with pytest.raises(ValueError):
        marching_cubes(ellipsoid_scalar, 0, mask=np.array([]))


def test_masked_marching_cubes_all_true():
    ellipsoid_scalar = ellipsoid(6, 10, 16, levelset=True)
    mask = np.ones_like(ellipsoid_scalar, dtype=bool)
    ver_m, faces_m, _, _ = marching_cubes(ellipsoid_scalar, 0, mask=mask)
    ver, faces, _, _ = marching_cubes(ellipsoid_scalar, 0)
    assert_allclose(ver_m, ver, rtol=0.00001)
    assert_allclose(faces_m, faces, rtol=0.00001)


# The same input through both: what a user replacing the import sees.

def _matched(ours, theirs, tolerance):
    """(our vertex indices, theirs) pairing each vertex with the nearest of the other mesh;
    asserts that every vertex of either mesh has one within @a tolerance. Both put one vertex on
    each crossed edge; theirs may lie on a sample (a few then coincide), ours are kept 0.001
    voxel inside the edge."""
    spatial = pytest.importorskip("scipy.spatial")  # scikit-image depends on scipy
    distance, nearest = spatial.cKDTree(theirs).query(ours)
    back_distance, _ = spatial.cKDTree(ours).query(theirs)
    tolerance += 1e-5  # float32 rounding of coordinates up to 50
    assert distance.max() <= tolerance and back_distance.max() <= tolerance
    assert len(ours) == len(theirs)
    return np.arange(len(ours)), nearest


def _signed_volume(verts, faces):
    a, b, c = (np.asarray(verts, dtype=np.float64)[faces[:, i]] for i in range(3))
    return np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6


def _donut():
    """scikit-image's double torus (by Thomas Lewiner), 48^3."""
    n = 48
    z, y, x = np.meshgrid(*[np.arange(n) * 2.5 / n - 1.25] * 3, indexing="ij")
    r1 = (8 * x) ** 2 + (8 * y - 2) ** 2 + (8 * z) ** 2 + 16 - 1.85**2
    r2 = (8 * x) ** 2 + (8 * y + 2) ** 2 + (8 * z) ** 2 + 16 - 1.85**2
    return ((r1 * r1 - 64 * ((8 * x) ** 2 + (8 * y - 2) ** 2)) * (r2 * r2 - 64 * ((8 * y + 2) ** 2 + (8 * z) ** 2))
            + 1025).astype(np.float32)


@pytest.mark.parametrize("volume, level, spacing", [
    (ellipsoid(6, 10, 16, levelset=True), 0.0, (1.0, 1.0, 1.0)),
    (ellipsoid(6, 10, 16, spacing=(1.0, 10 / 6, 16 / 6), levelset=True), 0.0, (1.0, 10 / 6, 16 / 6)),
    (_donut(), 0.0, (1.0, 1.0, 1.0)),
    (ellipsoid(9, 9, 9, levelset=True)[:12], None, (0.5, 1.0, 2.0)),  # cut by the border; level: the midpoint
])
def test_the_same_vertices_winding_normals_and_values_as_scikit_image(volume, level, spacing):
    verts, faces, normals, values = marching_cubes(volume, level, spacing=spacing)
    sk_verts, sk_faces, sk_normals, sk_values = skimage_measure.marching_cubes(volume, level, spacing=spacing)
    assert verts.dtype == sk_verts.dtype and faces.dtype == sk_faces.dtype
    assert normals.dtype == sk_normals.dtype and values.dtype == sk_values.dtype
    # Vertices: the same interpolation, ours kept 0.001 voxel inside the edge (a vertex on a
    # sample moves by that, times a spacing of at most 2.7).
    ours, theirs = _matched(verts, sk_verts, 3e-3)
    # Normals: both the data's gradient interpolated along the edge (theirs weighted by the
    # ends' closeness to the level); unit length, pointing the same way within a few degrees.
    assert_allclose(np.linalg.norm(normals, axis=1), 1, rtol=1e-5)
    # (cosine measured: 0.99 and more on the closed level sets, 0.966 on the cut ellipsoid,
    # where ours are one-sided at the border and theirs one-sided within each cell).
    assert np.mean(np.einsum("ij,ij->i", normals[ours], sk_normals[theirs])) > 0.95
    # Values: the largest value range of the cells round the vertex, the same cells but where
    # a vertex of theirs lies on a sample (the level equals it), on which edge's cells it
    # counts: 4 of 856 vertices on the cut ellipsoid; 1% allowed.
    same = np.isclose(values[ours], sk_values[theirs], rtol=1e-5)
    assert np.count_nonzero(~same) <= 0.01 * len(verts)
    # Winding: the same orientation everywhere, so the same signed volume and area as their
    # "lorensen" (whose case table splits ambiguous cells as ours does; Lewiner's splits some
    # the other way: on the double torus 1.3% less area, the same volume to 0.02%), up to the
    # vertices' 0.001 voxel: 0.1%; the signed volume 0.5% (of an open mesh it also depends on
    # the cells along the cut).
    for direction in ("descent", "ascent"):
        v, f = marching_cubes(volume, level, spacing=spacing, gradient_direction=direction)[:2]
        sk_v, sk_f = skimage_measure.marching_cubes(volume, level, spacing=spacing, gradient_direction=direction,
                                                    method="lorensen")[:2]
        assert _signed_volume(v, f) == pytest.approx(_signed_volume(sk_v, sk_f), rel=5e-3)
        assert mesh_surface_area(v, f) == pytest.approx(mesh_surface_area(sk_v, sk_f), rel=1e-3)


@pytest.mark.parametrize("step_size", [2, 3])
def test_step_size_meshes_every_nth_sample_as_scikit_image(step_size):
    volume = ellipsoid(6, 10, 16, levelset=True)
    verts, faces = marching_cubes(volume, 0, step_size=step_size)[:2]
    sk_verts, sk_faces = skimage_measure.marching_cubes(volume, 0, step_size=step_size)[:2]
    _matched(verts, sk_verts, 1e-3 * step_size)
    assert mesh_surface_area(verts, faces) == pytest.approx(mesh_surface_area(sk_verts, sk_faces), rel=5e-3)


def test_a_mask_keeps_the_cells_scikit_image_keeps():
    volume = ellipsoid(6, 10, 16, levelset=True)
    mask = np.zeros(volume.shape, dtype=bool)
    mask[4:12, 3:, 10:25] = True
    for step_size in (1, 2):
        verts, faces = marching_cubes(volume, 0, mask=mask, step_size=step_size)[:2]
        sk_verts, sk_faces = skimage_measure.marching_cubes(volume, 0, mask=mask, step_size=step_size)[:2]
        assert len(faces) == len(sk_faces)  # no ambiguous cell on this ellipsoid
        _matched(verts, sk_verts, 1e-3 * step_size)
        assert mesh_surface_area(verts, faces) == pytest.approx(mesh_surface_area(sk_verts, sk_faces), rel=1e-3)


def test_the_surface_is_open_at_the_border_as_scikit_image_s():
    volume = ellipsoid(9, 9, 9, levelset=True)[:12]
    verts, faces = marching_cubes(volume, 0)[:2]
    figures = vdbmesh.check(verts, faces)
    assert not figures["closed"] and figures["boundary_edges"] > 0
    closed = vdbmesh.check(*vdbmesh.mesh(volume, 0, method="mc"))
    assert closed["closed"] and closed["boundary_edges"] == 0


@pytest.mark.parametrize("volume, level, options", [
    (np.zeros((4, 4, 4)), 0.0, {}),
    (np.arange(64.0).reshape(4, 4, 4), 63.0, {}),
    (np.arange(27.0).reshape(3, 3, 3), 13.5, {"step_size": 5}),  # not one cell of 5 samples
    (np.arange(27.0).reshape(3, 3, 3), 13.5, {"mask": np.zeros((3, 3, 3), dtype=bool)}),
])
def test_no_surface_is_a_runtime_error_as_in_scikit_image(volume, level, options):
    with pytest.raises(RuntimeError, match="No surface found at the given iso value"):
        skimage_measure.marching_cubes(volume, level, **options)
    with pytest.raises(RuntimeError, match="No surface found at the given iso value"):
        marching_cubes(volume, level, **options)


@pytest.mark.parametrize("level", [-1.5, 4.0])
def test_a_level_outside_the_data_range_is_a_value_error_as_in_scikit_image(level):
    volume = ellipsoid(3, 4, 5, levelset=True)
    with pytest.raises(ValueError):
        skimage_measure.marching_cubes(volume, level)
    with pytest.raises(ValueError, match="level: expected a value within the data range"):
        marching_cubes(volume, level)


@pytest.mark.parametrize("options, message", [
    ({"gradient_direction": "up"}, 'gradient_direction: expected "descent" or "ascent"'),
    ({"method": "_lorensen"}, 'method: expected "lewiner" or "lorensen"'),
    ({"step_size": 0}, "step_size: expected at least 1"),
    ({"spacing": (1, 1)}, "spacing: expected three positive numbers"),
    ({"mask": np.ones((2, 2, 2), dtype=bool)}, "mask: expected the volume's shape"),
])
def test_bad_options_are_value_errors_naming_the_option(options, message):
    with pytest.raises(ValueError, match=message):
        marching_cubes(ellipsoid(3, 4, 5, levelset=True), 0, **options)


def test_nan_samples_count_as_below_the_level_as_in_scikit_image():
    volume = ellipsoid(6, 10, 16, levelset=True)
    volume[8, 12, 18] = np.nan  # far inside the ellipsoid (below the level): no surface changes
    volume[0, 0, 0] = np.nan  # outside it, at a corner: a small cap round it, open at the border
    sk_verts = skimage_measure.marching_cubes(volume, 0)[0]
    verts, faces, normals, values = marching_cubes(volume, 0)
    assert np.all(np.isfinite(verts)) and np.all(np.isfinite(normals)) and np.all(np.isfinite(values))
    # The same crossed edges; by the corner scikit-image's vertices are NaN, ours lie where
    # the NaN's stand-in below the range puts them (on the corner's three edges).
    assert len(verts) == len(sk_verts)
    near_corner = np.all(verts < 1, axis=1)
    assert np.count_nonzero(near_corner) == 3
    _matched(verts[~near_corner], sk_verts[np.all(np.isfinite(sk_verts), axis=1)], 1e-3)


@pytest.mark.parametrize("dtype", [bool, np.uint8, np.int64, np.uint64, np.float16, np.float64])
def test_any_type_numpy_casts_safely(dtype):
    volume = (ellipsoid(6, 10, 16) * 3).astype(dtype)
    sk_verts = skimage_measure.marching_cubes(volume)[0]
    verts = marching_cubes(volume)[0]
    _matched(verts, sk_verts, 1e-3)
