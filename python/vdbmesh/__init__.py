"""vdbmesh: tomography to clean triangle meshes through sparse OpenVDB grids.

Axis convention (scikit-image's): a volume is a 3D numpy array indexed ``a[i, j, k]``,
``spacing`` gives world units per step along i, j and k, and without an ``affine`` the
vertices are ``(i, j, k) * spacing``, in that order, exactly where
``skimage.measure.marching_cubes(a, iso, spacing=spacing)`` puts them. A 4 x 4 (or 3 x 4)
``affine`` maps ``(i, j, k, 1)`` to the world instead. The last axis is the fastest one of a
scan file: ``read_volume`` returns ``a[z, y, x]``, C-ordered, which is how the library
streams it, so C-ordered arrays are read in memory order (Fortran-ordered ones give the same
mesh, read with strides).

Meshes are ``(vertices, faces)``: vertices N x 3 float32 in world units, faces M x 3 int32,
counter-clockwise seen from outside the object (normals point out).

Errors carry the library's messages: a bad argument raises ValueError, input that does not
match its format ``vdbmesh.FormatError`` (a ValueError and a ``vdbmesh.Error``), other
runtime failures ``vdbmesh.Error`` (a RuntimeError), a missing input FileNotFoundError.
"""

import errno
import os

import numpy as np

from ._vdbmesh import Error, FormatError
from . import _vdbmesh

__all__ = ["read_volume", "mesh", "mesh_labels", "check", "read_mesh", "write_mesh", "to_vdb", "Error", "FormatError"]


def read_volume(path):
    """Reads a scan in any format vdbmesh reads (NIfTI, Analyze, OpenQVis, MetaImage, NRRD,
    a DICOM folder).

    Returns ``(array, spacing, affine)``: the samples as a float32 array ``a[z, y, x]`` (value
    scale applied), the spacing per array axis and the 4 x 4 affine from array index
    ``(i, j, k, 1)`` to the world.
    """
    return _vdbmesh.read_volume(_existing_path(path))


def mesh(volume_or_path, iso, method="dc", error=0.0, inside="above", spacing=None, affine=None, adaptivity=0.0):
    """Meshes the isosurface ``iso`` of a volume: a 3D array, or the path of a scan or .vdb file
    (which carries its own geometry: then give neither spacing nor affine).

    method: "dc" (intersection-free Dual Contouring, adaptive with ``error`` > 0, in voxels,
    closed, manifold and free of self-intersections by construction; at 0 it equals Marching
    Cubes), "dmc" (Dual Marching Cubes, made clean by a check-and-refine loop), "mc"
    (Marching Cubes) or "openvdb" (volumeToMesh, adaptive with ``adaptivity`` in [0, 1]). inside: "above" (values above iso are the object) or "below".
    The surface is closed where the object meets the border of the volume.

    Returns ``(vertices, faces)``: N x 3 float32 in world units and M x 3 int32.
    """
    if isinstance(volume_or_path, (str, os.PathLike)):
        if spacing is not None or affine is not None:
            raise ValueError("spacing, affine: only for arrays; a file carries its own geometry")
        return _vdbmesh.mesh_file(_existing_path(volume_or_path), float(iso), method, float(error), float(adaptivity),
                                  inside)
    return _vdbmesh.mesh_array(_volume_array(volume_or_path), float(iso), method, float(error), float(adaptivity),
                               inside, _array_to_world(spacing, affine))


def mesh_labels(labels_or_path, labels="all", spacing=None, affine=None, smoothing_iterations=16):
    """Meshes a label map (0 = background, 1..65535 = structures): a 3D integer array, or the
    path of a scan file (which carries its own geometry: then give neither spacing nor affine).

    labels: "all", or an iterable of label values; other labels count as background. Every
    label's mesh is closed, manifold, outward and free of self-intersections, the walls between
    two labels are the same triangles in both (as ``vdbmesh mesh --labels``).

    Returns ``{label: (vertices, faces)}`` in ascending label order.
    """
    wanted = [] if isinstance(labels, str) and labels == "all" else sorted({int(v) for v in labels})
    if isinstance(labels, str) and labels != "all":
        raise ValueError(f'labels: expected "all" or label values, got "{labels}"')
    if any(v < 1 or v > 65535 for v in wanted) or (not isinstance(labels, str) and not wanted):
        raise ValueError(f"labels: expected label values 1..65535, got {labels!r}")
    if isinstance(labels_or_path, (str, os.PathLike)):
        if spacing is not None or affine is not None:
            raise ValueError("spacing, affine: only for arrays; a file carries its own geometry")
        return _vdbmesh.mesh_labels_file(_existing_path(labels_or_path), wanted, int(smoothing_iterations))
    array = np.asarray(labels_or_path)
    if array.dtype.kind not in "biu":
        raise ValueError(f"labels: expected an integer (or boolean) array, got {array.dtype}")
    return _vdbmesh.mesh_labels_array(array.astype(np.int64, copy=False), _array_to_world(spacing, affine), wanted,
                                      int(smoothing_iterations))


def check(vertices, faces):
    """Validates and measures a mesh without repairing anything; returns the figures of
    ``vdbmesh check --json`` as a dict (clean, closed, boundary_edges, nonmanifold_edges,
    self_intersecting_pairs, components, genus, area, volume, centroid, ...)."""
    return _vdbmesh.check(np.asarray(vertices), np.asarray(faces))


def read_mesh(path):
    """Reads an STL, PLY or OBJ file as ``(vertices, faces)``, welding only bit-identical corners."""
    return _vdbmesh.read_mesh(_existing_path(path))


def write_mesh(path, vertices, faces, ascii=False, normals=False):
    """Writes a mesh as STL, PLY or OBJ (by extension), atomically. ``ascii``: ASCII STL or PLY;
    ``normals``: per-vertex normals in PLY and OBJ."""
    _vdbmesh.write_mesh(os.fspath(path), np.asarray(vertices), np.asarray(faces), bool(ascii), bool(normals))


def to_vdb(array, iso, path, spacing=None, affine=None):
    """Converts a 3D array into a sparse OpenVDB grid around the isosurface ``iso`` and writes
    it to ``path`` (.vdb), with the transform of ``spacing`` or ``affine`` (as in ``mesh``)."""
    _vdbmesh.array_to_vdb(_volume_array(array), float(iso), os.fspath(path), _array_to_world(spacing, affine))


def _existing_path(path):
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(errno.ENOENT, os.strerror(errno.ENOENT), path)
    return path


def _volume_array(volume):
    """The volume as a numpy array the library reads in place: any layout, native byte order;
    booleans are read as uint8 (a view, no copy)."""
    array = np.asarray(volume)
    if array.dtype == np.bool_:
        return array.view(np.uint8)
    if not array.dtype.isnative:
        return array.astype(array.dtype.newbyteorder("="))
    return array


def _array_to_world(spacing, affine):
    """The 3 x 4 affine from array index (i, j, k, 1) to the world, as nested lists."""
    if spacing is not None and affine is not None:
        raise ValueError("spacing, affine: give one of them (an affine includes the spacing)")
    if affine is not None:
        matrix = np.asarray(affine, dtype=np.float64)
        if matrix.shape not in ((3, 4), (4, 4)) or not np.all(np.isfinite(matrix)):
            raise ValueError(f"affine: expected a finite 4 x 4 or 3 x 4 matrix, got shape {matrix.shape}")
        if matrix.shape == (4, 4) and not np.array_equal(matrix[3], [0, 0, 0, 1]):
            raise ValueError(f"affine: expected a last row of 0, 0, 0, 1, got {matrix[3].tolist()}")
        return matrix[:3].tolist()
    steps = np.ones(3) if spacing is None else np.asarray(spacing, dtype=np.float64)
    if steps.shape != (3,) or not np.all(np.isfinite(steps) & (steps > 0)):
        raise ValueError(f"spacing: expected three positive numbers, got {spacing!r}")
    return np.hstack([np.diag(steps), np.zeros((3, 1))]).tolist()
