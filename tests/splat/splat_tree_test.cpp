// The splat hierarchy judged against what it was fitted to: the sphere of an exact distance
// field, and the Marching Cubes vertices of the same grid (mesh_grid(), not the splat code).

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <random>

#include "splat_test_math.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/splats.h"

namespace vdbmesh {
namespace {

constexpr double kRadius = 10.0;                     // world units
constexpr double kVoxel = 0.5;                       // world units: the sphere is 20 voxels wide
const openvdb::Vec3d kCentre(3.1, -2.2, 1.7);        // world: off the sample lattice
using test::kPi;
using test::vec;

/// The signed distance to the sphere (positive inside, isovalue 0), dense over its box plus a
/// margin, in a grid of voxel kVoxel offset from the origin (so world space is exercised).
openvdb::FloatGrid::Ptr sphere_grid() {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(-4.0f);
    auto transform = openvdb::math::Transform::createLinearTransform(kVoxel);
    transform->postTranslate(openvdb::Vec3d(0.25, -0.5, 0.75));
    grid->setTransform(transform);
    const openvdb::Coord lo = transform->worldToIndexCellCentered(kCentre - openvdb::Vec3d(kRadius + 2));
    const openvdb::Coord hi = transform->worldToIndexCellCentered(kCentre + openvdb::Vec3d(kRadius + 2));
    auto accessor = grid->getAccessor();
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) {
                const openvdb::Vec3d p = transform->indexToWorld(openvdb::Coord(x, y, z));
                accessor.setValue(openvdb::Coord(x, y, z), float(kRadius - (p - kCentre).length()));
            }
    return grid;
}

SplatOptions sphere_options(double tolerance = 0.1) {
    SplatOptions options;
    options.iso = 0;
    options.inside = Inside::above;
    options.coplanar_tolerance = tolerance;
    return options;
}

/// The angle between two directions (atan2: accurate near 0, where acos is not).
double angle(const std::array<float, 3>& a, const std::array<float, 3>& b) {
    return std::atan2(vec(a).cross(vec(b)).length(), vec(a).dot(vec(b)));
}

/// The Marching Cubes vertices of @a grid (world space), from the mesh stage.
std::vector<openvdb::Vec3d> mc_vertices(const openvdb::FloatGrid& grid) {
    MeshOptions options;
    options.method = MeshMethod::mc;
    options.iso = 0;
    const MeshResult result = mesh_grid(grid, options);
    std::vector<openvdb::Vec3d> points;
    for (const auto& v : result.mesh.vertices) points.emplace_back(v[0], v[1], v[2]);
    return points;
}

/// How many of @a points lie in no childless node's disc sphere (radius plus @a slack).
std::size_t uncovered(const SplatTree& tree, const std::vector<openvdb::Vec3d>& points, double slack) {
    std::size_t missing = 0;
    for (const openvdb::Vec3d& p : points) {
        bool covered = false;
        for (const SplatNode& n : tree.nodes)
            if (n.child_count == 0 && (p - vec(n.centre)).length() <= n.radius + slack) {
                covered = true;
                break;
            }
        missing += !covered;
    }
    return missing;
}

std::string file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(SplatTree, FinestSplatsLieOnTheSphereFacingOut) {
    const SplatTree tree = build_splat_tree(*sphere_grid(), sphere_options(0));
    ASSERT_FALSE(tree.nodes.empty());
    EXPECT_EQ(tree.nodes[0].level, kSplatRootLevel);
    // A chord of half-length h/2 (h = kVoxel) leaves a circle of radius R by (h/2)^2 / (2R).
    const double kInterpolation = kVoxel * kVoxel / (8 * kRadius);
    std::size_t finest = 0;
    double tilt_sum = 0;
    for (const SplatNode& n : tree.nodes) {
        if (n.child_count != 0) continue;
        ++finest;
        EXPECT_EQ(n.level, 0);  // tolerance 0: nothing collapsed
        const openvdb::Vec3d offset = vec(n.centre) - kCentre;
        // The centre is the mean of crossings on a cap of radius n.radius: it lies inside the
        // sphere by at most the cap's height r^2 / (2R); the crossings themselves are off the
        // sphere by the linear interpolation of the distance along an edge, kInterpolation.
        EXPECT_NEAR(offset.length(), kRadius, n.radius * n.radius / (2 * kRadius) + kInterpolation);
        // The normals over that cap turn by r / R; the least-squares normal lies among them,
        // tilted by the crossings' interpolation error d across their spread r (2 d / r).
        const std::array<float, 3> radial{float(offset.x() / offset.length()), float(offset.y() / offset.length()),
                                          float(offset.z() / offset.length())};
        const double tilt = angle(n.normal, radial);
        EXPECT_LE(tilt, n.radius / kRadius + 2 * kInterpolation / n.radius + 0.01);
        tilt_sum += tilt;
        // A 2^3-voxel cube's closed box: no crossing farther than its diagonal.
        EXPECT_LE(n.radius, 2 * std::sqrt(3.0) * kVoxel + 1e-5);
    }
    // About the sphere's area over a cube face per finest splat (4 pi 20^2 / 2^2 ~ 1257 in voxels).
    EXPECT_GT(finest, 600u);
    EXPECT_LT(finest, 3000u);
    EXPECT_LT(tilt_sum / finest, 0.05);  // on average well within the sphere's turn over a cube (~0.09)
}

TEST(SplatTree, FinestSplatsCoverEveryMarchingCubesVertex) {
    const auto grid = sphere_grid();
    const std::vector<openvdb::Vec3d> vertices = mc_vertices(*grid);
    ASSERT_GT(vertices.size(), 1000u);
    for (double tolerance : {0.0, 0.1, 0.5}) {
        // Slack: float rounding of centres and radii (world coordinates of size ~15).
        EXPECT_EQ(uncovered(build_splat_tree(*grid, sphere_options(tolerance)), vertices, 1e-4), 0u) << tolerance;
    }
}

TEST(SplatTree, InnerNodesEncloseTheirChildren) {
    const SplatTree tree = build_splat_tree(*sphere_grid(), sphere_options());
    std::size_t inner = 0;
    for (const SplatNode& n : tree.nodes) {
        for (std::uint32_t c = n.first_child; c < n.first_child + n.child_count; ++c) {
            const SplatNode& child = tree.nodes[c];
            ++inner;
            EXPECT_EQ(child.level + 1, n.level == kSplatRootLevel ? kSplatRootLevel : n.level);
            // The cone holds the child's normal and its whole cone; float slack 1e-5 rad.
            EXPECT_LE(std::min(angle(n.normal, child.normal) + child.cone, kPi), n.cone + 1e-5);
            EXPECT_LE((vec(child.centre) - vec(n.centre)).length() + child.radius, n.radius + 1e-4);
        }
    }
    EXPECT_EQ(inner + 1, tree.nodes.size());  // breadth-first: every node but the root is a child once
    // The whole closed sphere: the root's cone opens to (nearly) every direction.
    EXPECT_GT(tree.nodes[0].cone, 3.0);
}

TEST(SplatTree, CoplanarChildrenCollapseWithinTheTolerance) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(-4.0f);
    auto accessor = grid->getAccessor();
    for (int z = 0; z < 32; ++z)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) accessor.setValue(openvdb::Coord(x, y, z), float(13.3 - z - 0.2 * x));
    // Counted away from the block's sides, where the inside meets the background (edges and
    // corners, not coplanar).
    const auto levels = [&](double tolerance) {
        std::array<std::size_t, kSplatRootLevel + 1> count{};
        for (const SplatNode& n : build_splat_tree(*grid, sphere_options(tolerance)).nodes)
            if (n.centre[0] > 8 && n.centre[0] < 24 && n.centre[1] > 8 && n.centre[1] < 24) ++count[n.level];
        return count;
    };
    const auto kept = levels(0), collapsed = levels(0.1);
    EXPECT_GT(kept[0], 30u);
    EXPECT_EQ(collapsed[0], 0u);  // a plane: every finest and middle child within any tolerance
    EXPECT_EQ(collapsed[1], 0u);
    EXPECT_EQ(collapsed[kSplatLeafLevel], kept[kSplatLeafLevel]);  // never above leaf level
}

TEST(SplatTree, SameTreeForOneAndTwoThreads) {
    const auto grid = sphere_grid();
    test::ScratchDir dir;
    tbb::task_arena(1).execute([&] { write_splat_file(build_splat_tree(*grid, sphere_options()), dir / "one.splat"); });
    tbb::task_arena(2).execute([&] { write_splat_file(build_splat_tree(*grid, sphere_options()), dir / "two.splat"); });
    const std::string one = file_bytes(dir / "one.splat");
    EXPECT_GT(one.size(), 1000u);
    EXPECT_EQ(one, file_bytes(dir / "two.splat"));
}

TEST(SplatFile, RoundTripWithinItsQuantisation) {
    const auto grid = sphere_grid();
    const SplatTree tree = build_splat_tree(*grid, sphere_options());
    test::ScratchDir dir;
    SplatTree with_grid = tree;
    with_grid.grid = SplatGridId{123456789, "0123abcd", 0, 0xFEEDFACEull};
    write_splat_file(with_grid, dir / "sphere.splat");
    // The header (70 bytes and the checksum's 8), 12 bytes a node, 2 a childless node's weight.
    EXPECT_EQ(std::filesystem::file_size(dir / "sphere.splat"), 70 + 8 + 12 * tree.nodes.size() + 2 * tree.leaf_count());
    const SplatTree read = read_splat_file(dir / "sphere.splat");
    ASSERT_EQ(read.nodes.size(), tree.nodes.size());
    EXPECT_EQ(read.grid, with_grid.grid);
    EXPECT_EQ(read.iso, tree.iso);
    EXPECT_EQ(read.inside, tree.inside);
    EXPECT_FLOAT_EQ(read.tolerance, tree.tolerance);
    // The box of centres is the sphere's (20 + a bit world units): 16-bit steps of ~3e-4.
    const double step = 2 * (kRadius + 1) / 65535;
    for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
        const SplatNode &a = tree.nodes[i], &b = read.nodes[i];
        EXPECT_EQ(a.level, b.level);
        EXPECT_EQ(a.child_count, b.child_count);
        EXPECT_EQ(a.first_child, b.first_child);
        EXPECT_EQ(a.weight, b.weight);  // kept exactly: the close-up's estimate of triangles
        EXPECT_LE((vec(a.centre) - vec(b.centre)).length(), step);
        EXPECT_GE(b.radius, a.radius);
        EXPECT_LE(b.radius, a.radius + 4 * step);
        EXPECT_LE(angle(a.normal, b.normal), detail::kSplatNormalRounding);
        EXPECT_GE(b.cone, a.cone);
    }
    EXPECT_EQ(uncovered(read, mc_vertices(*grid), 1e-4), 0u);  // still covering after rounding
}

TEST(SplatFile, NormalRoundingStaysWithinItsBound) {
    std::mt19937 rng(7);
    std::normal_distribution<float> gauss;
    double worst = 0;
    for (int i = 0; i < 100000; ++i) {
        openvdb::Vec3d v(gauss(rng), gauss(rng), gauss(rng));
        v.normalize();
        const std::array<float, 3> n{float(v.x()), float(v.y()), float(v.z())};
        worst = std::max(worst, angle(n, detail::decode_splat_normal(detail::encode_splat_normal(n))));
    }
    EXPECT_LE(worst, detail::kSplatNormalRounding);
    EXPECT_GT(worst, detail::kSplatNormalRounding / 4);  // the bound is not loose by much
}

TEST(SplatFile, DamagedFilesAreRejectedNamingTheField) {
    test::ScratchDir dir;
    write_splat_file(build_splat_tree(*sphere_grid(), sphere_options()), dir / "sphere.splat");
    std::string bytes = file_bytes(dir / "sphere.splat");
    const auto expect_error = [&](const std::string& content, const std::string& field) {
        std::ofstream(dir / "bad.splat", std::ios::binary) << content;
        try {
            read_splat_file(dir / "bad.splat");
            ADD_FAILURE() << "no error for " << field;
        } catch (const FormatError& e) {
            EXPECT_NE(std::string(e.what()).find("bad.splat: " + field), std::string::npos) << e.what();
        }
    };
    expect_error(bytes.substr(0, bytes.size() - 5), "size");
    expect_error("NOTSPLAT" + bytes.substr(8), "header");
    std::string wrong_count = bytes;
    wrong_count[12] = char(wrong_count[12] + 1);  // the root's child count
    expect_error(wrong_count, "");
    EXPECT_THROW(read_splat_file(dir / "missing.splat"), Error);
}

/// @a unbounded without the levels under @a finest (breadth-first, a level's nodes come after
/// those above: the tree cut short), the nodes of level @a finest made childless.
std::vector<SplatNode> pruned(const SplatTree& unbounded, int finest) {
    std::vector<SplatNode> nodes;
    for (const SplatNode& node : unbounded.nodes)
        if (node.level >= finest) nodes.push_back(node);
    return nodes;
}

void expect_pruned_at(const SplatTree& bounded, const SplatTree& unbounded, int finest) {
    EXPECT_EQ(int(bounded.finest_kept), finest);
    const std::vector<SplatNode> expected = pruned(unbounded, finest);
    ASSERT_EQ(bounded.nodes.size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const SplatNode &got = bounded.nodes[i], &want = expected[i];
        test::expect_same_splat(got, want, i);
        if (want.level == finest) {
            EXPECT_EQ(got.child_count, 0u) << i;
        } else {
            EXPECT_EQ(got.child_count, want.child_count) << i;
            EXPECT_EQ(got.first_child, want.first_child) << i;
        }
    }
}

/// SplatOptions::max_bytes (view --memory): the tree built by region within it is the unbounded
/// tree with its finest levels cut off, the fewest that fit at kSplatBuildBytesPerNode a node;
/// a bound below a splat per cell is an error. The sphere spans 8 of the 128^3 nodes read one
/// at a time, so pruning is decided between them, once the first nodes' levels are in.
TEST(SplatTree, ABoundPrunesTheFinestLevelsOfTheUnboundedTree) {
    const auto regions = grid_regions_in_memory(sphere_grid());
    ASSERT_GT(regions->nodes().size(), 1u);
    const SplatTree unbounded = build_splat_tree(*regions, sphere_options());
    EXPECT_EQ(unbounded.finest_kept, 0);
    SplatOptions options = sphere_options();
    options.max_bytes = unbounded.nodes.size() * kSplatBuildBytesPerNode;
    expect_pruned_at(build_splat_tree(*regions, options), unbounded, 0);  // fits as it is
    for (int finest = 1; finest <= kSplatLeafLevel; ++finest) {
        const std::uint64_t kept = pruned(unbounded, finest).size();
        ASSERT_LT(kept, pruned(unbounded, finest - 1).size());  // each level holds nodes
        options.max_bytes = kept * kSplatBuildBytesPerNode;
        expect_pruned_at(build_splat_tree(*regions, options), unbounded, finest);
        options.max_bytes = pruned(unbounded, finest - 1).size() * kSplatBuildBytesPerNode - 1;  // a byte short of the level below
        expect_pruned_at(build_splat_tree(*regions, options), unbounded, finest);
    }
    options.max_bytes = pruned(unbounded, kSplatLeafLevel).size() * kSplatBuildBytesPerNode - 1;
    EXPECT_THROW(build_splat_tree(*regions, options), Error);
}

TEST(SplatTree, NegativeToleranceIsAUsageError) {
    EXPECT_THROW(build_splat_tree(*sphere_grid(), sphere_options(-1)), UsageError);
}

}  // namespace
}  // namespace vdbmesh
