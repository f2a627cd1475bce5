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
counter-clockwise seen from outside the object (normals point out). ``marching_cubes`` is
``skimage.measure.marching_cubes``'s drop-in instead: its arguments, its
``(verts, faces, normals, values)``, its conventions (open at the array's border).

Long calls release the GIL and stop on Ctrl-C (KeyboardInterrupt), writing nothing.

Errors carry the library's messages: a bad argument raises ValueError, input that does not
match its format ``vdbmesh.FormatError`` (a ValueError and a ``vdbmesh.Error``), other
runtime failures ``vdbmesh.Error`` (a RuntimeError; no surface at the level is one), a
missing input FileNotFoundError.
"""

import errno
import operator
import os
import warnings

import numpy as np

from ._vdbmesh import Error, FormatError
from . import _arrays, _vdbmesh
from ._skimage import marching_cubes

__all__ = ["read_volume", "mesh", "marching_cubes", "mesh_labels", "check", "read_mesh", "write_mesh", "to_vdb",
           "Error", "FormatError"]


def read_volume(path):
    """Reads a scan in any format vdbmesh reads (NIfTI, Analyze, OpenQVis, MetaImage, NRRD,
    a DICOM folder).

    Returns ``(array, spacing, affine)``: the samples as a float32 array ``a[z, y, x]`` (value
    scale applied), the spacing per array axis and the 4 x 4 affine from array index
    ``(i, j, k, 1)`` to the world.
    """
    return _vdbmesh.read_volume(_existing_path(path))


def mesh(volume_or_path, iso=None, method="dc", error=0.0, inside="auto", spacing=None, affine=None, adaptivity=0.0,
         *, level=None, closed=True, triangles=None, sharp=False):
    """Meshes the isosurface at ``iso`` (or ``level``, its alias) of a volume: a 3D array, or the
    path of a scan or .vdb file (which carries its own geometry: then give neither spacing nor
    affine). The closed, guaranteed call; ``marching_cubes`` is scikit-image's drop-in.

    iso, level: for an array, by default the midpoint of its data range (as scikit-image);
    a level outside the range raises ValueError. A .vdb file defaults to the isovalue convert
    stored (0 for a level set); a scan file needs one.
    method: "dc" (intersection-free Dual Contouring, adaptive with ``error`` > 0, in voxels,
    closed, manifold and free of self-intersections by construction; at 0 it equals Marching
    Cubes), "mc" (Marching Cubes) or "openvdb" (volumeToMesh, adaptive with ``adaptivity``
    in [0, 1]). "dmc" (Dual Marching Cubes) was retired: it runs "dc", with a
    DeprecationWarning (docs/dmc.md says why).
    inside: "above" (values above the level are the object), "below", or "auto": the side
    that touches less of the volume's border (a level set's negative inside, a CT's dense
    material, not their complement; above on a tie; a .vdb that records no scanned box:
    below for a level set, else the side away from its background).
    closed: the surface is closed where the object meets the border of the volume; False
    leaves it open there (method "mc").
    triangles: at most this many triangles (a whole number from 1 to 2**32 - 1), the closest
    such mesh, as ``vdbmesh mesh --triangles N``, keeping every guarantee of "dc": below DC's
    lightest mesh (error 2), that mesh decimated by the guaranteed decimator to exactly
    ``triangles`` (one fewer for an odd number: a closed mesh has an even count); else the DC
    mesh of the smallest error (0, then 0.1 to 1) that fits. Method "dc" only, without ``error``
    (the budget picks it).
    A budget above the error-0 mesh's triangles, or below where the decimation must stop to keep
    the guarantees, raises ValueError; a number that is not whole (a float, a bool) TypeError.
    sharp: True puts the vertices of cells on sharp edges and corners on the feature, up to a
    voxel beyond ``error`` there (as ``vdbmesh mesh --sharp``; docs/dmc.md, "Sharp features").
    Method "dc" with ``error`` above 0 only, not with ``triangles`` (ValueError); a value other
    than True or False raises TypeError.
    NaN samples count as outside the object (as scikit-image counts them: not above the level);
    the surface passes next to them.
    Arrays of int64, uint64 and float16 are cast (numpy's safe casts); other types raise.

    Returns ``(vertices, faces)``: N x 3 float32 in world units and M x 3 int32. Raises
    vdbmesh.Error when there is no surface at the level.
    """
    if volume_or_path is None:
        raise ValueError("volume_or_path: expected a 3D array or the path of a scan or .vdb file, got None")
    level = _alias(iso, level)
    if method == "dmc":
        warnings.warn("dmc was retired: it runs dc, see docs/dmc.md", DeprecationWarning, stacklevel=2)
        method = "dc"
    _check_applicable(method, error, adaptivity, closed)
    if not isinstance(sharp, bool):
        raise TypeError(f"sharp: expected True or False, got {type(sharp).__name__} {sharp!r}")
    _vdbmesh.refuse_sharp_conflicts(sharp, method, float(error), triangles is not None)
    triangles = _triangle_budget(triangles, method, error)
    _arrays.check_inside(inside)
    if isinstance(volume_or_path, (str, os.PathLike)):
        if spacing is not None or affine is not None:
            raise ValueError("spacing, affine: only for arrays; a file carries its own geometry")
        vertices, faces = _vdbmesh.mesh_file(_existing_path(volume_or_path), None if level is None else float(level),
                                             method, float(error), float(adaptivity), inside, not closed,
                                             triangles, sharp)
    else:
        array = _arrays.volume_array(volume_or_path)
        data_range = _arrays.data_range(array)
        level = _arrays.surface_level(level, data_range)
        array = _arrays.nan_at_level(array, level)
        array_to_world, unit = _array_to_world(spacing, affine)
        vertices, faces = _vdbmesh.mesh_array(array, level, method, float(error), float(adaptivity), inside, not closed,
                                              array_to_world, triangles, sharp)
        if unit != 1:
            vertices *= unit
    if len(faces) == 0:
        raise Error(f"no surface at level {level!r}" if level is not None else "no surface at the stored isovalue")
    return vertices, faces


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
    # No rescaling: a label map's voxels are not the sub-micrometre ones _array_to_world() rescales for.
    array_to_world, _ = _array_to_world(spacing, affine, rescale=False)
    return _vdbmesh.mesh_labels_array(array.astype(np.int64, copy=False), array_to_world, wanted, int(smoothing_iterations))


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
    it to ``path`` (.vdb), with the transform of ``spacing`` or ``affine`` (as in ``mesh``).
    OpenVDB holds no voxel under 3e-15 cubic units: give such a spacing in a smaller unit."""
    array_to_world, _ = _array_to_world(spacing, affine, rescale=False)
    _vdbmesh.array_to_vdb(_arrays.volume_array(array), float(iso), os.fspath(path), array_to_world)


def _existing_path(path):
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(errno.ENOENT, os.strerror(errno.ENOENT), path)
    return path


def _alias(iso, level):
    """The level given as ``iso`` or as ``level`` (None when neither)."""
    if iso is not None and level is not None:
        raise ValueError("iso, level: give one of them (level is an alias of iso)")
    return level if iso is None else iso


def _check_applicable(method, error, adaptivity, closed):
    """Refuses options that the method does not use, rather than ignoring them."""
    if error != 0 and method != "dc":
        raise ValueError(f'error: only for method "dc", got method {method!r}')
    if adaptivity != 0 and method != "openvdb":
        raise ValueError(f'adaptivity: only for method "openvdb", got method {method!r}')
    if not closed and method != "mc":
        raise ValueError(f'closed=False: only for method "mc" (method {method!r} closes the surface)')


# The most triangles a budget may ask: a mesh's indices are 32-bit (as `vdbmesh mesh --triangles`).
_MAX_TRIANGLES = 2**32 - 1


def _triangle_budget(triangles, method, error):
    """The budget as an int, or None; refuses what `vdbmesh mesh --triangles` refuses."""
    if triangles is None:
        return None
    if isinstance(triangles, bool) or not hasattr(type(triangles), "__index__"):
        raise TypeError(f"triangles: expected a whole number, got {type(triangles).__name__} {triangles!r}")
    count = operator.index(triangles)
    if not 1 <= count <= _MAX_TRIANGLES:
        raise ValueError(f"triangles: expected a whole number of triangles from 1 to {_MAX_TRIANGLES}, got {count}")
    if method != "dc":
        raise ValueError(f'triangles: only for method "dc", got method {method!r}')
    if error != 0:
        raise ValueError(f"triangles: not with error (the budget picks the error), got error={error!r}")
    return count


# Voxels smaller than this (cube root of the determinant) are meshed in a unit a power of two
# larger: OpenVDB refuses a transform whose determinant is below 3e-15 (math::AffineMap),
# whatever its scale, so a 10 um voxel in metres would otherwise be "singular".
_SMALLEST_VOXEL = 2.0**-10


def _array_to_world(spacing, affine, rescale=True):
    """(the 3 x 4 affine from array index (i, j, k, 1) to the world as nested lists, unit):
    with ``rescale``, a tiny voxel's affine is divided by ``unit``, a power of two (so
    multiplying the vertices back is exact), else unit is 1."""
    if spacing is not None and affine is not None:
        raise ValueError("spacing, affine: give one of them (an affine includes the spacing)")
    if affine is not None:
        matrix = np.asarray(affine, dtype=np.float64)
        if matrix.shape not in ((3, 4), (4, 4)) or not np.all(np.isfinite(matrix)):
            raise ValueError(f"affine: expected a finite 4 x 4 or 3 x 4 matrix, got shape {matrix.shape}")
        if matrix.shape == (4, 4) and not np.array_equal(matrix[3], [0, 0, 0, 1]):
            raise ValueError(f"affine: expected a last row of 0, 0, 0, 1, got {matrix[3].tolist()}")
        matrix = matrix[:3]
    else:
        steps = np.ones(3) if spacing is None else np.asarray(spacing, dtype=np.float64)
        if steps.shape != (3,) or not np.all(np.isfinite(steps) & (steps > 0)):
            raise ValueError(f"spacing: expected three positive numbers, got {spacing!r}")
        matrix = np.hstack([np.diag(steps), np.zeros((3, 1))])
    voxel = abs(np.linalg.det(matrix[:, :3])) ** (1 / 3)
    unit = 1.0
    if rescale and 0 < voxel < _SMALLEST_VOXEL:
        unit = 2.0 ** round(np.log2(voxel))
    return (matrix / unit).tolist(), unit
