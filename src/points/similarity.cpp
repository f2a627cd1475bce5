// Similarity of two solids (chapter 3.5): coarse PCA alignment, then Levenberg-Marquardt.

#include "vdbmesh/error.h"
#include "vdbmesh/points.h"

namespace vdbmesh {

SimilarityResult compare_to(const PointCloud&, const PointCloud&, const RbfField&, const SimilarityOptions&) {
    throw Error("similarity: not implemented yet");
}

}  // namespace vdbmesh
