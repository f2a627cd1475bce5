// smooth_grid(): OpenVDB's filters (tools/Filter.h) on the samples around the surface, for noisy
// tomography (shared seed 000 smooths with an "averaging" radius before meshing).
#include <openvdb/tools/Filter.h>
#include <openvdb/tools/Morphology.h>

#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/grid_filter.h"

namespace vdbmesh {

namespace {
constexpr int kGaussianBoxPasses = 4;  ///< Filter::gaussian is four box filters
}

int smoothing_reach(int radius, SmoothFilter filter) {
    return radius * (filter == SmoothFilter::gaussian ? kGaussianBoxPasses : 1);
}

void smooth_grid(openvdb::FloatGrid& grid, int radius, SmoothFilter filter) {
    if (radius < 1) throw UsageError("smoothing radius: expected a whole number of voxels >= 1, got " + std::to_string(radius));
    // A filtered sample reads samples up to its reach away; the surface can move no farther.
    openvdb::tools::dilateActiveValues(grid.tree(), smoothing_reach(radius, filter) + 1, openvdb::tools::NN_FACE_EDGE_VERTEX,
                                       openvdb::tools::IGNORE_TILES);
    openvdb::tools::Filter<openvdb::FloatGrid> smoother(grid);
    switch (filter) {
        case SmoothFilter::gaussian: smoother.gaussian(radius); break;
        case SmoothFilter::mean: smoother.mean(radius); break;
        case SmoothFilter::median: smoother.median(radius); break;
    }
}

}  // namespace vdbmesh
