"""vdbmesh.check: the figures of `vdbmesh check` on meshes whose figures are known."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import vdbmesh

TETRAHEDRON = (
    np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32),
    np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32),
)


def test_a_tetrahedron_is_clean_with_its_exact_integrals():
    figures = vdbmesh.check(*TETRAHEDRON)
    assert figures["clean"] and figures["closed"] and figures["outward"]
    assert (figures["triangles"], figures["vertices"], figures["edges"]) == (4, 4, 6)
    assert (figures["euler_characteristic"], figures["genus"], figures["components"]) == (2, 0, 1)
    assert figures["volume"] == pytest.approx(1 / 6)
    assert figures["area"] == pytest.approx(1.5 + np.sqrt(3) / 2)
    np.testing.assert_allclose(figures["centroid"], [0.25, 0.25, 0.25])


def test_an_inside_out_tetrahedron_is_not_clean():
    vertices, faces = TETRAHEDRON
    figures = vdbmesh.check(vertices, faces[:, ::-1])
    assert not figures["clean"] and not figures["outward"]
    assert figures["volume"] == pytest.approx(-1 / 6)


def test_an_open_mesh_reports_its_boundary():
    vertices, faces = TETRAHEDRON
    figures = vdbmesh.check(vertices, faces[:3])
    assert not figures["closed"] and not figures["clean"]
    assert (figures["boundary_edges"], figures["boundary_loops"]) == (3, 1)


def test_figures_equal_those_of_the_command_line(tmp_path):
    # The program is built beside the module: build/vdbmesh and build/python/vdbmesh/.
    program = Path(vdbmesh._vdbmesh.__file__).resolve().parents[2] / "vdbmesh"
    if not program.exists():
        pytest.skip(f"{program} is not built")
    vdbmesh.write_mesh(tmp_path / "tetrahedron.ply", *TETRAHEDRON)
    run = subprocess.run([program, "check", tmp_path / "tetrahedron.ply", "--json"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    expected = json.loads(run.stdout)
    figures = vdbmesh.check(*TETRAHEDRON)
    assert list(figures) == list(expected)
    for name, value in expected.items():
        np.testing.assert_allclose(figures[name], value, rtol=1e-12, err_msg=name)


def test_self_intersections_are_counted():
    vertices, faces = TETRAHEDRON
    shifted = vertices + np.float32([0.2, 0.2, 0.2])
    both = np.vstack([vertices, shifted]), np.vstack([faces, faces + 4])
    figures = vdbmesh.check(*both)
    assert figures["self_intersecting_pairs"] > 0 and not figures["clean"]
