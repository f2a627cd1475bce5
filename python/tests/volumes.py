"""Synthetic volumes shared by the tests."""

import numpy as np


def ellipsoid_field(shape, center, radii):
    """1 - |(p - center) / radii| over the array indices p: positive inside the ellipsoid,
    0 on it (for a sphere, the signed distance in units of the radius)."""
    grids = np.meshgrid(*[np.arange(n, dtype=np.float64) for n in shape], indexing="ij")
    scaled = sum(((g - c) / r) ** 2 for g, c, r in zip(grids, center, radii))
    return (1.0 - np.sqrt(scaled)).astype(np.float32)


def sphere_field(size, radius):
    """radius - |p - center| at the centre of a size^3 array: the signed distance to a sphere."""
    center = (size - 1) / 2 + 0.13  # off the grid's symmetry planes, so no sample lies exactly on it
    return (radius * ellipsoid_field((size,) * 3, (center,) * 3, (radius,) * 3)).astype(np.float32)


def ball(shape, value, background=0):
    """A ball of @a value in a box of @a background, as a float array (exact in every sample type)."""
    inside = ellipsoid_field(shape, [(n - 1) / 2 + 0.3 for n in shape], [n / 3 for n in shape]) > 0
    return np.where(inside, value, background).astype(np.float64)
