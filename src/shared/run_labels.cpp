#include "shared/run_labels.h"

#include <algorithm>

#include "vdbmesh/union_find.h"

namespace vdbmesh::detail {

RunLabels label_runs(const BoxRuns& box, bool periodic) {
    const auto& lines = box.lines;
    RunLabels out;
    out.first.assign(lines.size() + 1, 0);
    for (std::size_t l = 0; l < lines.size(); ++l) out.first[l + 1] = out.first[l] + std::uint32_t(lines[l].size());
    UnionFind uf(out.first.back());
    auto join = [&](std::size_t la, std::size_t lb) {
        const auto& a = lines[la];
        const auto& b = lines[lb];
        std::size_t i = 0, j = 0;
        while (i < a.size() && j < b.size()) {
            if (a[i].z1 >= b[j].z0 && b[j].z1 >= a[i].z0) uf.unite(out.first[la] + std::uint32_t(i), out.first[lb] + std::uint32_t(j));
            if (a[i].z1 < b[j].z1) ++i;
            else ++j;
        }
    };
    const int nx = box.nx, ny = box.ny, nz = box.nz;
    for (int x = 0; x < nx; ++x)
        for (int y = 0; y < ny; ++y) {
            const std::size_t l = std::size_t(x) * ny + y;
            if (x + 1 < nx) join(l, l + ny);
            else if (periodic && nx > 1) join(l, std::size_t(y));
            if (y + 1 < ny) join(l, l + 1);
            else if (periodic && ny > 1) join(l, std::size_t(x) * ny);
            const auto& runs = lines[l];
            if (periodic && runs.size() > 1 && runs.front().z0 == 0 && runs.back().z1 == nz - 1) {
                uf.unite(out.first[l], out.first[l] + std::uint32_t(runs.size() - 1));
            }
        }
    out.label = uf.labels(out.count);
    return out;
}

std::int64_t RunLabels::at(const BoxRuns& box, int x, int y, int z) const {
    const std::size_t l = std::size_t(x) * box.ny + y;
    const auto& runs = box.lines[l];
    const auto it = std::partition_point(runs.begin(), runs.end(), [z](const ZRun& r) { return r.z1 < z; });
    if (it == runs.end() || it->z0 > z) return -1;
    return label[first[l] + std::size_t(it - runs.begin())];
}

std::vector<std::uint64_t> RunLabels::voxels(const BoxRuns& box) const {
    std::vector<std::uint64_t> out(count, 0);
    for (std::size_t l = 0; l < box.lines.size(); ++l) {
        for (std::size_t r = 0; r < box.lines[l].size(); ++r) out[label[first[l] + r]] += std::uint64_t(box.lines[l][r].z1 - box.lines[l][r].z0 + 1);
    }
    return out;
}

}  // namespace vdbmesh::detail
