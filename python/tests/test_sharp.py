"""vdbmesh.mesh(..., sharp=True): `vdbmesh mesh --sharp`, refused in the same cases with the
same words (the library's sharp_refusal() makes both messages)."""

import subprocess
from pathlib import Path

import numpy as np
import pytest

import vdbmesh

HALF_SIDE = 10.0
CENTRE = 19.5 + 0.13  # off the grid's symmetry planes
CORNERS = np.array([[CENTRE + sx * HALF_SIDE, CENTRE + sy * HALF_SIDE, CENTRE + sz * HALF_SIDE]
                    for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])


@pytest.fixture(scope="module")
def cube():
    """HALF_SIDE - max |p - centre| over a 40^3 array: positive inside an axis-aligned cube of
    edge 20, whose corners the trilinear surface rounds and --sharp's vertices reach for."""
    grids = np.meshgrid(*[np.arange(40, dtype=np.float64)] * 3, indexing="ij")
    chebyshev = np.max([np.abs(g - CENTRE) for g in grids], axis=0)
    return (HALF_SIDE - chebyshev).astype(np.float32)


def _corner_gaps(vertices):
    """For each cube corner, the distance to the nearest mesh vertex (array index = world here)."""
    return np.min(np.linalg.norm(vertices[None, :, :] - CORNERS[:, None, :], axis=2), axis=1)


def _assert_closed_and_consistent(faces):
    # Each directed edge once and its reverse once: closed, edge-manifold, consistently oriented.
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]).tolist()
    keys = {tuple(e) for e in directed}
    assert len(keys) == len(directed)
    assert all((b, a) in keys for a, b in keys)


def test_sharp_vertices_come_closer_to_the_corners(cube):
    plain_vertices, plain_faces = vdbmesh.mesh(cube, 0.0, error=0.25, inside="above")
    vertices, faces = vdbmesh.mesh(cube, 0.0, error=0.25, inside="above", sharp=True)
    _assert_closed_and_consistent(faces)
    assert len(faces) != len(plain_faces) or not np.array_equal(vertices, plain_vertices)
    # Without --sharp the corners are rounded off by the trilinear surface (about half a voxel
    # here); with it some vertex lands nearer each, and the worst corner is nearer too.
    plain, sharp = _corner_gaps(plain_vertices), _corner_gaps(vertices)
    assert np.all(sharp <= plain + 1e-6), (plain, sharp)
    assert sharp.max() < plain.max(), (plain, sharp)


def test_sharp_is_the_command_lines_mesh(tmp_path, cube):
    # The program is built beside the module: build/vdbmesh and build/python/vdbmesh/.
    program = Path(vdbmesh._vdbmesh.__file__).resolve().parents[2] / "vdbmesh"
    if not program.exists():
        pytest.skip(f"{program} is not built")
    grid = tmp_path / "cube.vdb"
    vdbmesh.to_vdb(cube, 0.0, grid)
    out = tmp_path / "cube.ply"
    run = subprocess.run([program, "mesh", grid, "--error", "0.25", "--sharp", "--inside", "above", "-o", out, "--quiet"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    expected_vertices, expected_faces = vdbmesh.read_mesh(out)
    vertices, faces = vdbmesh.mesh(grid, error=0.25, inside="above", sharp=True)
    np.testing.assert_array_equal(faces, expected_faces)
    np.testing.assert_array_equal(vertices, expected_vertices)


@pytest.mark.parametrize("sharp", [1, 0, "yes", None, 1.0])
def test_sharp_that_is_not_a_bool_is_a_type_error(cube, sharp):
    with pytest.raises(TypeError, match="sharp: expected True or False"):
        vdbmesh.mesh(cube, 0.0, error=0.25, sharp=sharp)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"method": "mc"}, 'sharp=True: only with method="dc", got method="mc"'),
        ({"method": "openvdb", "adaptivity": 0.5}, 'sharp=True: only with method="dc", got method="openvdb"'),
        ({}, r"sharp=True: only with error above 0 \(at 0 no cell merges\), got error=0$"),
        ({"error": 0.25, "triangles": 600},
         r"sharp=True: only without triangles \(the budget's decimator keeps no feature\), got triangles$"),
        ({"triangles": 600}, r"sharp=True: only with error above 0"),  # the command line's order: the error first
    ],
)
def test_sharp_with_options_it_cannot_take_is_refused(cube, options, message):
    with pytest.raises(ValueError, match=message):
        vdbmesh.mesh(cube, 0.0, sharp=True, **options)


def test_sharp_false_changes_nothing(cube):
    for method in ("mc", "dc"):
        a = vdbmesh.mesh(cube, 0.0, method=method, inside="above")
        b = vdbmesh.mesh(cube, 0.0, method=method, inside="above", sharp=False)
        np.testing.assert_array_equal(a[0], b[0])
        np.testing.assert_array_equal(a[1], b[1])
