// Intersection-free octree contouring brick by brick (docs/dmc.md, "Bricks"): each brick of
// whole nodes is read with a halo of one node, its octree and coarse merges are built there,
// and only its own blocks are contoured; the nodes' outputs are welded in z-major order, so
// the mesh is the whole-grid run's, byte for byte.

#include <algorithm>
#include <functional>
#include <iterator>
#include <array>
#include <string>
#include <set>
#include <tuple>

#include "mesh/ifc.h"
#include "mesh/ifc_spill.h"
#include "mesh/mesh_phases.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

/// Floor division of a node coordinate (a multiple of kNodeVoxels) into brick units.
int brick_of(int voxel, int brick_voxels) { return voxel >= 0 ? voxel / brick_voxels : -((-voxel + brick_voxels - 1) / brick_voxels); }

/// The bricks (minimum corners in voxels) holding a node that may hold surface, in z-major
/// order: the nodes @a source lists and the 7 below each (a block's cells read samples up to
/// 8 beyond its origin, so a node whose upper neighbours hold surface may too).
std::vector<openvdb::Coord> bricks_to_visit(const GridRegionSource& source, int brick_voxels) {
    std::set<std::tuple<int, int, int>> bricks;  // z, y, x: z-major
    for (const NodeWeight& node : source.nodes()) {
        for (int d = 0; d < 8; ++d) {
            const int x = node.origin[0] - kNodeVoxels * (d & 1), y = node.origin[1] - kNodeVoxels * ((d >> 1) & 1);
            const int z = node.origin[2] - kNodeVoxels * (d >> 2);
            bricks.insert({brick_of(z, brick_voxels), brick_of(y, brick_voxels), brick_of(x, brick_voxels)});
        }
    }
    std::vector<openvdb::Coord> corners;
    for (const auto& [z, y, x] : bricks) corners.emplace_back(x * brick_voxels, y * brick_voxels, z * brick_voxels);
    return corners;
}

/// The region a brick reads: its box widened by the one-node halo and a leaf more, for the
/// blocks' sample windows (-1..9) and the far faces of the halo's nodes.
IndexBox halo_box(const openvdb::CoordBBox& owned) {
    constexpr int kWiden = kNodeVoxels + 8;
    IndexBox box;
    for (int a = 0; a < 3; ++a) {
        box.min[std::size_t(a)] = owned.min()[a] - kWiden;
        box.max[std::size_t(a)] = owned.max()[a] + 1 + kWiden;
    }
    return box;
}

/// Bytes of the mesher's work per byte of grid it reads (the cells of the octree and coarse
/// merges, the keyed triangles and vertices): a first guess, not yet calibrated (bench/README.md, "Bricks").
constexpr double kWorkPerGridByte = 2.0;
/// What the process holds before it reads a grid (the program, its libraries, the thread
/// pool): a first guess, not yet calibrated (bench/README.md, "Bricks").
constexpr std::uint64_t kBaseBytes = std::uint64_t(24) << 20;

}  // namespace

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
    int extent = 1;  // nodes per edge of a brick holding them all, and their lower neighbours
    for (std::size_t a = 0; a < 3; ++a) extent = std::max(extent, (hi[a] - lo[a]) / kNodeVoxels + 2);
    if (memory_bytes == 0) return extent;  // no limit: one brick
    for (int n = extent; n >= 1; --n) {
        if (brick_peak_bytes(source, n) <= memory_bytes) return n;
    }
    const std::uint64_t smallest = brick_peak_bytes(source, 1);
    constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
    throw UsageError("memory: " + std::to_string(memory_bytes / kMiB) + "M is too small: a brick of one node with its halo needs about " +
                     std::to_string((smallest + kMiB - 1) / kMiB) + "M here; the smallest limit that works is " +
                     std::to_string((smallest + kMiB - 1) / kMiB) + "M");
}

void for_each_brick(const GridRegionSource& source, const MeshOptions& options, const BrickOptions& bricks, MeshReport& report,
                    const std::function<void(std::vector<IfcNodeOutput>&&)>& consume) {
    const int brick_voxels = bricks.nodes_per_brick * kNodeVoxels;
    const std::vector<openvdb::Coord> corners = bricks_to_visit(source, brick_voxels);
    const SampleClassifier classifier(*source.description(), options);
    MeshOptions per_brick = options;
    per_brick.progress = nullptr;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        PhaseClock clock;
        const openvdb::CoordBBox owned(corners[i], corners[i].offsetBy(brick_voxels - 1));
        std::shared_ptr<openvdb::FloatGrid> region = source.read(halo_box(owned));
        clock.lap(report, "read");
        std::vector<IfcNodeOutput> made = contour_ifc_nodes(*region, classifier, per_brick, &owned, report);
        region.reset();
        consume(std::move(made));
        if (options.progress) options.progress(0.9 * double(i + 1) / double(corners.size()));
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
    const int brick_voxels = nodes_per_brick * kNodeVoxels;
    std::uint64_t peak = detail::kBaseBytes;
    for (const openvdb::Coord& corner : detail::bricks_to_visit(source, brick_voxels)) {
        const IndexBox box = detail::halo_box(openvdb::CoordBBox(corner, corner.offsetBy(brick_voxels - 1)));
        peak = std::max(peak, detail::kBaseBytes + std::uint64_t(double(source.estimated_bytes(box)) * (1.0 + detail::kWorkPerGridByte)));
    }
    return peak;
}

}  // namespace vdbmesh
