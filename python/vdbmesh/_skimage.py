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
    ``vdbmesh.mesh`` for a closed one). NaN samples count as below the level, as there (where
    its vertices next to a NaN are NaN, ours lie 0.001 voxel from it); ``level`` defaults to
    the midpoint of the data range (NaNs left out) and must lie within it.

    The same errors as scikit-image: ValueError for a volume that is not 3D or smaller than
    2 x 2 x 2, a level outside the data range, a spacing that is not three numbers, a step
    size below 1, a mask of another shape, an unknown ``gradient_direction`` or ``method``;
    RuntimeError (vdbmesh.Error) when there is no surface at the level.

    Differences a user can see: ambiguous cells are split as Lorensen's table splits them
    (scikit-image's "lorensen"; "lewiner" gives the same mesh here, where Lewiner's splits
    some the other way), vertices are kept 0.001 voxel inside their edge (never on a sample),
    so no triangle is degenerate and ``allow_degenerate`` changes nothing; normals are central
    differences, not scikit-image's one-sided ones per cell (a few degrees apart).
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

    verts, faces = _vdbmesh.mesh_array(samples, level, "mc", 0.0, 0.0, "above", True, _INDEX_SPACE, None, False)
    if len(faces) > 0:
        verts, faces, normals, values = _vdbmesh.marching_cubes_extras(samples, verts, faces, cell_mask)
    if len(faces) == 0:
        raise Error("No surface found at the given iso value.")
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
