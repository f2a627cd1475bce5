// Deposition, etching and CSG on the shared tree against their plain references (the same
// per-voxel rule on the expanded grid), on random and periodic inputs; the deposition of a
// stepped wafer phantom measured against the exact offset and against OpenVDB's own offset.

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "shared_test_util.h"
#include "vdbmesh/lattice.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/shared_process.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {
namespace {

LatticeOptions periodic_gyroid() {
    LatticeOptions o;
    o.voxel = 0.125;
    o.period = 2.0;     // 16 voxels
    o.thickness = 0.5;  // 4 voxels
    o.box = {6, 6, 6};  // 48 voxels
    return o;
}

/// A level set with background 1 from random_grid's values (already within [-1, 1]).
std::vector<openvdb::FloatGrid::Ptr> inputs() {
    return {random_grid(11), random_grid(12), to_float_grid(build_shared_tree(*make_lattice_field(periodic_gyroid())))};
}

TEST(SharedProcess, DepositionIsPlainDeposition) {
    for (const auto& grid : inputs()) {
        const double h = grid->voxelSize()[0];
        const bool lattice = grid->background() != 1.0f;
        for (double voxels : lattice ? std::vector<double>{1.5, 9.0} : std::vector<double>{1.5, 3.0}) {  // 9: two passes
            const SharedTree shared = shared_deposit(build_shared_tree(*grid), voxels * h);
            expect_same_grid(*to_float_grid(shared), *plain_deposit(*grid, voxels * h));
        }
    }
}

/// A slab stop layer z in [zlo, zhi] (voxels), as a level set with background @a bg.
openvdb::FloatGrid::Ptr slab(int zlo, int zhi, double h, float bg, int extent) {
    auto grid = openvdb::FloatGrid::create(bg);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
    auto acc = grid->getAccessor();
    for (int x = -extent; x < extent; ++x)
        for (int y = -extent; y < extent; ++y)
            for (int z = zlo - 4; z <= zhi + 4; ++z) {
                const double d = std::max(double(zlo - z), double(z - zhi)) * h;
                const float v = float(std::clamp(d, -double(bg), double(bg)));
                if (std::abs(v) < bg) acc.setValue(openvdb::Coord(x, y, z), v);
                else if (v < 0) acc.setValueOff(openvdb::Coord(x, y, z), v);
            }
    return grid;
}

TEST(SharedProcess, EtchIsPlainEtch) {
    for (const auto& grid : inputs()) {
        const double h = grid->voxelSize()[0];
        const auto stop = slab(8, 10, h, grid->background(), 64);
        for (int sign : {1, -1}) {
            for (const openvdb::FloatGrid* s : {static_cast<const openvdb::FloatGrid*>(nullptr), static_cast<const openvdb::FloatGrid*>(stop.get())}) {
                const SharedTree shared = shared_etch(build_shared_tree(*grid), 2, sign, 5 * h, s);
                expect_same_grid(*to_float_grid(shared), *plain_etch(*grid, 2, sign, 5 * h, s));
            }
        }
        const SharedTree deep = shared_etch(build_shared_tree(*grid), 0, 1, 12 * h, nullptr);  // two passes
        expect_same_grid(*to_float_grid(deep), *plain_etch(*grid, 0, 1, 12 * h, nullptr));
    }
}

TEST(SharedProcess, CsgIsPlainCsg) {
    for (const auto& grid : inputs()) {
        const double h = grid->voxelSize()[0];
        const float half_width = grid->background() / float(h);
        const auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(float(12 * h), openvdb::Vec3f(float(10 * h)), float(h), half_width);
        ASSERT_FLOAT_EQ(sphere->background(), grid->background());
        for (CsgOp op : {CsgOp::unite, CsgOp::intersect, CsgOp::subtract}) {
            const SharedTree shared = shared_csg(build_shared_tree(*grid), *sphere, op);
            expect_same_grid(*to_float_grid(shared), *plain_csg(*grid, *sphere, op));
        }
    }
}

TEST(SharedProcess, SameTreeForAnyThreadCount) {
    const SharedTree in = build_shared_tree(*make_lattice_field(periodic_gyroid()));
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return shared_etch(shared_deposit(in, 0.25), 2, 1, 0.5, nullptr);
    };
    const SharedTree one = run(1), two = run(2);
    ASSERT_EQ(one.leaves.size(), two.leaves.size());
    for (std::size_t i = 0; i < one.leaves.size(); ++i) EXPECT_EQ(std::memcmp(&one.leaves[i], &two.leaves[i], sizeof(SharedLeaf)), 0);
    ASSERT_EQ(one.root.size(), two.root.size());
    EXPECT_EQ(one.nodes1.size(), two.nodes1.size());
    for (std::size_t i = 0; i < one.nodes1.size(); ++i) EXPECT_EQ(one.nodes1[i].children, two.nodes1[i].children);
}

TEST(SharedProcess, PeriodicDepositionComputesDistinctNeighbourhoodsOnly) {
    // Sharing survives: the deposited lattice still stores few distinct leaves.
    const SharedTree in = build_shared_tree(*make_lattice_field(periodic_gyroid()));
    const SharedTree out = shared_deposit(in, 2 * 0.125);
    const SharedStats s = shared_stats(out);
    EXPECT_LT(s.stored[0] * 3, s.represented[0]);
}

/// The stepped wafer phantom: a substrate z < 8 voxels with steps of 6, 12 and 18 voxels.
struct Wafer final : LeafField {
    double h = 1.0;
    float bg = 3.0f;
    static double box_sdf(const double p[3], const double lo[3], const double hi[3]) {
        double outside = 0, inside = -1e300;
        for (int a = 0; a < 3; ++a) {
            const double d = std::max(lo[a] - p[a], p[a] - hi[a]);
            outside += std::max(d, 0.0) * std::max(d, 0.0);
            inside = std::max(inside, d);
        }
        return inside > 0 ? std::sqrt(outside) : inside;
    }
    /// Exact outside the solid (a union of boxes: the smallest of their distances).
    static double sdf(const double p[3]) {
        const double boxes[4][2][3] = {{{0, 0, 0}, {96, 64, 8}}, {{16, 0, 8}, {80, 64, 14}}, {{32, 0, 14}, {64, 64, 20}}, {{44, 0, 20}, {52, 64, 26}}};
        double d = 1e300;
        for (const auto& b : boxes) d = std::min(d, box_sdf(p, b[0], b[1]));
        return d;
    }
    float background() const override { return bg; }
    double voxel_size() const override { return h; }
    std::array<Coord3, 2> bounds() const override { return {Coord3{-16, -16, -16}, Coord3{112, 80, 48}}; }
    void evaluate(const Coord3& o, SharedLeaf& leaf) const override {
        for (int i = 0; i < 512; ++i) {
            const double p[3] = {double(o[0] + (i >> 6)), double(o[1] + ((i >> 3) & 7)), double(o[2] + (i & 7))};
            const float v = float(std::clamp(sdf(p), -double(bg), double(bg)));
            const bool active = v > -bg && v < bg;
            leaf.values[i] = v;
            leaf.set_active(i, active);
        }
    }
};

TEST(SharedProcess, WaferDepositionIsThreeVoxelsFromTheOldSurfaceAndAgreesWithOpenVdb) {
    const Wafer wafer;
    const SharedTree in = build_shared_tree(wafer);
    const SharedTree out = shared_deposit(in, 3.0);
    const auto deposited = to_float_grid(out);
    MeshOptions mc;
    mc.method = MeshMethod::mc;
    mc.inside = Inside::below;
    const Mesh surface = mesh_grid(*deposited, mc).mesh;
    ASSERT_FALSE(surface.triangles.empty());
    double worst = 0;
    for (const auto& v : surface.vertices) {
        const double p[3] = {v[0], v[1], v[2]};
        worst = std::max(worst, std::abs(Wafer::sdf(p) - 3.0));
    }
    std::cout << "[ figures  ] wafer deposition 3 voxels: the new surface lies 3 +- " << worst << " voxels from the old\n";
    EXPECT_LE(worst, 0.5);
    // OpenVDB's own offset of the same input.
    auto openvdb_grid = to_float_grid(in);
    openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*openvdb_grid);
    filter.offset(-3.0f);
    const Mesh theirs = mesh_grid(*openvdb_grid, mc).mesh;
    openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> ours(*deposited);
    double disagreement = 0, their_worst = 0;
    for (const auto& v : theirs.vertices) {
        disagreement = std::max(disagreement, std::abs(double(ours.wsSample(openvdb::Vec3d(v[0], v[1], v[2])))));
        const double p[3] = {v[0], v[1], v[2]};
        their_worst = std::max(their_worst, std::abs(Wafer::sdf(p) - 3.0));
    }
    std::cout << "[ figures  ] OpenVDB LevelSetFilter::offset: 3 +- " << their_worst << " voxels; our level set at its surface: |value| <= "
              << disagreement << " voxels\n";
    EXPECT_LE(disagreement, 0.5);
}

}  // namespace
}  // namespace vdbmesh
