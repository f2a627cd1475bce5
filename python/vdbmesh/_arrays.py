"""Arrays as the library reads them, their level and their NaN samples: the rules ``mesh`` and
``marching_cubes`` share (scikit-image's where it has one)."""

import warnings

import numpy as np

from ._vdbmesh import FormatError

# The sample types the library reads in place; other numeric types numpy casts safely to
# float64 (int64, uint64, float16) are cast, to float32 where that is exact.
_READ_IN_PLACE = {np.dtype(t) for t in ("uint8", "int8", "uint16", "int16", "uint32", "int32", "float32", "float64")}


def volume_array(volume):
    """The volume as a 3D numpy array the library reads: any layout, native byte order;
    booleans as uint8 (a view), int64, uint64 and float16 cast. Raises ValueError otherwise."""
    if volume is None:
        raise ValueError("volume: expected a 3D array, got None")
    array = np.asarray(volume)
    if array.ndim != 3:
        raise ValueError(f"volume: expected a 3D array, got {array.ndim}D")
    if array.size == 0:
        raise ValueError(f"volume: expected at least one sample along each axis, got shape {array.shape}")
    if array.dtype == np.bool_:
        return array.view(np.uint8)
    native = array.dtype.newbyteorder("=")
    if native in _READ_IN_PLACE:
        return array if array.dtype.isnative else array.astype(native)
    if array.dtype.kind in "iuf" and np.can_cast(array.dtype, np.float64):
        return array.astype(np.float32 if np.can_cast(array.dtype, np.float32) else np.float64)
    raise ValueError("volume: expected a 3D array of uint8, int8, uint16, int16, uint32, int32, float32, float64 or a "
                     f"type numpy casts safely to float64 (int64, uint64, float16, bool), got {array.dtype}")


def data_range(array):
    """(lowest, highest) sample, NaNs left out. Raises FormatError naming the first infinite
    sample (the library reads only finite ones) and ValueError when every sample is NaN."""
    floating = array.dtype.kind == "f"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # "All-NaN slice": reported below
        lo, hi = (np.nanmin(array), np.nanmax(array)) if floating else (array.min(), array.max())
    if floating and np.isnan(lo):
        raise ValueError("volume: every sample is NaN")
    if not (np.isfinite(lo) and np.isfinite(hi)):
        index = ", ".join(str(i) for i in np.argwhere(np.isinf(array))[0])
        raise FormatError(f"array: sample [{index}]: expected a finite number, got infinity")
    return float(lo), float(hi)


def surface_level(level, data_range):
    """The level to mesh at: the midpoint of the data range when None (scikit-image's
    default), else ``level``, which must lie within the range (scikit-image raises there too:
    outside it the surface would be the whole box or nothing)."""
    lo, hi = data_range
    if level is None:
        return 0.5 * (lo + hi)
    level = float(level)
    if not lo <= level <= hi:
        raise ValueError(f"level: expected a value within the data range [{lo:g}, {hi:g}], got {level:g}")
    return level


def check_inside(inside):
    """Raises ValueError unless ``inside`` is one of the sides ``mesh`` takes ("auto": the side
    that touches less of the volume's border, decided by the library on the grid)."""
    if inside not in ("auto", "above", "below"):
        raise ValueError(f'inside: expected "auto", "above" or "below", got {inside!r}')


def nan_at_level(array, level):
    """``array`` with its NaN samples set to the level: a sample at the level is outside the
    object on either side (the library's rule), as scikit-image counts a NaN (not above the
    level), and takes no side when "auto" decides one. The surface then passes next to it.
    A copy only when there are NaNs."""
    if array.dtype.kind != "f":
        return array
    nan = np.isnan(array)
    if not nan.any():
        return array
    if array.dtype.type(level) != level:  # not a value of the array's type: hold it exactly
        array = array.astype(np.float64)
    return np.where(nan, array.dtype.type(level), array)
