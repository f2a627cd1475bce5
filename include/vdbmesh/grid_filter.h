#pragma once
/// @file grid_filter.h
/// @brief Processing a grid before meshing (`vdbmesh mesh --smooth, --slab, --step,
/// --keep-largest, --min-component-volume`; `vdbmesh measure --refine`): smoothing with
/// OpenVDB's filters, a slab of slices closed at the cut, coarser sampling, dropping small
/// solids, and vertices moved onto a smoother isosurface. Grids are taken by reference
/// (openvdb_fwd.h); to make or look into one, include vdbmesh/grid.h.

#include <cstddef>
#include <memory>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/openvdb_fwd.h"

namespace vdbmesh {

enum class SmoothFilter {
    gaussian,  ///< openvdb::tools::Filter::gaussian (four box passes)
    mean,      ///< openvdb::tools::Filter::mean (a box of 2 radius + 1 voxels)
    median,    ///< openvdb::tools::Filter::median (over 2 radius + 1 voxels per axis)
};

/// How far (voxels) smooth_grid() reads from a sample: radius, times four for the Gaussian.
/// Converting a scan with a band of at least reach + 1 gives the filters true samples only.
int smoothing_reach(int radius, SmoothFilter filter);

/// @brief Smooths the samples of @a grid with @a filter of @a radius voxels (the filters'
/// half-width: 2 radius + 1 voxels). The active band is first dilated by smoothing_reach() + 1,
/// so every sample the smoothed surface can move through is filtered.
/// @throw UsageError for radius < 1.
void smooth_grid(openvdb::FloatGrid& grid, int radius, SmoothFilter filter);

/// @brief Keeps only the slices @a first..@a last (inclusive, index space) along @a axis
/// (0 x, 1 y, 2 z): the grid's scanned box (kMetaScanMin/Max) is cut to them, so the meshers
/// treat everything beyond as outside and close the surface at the cut (unless open_boundary).
/// A grid without a scanned box gets its leaves' box.
/// @throw UsageError when the slab misses the scanned box, or first > last.
void restrict_to_slab(openvdb::FloatGrid& grid, int axis, int first, int last);

/// @brief Every @a step-th sample: voxel (i, j, k) of the result is voxel (step i, step j,
/// step k) of @a grid, tiles included; the transform grows by @a step, the scanned box shrinks to
/// the samples kept, and the other metadata are kept. @throw UsageError for step < 1.
std::shared_ptr<openvdb::FloatGrid> subsample_grid(const openvdb::FloatGrid& grid, int step);

/// Which solids select_solids() keeps.
struct SolidSelection {
    bool keep_largest = false;  ///< only the largest solid
    double min_volume = 0;      ///< drop solids smaller than this (world units^3)
};

/// What select_solids() did.
struct SolidSelectionReport {
    std::size_t solids = 0;   ///< face-connected regions of inside samples found
    std::size_t dropped = 0;  ///< of those, set outside
};

/// @brief Drops small solids before meshing: the samples inside the object (options.iso,
/// options.inside, within the scanned box) are split into face-connected regions, and the
/// samples of every region not selected are set outside. A region's volume is its sample count
/// times the voxel volume. @throw UsageError for a negative or non-finite min_volume.
SolidSelectionReport select_solids(openvdb::FloatGrid& grid, const MeshOptions& options, const SolidSelection& selection);

/// @brief Splits each triangle of @a mesh (meshed from @a grid at @a iso) into four at its edge
/// midpoints, then moves each vertex onto the isosurface of the triquadratic interpolant of the
/// samples (parabolas through three scanned samples per axis, exact for quadratic fields), by
/// Newton steps along its gradient, for measuring smooth solids beyond the linear interpolation
/// of Marching Cubes (which puts vertices inside convex surfaces). A vertex that would move more
/// than half a voxel, or out of the scanned box, stays. The
/// mesh's guarantees (no self-intersection) are not checked afterwards: this is for measuring.
void refine_to_isosurface(Mesh& mesh, const openvdb::FloatGrid& grid, double iso);

}  // namespace vdbmesh
