"""``marching_cubes``: scikit-image's ``skimage.measure.marching_cubes`` as a drop-in, on the
library's Marching Cubes (open at the array's border, as scikit-image's is)."""

import numpy as np

from . import _arrays, _vdbmesh
from ._vdbmesh import Error

# The library's Marching Cubes as a function of the array: index space (the spacing is applied
# after, as scikit-image does), the object above the level, open at the border.
_INDEX_SPACE = np.hstack([np.eye(3), np.zeros((3, 1))]).tolist()


def marching_cubes(volume, level=None, *, spacing=(1.0, 1.0, 1.0), gradient_direction="descent", step_size=1,
                   allow_degenerate=True, method="lewiner", mask=None):
    """Marching Cubes with the signature and conventions of ``skimage.measure.marching_cubes``
    (scikit-image 0.19), so that replacing the import is all a user does.

    Returns ``(verts, faces, normals, values)``: verts (V, 3) float32 in array index order times
    ``spacing``; faces (F, 3) int32 wound as scikit-image winds them ("descent": the normal by
    the right-hand rule points towards higher values, "ascent": towards lower ones); normals
    (V, 3) float32, the data's gradient at each vertex in index space, pointing towards lower
    values, unit length; values (V,) float32, the largest value range (max - min) of the cells
    around each vertex. The surface is open where it meets the border of the array (use
    ``vdbmesh.mesh`` for a closed one). NaN samples count as below the level, as there;
    ``level`` defaults to the midpoint of the data range (NaNs left out) and must lie within it.

    The same errors as scikit-image: ValueError for a volume that is not 3D or smaller than
    2 x 2 x 2, a level outside the data range, a spacing that is not three numbers, a step
    size below 1, a mask of another shape, an unknown ``gradient_direction`` or ``method``;
    RuntimeError (vdbmesh.Error) when there is no surface at the level.

    Differences a user can see: the triangulation of ambiguous cells is the library's (its
    Marching Cubes table keeps the surface closed and manifold, as Lewiner's does, but may
    split a cell the other way), vertices are kept 0.001 voxel inside their edge (never on
    a sample), so no triangle is degenerate and ``allow_degenerate`` changes nothing, and
    "lewiner" and "lorensen" give the same mesh.
    """
    _check_options(gradient_direction, method, allow_degenerate)
    array = _arrays.volume_array(volume)
    if min(array.shape) < 2:
        raise ValueError(f"volume: expected an array of at least 2 x 2 x 2, got {' x '.join(map(str, array.shape))}")
    steps = _spacing(spacing)
    step = _step(step_size)
    cell_mask = _cell_mask(mask, array.shape, step)
    data_range = _arrays.data_range(array)  # the whole array's, as scikit-image checks the level
    level = _arrays.surface_level(level, data_range)
    samples = array[::step, ::step, ::step].astype(np.float32, copy=False)  # as scikit-image compares them
    samples = _arrays.nan_at_level(samples, level)

    verts, faces = _vdbmesh.mesh_array(samples, level, "mc", 0.0, 0.0, "above", True, _INDEX_SPACE)
    cells = _face_cells(verts, faces, samples.shape)
    if cell_mask is not None:
        keep = cell_mask[cells[:, 0], cells[:, 1], cells[:, 2]]
        verts, faces, cells = _referenced(verts, faces[keep]) + (cells[keep],)
    if len(faces) == 0:
        raise Error("No surface found at the given iso value.")

    normals = _normals(samples, verts)
    values = _values(samples, faces, cells, len(verts))
    if gradient_direction == "descent":
        faces = faces[:, ::-1].copy()  # the library's triangles face lower values
    verts = verts * np.float32(step)
    if not np.array_equal(steps, (1, 1, 1)):
        verts = verts * steps  # float64, as scikit-image's
    return verts, faces, normals, values


def _check_options(gradient_direction, method, allow_degenerate):
    if gradient_direction not in ("descent", "ascent"):
        raise ValueError(f'gradient_direction: expected "descent" or "ascent", got {gradient_direction!r}')
    if method not in ("lewiner", "lorensen"):
        raise ValueError(f'method: expected "lewiner" or "lorensen", got {method!r}')
    if not isinstance(allow_degenerate, (bool, np.bool_)):
        raise ValueError(f"allow_degenerate: expected True or False, got {allow_degenerate!r}")


def _spacing(spacing):
    steps = np.asarray(spacing, dtype=np.float64)
    if steps.shape != (3,) or not np.all(np.isfinite(steps) & (steps > 0)):
        raise ValueError(f"spacing: expected three positive numbers, got {spacing!r}")
    return steps


def _step(step_size):
    step = int(step_size)
    if step < 1:
        raise ValueError(f"step_size: expected at least 1, got {step_size!r}")
    return step


def _cell_mask(mask, shape, step):
    """Which cells of the stepped grid to mesh: scikit-image meshes the cell whose first corner
    is (i, j, k) when mask[i + step, j + step, k + step] is true (its last corner)."""
    if mask is None:
        return None
    mask = np.asarray(mask)
    if mask.shape != shape:
        raise ValueError(f"mask: expected the volume's shape {shape}, got {mask.shape}")
    return mask.astype(bool, copy=False)[step::step, step::step, step::step]


def _face_cells(verts, faces, shape):
    """The cell (index of its first corner) of each triangle: every vertex lies strictly inside
    an edge of its cell, so the triangle's centroid lies strictly inside the cell."""
    centroids = verts[faces].mean(axis=1)
    cells = np.floor(centroids).astype(np.int64)
    return np.clip(cells, 0, np.array(shape) - 2)


def _referenced(verts, faces):
    """(verts, faces) without the vertices no face uses, in their order."""
    used = np.zeros(len(verts), dtype=bool)
    used[faces.ravel()] = True
    renumbered = np.cumsum(used, dtype=np.int64) - 1
    return verts[used], renumbered[faces].astype(np.int32)


def _normals(samples, verts):
    """The gradient of the samples (central differences, one-sided at the border, as
    np.gradient) interpolated linearly along each vertex's edge, negated and normalised."""
    gradient = np.stack(np.gradient(samples.astype(np.float64)), axis=-1)
    fraction = verts - np.round(verts)
    axis = np.argmax(np.abs(fraction), axis=1)  # the coordinate that is not a sample index
    first = np.round(verts).astype(np.int64)
    first[np.arange(len(verts)), axis] = np.floor(verts[np.arange(len(verts)), axis])
    second = first.copy()
    second[np.arange(len(verts)), axis] += 1
    t = (verts[np.arange(len(verts)), axis] - first[np.arange(len(verts)), axis])[:, None]
    g = (1 - t) * gradient[tuple(first.T)] + t * gradient[tuple(second.T)]
    length = np.linalg.norm(g, axis=1, keepdims=True)
    return (-g / np.where(length > 0, length, 1)).astype(np.float32)


def _values(samples, faces, cells, vertex_count):
    """Per vertex, the largest value range (max - min of the 8 corners) of the cells whose
    triangles use it, as scikit-image reports it."""
    corners = np.stack([samples[cells[:, 0] + di, cells[:, 1] + dj, cells[:, 2] + dk]
                        for di in (0, 1) for dj in (0, 1) for dk in (0, 1)], axis=1)
    ranges = (corners.max(axis=1) - corners.min(axis=1)).astype(np.float32)
    values = np.zeros(vertex_count, dtype=np.float32)
    for corner in range(3):
        np.maximum.at(values, faces[:, corner], ranges)
    return values
