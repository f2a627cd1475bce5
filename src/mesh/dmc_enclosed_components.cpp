// Enclosed sign components of a sample block (see dmc_enclosed_components.h): a flood fill of
// each component from its first sample, noting whether it reaches the block's outer layer.

#include "mesh/dmc_enclosed_components.h"

#include <vector>

namespace vdbmesh::detail {

namespace {

constexpr int kDim = SampleBlock::kDim;
constexpr std::array<int, 3> kStride = {kDim * kDim, kDim, 1};  // SampleBlock::index, x slowest

bool on_outer_layer(int index) {
    for (int stride : kStride) {
        const int c = index / stride % kDim;
        if (c == 0 || c == kDim - 1) return true;
    }
    return false;
}

}  // namespace

std::array<bool, kBlockSamples> enclosed_components(const SampleBlock& block) {
    std::array<bool, kBlockSamples> enclosed{};
    std::array<bool, kBlockSamples> seen{};
    std::vector<int> component, stack;
    for (int start = 0; start < kBlockSamples; ++start) {
        if (seen[std::size_t(start)]) continue;
        const bool side = block.inside[std::size_t(start)];
        component.clear();
        stack.assign(1, start);
        seen[std::size_t(start)] = true;
        bool reaches_outer_layer = false;
        while (!stack.empty()) {
            const int index = stack.back();
            stack.pop_back();
            component.push_back(index);
            reaches_outer_layer = reaches_outer_layer || on_outer_layer(index);
            for (int stride : kStride) {
                const int c = index / stride % kDim;
                for (int step : {-1, 1}) {
                    if (c + step < 0 || c + step >= kDim) continue;
                    const int next = index + step * stride;
                    if (seen[std::size_t(next)] || block.inside[std::size_t(next)] != side) continue;
                    seen[std::size_t(next)] = true;
                    stack.push_back(next);
                }
            }
        }
        if (!reaches_outer_layer) {
            for (int index : component) enclosed[std::size_t(index)] = true;
        }
    }
    return enclosed;
}

}  // namespace vdbmesh::detail
