// The block window of dc (src/mesh/dc_octree.cpp, dc_block.h) and the check that skips
// blocks without surface (src/mesh/surface_blocks.cpp), judged sample by sample through the
// grid's own accessor: every crossed edge, mixed cell and configuration the rows of bits give,
// and every block the check skips, must agree with what getValue() and the classifier say.
// Grids mix leaves of noise, uniform leaves and tiles on both sides, with and without a
// scanned box that cuts through blocks.

#include <gtest/gtest.h>

#include <openvdb/openvdb.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "mesh/dc_block.h"
#include "mesh/sample_classifier.h"
#include "mesh/surface_blocks.h"
#include "vdbmesh/grid.h"

namespace vdbmesh::detail {
namespace {

constexpr double kIso = 0.5;

/// Leaves of three kinds (noise about the isovalue, all inside, all outside) and tiles of
/// both sides, at random over a few internal nodes.
openvdb::FloatGrid::Ptr mixed_grid(unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> noise(0.0f, 1.0f);
    auto grid = openvdb::FloatGrid::create(0.0f);
    openvdb::FloatTree& tree = grid->tree();
    tree.addTile(1, openvdb::Coord(128, 0, 0), 1.0f, true);  // a 128^3 inside tile
    for (int x = -16; x < 160; x += 8) {
        for (int y = -16; y < 48; y += 8) {
            for (int z = -16; z < 48; z += 8) {
                const int kind = int(random() % 4);
                if (kind == 0) continue;  // background or tile
                auto* leaf = tree.touchLeaf(openvdb::Coord(x, y, z));
                for (auto v = leaf->beginValueAll(); v; ++v) {
                    v.setValue(kind == 1 ? noise(random) : kind == 2 ? 0.9f : 0.1f);
                    v.setValueOn();
                }
            }
        }
    }
    return grid;
}

bool brute_inside(openvdb::FloatGrid::ConstAccessor& accessor, const SampleClassifier& classifier, const openvdb::Coord& ijk) {
    return classifier.inside(classifier.sample_value(ijk, accessor.getValue(ijk)));
}

/// Checks every candidate block of @a grid; counts in @a skipped those the check skips.
void check_grid(const openvdb::FloatGrid& grid, int& skipped) {
    MeshOptions options;
    options.iso = kIso;
    const SampleClassifier classifier(grid, options);
    auto accessor = grid.getConstAccessor();
    auto samples = std::make_unique<IfcSamples>();
    for (const openvdb::Coord& origin : surface_blocks(grid, classifier)) {
        // The cells' samples origin .. origin + 8: on both sides or not.
        bool seen[2] = {false, false};
        for (int x = 0; x <= kBlockDim; ++x) {
            for (int y = 0; y <= kBlockDim; ++y) {
                for (int z = 0; z <= kBlockDim; ++z) seen[brute_inside(accessor, classifier, origin.offsetBy(x, y, z))] = true;
            }
        }
        const bool mixed = seen[0] && seen[1];
        const bool may = block_may_hold_surface(accessor, classifier, origin);
        if (mixed) EXPECT_TRUE(may) << origin;
        const openvdb::CoordBBox window(origin, origin.offsetBy(kBlockDim));
        if (!classifier.scan_box() || classifier.scan_box()->isInside(window)) EXPECT_EQ(may, mixed) << origin;
        skipped += !may;

        samples->origin = origin;
        load_ifc_samples(accessor, classifier, *samples);
        bool any[2] = {false, false};
        for (int x = -1; x <= kBlockDim + 1; ++x) {
            for (int y = -1; y <= kBlockDim + 1; ++y) {
                for (int z = -1; z <= kBlockDim + 1; ++z) {
                    const openvdb::Coord ijk = origin.offsetBy(x, y, z);
                    const bool in = brute_inside(accessor, classifier, ijk);
                    any[in] = true;
                    ASSERT_EQ(samples->in(x, y, z), in) << ijk;
                    ASSERT_EQ(samples->at(x, y, z), classifier.sample_value(ijk, accessor.getValue(ijk))) << ijk;
                }
            }
        }
        EXPECT_EQ(samples->uniform(), !(any[0] && any[1])) << origin;
        for (int x = -1; x < kBlockDim + 1; ++x) {
            for (int y = -1; y < kBlockDim + 1; ++y) {
                for (int z = -1; z < kBlockDim + 1; ++z) {
                    for (int axis = 0; axis < 3; ++axis) {
                        const openvdb::Coord a = origin.offsetBy(x, y, z);
                        const openvdb::Coord b = a.offsetBy(axis == 0, axis == 1, axis == 2);
                        const bool crossed = brute_inside(accessor, classifier, a) != brute_inside(accessor, classifier, b);
                        ASSERT_EQ(bool((samples->crossed_row(x, y, axis) >> (z + 1)) & 1u), crossed) << a << " axis " << axis;
                    }
                    unsigned config = 0;
                    for (unsigned c = 0; c < 8; ++c) {
                        config |= unsigned(brute_inside(accessor, classifier, origin.offsetBy(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2)))) << c;
                    }
                    ASSERT_EQ(samples->config(x, y, z), config) << origin.offsetBy(x, y, z);
                    ASSERT_EQ(bool((samples->mixed_cells_row(x, y) >> (z + 1)) & 1u), config != 0 && config != 255) << origin.offsetBy(x, y, z);
                }
            }
        }
    }
}

TEST(IfcSamplesTest, RowsOfBitsAgreeWithTheGridSampleBySample) {
    // The grids are made so that blocks without surface occur among the candidates.
    for (unsigned seed : {1u, 2u, 3u}) {
        int skipped = 0;
        check_grid(*mixed_grid(seed), skipped);
        EXPECT_GT(skipped, 0) << seed;
    }
}

TEST(IfcSamplesTest, ABoxCuttingThroughBlocksIsReadAsOutsideBeyondIt) {
    for (unsigned seed : {4u, 5u}) {
        auto grid = mixed_grid(seed);
        grid->insertMeta(kMetaScanMin, openvdb::Vec3IMetadata(openvdb::Vec3i(-11, -5, 3)));
        grid->insertMeta(kMetaScanMax, openvdb::Vec3IMetadata(openvdb::Vec3i(140, 37, 29)));
        ASSERT_TRUE(stored_scan_box(*grid));
        int skipped = 0;
        check_grid(*grid, skipped);
    }
}

TEST(IfcSamplesTest, RowsOfBitsClassifyFloatsAsTheDoubleComparisonDoes) {
    // inside_bits() compares floats with the nearest float beyond the isovalue; inside()
    // compares doubles. Isovalues on a float, half way between two, just off one, and
    // beyond the float range; values at, next to and far from them, and the infinities.
    auto grid = openvdb::FloatGrid::create(0.0f);
    const float one_up = std::nextafter(1200.5f, 2000.0f);
    for (double iso : {1200.5, (double(1200.5f) + double(one_up)) / 2, 1200.5 + 1e-9, 0.1, -3.0, 1e39}) {
        for (Inside inside : {Inside::above, Inside::below}) {
            MeshOptions options;
            options.iso = iso;
            options.inside = inside;
            const SampleClassifier classifier(*grid, options);
            const float nearest = float(iso);
            const float inf = std::numeric_limits<float>::infinity();
            const std::array<float, 11> values = {nearest, std::nextafter(nearest, inf), std::nextafter(nearest, -inf), one_up, 1200.5f,
                                                  0.0f, -inf, inf, 1e30f, -1e30f, float(iso * 2)};
            const std::uint32_t bits = classifier.inside_bits(values.data(), int(values.size()));
            int inside_count = 0;
            for (std::size_t i = 0; i < values.size(); ++i) {
                EXPECT_EQ(bool((bits >> i) & 1u), classifier.inside(values[i])) << "iso " << iso << " value " << values[i];
                inside_count += classifier.inside(values[i]);
            }
            EXPECT_GT(inside_count, 0);
            EXPECT_LT(inside_count, int(values.size()));
        }
    }
}

}  // namespace
}  // namespace vdbmesh::detail
