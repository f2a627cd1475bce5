// Tests of the topology tests of Dual Marching Cubes' octree merging: the single-sheet test
// (src/mesh/dmc_single_sheet.cpp) and the enclosed sign components (dmc_enclosed_components.cpp).

#include <gtest/gtest.h>

#include <functional>
#include <memory>

#include "mesh/dmc_enclosed_components.h"
#include "mesh/dmc_single_sheet.h"

namespace vdbmesh {
namespace {

/// A sample block whose inside flags come from @a inside(x, y, z) over local [-1, 8]^3.
std::unique_ptr<detail::SampleBlock> block_of(const std::function<bool(int, int, int)>& inside) {
    auto block = std::make_unique<detail::SampleBlock>();
    for (int x = -1; x <= 8; ++x) {
        for (int y = -1; y <= 8; ++y) {
            for (int z = -1; z <= 8; ++z) block->inside[std::size_t(detail::SampleBlock::index(x, y, z))] = inside(x, y, z);
        }
    }
    return block;
}

TEST(DmcSingleSheetTest, TiltedPlaneIsOneSheet) {
    const auto block = block_of([](int x, int y, int z) { return x + 2 * y + 3 * z < 20; });
    EXPECT_TRUE(detail::single_sheet(*block, -1, -1, -1, 10));
    EXPECT_TRUE(detail::single_sheet(*block, 0, 0, 0, 6));
}

TEST(DmcSingleSheetTest, SlabHasTwoSheets) {
    const auto block = block_of([](int, int, int z) { return z >= 2 && z <= 4; });
    EXPECT_FALSE(detail::single_sheet(*block, -1, -1, -1, 10));  // two outside components
}

TEST(DmcSingleSheetTest, TubeThroughTheCubeIsNotADisc) {
    // Inside and outside are each connected, but the tube meets the shell in two discs.
    const auto block = block_of([](int x, int y, int) { return (x - 4) * (x - 4) + (y - 4) * (y - 4) <= 2; });
    EXPECT_FALSE(detail::single_sheet(*block, 0, 0, 0, 8));
}

TEST(DmcSingleSheetTest, EnclosedBubbleIsNotADisc) {
    const auto block = block_of([](int x, int y, int z) { return x == 4 && y == 4 && z == 4; });
    EXPECT_FALSE(detail::single_sheet(*block, 2, 2, 2, 4));  // no inside sample on the shell
    EXPECT_FALSE(detail::single_sheet(*block, 3, 3, 3, 4));  // inside, but not on the shell here either
}

TEST(DmcSingleSheetTest, CornerTouchingIsNotConnected) {
    // Two inside samples meeting only at a corner are two 6-connected components.
    const auto block = block_of([](int x, int y, int z) { return (x == 0 && y == 0 && z == 0) || (x == 1 && y == 1 && z == 1); });
    EXPECT_FALSE(detail::single_sheet(*block, 0, 0, 0, 4));
    const auto one = block_of([](int x, int y, int z) { return x == 0 && y == 0 && z == 0; });
    EXPECT_TRUE(detail::single_sheet(*one, 0, 0, 0, 4));
}

bool enclosed_at(const detail::SampleBlock& block, int x, int y, int z) {
    return detail::enclosed_components(block)[std::size_t(detail::SampleBlock::index(x, y, z))];
}

TEST(DmcEnclosedComponentsTest, SpeckInsideTheBlockIsEnclosed) {
    const auto block = block_of([](int x, int y, int z) { return z < 2 || (x == 5 && y == 5 && (z == 5 || z == 6)); });
    EXPECT_TRUE(enclosed_at(*block, 5, 5, 5));
    EXPECT_TRUE(enclosed_at(*block, 5, 5, 6));
    EXPECT_FALSE(enclosed_at(*block, 5, 5, 0));  // the slab reaches the outer layer
    EXPECT_FALSE(enclosed_at(*block, 0, 0, 5));  // and so does the outside around the speck
}

TEST(DmcEnclosedComponentsTest, PoreIsEnclosedButATunnelToTheOuterLayerIsNot) {
    const auto pore = block_of([](int x, int y, int z) { return !(x == 3 && y == 4 && z == 4); });
    EXPECT_TRUE(enclosed_at(*pore, 3, 4, 4));
    EXPECT_FALSE(enclosed_at(*pore, 0, 0, 0));
    const auto tunnel = block_of([](int x, int y, int) { return !(x == 3 && y == 4); });
    EXPECT_FALSE(enclosed_at(*tunnel, 3, 4, 4));
}

TEST(DmcEnclosedComponentsTest, DiagonalNeighboursAreNotConnected) {
    // 6-connectivity, as the single-sheet test: a diagonal chain of samples from the outer
    // layer is a chain of specks, each enclosed but the first.
    const auto block = block_of([](int x, int y, int z) { return z == 4 && x == y && x <= 3; });
    EXPECT_FALSE(enclosed_at(*block, -1, -1, 4));
    EXPECT_TRUE(enclosed_at(*block, 0, 0, 4));
    EXPECT_TRUE(enclosed_at(*block, 3, 3, 4));
}

}  // namespace
}  // namespace vdbmesh
