// The single-sheet test of Dual Marching Cubes' octree merging (see dmc_single_sheet.h). The
// cube's samples are rows of bits along z, one row per (x, y); a component is grown from one
// sample by shifting the filled bits one step along every axis and keeping the wanted ones,
// until nothing changes; the side is one component iff the fill reaches every wanted sample.

#include "mesh/dmc_single_sheet.h"

#include <array>
#include <cstdint>

namespace vdbmesh::detail {

namespace {

constexpr int kMaxCube = SampleBlock::kDim;  // 10
using Rows = std::array<std::uint16_t, kMaxCube * kMaxCube>;

/// Whether the set bits of @a wanted (n x n rows of n bits) form exactly one 6-connected component.
bool one_component(const Rows& wanted, int n) {
    int first = 0;
    while (first < n * n && wanted[std::size_t(first)] == 0) ++first;
    if (first == n * n) return false;
    Rows fill{};
    const std::uint16_t w = wanted[std::size_t(first)];
    fill[std::size_t(first)] = std::uint16_t(w & -w);
    for (bool grew = true; grew;) {
        grew = false;
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) {
                const std::size_t r = std::size_t(i * n + j);
                std::uint16_t next = std::uint16_t(fill[r] | (fill[r] << 1) | (fill[r] >> 1));
                if (i > 0) next |= fill[r - std::size_t(n)];
                if (i + 1 < n) next |= fill[r + std::size_t(n)];
                if (j > 0) next |= fill[r - 1];
                if (j + 1 < n) next |= fill[r + 1];
                next &= wanted[r];
                if (next != fill[r]) {
                    fill[r] = next;
                    grew = true;
                }
            }
        }
    }
    return fill == wanted;
}

}  // namespace

bool single_sheet(const SampleBlock& block, int x, int y, int z, int n) {
    Rows inside{}, outside{}, inside_shell{}, outside_shell{};
    const std::uint16_t all = std::uint16_t((1u << n) - 1);
    const std::uint16_t ends = std::uint16_t(1u | (1u << (n - 1)));
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            std::uint16_t bits = 0;
            for (int k = 0; k < n; ++k) {
                bits |= std::uint16_t(block.inside[std::size_t(SampleBlock::index(x + i, y + j, z + k))]) << k;
            }
            const std::size_t r = std::size_t(i * n + j);
            const bool side = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            const std::uint16_t shell = side ? all : ends;
            inside[r] = bits;
            outside[r] = std::uint16_t(~bits & all);
            inside_shell[r] = std::uint16_t(bits & shell);
            outside_shell[r] = std::uint16_t(~bits & shell);
        }
    }
    return one_component(inside, n) && one_component(outside, n) && one_component(inside_shell, n) &&
           one_component(outside_shell, n);
}

}  // namespace vdbmesh::detail
