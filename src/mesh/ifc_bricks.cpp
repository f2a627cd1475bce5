// Intersection-free octree contouring brick by brick (docs/dmc.md, "Bricks"): a brick is
// n x n nodes across and one node high; the bricks of one column of n x n nodes are contoured
// bottom to top by one wavefront (ifc_wavefront.cpp), and the nodes' outputs are welded in
// z-major order, so the mesh is the whole-grid run's, byte for byte.

#include <algorithm>
#include <functional>
#include <iterator>
#include <array>
#include <map>
#include <string>
#include <tuple>

#include "mesh/ifc.h"
#include "mesh/ifc_spill.h"
#include "mesh/ifc_wavefront.h"
#include "mesh/mesh_phases.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

/// Floor division of a voxel coordinate by @a size.
int floor_div(int voxel, int size) { return voxel >= 0 ? voxel / size : -((-voxel + size - 1) / size); }

/// Bytes of the mesher's work per byte of grid it reads (the cells of the octree and coarse
/// merges, the keyed triangles and vertices): a first guess, not yet calibrated (bench/README.md, "Bricks").
constexpr double kWorkPerGridByte = 2.0;
/// What the process holds before it reads a grid (the program, its libraries, the thread
/// pool): a first guess, not yet calibrated (bench/README.md, "Bricks").
constexpr std::uint64_t kBaseBytes = std::uint64_t(24) << 20;

/// The column of bricks @a brick belongs to, owned part.
IfcColumn column_of(const IfcBrick& brick, int column_voxels) {
    return {brick.column_x * column_voxels, brick.column_y * column_voxels, (brick.column_x + 1) * column_voxels - 1,
            (brick.column_y + 1) * column_voxels - 1};
}

/// What a column's wavefront holds when it contours @a brick: three node layers and a leaf row
/// of the column's nodes and their ring (ifc_wavefront.h), read from @a source.
IndexBox wavefront_box(const IfcBrick& brick, int column_voxels) {
    const IfcColumn column = column_of(brick, column_voxels);
    constexpr int kWiden = kNodeVoxels + 8;
    return {{column.min_x - kWiden, column.min_y - kWiden, (brick.layer - 1) * kNodeVoxels},
            {column.max_x + 1 + kWiden, column.max_y + 1 + kWiden, (brick.layer + 2) * kNodeVoxels + 8}};
}

}  // namespace

std::vector<IfcBrick> plan_ifc_bricks(const GridRegionSource& source, int nodes_per_brick) {
    const int column_voxels = nodes_per_brick * kNodeVoxels;
    // Column (y, x), layer -> active voxels. The nodes meshed are those listed and the 7 below
    // each: a block's cells read samples up to 8 beyond its origin, so a node whose upper
    // neighbours hold surface may too.
    std::map<std::tuple<int, int, int>, std::uint64_t> weights;
    for (const NodeWeight& node : source.nodes()) {
        for (int d = 0; d < 8; ++d) {
            const int x = node.origin[0] - kNodeVoxels * (d & 1), y = node.origin[1] - kNodeVoxels * ((d >> 1) & 1);
            const int z = node.origin[2] - kNodeVoxels * (d >> 2);
            weights[{floor_div(y, column_voxels), floor_div(x, column_voxels), floor_div(z, kNodeVoxels)}] += d == 0 ? node.active_voxels : 0;
        }
    }
    std::vector<IfcBrick> bricks;
    for (auto it = weights.begin(); it != weights.end(); ++it) {
        const auto& [y, x, layer] = it->first;
        // A column's layers run without gaps, so one wavefront climbs each column.
        if (!bricks.empty() && bricks.back().column_x == x && bricks.back().column_y == y) {
            for (int l = bricks.back().layer + 1; l < layer; ++l) bricks.push_back({x, y, l, 0});
        }
        bricks.push_back({x, y, layer, it->second});
    }
    return bricks;
}

int plan_brick_size(const GridRegionSource& source, std::uint64_t memory_bytes) {
    const std::vector<NodeWeight> nodes = source.nodes();
    if (nodes.empty()) return 1;
    std::array<int, 3> lo = nodes.front().origin, hi = lo;
    for (const NodeWeight& node : nodes) {
        for (std::size_t a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], node.origin[a]);
            hi[a] = std::max(hi[a], node.origin[a]);
        }
    }
    int extent = 1;  // nodes across a column holding them all, and their lower neighbours
    for (std::size_t a = 0; a < 2; ++a) extent = std::max(extent, (hi[a] - lo[a]) / kNodeVoxels + 2);
    if (memory_bytes == 0) return extent;  // no limit: one column
    for (int n = extent; n >= 1; --n) {
        if (brick_peak_bytes(source, n) <= memory_bytes) return n;
    }
    const std::uint64_t smallest = brick_peak_bytes(source, 1);
    constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
    throw UsageError("memory: " + std::to_string(memory_bytes / kMiB) + "M is too small: a column of one node with its ring needs about " +
                     std::to_string((smallest + kMiB - 1) / kMiB) + "M here; the smallest limit that works is " +
                     std::to_string((smallest + kMiB - 1) / kMiB) + "M");
}

void for_each_brick(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks, MeshReport& report,
                    const std::function<void(std::vector<IfcNodeOutput>&&)>& consume) {
    const int column_voxels = bricks.nodes_per_brick * kNodeVoxels;
    const std::vector<IfcBrick> planned = plan_ifc_bricks(source, bricks.nodes_per_brick);
    const SampleClassifier classifier(*source.description(), options);
    MeshOptions per_column = options;
    per_column.progress = nullptr;
    std::size_t done = 0;
    for (std::size_t first = 0; first < planned.size();) {
        std::size_t last = first;  // the bricks of one column, consecutive layers
        while (last + 1 < planned.size() && planned[last + 1].column_x == planned[first].column_x &&
               planned[last + 1].column_y == planned[first].column_y)
            ++last;
        IfcColumnWavefront wavefront(source, classifier, per_column, column_of(planned[first], column_voxels), report);
        wavefront.run(planned[first].layer, planned[last].layer, [&](std::vector<IfcNodeOutput>&& made) {
            consume(std::move(made));
            if (options.progress) options.progress(0.9 * double(++done) / double(planned.size()));
        });
        first = last + 1;
    }
}

Mesh bricked_contouring(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks, MeshReport& report) {
    std::vector<IfcNodeOutput> nodes;
    for_each_brick(source, options, bricks, report, [&](std::vector<IfcNodeOutput>&& made) {
        std::move(made.begin(), made.end(), std::back_inserter(nodes));
    });
    PhaseClock clock;
    std::stable_sort(nodes.begin(), nodes.end(), [](const IfcNodeOutput& a, const IfcNodeOutput& b) { return ifc_node_before(a.origin, b.origin); });
    Mesh mesh = weld_ifc_nodes(std::move(nodes));
    clock.lap(report, "weld");
    if (options.progress) options.progress(1.0);
    return mesh;
}

void bricked_contouring_to_stream(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks, bool mirrored,
                                  MeshStreamSink& sink, MeshReport& report) {
    IfcSpill spill;
    for_each_brick(source, options, bricks, report, [&](std::vector<IfcNodeOutput>&& made) {
        PhaseClock clock;
        for (IfcNodeOutput& node : made) spill.append(std::move(node));
        clock.lap(report, "spill");
    });
    PhaseClock clock;
    spill.emit(sink, mirrored);
    clock.lap(report, "write");
    if (options.progress) options.progress(1.0);
}

}  // namespace vdbmesh::detail

namespace vdbmesh {

std::uint64_t brick_peak_bytes(const GridRegionSource& source, int nodes_per_brick) {
    const int column_voxels = nodes_per_brick * kNodeVoxels;
    std::uint64_t peak = detail::kBaseBytes;
    for (const detail::IfcBrick& brick : detail::plan_ifc_bricks(source, nodes_per_brick)) {
        const IndexBox box = detail::wavefront_box(brick, column_voxels);
        peak = std::max(peak, detail::kBaseBytes + std::uint64_t(double(source.estimated_bytes(box)) * (1.0 + detail::kWorkPerGridByte)));
    }
    return peak;
}

}  // namespace vdbmesh
