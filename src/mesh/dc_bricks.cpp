// Intersection-free octree contouring brick by brick (docs/dmc.md, "Bricks"): a brick is
// nx x ny nodes across and one node high; the bricks of one column (the same x, y) are contoured
// bottom to top by one wavefront (dc_wavefront.cpp), and the nodes' outputs are welded in
// z-major order, so the mesh is the whole-grid run's, byte for byte.

#include <tbb/task_arena.h>

#include <algorithm>
#include <functional>
#include <future>
#include <iterator>
#include <limits>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <tuple>

#include "mesh/dual_contouring.h"
#include "mesh/dc_spill.h"
#include "mesh/dc_wavefront.h"
#include "mesh/marching_cubes.h"
#include "mesh/mesh_phases.h"
#include "vdbmesh/error.h"
#include "vdbmesh/program_memory.h"
#include "vdbmesh/ranks.h"

namespace vdbmesh::detail {

namespace {

/// Bytes of the mesher's cells per byte of grid held (the wavefront holds the cells of two node
/// layers and the samples of three): measured about 0.6 on the bunny tiled 3 x 3 x 3 (from the
/// raw scan in one column: peak 1.37 GB where the grid held and the band and windows read
/// account for 1.09 GB; bench/README.md, "Scale"), taken as 1 for an upper estimate.
constexpr double kWorkPerGridByte = 1.0;

/// The column of bricks @a brick belongs to, owned part.
IfcColumn column_of(const IfcBrick& brick, const BrickShape& shape) {
    return {brick.min_x, brick.min_y, brick.min_x + shape.nodes_x * kNodeVoxels - 1, brick.min_y + shape.nodes_y * kNodeVoxels - 1};
}

/// The boxes of what a column's wavefront holds when it contours @a brick: three node layers
/// and a leaf row of the column's nodes and their ring (dc_wavefront.h), and the layer it reads
/// then.
struct WavefrontBoxes {
    IndexBox held, read;
};
WavefrontBoxes wavefront_boxes(const IfcBrick& brick, const BrickShape& shape) {
    const IfcColumn column = column_of(brick, shape);
    constexpr int kWiden = kNodeVoxels + 8;
    const IndexBox held{{column.min_x - kWiden, column.min_y - kWiden, (brick.layer - 1) * kNodeVoxels},
                        {column.max_x + 1 + kWiden, column.max_y + 1 + kWiden, (brick.layer + 2) * kNodeVoxels + 8}};
    IndexBox read = held;
    read.min[2] = (brick.layer + 2) * kNodeVoxels;
    read.max[2] = (brick.layer + 3) * kNodeVoxels;
    return {held, read};
}

/// The nodes meshed: those listed and the 7 below each (a block's cells read samples up to 8
/// beyond its origin, so a node whose upper neighbours hold surface may too), with the active
/// voxels of the listed ones.
std::vector<std::pair<openvdb::Coord, std::uint64_t>> meshed_nodes(const GridRegionSource& source) {
    std::vector<std::pair<openvdb::Coord, std::uint64_t>> meshed;
    for (const NodeWeight& node : source.nodes()) {
        for (int d = 0; d < 8; ++d) {
            const openvdb::Coord origin(node.origin[0] - kNodeVoxels * (d & 1), node.origin[1] - kNodeVoxels * ((d >> 1) & 1),
                                        node.origin[2] - kNodeVoxels * (d >> 2));
            meshed.push_back({origin, d == 0 ? node.active_voxels : 0});
        }
    }
    return meshed;
}

/// Where columns start: the lowest meshed node in x and y, so that the narrowest column
/// holding every node is one column.
openvdb::Coord columns_origin(const std::vector<std::pair<openvdb::Coord, std::uint64_t>>& meshed) {
    openvdb::Coord low(std::numeric_limits<int>::max());
    for (const auto& [origin, active] : meshed) low = openvdb::Coord::minComponent(low, origin);
    return low;
}

/// The octree work of meshing in columns of @a shape: each node's active voxels times the
/// columns that build it (its own and those whose ring holds it).
std::uint64_t built_voxels(const std::vector<std::pair<openvdb::Coord, std::uint64_t>>& meshed, const openvdb::Coord& low,
                           const openvdb::Coord& extent, const BrickShape& shape) {
    // The columns (along one axis) whose extent widened by the ring holds node @a i of @a nodes.
    auto builders = [](int i, int width, int nodes) {
        return 1 + (i % width == 0 && i > 0 ? 1 : 0) + (i % width == width - 1 && i + 1 < nodes ? 1 : 0);
    };
    std::uint64_t built = 0;
    for (const auto& [origin, active] : meshed) {
        const int ix = (origin.x() - low.x()) / kNodeVoxels, iy = (origin.y() - low.y()) / kNodeVoxels;
        built += active * std::uint64_t(builders(ix, shape.nodes_x, extent.x()) * builders(iy, shape.nodes_y, extent.y()));
    }
    return built;
}

bool same_column(const IfcBrick& a, const IfcBrick& b) { return a.min_x == b.min_x && a.min_y == b.min_y; }

/// The columns of @a planned's bricks, in visiting order.
std::vector<IfcColumn> columns_of(const std::vector<IfcBrick>& planned, const BrickShape& shape) {
    std::vector<IfcColumn> columns;
    for (std::size_t b = 0; b < planned.size(); ++b) {
        if (b == 0 || !same_column(planned[b - 1], planned[b])) columns.push_back(column_of(planned[b], shape));
    }
    return columns;
}

/// Whether node @a node is one of @a column's or of its ring's.
bool within_ring(const IfcColumn& column, const openvdb::Coord& node) {
    return node.x() >= column.min_x - kNodeVoxels && node.x() <= column.max_x + 1 && node.y() >= column.min_y - kNodeVoxels &&
           node.y() <= column.max_y + 1;
}

/// A rank's share of the planned bricks: a contiguous run (ranks.h's rule), and the ranks owning
/// the bricks just under and over it when those lie in the same column (-1: none).
struct RankRun {
    std::vector<IfcBrick> bricks;
    int below = -1, above = -1;
};

RankRun run_of_rank(const std::vector<IfcBrick>& planned, int rank, int ranks) {
    std::vector<std::uint64_t> weights(planned.size());
    for (std::size_t b = 0; b < planned.size(); ++b) weights[b] = planned[b].active_voxels;
    const std::vector<int> rank_of = bricks_to_ranks(weights, ranks);
    RankRun run;
    for (std::size_t b = 0; b < planned.size(); ++b) {
        if (rank_of[b] != rank) continue;
        if (run.bricks.empty() && b > 0 && same_column(planned[b - 1], planned[b])) run.below = rank_of[b - 1];
        run.bricks.push_back(planned[b]);
        if (b + 1 < planned.size() && rank_of[b + 1] != rank && same_column(planned[b], planned[b + 1])) run.above = rank_of[b + 1];
    }
    return run;
}

/// The cells at the borders between this rank's run and the runs under and over it in the
/// same column, posted to the ranks owning those (docs/scale.md, "Borders between ranks"): the
/// top block rows of its last layer up before its run starts (that layer built first), the
/// bottom rows of its first layer down as soon as they are built; each taken only when needed,
/// by then long posted.
class RankBorders {
public:
    RankBorders(const RankCollectives& ranks, int below, int above) : ranks_(ranks), below_(below), above_(above) {}

    void post_top_rows(std::string rows) { ranks_.post(above_, kTopRows, std::move(rows)); }
    void post_bottom_rows(std::string rows) { ranks_.post(below_, kBottomRows, std::move(rows)); }
    const std::string& rows_above() { return taken(rows_above_, above_, kBottomRows); }
    const std::string& rows_below() { return taken(rows_below_, below_, kTopRows); }

private:
    static constexpr int kBottomRows = 28001, kTopRows = 28002;  // message tags

    const std::string& taken(std::optional<std::string>& rows, int from, int tag) {
        if (!rows) rows = ranks_.take(from, tag);
        return *rows;
    }

    const RankCollectives& ranks_;
    const int below_, above_;
    std::optional<std::string> rows_above_, rows_below_;
};

/// Marching Cubes (error 0) brick by brick, into @a consume: a brick's nodes and a leaf beyond
/// them on the far sides (its blocks' cells read one sample further) read, its blocks marched.
/// No halo: a cell needs nothing but its 8 samples.
void march_bricks(const GridRegionSource& source, const SampleClassifier& classifier, const MeshOptions& options,
                  const std::vector<IfcBrick>& planned, const BrickShape& shape, MeshReport& report,
                  const std::function<void(std::vector<IfcNodeOutput>&&)>& consume) {
    constexpr int kLeafVoxels = 8;
    for (std::size_t b = 0; b < planned.size(); ++b) {
        const IfcColumn column = column_of(planned[b], shape);
        const int z0 = planned[b].layer * kNodeVoxels;
        const openvdb::CoordBBox owned({column.min_x, column.min_y, z0}, {column.max_x, column.max_y, z0 + kNodeVoxels - 1});
        const IndexBox read{{column.min_x, column.min_y, z0},
                            {column.max_x + 1 + kLeafVoxels, column.max_y + 1 + kLeafVoxels, z0 + kNodeVoxels + kLeafVoxels}};
        PhaseClock clock;
        const std::shared_ptr<openvdb::FloatGrid> region = source.read(read);
        clock.lap(report, "read");
        std::vector<IfcNodeOutput> nodes = marching_cubes_nodes(*region, classifier, options, owned);
        clock.lap(report, "contour");
        consume(std::move(nodes));
        if (options.progress) options.progress(0.9 * double(b + 1) / double(planned.size()));
    }
}

}  // namespace

std::vector<IfcBrick> plan_ifc_bricks(const GridRegionSource& source, const BrickShape& shape) {
    const int width_x = shape.nodes_x * kNodeVoxels, width_y = shape.nodes_y * kNodeVoxels;
    const std::vector<std::pair<openvdb::Coord, std::uint64_t>> meshed = meshed_nodes(source);
    const openvdb::Coord low = columns_origin(meshed);
    // Keyed column (y, x), layer -> active voxels.
    std::map<std::tuple<int, int, int>, std::uint64_t> weights;
    for (const auto& [origin, active] : meshed) {
        weights[{(origin.y() - low.y()) / width_y, (origin.x() - low.x()) / width_x, origin.z() / kNodeVoxels}] += active;
    }
    std::vector<IfcBrick> bricks;
    for (const auto& [key, active] : weights) {
        const auto& [y, x, layer] = key;
        const IfcBrick brick{low.x() + x * width_x, low.y() + y * width_y, layer, active};
        // A column's layers run without gaps, so one wavefront climbs each column.
        if (!bricks.empty() && bricks.back().min_x == brick.min_x && bricks.back().min_y == brick.min_y) {
            for (int l = bricks.back().layer + 1; l < layer; ++l) bricks.push_back({brick.min_x, brick.min_y, l, 0});
        }
        bricks.push_back(brick);
    }
    return bricks;
}

BrickShape plan_brick_shape(const GridRegionSource& source, std::uint64_t memory_bytes) {
    const std::vector<std::pair<openvdb::Coord, std::uint64_t>> meshed = meshed_nodes(source);
    if (meshed.empty()) return {1, 1};
    const openvdb::Coord low = columns_origin(meshed);
    openvdb::Coord high = low;
    for (const auto& [origin, active] : meshed) high = openvdb::Coord::maxComponent(high, origin);
    const int extent_x = (high.x() - low.x()) / kNodeVoxels + 1, extent_y = (high.y() - low.y()) / kNodeVoxels + 1;
    const openvdb::Coord extent(extent_x, extent_y, 1);
    if (memory_bytes == 0) return {extent_x, extent_y};  // no limit: one column
    // The widths that cut an extent into 1, 2, 3 ... columns.
    auto widths = [](int extent) {
        std::vector<int> found;
        for (int columns = 1; columns <= extent; ++columns) {
            const int width = (extent + columns - 1) / columns;
            if (found.empty() || found.back() != width) found.push_back(width);
        }
        return found;
    };
    // Shapes by the octree work their rings repeat, then the fewest columns; the first that fits.
    std::vector<std::tuple<std::uint64_t, int, BrickShape>> shapes;
    for (const int x : widths(extent_x)) {
        for (const int y : widths(extent_y)) {
            const BrickShape shape{x, y};
            const int columns = ((extent_x + x - 1) / x) * ((extent_y + y - 1) / y);
            shapes.push_back({built_voxels(meshed, low, extent, shape), columns, shape});
        }
    }
    std::stable_sort(shapes.begin(), shapes.end(), [](const auto& a, const auto& b) {
        return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
    });
    for (const auto& candidate : shapes) {
        if (brick_peak_bytes(source, std::get<2>(candidate)) <= memory_bytes) return std::get<2>(candidate);
    }
    const std::uint64_t smallest = brick_peak_bytes(source, {1, 1});
    constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
    throw UsageError("memory: " + std::to_string(memory_bytes / kMiB) + "M is too small: a column of one node with its ring needs about " +
                     std::to_string((smallest + kMiB - 1) / kMiB) + "M here; the smallest limit that works is " +
                     std::to_string((smallest + kMiB - 1) / kMiB) + "M");
}

void for_each_brick(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks, MeshReport& report,
                    const std::function<void(std::vector<IfcNodeOutput>&&)>& consume) {
    std::vector<IfcBrick> planned = plan_ifc_bricks(source, bricks.shape);
    report.brick_shape = bricks.shape;
    report.bricks = planned.size();
    report.estimated_peak_bytes = brick_peak_bytes(source, bricks.shape);
    RankRun run{planned};
    if (bricks.ranks > 1) run = run_of_rank(planned, bricks.rank, bricks.ranks);
    const std::size_t total = planned.size();
    planned = std::move(run.bricks);
    const SampleClassifier classifier(*source.description(), options);
    if (options.method == MeshMethod::mc || options.error <= 0) {
        march_bricks(source, classifier, options, planned, bricks.shape, report, consume);
        return;
    }
    MeshOptions per_column = options;
    per_column.progress = nullptr;
    std::size_t done = 0;
    auto consume_counted = [&](std::vector<IfcNodeOutput>&& made) {
        consume(std::move(made));
        if (options.progress) options.progress(0.9 * double(++done) / double(total));
    };
    // Ranks that can talk build the layers at their borders once (simulated ranks, which run
    // one after another, each build them).
    std::optional<RankBorders> borders;
    if (bricks.ranks > 1 && bricks.collectives) borders.emplace(*bricks.collectives, run.below, run.above);
    // Where columns' rings reach into each other, a node one column built is kept for the next;
    // and the last layer, with a rank above, is built first and kept until its turn.
    const std::vector<IfcColumn> columns = columns_of(planned, bricks.shape);
    const bool release_memory = bricks.memory_bytes > 0;
    std::size_t column = 0;
    std::optional<IfcNodeCache> cache;
    if (columns.size() > 1 || (borders && run.above >= 0)) {
        cache.emplace([&](const openvdb::Coord& node) {
            return std::any_of(columns.begin() + std::ptrdiff_t(column) + 1, columns.end(),
                               [&](const IfcColumn& later) { return within_ring(later, node); });
        });
    }
    if (borders && run.above >= 0) {
        IfcColumnWavefront ahead(source, classifier, per_column, columns.back(), report, &*cache, release_memory);
        borders->post_top_rows(ahead.prebuild_last_layer(planned.back().layer));
    }
    for (std::size_t first = 0; first < planned.size(); ++column) {
        std::size_t last = first;  // the bricks of one column, consecutive layers
        while (last + 1 < planned.size() && same_column(planned[last + 1], planned[first])) ++last;
        IfcColumnBorders column_borders;
        if (borders) {
            column_borders.below = first == 0 && run.below >= 0;
            column_borders.above = last + 1 == planned.size() && run.above >= 0;
            column_borders.first_layer_built = [&](std::string rows) { borders->post_bottom_rows(std::move(rows)); };
            column_borders.rows_below = [&]() -> const std::string& { return borders->rows_below(); };
            column_borders.rows_above = [&]() -> const std::string& { return borders->rows_above(); };
        }
        IfcColumnWavefront wavefront(source, classifier, per_column, columns[column], report, cache ? &*cache : nullptr, release_memory);
        wavefront.run(planned[first].layer, planned[last].layer, consume_counted, borders ? &column_borders : nullptr);
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
    IfcSpill spill(bricks.memory_bytes > 0 ? TempFile::Held::on_disk : TempFile::Held::in_memory);
    // A layer's nodes are appended to the spill while the next layer is built, one
    // layer at most in flight; with one thread, at once. "spill" times the waits.
    const std::launch when = tbb::this_task_arena::max_concurrency() == 1 ? std::launch::deferred : std::launch::async;
    std::future<void> appending;
    auto wait_for_appending = [&] {
        PhaseClock clock;
        if (appending.valid()) appending.get();
        clock.lap(report, "spill");
    };
    for_each_brick(source, options, bricks, report, [&](std::vector<IfcNodeOutput>&& made) {
        wait_for_appending();
        appending = std::async(when, [&spill, made = std::move(made)]() mutable {
            for (IfcNodeOutput& node : made) spill.append(std::move(node));
        });
        if (when == std::launch::deferred) wait_for_appending();
    });
    wait_for_appending();
    PhaseClock clock;
    if (bricks.ranks > 1 && bricks.collectives && sink.ranges()) {
        spill.emit_on_ranks(*sink.ranges(), sink.needs_corners(), mirrored, *bricks.collectives);
        clock.lap(report, "write");
        if (options.progress) options.progress(1.0);
        return;
    }
    if (bricks.ranks > 1) {
        IfcSpill::Receiver receiver(spill);
        bricks.gather(bricks.rank == 0 ? RankPart{} : spill.part(), receiver);
        clock.lap(report, "gather");
        if (bricks.rank != 0) return;
    }
    spill.emit(sink, mirrored);
    clock.lap(report, "write");
    if (options.progress) options.progress(1.0);
}

}  // namespace vdbmesh::detail

namespace vdbmesh {

std::uint64_t brick_peak_bytes(const GridRegionSource& source, const BrickShape& shape) {
    std::uint64_t peak = kProgramBytes + source.opening_bytes();
    for (const detail::IfcBrick& brick : detail::plan_ifc_bricks(source, shape)) {
        // The grid held, the mesher's cells on it, and the next layer being read.
        const detail::WavefrontBoxes boxes = detail::wavefront_boxes(brick, shape);
        const double held = double(source.grid_bytes(boxes.held)) * (1.0 + detail::kWorkPerGridByte);
        peak = std::max(peak, kProgramBytes + std::uint64_t(held) + source.estimated_bytes(boxes.read));
    }
    return peak;
}

}  // namespace vdbmesh
