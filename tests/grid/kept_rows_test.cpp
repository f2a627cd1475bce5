// The survey's rows kept on disk (src/grid/kept_rows.h): what is read back has the bits that were
// kept, whichever way its values were stored, and a rectangle of node columns returns exactly
// the leaves and tiles that lie in it.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <tuple>

#include "grid/kept_rows.h"

namespace vdbmesh::detail {
namespace {

using Key = std::tuple<int, int, int>;
Key key_of(const openvdb::Coord& c) { return {c.x(), c.y(), c.z()}; }

/// A leaf at @a origin whose value n is @a value(n), with every third voxel active.
template <typename ValueOf>
std::unique_ptr<Leaf> leaf_at(const openvdb::Coord& origin, ValueOf value) {
    auto leaf = std::make_unique<Leaf>(origin, 0.0f);
    for (openvdb::Index n = 0; n < Leaf::SIZE; ++n) {
        leaf->setValueOnly(n, value(n));
        if (n % 3 == 0) leaf->setActiveState(n, true);
    }
    return leaf;
}

/// Two rows over node columns -1 .. 1 in x and y (first column -1): leaves of 16-bit
/// unsigned values, of signed ones, and of floats no 16-bit integer holds (a fraction, -0, NaN,
/// the lowest float the converter puts outside a scan), and tiles.
std::vector<ConvertedRow> sample_rows() {
    std::vector<ConvertedRow> rows(2);
    for (int r = 0; r < 2; ++r) {
        ConvertedRow& row = rows[r];
        row.z0 = 8 * r;
        for (int y : {-128, 0, 128})
            for (int x : {-128, 0, 128}) {
                const openvdb::Coord a(x + 8, y + 16, row.z0), b(x + 64, y, row.z0), c(x, y + 120, row.z0);
                row.leaves.push_back(leaf_at(a, [&](openvdb::Index n) { return float(n * 100 + x + 128); }));
                row.leaves.push_back(leaf_at(b, [&](openvdb::Index n) { return float(int(n) - 300 + y); }));
                row.leaves.push_back(leaf_at(c, [&](openvdb::Index n) {
                    if (n == 0) return -0.0f;
                    if (n == 1) return std::numeric_limits<float>::quiet_NaN();
                    if (n == 2) return std::numeric_limits<float>::lowest();
                    return 0.5f + float(n);
                }));
                row.tiles.emplace_back(openvdb::Coord(x + 32, y + 40, row.z0), float(x - y) + 0.25f);
            }
    }
    return rows;
}

bool same_bits(const Leaf& a, const Leaf& b) {
    return a.origin() == b.origin() && a.getValueMask() == b.getValueMask() &&
           std::memcmp(a.buffer().data(), b.buffer().data(), Leaf::SIZE * sizeof(float)) == 0;
}

TEST(KeptRowsTest, EveryLeafComesBackWithItsBitsAndOnlyTheAskedColumns) {
    const std::vector<ConvertedRow> rows = sample_rows();
    KeptRows kept(-1, 3, 3);
    for (const ConvertedRow& row : rows) kept.add(row);
    std::map<Key, const Leaf*> written;
    for (const ConvertedRow& row : rows)
        for (const auto& leaf : row.leaves) written[key_of(leaf->origin())] = leaf.get();

    // Node columns x in [0, 2), y in [1, 3) (indices from the first column): voxels x in
    // [-128, 128), y in [0, 256); the second row only.
    const std::vector<ConvertedRow> read = kept.read(8, 8, 0, 2, 1, 3);
    ASSERT_EQ(read.size(), 1u);
    EXPECT_EQ(read[0].z0, 8);
    EXPECT_EQ(read[0].leaves.size(), 2u * 2u * 3u);
    for (const auto& leaf : read[0].leaves) {
        const openvdb::Coord& o = leaf->origin();
        EXPECT_TRUE(o.x() >= -128 && o.x() < 128 && o.y() >= 0 && o.y() < 256 && o.z() == 8) << o;
        ASSERT_TRUE(written.count(key_of(o))) << o;
        EXPECT_TRUE(same_bits(*leaf, *written[key_of(o)])) << o;
    }
    EXPECT_EQ(read[0].tiles.size(), 4u);
    for (const auto& [origin, value] : read[0].tiles) {
        EXPECT_TRUE(origin.x() >= -128 && origin.x() < 128 && origin.y() >= 0 && origin.y() < 256) << origin;
        EXPECT_EQ(value, float(origin.x() - 32 - (origin.y() - 40)) + 0.25f);
    }
}

TEST(KeptRowsTest, AllRowsAndColumnsReadBackWhole) {
    const std::vector<ConvertedRow> rows = sample_rows();
    KeptRows kept(-1, 3, 3);
    for (const ConvertedRow& row : rows) kept.add(row);
    const std::vector<ConvertedRow> read = kept.read(-100, 100, -5, 9, -5, 9);  // clipped to the kept columns
    ASSERT_EQ(read.size(), 2u);
    for (std::size_t r = 0; r < 2; ++r) {
        std::map<Key, const Leaf*> back;
        for (const auto& leaf : read[r].leaves) back[key_of(leaf->origin())] = leaf.get();
        ASSERT_EQ(back.size(), rows[r].leaves.size());
        for (const auto& leaf : rows[r].leaves) {
            ASSERT_TRUE(back.count(key_of(leaf->origin())));
            EXPECT_TRUE(same_bits(*leaf, *back[key_of(leaf->origin())])) << leaf->origin();
        }
        EXPECT_EQ(read[r].tiles.size(), rows[r].tiles.size());
    }
    EXPECT_GT(kept.buffer_bytes(), 0u);
    EXPECT_TRUE(kept.read(16, 100, 0, 3, 0, 3).empty());  // above the last row
}

}  // namespace
}  // namespace vdbmesh::detail
