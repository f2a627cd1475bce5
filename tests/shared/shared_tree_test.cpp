// The shared tree and its operations against their plain references (issue 14), on random
// grids (repeated leaves planted on purpose, tiles at every level) and on periodic lattices.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "same_triangles.h"
#include "shared_test_util.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/lattice.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {
namespace {

Mesh plain_mc(const openvdb::FloatGrid& grid) {
    MeshOptions options;
    options.method = MeshMethod::mc;
    options.iso = 0.0;
    options.inside = Inside::below;
    return mesh_grid(grid, options).mesh;
}

LatticeOptions small_gyroid() {
    LatticeOptions o;
    o.kind = LatticeKind::gyroid;
    o.voxel = 0.125;
    o.period = 2.0;      // 16 voxels
    o.thickness = 0.5;   // 4 voxels
    o.box = {8, 8, 8};   // 64 voxels
    return o;
}

/// The same field with every shortcut (periodic keys) turned off: the unshared evaluation.
class NoShortcuts final : public LeafField {
public:
    explicit NoShortcuts(const LeafField& f) : f_(f) {}
    float background() const override { return f_.background(); }
    double voxel_size() const override { return f_.voxel_size(); }
    std::array<Coord3, 2> bounds() const override { return f_.bounds(); }
    void evaluate(const Coord3& o, SharedLeaf& leaf) const override { f_.evaluate(o, leaf); }

private:
    const LeafField& f_;
};

bool same_tree(const SharedTree& a, const SharedTree& b) {
    if (a.tiles.size() != b.tiles.size() || a.leaves.size() != b.leaves.size() || a.nodes1.size() != b.nodes1.size() ||
        a.nodes2.size() != b.nodes2.size() || a.root.size() != b.root.size())
        return false;
    for (std::size_t i = 0; i < a.tiles.size(); ++i)
        if (std::memcmp(&a.tiles[i].value, &b.tiles[i].value, 4) != 0 || a.tiles[i].active != b.tiles[i].active) return false;
    for (std::size_t i = 0; i < a.leaves.size(); ++i)
        if (std::memcmp(&a.leaves[i], &b.leaves[i], sizeof(SharedLeaf)) != 0) return false;
    for (std::size_t i = 0; i < a.nodes1.size(); ++i)
        if (a.nodes1[i].children != b.nodes1[i].children) return false;
    for (std::size_t i = 0; i < a.nodes2.size(); ++i)
        if (a.nodes2[i].children != b.nodes2[i].children) return false;
    for (std::size_t i = 0; i < a.root.size(); ++i)
        if (a.root[i].origin != b.root[i].origin || a.root[i].ref != b.root[i].ref) return false;
    return true;
}

TEST(SharedTree, RandomGridRoundTripsAndSharesCopies) {
    for (unsigned seed : {1u, 2u, 3u}) {
        const auto grid = random_grid(seed);
        const SharedTree tree = build_shared_tree(*grid);
        const SharedStats stats = shared_stats(tree);
        EXPECT_EQ(stats.represented[0], grid->tree().leafCount());
        EXPECT_LT(stats.stored[0], stats.represented[0]);  // copies are stored once
        EXPECT_EQ(stats.active_voxels, grid->tree().activeVoxelCount());
        expect_same_grid(*grid, *to_float_grid(tree));
    }
}

TEST(SharedTree, PeriodicLatticeEqualsUnsharedEvaluation) {
    const auto field = make_lattice_field(small_gyroid());
    const SharedTree shared = build_shared_tree(*field);
    const SharedTree plain = build_shared_tree(NoShortcuts(*field));
    EXPECT_TRUE(same_tree(shared, plain));  // the periodic keys never change a voxel
    const SharedStats stats = shared_stats(shared);
    EXPECT_LE(stats.stored[0] * 4, stats.represented[0]);
    // The tree of the expanded grid is the same tree again.
    EXPECT_TRUE(same_tree(shared, build_shared_tree(*to_float_grid(shared))));
}

TEST(SharedTree, SameTreeForAnyThreadCount) {
    const auto field = make_lattice_field(small_gyroid());
    SharedTree one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = build_shared_tree(*field);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 4);
        two = build_shared_tree(*field);
    }
    EXPECT_TRUE(same_tree(one, two));
    const auto grid = random_grid(7);
    SharedTree a, b;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        a = build_shared_tree(*grid);
    }
    b = build_shared_tree(*grid);
    EXPECT_TRUE(same_tree(a, b));
}

TEST(SharedOps, SameResultsForAnyThreadCount) {
    const SharedTree tree = build_shared_tree(*random_grid(5));
    const SharedTree lattice = build_shared_tree(*make_lattice_field(small_gyroid()));
    struct Results {
        Mesh mesh;
        double volume, area;
        std::uint64_t components;
        std::size_t parts;
    };
    auto run = [&](int threads, const SharedTree& t) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return Results{shared_marching_cubes(t), shared_volume(t), shared_area(t), shared_components(t), shared_marching_cubes_instanced(t).parts.size()};
    };
    for (const SharedTree* t : {&tree, &lattice}) {
        const Results one = run(1, *t), two = run(2, *t);
        EXPECT_EQ(one.mesh.vertices, two.mesh.vertices);
        EXPECT_EQ(one.mesh.triangles, two.mesh.triangles);
        EXPECT_EQ(one.volume, two.volume);
        EXPECT_EQ(one.area, two.area);
        EXPECT_EQ(one.components, two.components);
        EXPECT_EQ(one.parts, two.parts);
    }
}

TEST(SharedOps, CountAndVolumeMatchPlain) {
    for (unsigned seed : {1u, 2u}) {
        const auto grid = random_grid(seed);
        const SharedTree tree = build_shared_tree(*grid);
        EXPECT_EQ(shared_active_voxels(tree), plain_active_voxels(*grid));
        const double v = plain_volume(*grid);
        EXPECT_NEAR(shared_volume(tree), v, 1e-9 * v);
    }
    const SharedTree tree = build_shared_tree(*make_lattice_field(small_gyroid()));
    const auto grid = to_float_grid(tree);
    EXPECT_EQ(shared_active_voxels(tree), plain_active_voxels(*grid));
    const double v = plain_volume(*grid);
    EXPECT_NEAR(shared_volume(tree), v, 1e-9 * v);
}

TEST(SharedOps, MarchingCubesIsPlainMarchingCubes) {
    std::vector<openvdb::FloatGrid::Ptr> grids = {random_grid(1), random_grid(4)};
    grids.push_back(to_float_grid(build_shared_tree(*make_lattice_field(small_gyroid()))));
    LatticeOptions p = small_gyroid();
    p.kind = LatticeKind::schwarz_p;
    p.thickness.reset();
    p.level = 0.3;
    grids.push_back(to_float_grid(build_shared_tree(*make_lattice_field(p))));
    for (const auto& grid : grids) {
        const SharedTree tree = build_shared_tree(*grid);
        const Mesh plain = plain_mc(*grid);
        const Mesh shared = shared_marching_cubes(tree);
        ASSERT_FALSE(plain.triangles.empty());
        EXPECT_EQ(shared.triangles.size(), plain.triangles.size());
        EXPECT_EQ(shared.vertices.size(), plain.vertices.size());
        EXPECT_TRUE(test::same_triangles(shared, plain));
        const double area = mesh_integrals(plain).area;
        EXPECT_NEAR(shared_area(tree), area, 1e-5 * area);
        // The instanced form places the same number of triangles.
        const InstancedMesh inst = shared_marching_cubes_instanced(tree);
        std::size_t placed = 0;
        for (const auto& i : inst.instances) placed += inst.parts[i.part].triangles.size();
        EXPECT_EQ(placed, plain.triangles.size());
        EXPECT_LT(inst.parts.size(), inst.instances.size() + 1);
    }
}

TEST(SharedOps, ComponentsMatchPlain) {
    // Random grids: values in [-1, 1] make many small components.
    for (unsigned seed : {1u, 2u, 3u}) {
        const auto grid = random_grid(seed);
        const SharedTree tree = build_shared_tree(*grid);
        EXPECT_EQ(shared_components(tree), plain_components(*grid)) << "seed " << seed;
    }
    for (LatticeKind kind : {LatticeKind::gyroid, LatticeKind::bcc_struts, LatticeKind::schwarz_p}) {
        LatticeOptions o = small_gyroid();
        o.kind = kind;
        if (kind == LatticeKind::schwarz_p) {
            o.thickness.reset();
            o.level = 0.5;
        }
        const SharedTree tree = build_shared_tree(*make_lattice_field(o));
        const auto grid = to_float_grid(tree);
        const std::uint64_t n = plain_components(*grid);
        EXPECT_GE(n, 1u);
        EXPECT_EQ(shared_components(tree), n);
    }
}

TEST(SharedOps, ComponentsOfABoxedLatticeFromOnePeriod) {
    // The logic of the bench's 4096^3 figure at sizes where the whole box can be labelled voxel
    // by voxel: the components derived from one plainly labelled period cell (its versions cut
    // short by the box faces, joined across the faces between cells) are those of the whole.
    struct Case {
        LatticeKind kind;
        int box, period;
        double thickness;
        bool cut_pieces;  ///< whether the box faces cut pieces off the lattice (found by a first run)
    };
    for (const Case& c : {Case{LatticeKind::gyroid, 256, 64, 4, true}, Case{LatticeKind::bcc_struts, 100, 24, 6, false},
                          Case{LatticeKind::diamond, 150, 32, 3, false}}) {
        LatticeOptions o;
        o.kind = c.kind;
        o.voxel = 1.0;
        o.period = c.period;
        o.thickness = c.thickness;
        o.box = {double(c.box), double(c.box), double(c.box)};
        const auto field = make_lattice_field(o);
        const SharedTree tree = build_shared_tree(*field);
        const auto grid = to_float_grid(tree);
        // The box [0, box] keeps the voxels strictly inside it: 1 .. box - 1.
        const CropComponents crop = plain_components_from_crop(*field, {Coord3{1, 1, 1}, Coord3{c.box - 1, c.box - 1, c.box - 1}}, c.period);
        const std::uint64_t whole = plain_components(*grid);
        EXPECT_EQ(crop.components, whole) << "box " << c.box;
        EXPECT_EQ(shared_components(tree), whole) << "box " << c.box;
        std::uint64_t inside = 0;
        for (auto it = grid->tree().cbeginValueAll(); it; ++it) {
            if (*it < 0) inside += it.getVoxelCount();
        }
        std::uint64_t counted = 0;
        for (std::uint64_t v : crop.voxels) counted += v;
        EXPECT_EQ(counted, inside) << "box " << c.box;
        EXPECT_TRUE(std::is_sorted(crop.voxels.rbegin(), crop.voxels.rend()));
        EXPECT_GE(crop.crop_components, crop.crop_components_periodic);
        // Where the box cuts pieces off, the unbounded lattice (one period, opposite faces
        // touching) has fewer components than the box: the reference must count the cut cells.
        if (c.cut_pieces) EXPECT_GT(whole, crop.crop_components_periodic);
    }
}

TEST(Lattice, BadOptionsNameTheOption) {
    LatticeOptions o = small_gyroid();
    o.voxel = -1;
    try {
        check_lattice_options(o);
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("--voxel"), std::string::npos);
    }
    o = small_gyroid();
    o.level = 0.1;
    EXPECT_THROW(check_lattice_options(o), UsageError);  // both thickness and level
    o = small_gyroid();
    o.thickness = 5.0;
    EXPECT_THROW(check_lattice_options(o), UsageError);  // thicker than the period
    EXPECT_THROW(parse_lattice_kind("kelvin"), UsageError);
}

TEST(Lattice, SheetHasTheRequestedThickness) {
    // Along a line through the sheet, the inside run is about the thickness long.
    LatticeOptions o = small_gyroid();
    // On the surface g = 0 the value is -t/2; at distance t/2 along the normal it is ~0.
    const double v = lattice_value(o, {0.0, 0.0, 0.0});  // g(0) = 0: mid-sheet
    EXPECT_NEAR(v, -*o.thickness / 2, 1e-12);
}

}  // namespace
}  // namespace vdbmesh
