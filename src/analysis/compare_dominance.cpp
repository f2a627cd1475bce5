// Which rows of `vdbmesh compare` dominate each volumeToMesh row (issue 29's figure, item 5:
// the plain command shows the dominance).

#include <algorithm>
#include <string_view>
#include <tuple>

#include "vdbmesh/compare.h"

namespace vdbmesh {
namespace {

/// The counts on which @a ours does not beat or tie @a anchor.
std::vector<const char*> lost_counts(const MeshComparison& ours, const MeshComparison& anchor) {
    std::vector<const char*> lost;
    if (ours.analysis.triangles > anchor.analysis.triangles) lost.push_back("triangles");
    if (ours.accuracy.distance.hausdorff > anchor.accuracy.distance.hausdorff) lost.push_back("hausdorff");
    if (ours.analysis.small_angle_share > anchor.analysis.small_angle_share) lost.push_back("angles");
    if (!ours.analysis.is_clean()) lost.push_back("defects");
    const double factor = anchor.adaptivity.value_or(0) >= 1 ? kAdaptivityOneTimeFactor : 1.0;
    if (ours.seconds > factor * anchor.seconds) lost.push_back("time");
    return lost;
}

/// Whether a row losing on @a lost is nearer to dominating than one losing on @a other_lost:
/// fewer counts of quality lost (all but time), then not losing on time, then the faster.
bool closer_to_dominating(const std::vector<const char*>& lost, const MeshComparison& mesh,
                          const std::vector<const char*>& other_lost, const MeshComparison& other) {
    const auto key = [](const std::vector<const char*>& counts, const MeshComparison& m) {
        const bool slower = std::any_of(counts.begin(), counts.end(), [](const char* c) { return std::string_view(c) == "time"; });
        return std::make_tuple(counts.size() - (slower ? 1 : 0), slower, m.seconds);
    };
    return key(lost, mesh) < key(other_lost, other);
}

Dominance dominance_of(const std::vector<MeshComparison>& meshes, std::size_t anchor) {
    Dominance d;
    d.volume_to_mesh = anchor;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        if (meshes[i].method == MeshMethod::openvdb) continue;
        const std::vector<const char*> lost = lost_counts(meshes[i], meshes[anchor]);
        const bool only_time = lost.size() == 1 && std::string_view(lost[0]) == "time";
        if (lost.empty() || only_time) d.every_count.push_back(i);
        if (lost.empty()) d.with_time.push_back(i);
        const bool closer = !d.closest || closer_to_dominating(lost, meshes[i], d.closest_loses, meshes[*d.closest]);
        if (closer) {
            d.closest = i;
            d.closest_loses = lost;
        }
    }
    if (!d.with_time.empty()) {
        d.closest.reset();
        d.closest_loses.clear();
    }
    return d;
}

}  // namespace

std::vector<Dominance> find_dominance(const Comparison& comparison) {
    std::vector<Dominance> result;
    for (std::size_t i = 0; i < comparison.meshes.size(); ++i)
        if (comparison.meshes[i].method == MeshMethod::openvdb) result.push_back(dominance_of(comparison.meshes, i));
    return result;
}

}  // namespace vdbmesh
