// Index validation and degenerate-face classification (repeated index, or collinear corners
// by the exact predicates of exact_predicates.h).
#include "vdbmesh/geometry.h"

#include <tbb/parallel_for.h>

#include <string>

#include "geometry/exact_predicates.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

void check_indices(const Mesh& mesh) {
    const std::size_t count = mesh.vertices.size();
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        for (const std::uint32_t v : mesh.triangles[i]) {
            if (v >= count) {
                throw Error("mesh triangle " + std::to_string(i) + ": vertex index " + std::to_string(v) +
                            " out of range (" + std::to_string(count) + " vertices)");
            }
        }
    }
}

FaceClass classify_face(const std::array<std::uint32_t, 3>& ids, const Triangle3& corners) {
    if (ids[0] == ids[1] || ids[1] == ids[2] || ids[2] == ids[0]) return FaceClass::kRepeatedVertex;
    return collinear(corners[0], corners[1], corners[2]) ? FaceClass::kZeroArea : FaceClass::kRegular;
}

std::vector<FaceClass> classify_faces(const Mesh& mesh) {
    std::vector<FaceClass> classes(mesh.triangles.size());
    tbb::parallel_for(std::size_t{0}, mesh.triangles.size(), [&](std::size_t i) {
        const auto& t = mesh.triangles[i];
        const auto point = [&](int corner) {
            const auto& v = mesh.vertices[t[corner]];
            return Point3{v[0], v[1], v[2]};
        };
        classes[i] = classify_face(t, {point(0), point(1), point(2)});
    });
    return classes;
}

std::vector<std::uint32_t> regular_faces(const std::vector<FaceClass>& classes) {
    std::vector<std::uint32_t> regular;
    regular.reserve(classes.size());
    for (std::size_t i = 0; i < classes.size(); ++i) {
        if (classes[i] == FaceClass::kRegular) regular.push_back(std::uint32_t(i));
    }
    return regular;
}

}  // namespace vdbmesh::detail
