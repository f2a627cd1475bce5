"""vdbmesh.mesh(..., triangles=N): the triangle budget of `vdbmesh mesh --triangles N`.

The guarantees are judged here by code of the test's own (edges and vertex links counted with
numpy and Python), not by the library's checker: only self-intersections, which need exact
predicates, are left to vdbmesh.check."""

import collections

import numpy as np
import pytest

import vdbmesh
from volumes import sphere_field

RADIUS = 14.0


@pytest.fixture(scope="module")
def sphere():
    return sphere_field(40, RADIUS)


@pytest.fixture(scope="module")
def error_zero_count(sphere):
    return len(vdbmesh.mesh(sphere, 0.0)[1])


@pytest.fixture(scope="module")
def lightest_count(sphere):
    """The triangles of DC at error 2, where a budget starts (kBudgetBaseError): a smaller
    budget is met by the decimator, exactly."""
    return len(vdbmesh.mesh(sphere, 0.0, error=2.0)[1])


def _assert_closed_manifold_outward(vertices, faces):
    faces = np.asarray(faces, dtype=np.int64)
    # Every directed edge once, and its reverse too: each edge has exactly two triangles, which
    # run along it in opposite directions (closed, edge-manifold, consistently oriented).
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    as_keys = {tuple(e) for e in directed.tolist()}
    assert len(as_keys) == len(directed), "a directed edge is used twice (non-manifold or flipped)"
    assert all((b, a) in as_keys for a, b in as_keys), "an edge with one triangle (a hole)"
    # Vertex-manifold: the edges opposite a vertex in its triangles form a single cycle.
    link = collections.defaultdict(dict)
    for a, b, c in faces.tolist():
        link[a][b] = c
        link[b][c] = a
        link[c][a] = b
    for vertex, successor in link.items():
        start = next(iter(successor))
        steps, current = 0, start
        while True:
            current = successor[current]
            steps += 1
            if current == start:
                break
        assert steps == len(successor), f"vertex {vertex}: its triangles form more than one fan"
    # Outward: the enclosed volume is positive; and more than half the sphere's (a polyhedron of
    # 40 triangles inscribed in a sphere already holds about 60% of it).
    a, b, c = (vertices[faces[:, k]].astype(np.float64) for k in range(3))
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    assert 0.5 * (4 / 3 * np.pi * RADIUS**3) < volume < 1.1 * (4 / 3 * np.pi * RADIUS**3)


@pytest.mark.parametrize("budget", [40, 101, 150])
def test_a_budget_below_the_lightest_mesh_is_met_exactly_keeping_the_guarantees(sphere, lightest_count, budget):
    assert budget < lightest_count
    vertices, faces = vdbmesh.mesh(sphere, 0.0, triangles=budget)
    assert len(faces) == budget - budget % 2  # a closed triangle mesh has an even count
    _assert_closed_manifold_outward(vertices, faces)
    assert vdbmesh.check(vertices, faces)["self_intersecting_pairs"] == 0


@pytest.mark.parametrize("error", [0.0, 0.5])
def test_a_budget_a_dc_mesh_meets_gives_the_most_accurate_such_mesh(sphere, lightest_count, error):
    # Budgets from the lightest mesh up take the smallest of the errors 0, ..., 0.1, ..., 1 whose
    # mesh fits (mesh_budget.h): here the mesh at `error` itself, the error below having more.
    reference = vdbmesh.mesh(sphere, 0.0, error=error)
    assert len(reference[1]) > lightest_count
    vertices, faces = vdbmesh.mesh(sphere, 0.0, triangles=len(reference[1]))
    np.testing.assert_array_equal(faces, reference[1])
    np.testing.assert_array_equal(vertices, reference[0])
    _assert_closed_manifold_outward(vertices, faces)


def test_a_file_takes_the_budget_too(tmp_path, sphere):
    path = tmp_path / "sphere.vdb"
    vdbmesh.to_vdb(sphere, 0.0, path)
    vertices, faces = vdbmesh.mesh(path, triangles=np.int64(60))
    assert len(faces) == 60
    _assert_closed_manifold_outward(vertices, faces)


@pytest.mark.parametrize("budget", [2.0, 600.5, True, "600", [600]])
def test_a_budget_that_is_not_a_whole_number_is_a_type_error(sphere, budget):
    with pytest.raises(TypeError, match="triangles: expected a whole number"):
        vdbmesh.mesh(sphere, 0.0, triangles=budget)


@pytest.mark.parametrize("budget", [0, -4, 2**32])
def test_a_budget_out_of_range_is_a_value_error(sphere, budget):
    with pytest.raises(ValueError, match="triangles: expected a whole number of triangles from 1 to 4294967295"):
        vdbmesh.mesh(sphere, 0.0, triangles=budget)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"method": "mc"}, 'triangles: only for method "dc"'),
        ({"method": "openvdb", "adaptivity": 0.5}, 'triangles: only for method "dc"'),
        ({"error": 0.5}, "triangles: not with error"),
    ],
)
def test_a_budget_with_options_it_cannot_take_is_refused(sphere, options, message):
    with pytest.raises(ValueError, match=message):
        vdbmesh.mesh(sphere, 0.0, triangles=600, **options)


def test_a_budget_above_the_most_accurate_mesh_is_refused(sphere, error_zero_count):
    with pytest.raises(ValueError, match=rf"the most accurate mesh there is \(error=0\) has {error_zero_count} triangles"):
        vdbmesh.mesh(sphere, 0.0, triangles=error_zero_count + 2)


def test_a_budget_below_what_a_closed_mesh_can_have_is_refused(sphere):
    # A closed triangle mesh has at least 4 triangles: the decimation must stop above 2.
    with pytest.raises(ValueError, match="the decimation keeping the mesh closed, manifold .* stops at"):
        vdbmesh.mesh(sphere, 0.0, triangles=2)
