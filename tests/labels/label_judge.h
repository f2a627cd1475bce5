#pragma once
// The judge of a multi-label surface (tests of src/labels): CGAL on every label's mesh, CGAL on
// all walls together for crossings between labels, walls shared with opposite orientations,
// the pairs of labels sharing walls against the voxels' face neighbours, volumes against voxel
// counts. None of it uses the mesher's own checks.

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

#include "cgal_judge.h"
#include "vdbmesh/labels.h"

namespace vdbmesh::test {

/// Pairs {a < b} of labels (0: background and unmeshed) that touch across a voxel face.
inline std::set<std::pair<std::uint32_t, std::uint32_t>> voxel_neighbour_pairs(const LabelVolume& v,
                                                                               const std::vector<std::uint32_t>& meshed) {
    const std::set<std::uint32_t> keep(meshed.begin(), meshed.end());
    const auto label = [&](std::int64_t x, std::int64_t y, std::int64_t z) -> std::uint32_t {
        if (x < 0 || y < 0 || z < 0 || x >= v.header.dims[0] || y >= v.header.dims[1] || z >= v.header.dims[2]) return 0;
        const std::uint32_t l = v.at(x, y, z);
        return keep.count(l) ? l : 0;
    };
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (std::int64_t z = -1; z < v.header.dims[2]; ++z)
        for (std::int64_t y = -1; y < v.header.dims[1]; ++y)
            for (std::int64_t x = -1; x < v.header.dims[0]; ++x) {
                const std::uint32_t a = label(x, y, z);
                for (const std::uint32_t b : {label(x + 1, y, z), label(x, y + 1, z), label(x, y, z + 1)})
                    if (a != b) pairs.insert({std::min(a, b), std::max(a, b)});
            }
    return pairs;
}

struct LabelJudgement {
    std::size_t unclean_labels = 0;
    std::size_t crossing_pairs = 0;
    std::size_t volume_misses = 0;  ///< labels over 1000 voxels off their voxel volume by more than 2%
    double worst_volume_error = 0;  ///< relative, over labels above 1000 voxels
};

/// Judges @a surface of @a volume, with gtest expectations; returns the figures.
inline LabelJudgement judge_label_surface(const LabelSurface& surface, const LabelVolume& volume, bool check_volumes = true) {
    LabelJudgement j;
    const std::vector<LabelMeasure> measures = measure_labels(surface, volume);
    using Key = std::array<std::array<float, 3>, 3>;
    // Each label's triangles by position, rotated to start at the smallest corner.
    std::map<Key, std::uint32_t> oriented;
    for (std::size_t i = 0; i < surface.labels.size(); ++i) {
        const std::uint32_t label = surface.labels[i];
        const Mesh mesh = label_mesh(surface, label);
        const CgalVerdict verdict = judge_with_cgal(mesh);
        if (!verdict.clean()) ++j.unclean_labels;
        EXPECT_TRUE(verdict.clean()) << "label " << label << ": " << verdict.describe();
        // Volume from CGAL against the voxels (the tolerance of the issue: 2% above 1000 voxels).
        const LabelMeasure& m = measures[i];
        if (check_volumes && m.voxels > 1000) {
            const double error = std::abs(verdict.volume - m.voxel_volume) / m.voxel_volume;
            j.worst_volume_error = std::max(j.worst_volume_error, error);
            if (error > 0.02) ++j.volume_misses;
            EXPECT_LE(error, 0.02) << "label " << label << ": volume " << verdict.volume << " against " << m.voxel_volume;
        }
        for (const auto& t : mesh.triangles) {
            Key key{mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
            std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
            EXPECT_TRUE(oriented.emplace(key, label).second) << "label " << label << ": a triangle met twice in one direction";
        }
    }
    // A wall of two labels is one set of triangles, each met once in each direction.
    std::set<std::pair<std::uint32_t, std::uint32_t>> sharing;
    for (const auto& [key, label] : oriented) {
        Key reversed{key[0], key[2], key[1]};
        const auto other = oriented.find(reversed);
        if (other != oriented.end()) sharing.insert({std::min(label, other->second), std::max(label, other->second)});
    }
    std::set<std::pair<std::uint32_t, std::uint32_t>> expected;
    for (const auto& [a, b] : voxel_neighbour_pairs(volume, surface.labels))
        if (a != 0) expected.insert({a, b});
    // Voxels changed to keep labels manifold may part or join a pair at a point; none did here.
    if (surface.relabelled_voxels == 0) EXPECT_EQ(sharing, expected);
    else EXPECT_GE(sharing.size() + surface.relabelled_voxels, expected.size());
    const CgalCrossings crossings = cgal_crossings(surface.mesh);
    j.crossing_pairs = crossings.pairs;
    EXPECT_EQ(crossings.pairs, 0u);
    EXPECT_EQ(crossings.degenerate, 0u);
    return j;
}

}  // namespace vdbmesh::test
