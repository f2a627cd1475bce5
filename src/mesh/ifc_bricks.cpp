// Intersection-free octree contouring brick by brick (docs/dmc.md, "Bricks"): a brick is
// n x n nodes across and one node high; the bricks of one column of n x n nodes are contoured
// bottom to top by one wavefront (ifc_wavefront.cpp), and the nodes' outputs are welded in
// z-major order, so the mesh is the whole-grid run's, byte for byte.

#include <algorithm>
#include <functional>
#include <iterator>
#include <limits>
#include <array>
#include <map>
#include <string>
#include <tuple>

#include "mesh/ifc.h"
#include "mesh/ifc_spill.h"
#include "mesh/ifc_wavefront.h"
#include "mesh/mesh_phases.h"
#include "vdbmesh/error.h"
#include "vdbmesh/ranks.h"

namespace vdbmesh::detail {

namespace {

/// Bytes of the mesher's cells per byte of grid held (the wavefront holds the cells of two node
/// layers and the samples of three): measured about 0.6 on the bunny tiled 3 x 3 x 3 (from the
/// raw scan in one column: peak 1.37 GB where the grid held and the band and windows read
/// account for 1.09 GB; bench/README.md, "Scale"), taken as 1 for an upper estimate.
constexpr double kWorkPerGridByte = 1.0;
/// What the process holds before it reads a grid (the program, its libraries, the thread
/// pool): a first guess; the plans it gave were all above the measured peaks (bench/README.md, "Scale").
constexpr std::uint64_t kBaseBytes = std::uint64_t(24) << 20;

/// The column of bricks @a brick belongs to, owned part.
IfcColumn column_of(const IfcBrick& brick, int column_voxels) {
    return {brick.min_x, brick.min_y, brick.min_x + column_voxels - 1, brick.min_y + column_voxels - 1};
}

/// The boxes of what a column's wavefront holds when it contours @a brick: three node layers
/// and a leaf row of the column's nodes and their ring (ifc_wavefront.h), and the layer it reads
/// then.
struct WavefrontBoxes {
    IndexBox held, read;
};
WavefrontBoxes wavefront_boxes(const IfcBrick& brick, int column_voxels) {
    const IfcColumn column = column_of(brick, column_voxels);
    constexpr int kWiden = kNodeVoxels + 8;
    const IndexBox held{{column.min_x - kWiden, column.min_y - kWiden, (brick.layer - 1) * kNodeVoxels},
                        {column.max_x + 1 + kWiden, column.max_y + 1 + kWiden, (brick.layer + 2) * kNodeVoxels + 8}};
    IndexBox read = held;
    read.min[2] = (brick.layer + 2) * kNodeVoxels;
    read.max[2] = (brick.layer + 3) * kNodeVoxels;
    return {held, read};
}

/// The bricks of @a planned that ranks.h's rule gives @a rank of @a ranks: a contiguous run.
std::vector<IfcBrick> bricks_of_rank(std::vector<IfcBrick> planned, int rank, int ranks) {
    std::vector<std::uint64_t> weights(planned.size());
    for (std::size_t b = 0; b < planned.size(); ++b) weights[b] = planned[b].active_voxels;
    const std::vector<int> rank_of = bricks_to_ranks(weights, ranks);
    std::vector<IfcBrick> mine;
    for (std::size_t b = 0; b < planned.size(); ++b) {
        if (rank_of[b] == rank) mine.push_back(planned[b]);
    }
    return mine;
}

}  // namespace

std::vector<IfcBrick> plan_ifc_bricks(const GridRegionSource& source, int nodes_per_brick) {
    const int column_voxels = nodes_per_brick * kNodeVoxels;
    // The nodes meshed are those listed and the 7 below each: a block's cells read samples up
    // to 8 beyond its origin, so a node whose upper neighbours hold surface may too.
    std::vector<std::pair<openvdb::Coord, std::uint64_t>> meshed;  // origin, active voxels
    int low_x = std::numeric_limits<int>::max(), low_y = low_x;
    for (const NodeWeight& node : source.nodes()) {
        for (int d = 0; d < 8; ++d) {
            const openvdb::Coord origin(node.origin[0] - kNodeVoxels * (d & 1), node.origin[1] - kNodeVoxels * ((d >> 1) & 1),
                                        node.origin[2] - kNodeVoxels * (d >> 2));
            meshed.push_back({origin, d == 0 ? node.active_voxels : 0});
            low_x = std::min(low_x, origin.x());
            low_y = std::min(low_y, origin.y());
        }
    }
    // Columns start at the lowest meshed node, so the narrowest column holding every node is
    // one column. Keyed column (y, x), layer -> active voxels.
    std::map<std::tuple<int, int, int>, std::uint64_t> weights;
    for (const auto& [origin, active] : meshed) {
        weights[{(origin.y() - low_y) / column_voxels, (origin.x() - low_x) / column_voxels, origin.z() / kNodeVoxels}] += active;
    }
    std::vector<IfcBrick> bricks;
    for (const auto& [key, active] : weights) {
        const auto& [y, x, layer] = key;
        const IfcBrick brick{low_x + x * column_voxels, low_y + y * column_voxels, layer, active};
        // A column's layers run without gaps, so one wavefront climbs each column.
        if (!bricks.empty() && bricks.back().min_x == brick.min_x && bricks.back().min_y == brick.min_y) {
            for (int l = bricks.back().layer + 1; l < layer; ++l) bricks.push_back({brick.min_x, brick.min_y, l, 0});
        }
        bricks.push_back(brick);
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
    std::vector<IfcBrick> planned = plan_ifc_bricks(source, bricks.nodes_per_brick);
    report.nodes_per_brick = bricks.nodes_per_brick;
    report.bricks = planned.size();
    report.estimated_peak_bytes = brick_peak_bytes(source, bricks.nodes_per_brick);
    if (bricks.ranks > 1) planned = bricks_of_rank(std::move(planned), bricks.rank, bricks.ranks);
    const SampleClassifier classifier(*source.description(), options);
    MeshOptions per_column = options;
    per_column.progress = nullptr;
    std::size_t done = 0;
    for (std::size_t first = 0; first < planned.size();) {
        std::size_t last = first;  // the bricks of one column, consecutive layers
        while (last + 1 < planned.size() && planned[last + 1].min_x == planned[first].min_x && planned[last + 1].min_y == planned[first].min_y)
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
    if (bricks.ranks > 1) {
        const std::vector<std::string> parts = bricks.gather(bricks.rank == 0 ? std::string() : spill.serialized());
        for (std::size_t r = 1; r < parts.size(); ++r) spill.absorb(parts[r]);
        clock.lap(report, "gather");
        if (bricks.rank != 0) return;
    }
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
        // The grid held, the mesher's cells on it, and the next layer being read.
        const detail::WavefrontBoxes boxes = detail::wavefront_boxes(brick, column_voxels);
        const double held = double(source.grid_bytes(boxes.held)) * (1.0 + detail::kWorkPerGridByte);
        peak = std::max(peak, detail::kBaseBytes + std::uint64_t(held) + source.estimated_bytes(boxes.read));
    }
    return peak;
}

}  // namespace vdbmesh
