// Issue 28: the default mesher brick by brick (docs/dmc.md, "Bricks"; the dual mesh at error 0) gives the same bytes as
// the whole-grid run for any brick size, thread count and number of ranks, on phantoms placed so that node
// borders (multiples of 128 voxels) cross a sharp turn, a thin wall and coarse merges, and on
// a real scan; CGAL (cgal_judge.h) judges the bricked mesh clean.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <tbb/task_arena.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "cgal_judge.h"
#include "mesh/dc_block_bytes.h"
#include "mesh/dual_contouring.h"
#include "mesh/sample_classifier.h"
#include "phantom_grid.h"
#include "shared_scan.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/ranks.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh {
namespace {

MeshOptions dc_options(double error, double iso = 0.5) {
    MeshOptions options;
    options.method = MeshMethod::dc;
    options.iso = iso;
    options.error = error;
    return options;
}

MeshResult bricked(const openvdb::FloatGrid::Ptr& grid, const MeshOptions& options, const BrickShape& shape, int threads) {
    const std::unique_ptr<GridRegionSource> source = grid_regions_in_memory(grid);
    MeshResult result;
    tbb::task_arena(threads).execute([&] { result = mesh_bricks(*source, options, BrickOptions{shape}); });
    return result;
}

/// Collects what mesh_bricks_to_stream() sends, as a mesh; with @a wants_corners false, as a
/// sink of vertex numbers only (PLY, OBJ) does.
class CollectingSink final : public MeshStreamSink {
public:
    explicit CollectingSink(bool wants_corners = true) : wants_corners_(wants_corners) {}
    void begin(std::uint64_t vertex_count, std::uint64_t triangle_count) override {
        announced = {vertex_count, triangle_count};
    }
    void vertex(const std::array<float, 3>& position) override { mesh.vertices.push_back(position); }
    void triangle(const std::array<std::uint32_t, 3>& t, const std::array<std::array<float, 3>, 3>& corners) override {
        mesh.triangles.push_back(t);
        if (wants_corners_)
            for (int k = 0; k < 3; ++k) corners_match &= t[k] < mesh.vertices.size() && mesh.vertices[t[k]] == corners[k];
    }
    bool needs_corners() const override { return wants_corners_; }
    Mesh mesh;
    std::pair<std::uint64_t, std::uint64_t> announced;
    bool corners_match = true;

private:
    bool wants_corners_;
};

Mesh streamed(const openvdb::FloatGrid::Ptr& grid, const MeshOptions& options, const BrickShape& shape, bool wants_corners = true) {
    CollectingSink sink(wants_corners);
    mesh_bricks_to_stream(*grid_regions_in_memory(grid), options, BrickOptions{shape}, sink);
    EXPECT_EQ(sink.announced.first, sink.mesh.vertices.size());
    EXPECT_EQ(sink.announced.second, sink.mesh.triangles.size());
    EXPECT_TRUE(sink.corners_match);
    return sink.mesh;
}

/// mesh_bricks_to_stream() run as @a ranks ranks one after another in this process, the last
/// rank first: each hands its part to a stand-in for ranks.h's stream_to_rank0(), which keeps
/// it, and rank 0's hands them all to its receiver in rank order, in pieces of awkward sizes (5
/// bytes, inside the part's node count, then 4,093), as stream_to_rank0() does under mpirun.
/// Returns what rank 0 sent.
Mesh streamed_over_ranks(const openvdb::FloatGrid::Ptr& grid, const MeshOptions& options, const BrickShape& shape, int ranks) {
    const std::unique_ptr<GridRegionSource> source = grid_regions_in_memory(grid);
    std::vector<std::string> parts(static_cast<std::size_t>(ranks));
    for (int rank = ranks - 1; rank >= 0; --rank) {
        BrickOptions bricks{shape};
        bricks.rank = rank;
        bricks.ranks = ranks;
        bricks.gather = [&parts, rank](const RankPart& mine, PartReceiver& receiver) {
            if (rank != 0) {
                std::string& part = parts[std::size_t(rank)];
                part.resize(mine.size);
                mine.read(0, part.size(), part.data());
                return;
            }
            for (int from = 1; from < int(parts.size()); ++from) {
                const std::string& part = parts[std::size_t(from)];
                receiver.begin(from, part.size());
                for (std::size_t at = 0, piece = 5; at < part.size(); at += piece, piece = 4093)
                    receiver.piece(part.data() + at, std::min(piece, part.size() - at));
            }
        };
        CollectingSink sink;
        mesh_bricks_to_stream(*source, options, bricks, sink);
        if (rank == 0) return sink.mesh;
        EXPECT_EQ(sink.announced.second, 0u) << "rank " << rank << " of " << ranks << " sent a mesh";
    }
    return {};
}

struct Bricking {
    BrickShape shape;
    int threads;
};
/// Square columns of one node, strips along x and along y.
const std::vector<Bricking> kEveryBricking = {{{1, 1}, 1}, {{1, 1}, 2}, {{2, 1}, 2}, {{1, 3}, 1}};

std::string describe(const Bricking& b) {
    return std::to_string(b.shape.nodes_x) + " x " + std::to_string(b.shape.nodes_y) + " node(s) a brick, " + std::to_string(b.threads) +
           " thread(s)";
}

/// The whole-grid mesh (2 threads) and the bricked ones hold the same vertices and triangles in
/// the same order; CGAL finds the mesh of one-node bricks clean when @a judge.
void expect_same_as_whole(const openvdb::FloatGrid::Ptr& grid, const MeshOptions& options, const std::string& what,
                          const std::vector<Bricking>& brickings = kEveryBricking, bool judge = true) {
    Mesh whole;
    tbb::task_arena(2).execute([&] { whole = mesh_grid(*grid, options).mesh; });
    ASSERT_FALSE(whole.triangles.empty()) << what;
    for (const Bricking& b : brickings) {
        const Mesh mesh = bricked(grid, options, b.shape, b.threads).mesh;
        EXPECT_EQ(mesh.vertices, whole.vertices) << what << ", " << describe(b);
        EXPECT_EQ(mesh.triangles, whole.triangles) << what << ", " << describe(b);
    }
    // Through the spill, never held whole: the same.
    const Mesh stream = streamed(grid, options, {1, 1});
    EXPECT_EQ(stream.vertices, whole.vertices) << what << ", streamed";
    EXPECT_EQ(stream.triangles, whole.triangles) << what << ", streamed";
    EXPECT_EQ(streamed(grid, options, {2, 1}, /*wants_corners=*/false).triangles, whole.triangles) << what << ", streamed, numbers only";
    // Over ranks, each meshing its run of bricks and rank 0 assembling: the same.
    for (const int ranks : {2, 3}) {
        const Mesh assembled = streamed_over_ranks(grid, options, {1, 1}, ranks);
        EXPECT_EQ(assembled.vertices, whole.vertices) << what << ", " << ranks << " ranks";
        EXPECT_EQ(assembled.triangles, whole.triangles) << what << ", " << ranks << " ranks";
    }
    if (!judge) return;
    const test::CgalVerdict verdict = test::judge_with_cgal(bricked(grid, options, {1, 1}, 2).mesh);
    EXPECT_TRUE(verdict.clean()) << what << ": " << verdict.describe();
}

/// A phantom of 168^3 voxels centred near the grid point (128, 128, 128), where eight nodes meet.
openvdb::FloatGrid::Ptr phantom_on_node_corner(PhantomSpec spec) {
    spec.dims = {168, 168, 168};
    spec.centre = std::array<double, 3>{128.3, 127.6, 128.45};
    return test::phantom_scan_grid(spec);
}

TEST(BricksTest, SmoothSphereAcrossNodesMergesCoarseCellsAlike) {
    PhantomSpec spec;
    spec.radius = 36;
    const auto grid = phantom_on_node_corner(spec);
    // At error 2 the sphere's cells merge across blocks up to whole nodes, next to every border.
    for (const double error : {0.25, 2.0}) expect_same_as_whole(grid, dc_options(error), "sphere at " + std::to_string(error));
}

TEST(BricksTest, RotatedCubeSharpEdgesAcrossNodes) {
    PhantomSpec spec = phantom_preset("rotated-cube", {168, 168, 168});
    spec.side = 56;
    spec.blur = 1;  // sharp turns
    expect_same_as_whole(phantom_on_node_corner(spec), dc_options(0.5), "rotated cube");
}

TEST(BricksTest, ThinWallsAcrossNodes) {
    PhantomSpec spec;
    spec.shape = PhantomShape::cube_minus_sphere;
    spec.side = 60;
    spec.hole_radius = 41.5;  // walls about a voxel thick along the cube's edges
    spec.blur = 1;
    spec.noise_sigma = 0.02;
    expect_same_as_whole(phantom_on_node_corner(spec), dc_options(1.0), "cube minus sphere");
}

// The cells a rank hands another (docs/scale.md, "Borders between ranks") and a column keeps for
// the next (IfcNodeCache) go through bytes: every field must come back, or the identity tests
// above and in bricks_ranks_test.cpp fail somewhere far from the cause. A sphere on a node
// corner at error 2 has coarse cells, split parts and crossings in its blocks.
TEST(BricksTest, BlocksAsBytesComeBackAsTheyWere) {
    PhantomSpec spec;
    spec.radius = 36;
    const auto grid = phantom_on_node_corner(spec);
    const MeshOptions options = dc_options(2.0);
    const detail::SampleClassifier classifier(*grid, options);
    MeshReport report;
    const detail::IfcCellGrid built = detail::build_ifc_cell_grid(*grid, classifier, options, std::nullopt, report);
    ASSERT_GT(built.origins.size(), 100u);
    auto every = [](const openvdb::Coord&) { return true; };
    const std::string bytes = detail::ifc_blocks_bytes(built, every);
    const detail::IfcCellGrid back = detail::ifc_blocks_from_bytes(bytes);
    EXPECT_EQ(back.origins, built.origins);
    EXPECT_EQ(detail::ifc_blocks_bytes(back, every), bytes);
    std::size_t with_parts = 0, coarse = 0;
    for (std::size_t b = 0; b < back.blocks.size(); ++b) {
        ASSERT_EQ(bool(back.blocks[b]), bool(built.blocks[b]));
        if (!back.blocks[b]) continue;
        EXPECT_EQ(back.blocks[b]->crossings, built.blocks[b]->crossings);
        with_parts += back.blocks[b]->parts ? 1 : 0;
        coarse += !back.blocks[b]->cells.empty() && back.blocks[b]->cells[0].level > detail::kIfcMaxLevel ? 1 : 0;
    }
    EXPECT_GT(coarse, 0u) << "no coarse cell: the case does not exercise them";
    EXPECT_GT(with_parts, 0u) << "no block with split parts: the case does not exercise them";
    EXPECT_THROW(detail::ifc_blocks_from_bytes(bytes.substr(0, bytes.size() - 3)), Error);
}

// Five nodes along z: the halo of a one-node brick holds only three of them, so what a brick
// decides from its halo alone is checked against the whole grid. The slightly tilted
// cylinder's wall crosses four node borders, its flat caps turn sharply.
TEST(BricksTest, LongCylinderThroughFiveNodes) {
    const auto grid = test::phantom_scan_grid(test::cylinder_through_five_nodes());
    for (const double error : {0.5, 2.0}) expect_same_as_whole(grid, dc_options(error), "cylinder at " + std::to_string(error));
}

TEST(BricksTest, RealScanCThead) {
    openvdb::FloatGrid::Ptr grid;
    const test::SharedScan& scan = test::shared_scan("CThead");
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan, grid));
    if (!grid) return;
    expect_same_as_whole(grid, dc_options(0.5, scan.iso), "CThead", {{{1, 1}, 2}, {{3, 1}, 1}}, false);
    expect_same_as_whole(grid, dc_options(0.0, scan.iso), "CThead, Marching Cubes", {{{1, 1}, 2}}, false);
}

// The bunny CT (4 x 4 x 3 nodes): one-node bricks read a halo smaller than the scan. About a
// minute: with VDBMESH_FULL=1 only.
TEST(BricksTest, RealScanBunnyFull) {
    if (!std::getenv("VDBMESH_FULL")) GTEST_SKIP() << "VDBMESH_FULL=1 runs it";
    openvdb::FloatGrid::Ptr grid;
    const test::SharedScan& scan = test::shared_scan("BunnyCt");
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan, grid));
    if (!grid) return;
    expect_same_as_whole(grid, dc_options(0.25, scan.iso), "bunny", {{{1, 1}, 2}, {{2, 1}, 1}}, false);
}

TEST(BricksTest, InMemoryRegionsReadTheBoxExactly) {
    PhantomSpec spec;
    spec.radius = 36;
    const auto grid = phantom_on_node_corner(spec);
    const std::unique_ptr<GridRegionSource> source = grid_regions_in_memory(grid);
    const std::vector<NodeWeight> nodes = source->nodes();
    ASSERT_EQ(nodes.size(), 8u);  // 168^3 samples: two nodes a side
    EXPECT_EQ(nodes[1].origin, (std::array<std::int32_t, 3>{128, 0, 0}));  // z-major
    EXPECT_EQ(nodes[2].origin, (std::array<std::int32_t, 3>{0, 128, 0}));
    std::uint64_t active = 0;
    for (const NodeWeight& node : nodes) active += node.active_voxels;
    EXPECT_EQ(active, grid->activeVoxelCount());
    const IndexBox box{{100, 120, 60}, {140, 131, 190}};
    const auto region = source->read(box);
    EXPECT_EQ(region->transform(), grid->transform());
    EXPECT_EQ(region->background(), grid->background());
    auto whole = grid->getConstAccessor();
    auto part = region->getConstAccessor();
    for (int x = box.min[0]; x < box.max[0]; ++x) {
        for (int y = box.min[1]; y < box.max[1]; ++y) {
            for (int z = box.min[2]; z < box.max[2]; ++z) {
                const openvdb::Coord ijk(x, y, z);
                ASSERT_EQ(part.getValue(ijk), whole.getValue(ijk)) << ijk;
                ASSERT_EQ(part.isValueOn(ijk), whole.isValueOn(ijk)) << ijk;
            }
        }
    }
    EXPECT_LT(region->activeVoxelCount(), grid->activeVoxelCount());
}

// A mirroring transform (x flipped): the bricked and streamed meshes are wound as mesh_grid()'s.
TEST(BricksTest, MirroredGridIsWoundAlike) {
    const auto grid = test::mirrored_sphere_across_a_node_border();
    const Mesh whole = mesh_grid(*grid, dc_options(0.5)).mesh;
    EXPECT_EQ(bricked(grid, dc_options(0.5), {1, 1}, 2).mesh.triangles, whole.triangles);
    EXPECT_EQ(streamed(grid, dc_options(0.5), {1, 1}).triangles, whole.triangles);
    EXPECT_EQ(streamed(grid, dc_options(0.5), {1, 1}, /*wants_corners=*/false).triangles, whole.triangles);
}

TEST(BricksTest, RefusesBricksWithVolumeToMeshAndBadShapes) {
    PhantomSpec spec;
    spec.dims = {40, 40, 40};
    spec.radius = 12;
    const auto source = grid_regions_in_memory(test::phantom_scan_grid(spec));
    MeshOptions openvdb = dc_options(0.0);
    openvdb.method = MeshMethod::openvdb;
    openvdb.adaptivity = 0.5;
    EXPECT_THROW(mesh_bricks(*source, openvdb, BrickOptions{{1, 1}}), UsageError);
    EXPECT_THROW(mesh_bricks(*source, dc_options(0.5), BrickOptions{{-1, 1}}), UsageError);
    EXPECT_THROW(mesh_bricks(*source, dc_options(0.5), BrickOptions{{2, 0}}), UsageError);
    // One brick of the whole grid: any method, the same mesh as mesh_grid().
    EXPECT_EQ(mesh_bricks(*source, openvdb, BrickOptions{}).mesh.triangles.size(),
              mesh_grid(*test::phantom_scan_grid(spec), openvdb).mesh.triangles.size());
}

// The default error 0 (the dual mesh, through the same wavefront as every error) and Marching
// Cubes (--method mc) by bricks. Marching Cubes: a cell needs only its 8
// samples, so no halo; the blocks' order is the bricks' (node by node in z-major order), so the
// bytes are the whole grid's, through the spill and over ranks too. A sphere where eight nodes
// meet, a tilted cylinder through five nodes along z, and an open boundary (mc only) cut by the
// scan box across node borders.
TEST(BricksTest, MarchingCubesByBricksIsTheWholeGridsMesh) {
    PhantomSpec sphere;
    sphere.radius = 36;
    expect_same_as_whole(phantom_on_node_corner(sphere), dc_options(0.0), "sphere, the dual mesh at error 0");
    MeshOptions mc = dc_options(0.0);
    mc.method = MeshMethod::mc;
    expect_same_as_whole(test::phantom_scan_grid(test::cylinder_through_five_nodes()), mc, "cylinder, --method mc", kEveryBricking, false);
    PhantomSpec cut = sphere;
    cut.dims = {150, 150, 140};
    cut.centre = std::array<double, 3>{128.3, 127.6, 128.45};  // the sphere runs out of the box
    mc.open_boundary = true;
    expect_same_as_whole(test::phantom_scan_grid(cut), mc, "sphere cut by the box, --method mc, open boundary", kEveryBricking, false);
}

// A flat slab over 8 x 8 nodes, under a limit that one column exceeds but a cut along one axis
// meets: the plan cuts it into strips (the ring one node wide along one cut) rather than into
// squares (rings along two), and the shape it picks fits the limit.
TEST(BricksTest, PlanCutsIntoStripsWhereTheyFit) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->tree().denseFill(openvdb::CoordBBox({0, 0, 0}, {1023, 1023, 15}), 1.0f, true);
    const std::unique_ptr<GridRegionSource> source = grid_regions_in_memory(grid);
    // Columns start at the lowest meshed node (x, y = -128): 9 nodes across.
    const std::uint64_t whole = brick_peak_bytes(*source, {9, 9});
    const std::uint64_t strips = brick_peak_bytes(*source, {9, 3});
    ASSERT_LT(strips, whole);
    const std::uint64_t limit = (strips + whole) / 2;
    const BrickShape planned = detail::plan_brick_shape(*source, limit);
    EXPECT_LE(brick_peak_bytes(*source, planned), limit);
    EXPECT_TRUE(planned.nodes_x == 9 || planned.nodes_y == 9) << planned.nodes_x << " x " << planned.nodes_y;
    EXPECT_EQ(detail::plan_brick_shape(*source, 0).nodes_x, 9);  // no limit: one column
    EXPECT_THROW(detail::plan_brick_shape(*source, 1000), UsageError);
}

}  // namespace
}  // namespace vdbmesh
