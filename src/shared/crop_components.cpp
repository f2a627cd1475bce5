// The components of a periodic field cut by a box, from plain labellings of one period cell
// (the reference for shared_components() on lattices too large to label voxel by voxel).
//
// The box is tiled by cells of period^3 voxels from its minimum corner. Every cell holds the
// same inside voxels as the first one, except that the last cell along an axis is cut short
// where the box does not hold a whole number of periods: a cell is the first cell with its
// extent cut along the axes (bit mask: its type) where it is the last and short. Each type is
// labelled plainly (run_labels.h). Two cells that follow each other along an axis touch where
// the first one's last slice meets the second one's first slice; by periodicity that is the
// first cell's last slice against its own first slice, so the labels that touch across the
// face come from the two types' labellings. A union-find over (cell, label) then gives the
// components of the box, including the pieces that the box faces cut off (which the cut types'
// labellings find).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <functional>
#include <map>
#include <tuple>

#include "shared/run_labels.h"
#include "vdbmesh/union_find.h"
#include "vdbmesh/error.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {

namespace {

using detail::BoxRuns;
using detail::RunLabels;

int floor8(int v) { return v >= 0 ? v & ~7 : -((-v + 7) & ~7); }

/// Inside flags (value < 0) of the voxels of the box at @a origin of @a size voxels, evaluated
/// leaf by leaf; voxel (x, y, z) at (x * size[1] + y) * size[2] + z.
std::vector<std::uint8_t> evaluate_inside(const LeafField& field, const Coord3& origin, const std::array<int, 3>& size) {
    std::vector<std::uint8_t> inside(std::size_t(size[0]) * size[1] * size[2], 0);
    Coord3 first, count;
    for (int a = 0; a < 3; ++a) {
        first[a] = floor8(origin[a]);
        count[a] = (floor8(origin[a] + size[a] - 1) - first[a]) / 8 + 1;
    }
    tbb::parallel_for(tbb::blocked_range<int>(0, count[0] * count[1] * count[2]), [&](const auto& range) {
        SharedLeaf leaf;
        for (int n = range.begin(); n != range.end(); ++n) {
            const Coord3 o = {first[0] + 8 * (n / (count[1] * count[2])), first[1] + 8 * (n / count[2] % count[1]), first[2] + 8 * (n % count[2])};
            field.evaluate(o, leaf);
            for (int i = 0; i < 512; ++i) {
                const int p[3] = {o[0] + (i >> 6) - origin[0], o[1] + ((i >> 3) & 7) - origin[1], o[2] + (i & 7) - origin[2]};
                if (p[0] < 0 || p[1] < 0 || p[2] < 0 || p[0] >= size[0] || p[1] >= size[1] || p[2] >= size[2]) continue;
                inside[(std::size_t(p[0]) * size[1] + p[1]) * size[2] + p[2]] = leaf.values[i] < 0;
            }
        }
    });
    return inside;
}

/// A cell type's plain labelling.
struct CellLabels {
    std::array<int, 3> size{};
    BoxRuns runs;
    RunLabels labels;
    std::vector<std::uint64_t> voxels;  ///< per label
};

using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

/// The labels of @a a and @a b that touch where b follows a along @a axis (both of the same
/// extent across it): a's last slice against b's first.
Pairs touching(const CellLabels& a, const CellLabels& b, int axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    Pairs out;
    for (int i = 0; i < a.size[u]; ++i)
        for (int j = 0; j < a.size[v]; ++j) {
            int pa[3], pb[3];
            pa[axis] = a.size[axis] - 1;
            pb[axis] = 0;
            pa[u] = pb[u] = i;
            pa[v] = pb[v] = j;
            const std::int64_t la = a.labels.at(a.runs, pa[0], pa[1], pa[2]);
            const std::int64_t lb = b.labels.at(b.runs, pb[0], pb[1], pb[2]);
            if (la >= 0 && lb >= 0) out.push_back({std::uint32_t(la), std::uint32_t(lb)});
        }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace

CropComponents plain_components_from_crop(const LeafField& field, const std::array<Coord3, 2>& box, int period) {
    if (period < 1) throw UsageError("plain_components_from_crop: expected a period of at least 1 voxel, got " + std::to_string(period));
    std::array<int, 3> width, cells, last;  // per axis: voxels, cells, voxels of the last cell
    for (int a = 0; a < 3; ++a) {
        width[a] = box[1][a] - box[0][a] + 1;
        if (width[a] < 1) return {};
        cells[a] = (width[a] + period - 1) / period;
        last[a] = width[a] - (cells[a] - 1) * period;
    }
    const std::array<int, 3> crop = {std::min(period, width[0]), std::min(period, width[1]), std::min(period, width[2])};
    const std::vector<std::uint8_t> inside = evaluate_inside(field, box[0], crop);
    // Type t: cut to last[a] along the axes a of its bits.
    std::array<std::unique_ptr<CellLabels>, 8> types;
    auto type_of = [&](const std::array<int, 3>& c) {
        int t = 0;
        for (int a = 0; a < 3; ++a) t |= int(c[a] == cells[a] - 1 && last[a] < period) << a;
        return t;
    };
    auto labels_of = [&](int t) -> const CellLabels& {
        if (!types[t]) {
            auto l = std::make_unique<CellLabels>();
            for (int a = 0; a < 3; ++a) l->size[a] = (t >> a) & 1 ? last[a] : crop[a];
            l->runs = detail::collect_runs(l->size[0], l->size[1], l->size[2], [&] {
                return [&](int x, int y, int z) { return inside[(std::size_t(x) * crop[1] + y) * crop[2] + z] != 0; };
            });
            l->labels = detail::label_runs(l->runs, false);
            l->voxels = l->labels.voxels(l->runs);
            types[t] = std::move(l);
        }
        return *types[t];
    };
    auto cell_index = [&](const std::array<int, 3>& c) { return (std::size_t(c[0]) * cells[1] + c[1]) * cells[2] + c[2]; };
    auto for_each_cell = [&](const std::function<void(const std::array<int, 3>&)>& f) {
        for (int x = 0; x < cells[0]; ++x)
            for (int y = 0; y < cells[1]; ++y)
                for (int z = 0; z < cells[2]; ++z) f({x, y, z});
    };
    std::vector<std::uint32_t> offset(std::size_t(cells[0]) * cells[1] * cells[2] + 1, 0);
    for_each_cell([&](const std::array<int, 3>& c) { offset[cell_index(c) + 1] = labels_of(type_of(c)).labels.count; });
    for (std::size_t i = 1; i < offset.size(); ++i) offset[i] += offset[i - 1];
    detail::UnionFind uf(offset.back());
    std::map<std::tuple<int, int, int>, Pairs> faces;  // (type, next type, axis)
    for_each_cell([&](const std::array<int, 3>& c) {
        for (int axis = 0; axis < 3; ++axis) {
            if (c[axis] + 1 == cells[axis]) continue;
            std::array<int, 3> next = c;
            ++next[axis];
            const int t = type_of(c), tn = type_of(next);
            auto it = faces.find({t, tn, axis});
            if (it == faces.end()) it = faces.emplace(std::make_tuple(t, tn, axis), touching(labels_of(t), labels_of(tn), axis)).first;
            for (const auto& [a, b] : it->second) uf.unite(offset[cell_index(c)] + a, offset[cell_index(next)] + b);
        }
    });
    CropComponents out;
    std::uint32_t count = 0;
    const std::vector<std::uint32_t> label = uf.labels(count);
    out.components = count;
    out.voxels.assign(count, 0);
    for_each_cell([&](const std::array<int, 3>& c) {
        const std::vector<std::uint64_t>& voxels = labels_of(type_of(c)).voxels;
        for (std::size_t k = 0; k < voxels.size(); ++k) out.voxels[label[offset[cell_index(c)] + k]] += voxels[k];
    });
    std::sort(out.voxels.begin(), out.voxels.end(), std::greater<>());
    const CellLabels& first = labels_of(0);
    out.crop_components = first.labels.count;
    if (crop == std::array<int, 3>{period, period, period}) out.crop_components_periodic = detail::label_runs(first.runs, true).count;
    return out;
}

}  // namespace vdbmesh
