"""vdbmesh.mesh as a scikit-image user calls it: which side is the object (inside), which level
(iso or level, the midpoint by default, within the data range), closed or open, tiny voxels,
NaN samples and the array types numpy casts safely."""

import numpy as np
import pytest

import vdbmesh
from shared_data import testdata
from volumes import ball, sphere_field

METHODS = ["dc", "dmc", "mc", "openvdb"]
RADIUS = 10.0
SPHERE_VOLUME = 4 / 3 * np.pi * RADIUS**3


def _clean_sphere(vertices, faces, scale=1.0):
    """Asserts that the mesh is the sphere of sphere_field(32, RADIUS), closed and facing out."""
    figures = vdbmesh.check(vertices / scale, faces)
    assert figures["closed"] and figures["outward"] and figures["components"] == 1
    # Within 2% of the exact volume: Marching Cubes' inscribed surface is short by about 0.2%
    # at this radius (test_mesh_arrays.py), volumeToMesh's by 1.1% (measured). The other side
    # (or the box round it) would be far off.
    assert figures["volume"] == pytest.approx(SPHERE_VOLUME, rel=2e-2)


@pytest.mark.parametrize("method", METHODS)
def test_inside_below_meshes_the_low_values_facing_out(method):
    # Negative inside, as a level set: with inside="below" the object is the sphere.
    _clean_sphere(*vdbmesh.mesh(-sphere_field(32, RADIUS), 0.0, method=method, inside="below"))


@pytest.mark.parametrize("method", METHODS)
def test_inside_below_touching_the_border_is_closed_at_the_box(method):
    # The object is the box less the sphere: closed where it meets the array's border.
    figures = vdbmesh.check(*vdbmesh.mesh(sphere_field(32, RADIUS), 0.0, method=method, inside="below"))
    assert figures["closed"] and figures["outward"] and figures["components"] == 2
    # The box's faces lie between the last samples and one voxel beyond them (31^3 to 33^3).
    assert 31**3 - SPHERE_VOLUME < figures["volume"] < 33**3 - SPHERE_VOLUME


@pytest.mark.parametrize("method", METHODS)
def test_inside_auto_takes_the_side_away_from_the_border(method):
    _clean_sphere(*vdbmesh.mesh(sphere_field(32, RADIUS), 0.0, method=method))  # positive inside (CT-like)
    _clean_sphere(*vdbmesh.mesh(-sphere_field(32, RADIUS), 0.0, method=method))  # negative inside (level set)


@pytest.mark.parametrize("sign", [1, -1])
def test_inside_auto_decides_a_file_as_it_decides_its_array(tmp_path, sign):
    volume = sign * sphere_field(32, RADIUS)
    vdbmesh.to_vdb(volume, 0.0, tmp_path / "sphere.vdb")  # a density grid with its scanned box
    from_file = vdbmesh.mesh(tmp_path / "sphere.vdb")  # level: the one stored
    _clean_sphere(*from_file)
    from_array = vdbmesh.mesh(volume, 0.0)
    np.testing.assert_array_equal(from_file[0], from_array[0])
    np.testing.assert_array_equal(from_file[1], from_array[1])


def test_a_scikit_image_level_set_ellipsoid_is_meshed_as_the_ellipsoid():
    draw = pytest.importorskip("skimage.draw")
    volume, area = draw.ellipsoid_stats(6, 10, 16)
    vertices, faces = vdbmesh.mesh(draw.ellipsoid(6, 10, 16, levelset=True), 0)
    figures = vdbmesh.check(vertices, faces)
    assert figures["clean"] and figures["components"] == 1
    # scikit-image's tolerances for its own Marching Cubes of this ellipsoid: the area within
    # 1% below the exact one (test_marching_cubes.py); the volume likewise inscribed.
    assert area * 0.99 < figures["area"] < area
    assert volume * 0.98 < figures["volume"] < volume


@pytest.mark.parametrize("level", [-0.5, 1.5])
def test_a_level_outside_the_data_range_raises(level):
    with pytest.raises(ValueError, match=r"level: expected a value within the data range \[0, 1\]"):
        vdbmesh.mesh(ball((12, 12, 12), 1), level)


@pytest.mark.parametrize("inside", ["auto", "above", "below"])
def test_a_level_outside_a_scan_file_s_range_raises(inside):
    with pytest.raises(ValueError, match=r"level: expected a value within the data range \[0\.0+, 1\.0+\] of "
                                         r".*sphere_phantom.nii.gz, got 2"):
        vdbmesh.mesh(testdata("sphere_phantom.nii.gz"), 2.0, inside=inside)  # samples in [0, 1]


@pytest.mark.parametrize("method", METHODS)
def test_a_scan_file_with_the_inside_below_is_closed_at_its_box(method):
    # sphere_phantom.nii.gz: a 48^3 sphere of radius 15 voxels, 1 inside, 0 outside (unit spacing).
    figures = vdbmesh.check(*vdbmesh.mesh(testdata("sphere_phantom.nii.gz"), 0.5, method=method, inside="below"))
    assert figures["closed"] and figures["outward"] and figures["components"] == 2
    sphere = 4 / 3 * np.pi * 15**3
    assert 47**3 - 1.02 * sphere < figures["volume"] < 49**3 - 0.98 * sphere


def test_level_is_an_alias_of_iso_and_defaults_to_the_midpoint():
    volume = ball((16, 16, 16), 100)
    expected = vdbmesh.mesh(volume, 50.0)
    for actual in (vdbmesh.mesh(volume, level=50.0), vdbmesh.mesh(volume)):
        np.testing.assert_array_equal(actual[0], expected[0])
        np.testing.assert_array_equal(actual[1], expected[1])
    with pytest.raises(ValueError, match="iso, level: give one of them"):
        vdbmesh.mesh(volume, 50.0, level=50.0)


def test_no_surface_at_the_level_is_an_error():
    with pytest.raises(vdbmesh.Error, match="no surface at level 1"):
        vdbmesh.mesh(ball((12, 12, 12), 1), 1.0)  # the top of the range: nothing above it


@pytest.mark.parametrize("method", ["mc", "dmc"])
def test_closed_false_leaves_the_border_open(method):
    volume = sphere_field(32, RADIUS)[:16]  # the sphere cut in half by the array's border
    closed = vdbmesh.check(*vdbmesh.mesh(volume, 0.0, method=method))
    assert closed["closed"] and closed["boundary_edges"] == 0
    open_ = vdbmesh.check(*vdbmesh.mesh(volume, 0.0, method=method, closed=False))
    assert not open_["closed"] and open_["boundary_loops"] == 1


@pytest.mark.parametrize("options, message", [
    ({"closed": False}, 'closed=False: only for method "mc" or "dmc"'),
    ({"closed": False, "method": "openvdb"}, 'closed=False: only for method "mc" or "dmc"'),
    ({"error": 0.5, "method": "mc"}, 'error: only for method "dc" or "dmc"'),
    ({"adaptivity": 0.5}, 'adaptivity: only for method "openvdb"'),
    ({"inside": "outside"}, 'inside: expected "auto", "above" or "below", got \'outside\''),
])
def test_options_that_do_not_apply_are_refused(options, message):
    with pytest.raises(ValueError, match=message):
        vdbmesh.mesh(ball((12, 12, 12), 1), 0.5, **options)


def test_none_is_refused_with_a_clear_message():
    with pytest.raises(ValueError, match="volume_or_path: expected a 3D array or the path of a scan or .vdb file, got None"):
        vdbmesh.mesh(None, 0.5)
    with pytest.raises(ValueError, match="volume: expected a 3D array, got None"):
        vdbmesh.marching_cubes(None)
    with pytest.raises(ValueError, match="volume: every sample is NaN"):
        vdbmesh.mesh(np.full((4, 4, 4), np.nan))


@pytest.mark.parametrize("voxel", [1e-5, 1e-7])
def test_tiny_voxels_are_meshed_in_their_units(voxel):
    # A 10 um voxel in metres: OpenVDB's transform refuses a determinant under 3e-15.
    vertices, faces = vdbmesh.mesh(sphere_field(32, RADIUS), 0.0, spacing=(voxel,) * 3)
    expected = vdbmesh.mesh(sphere_field(32, RADIUS), 0.0)
    np.testing.assert_array_equal(faces, expected[1])
    # Meshed in a unit a power of two apart, then scaled back: float32 rounding of the
    # product only (relative 2^-24 per coordinate, well under 1e-6).
    np.testing.assert_allclose(vertices, expected[0] * np.float32(voxel), rtol=1e-6)


def test_a_tiny_voxel_written_to_a_vdb_names_openvdb_s_limit(tmp_path):
    with pytest.raises(vdbmesh.FormatError, match=r"spacing: expected voxels of at least 3e-15 cubic units"):
        vdbmesh.to_vdb(sphere_field(16, 5.0), 0.0, tmp_path / "tiny.vdb", spacing=(1e-5,) * 3)
    assert not (tmp_path / "tiny.vdb").exists()


@pytest.mark.parametrize("inside", ["above", "below"])
def test_nan_samples_are_outside_the_object(inside):
    volume = sphere_field(32, RADIUS) * (1 if inside == "above" else -1)
    volume[16, 16, 16] = np.nan  # at the centre, inside: a cavity round it
    volume[0, 0, 0] = np.nan  # outside: no change
    figures = vdbmesh.check(*vdbmesh.mesh(volume, 0.0, inside=inside))
    assert figures["clean"] and figures["components"] == 2
    assert figures["volume"] < SPHERE_VOLUME


@pytest.mark.parametrize("dtype", [np.int64, np.uint64, np.float16])
def test_types_numpy_casts_safely_are_meshed(dtype):
    volume = ball((20, 22, 24), 100)
    expected = vdbmesh.mesh(volume.astype(np.float32), 50)
    actual = vdbmesh.mesh(volume.astype(dtype), 50)
    np.testing.assert_array_equal(actual[0], expected[0])
    np.testing.assert_array_equal(actual[1], expected[1])
