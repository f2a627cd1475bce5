// mesh_to_budget() (`vdbmesh mesh --triangles N`): at most N triangles, exactly the even count
// at or below N when the decimator finishes the budget, every guarantee judged by CGAL
// (cgal_judge.h) on a phantom and a real CT at a few budgets, the same mesh for any thread
// count, the budgets it cannot meet as asked.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <vector>

#include "cgal_judge.h"
#include "phantom_grid.h"
#include "shared_scan.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesh_budget.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh::test {
namespace {

MeshOptions at_iso(double iso) {
    MeshOptions options;
    options.iso = iso;
    return options;
}

std::size_t triangles_at(const openvdb::FloatGrid& grid, double iso, double error) {
    MeshOptions options = at_iso(iso);
    options.error = error;
    return mesh_grid(grid, options).mesh.triangles.size();
}

/// Meshes @a grid to each share of its kBudgetBaseError mesh's triangles and checks the budget and the
/// guarantees: a closed mesh has an even count, and each collapse removes two triangles, so a
/// decimated budget ends at N or N - 1.
void expect_budgets_kept(const openvdb::FloatGrid& grid, double iso, const std::vector<double>& shares) {
    const std::size_t base = triangles_at(grid, iso, kBudgetBaseError);
    for (const double share : shares) {
        const auto budget = std::size_t(share * double(base)) | 1;  // odd: "at most" is N - 1 here
        BudgetReport report;
        const Mesh mesh = mesh_to_budget(grid, at_iso(iso), budget, &report).mesh;
        const std::string label = "budget " + std::to_string(budget) + " of " + std::to_string(base);
        EXPECT_EQ(mesh.triangles.size(), budget - 1) << label;
        EXPECT_EQ(report.error, kBudgetBaseError) << label;
        EXPECT_EQ(report.meshed_triangles, base) << label;
        EXPECT_GT(report.decimate.collapses, 0u) << label;
        const CgalVerdict verdict = judge_with_cgal(mesh);
        EXPECT_TRUE(verdict.clean()) << label << ": " << verdict.describe();
    }
}

TEST(MeshBudgetTest, PhantomKeepsTheBudgetAndTheGuarantees) {
    const auto grid = phantom_scan_grid(phantom_preset("cube-minus-sphere", {48, 48, 48}));
    expect_budgets_kept(*grid, 0.5, {0.9, 0.5, 0.2});
}

// The CThead (256 x 256 x 113, bone at 600.5): thin walls and specks, where DC keeps unit cells.
TEST(MeshBudgetTest, RealCtKeepsTheBudgetAndTheGuarantees) {
    openvdb::FloatGrid::Ptr grid;
    ASSERT_NO_FATAL_FAILURE(convert_shared_scan(shared_scan("CThead"), grid));
    if (!grid) return;  // skipped: the shared data is missing
    expect_budgets_kept(*grid, 600.5, {0.72, 0.4});
}

// A budget the kBudgetBaseError mesh fits: the most accurate of the smaller errors' meshes that still
// fits, with no decimation; above the error-0 mesh, that mesh (the caller refuses it).
TEST(MeshBudgetTest, RoomyBudgetTakesTheSmallestErrorThatFits) {
    const auto grid = phantom_scan_grid(phantom_preset("torus", {48, 48, 48}));
    const std::size_t at_quarter = triangles_at(*grid, 0.5, 0.25), at_zero = triangles_at(*grid, 0.5, 0);
    ASSERT_LT(at_quarter, at_zero);
    BudgetReport report;
    Mesh mesh = mesh_to_budget(*grid, at_iso(0.5), at_quarter, &report).mesh;
    EXPECT_EQ(report.error, 0.25);
    EXPECT_EQ(mesh.triangles.size(), at_quarter);
    EXPECT_EQ(report.decimate.collapses, 0u);
    mesh = mesh_to_budget(*grid, at_iso(0.5), at_zero + 10, &report).mesh;
    EXPECT_EQ(report.error, 0);
    EXPECT_EQ(mesh.triangles.size(), at_zero);
}

// Many specks (noise): the decimator stops where every collapse left would break a guarantee
// (a speck is at least a tetrahedron); the mesh where it stopped is returned, over the budget.
TEST(MeshBudgetTest, BudgetBelowWhatTheDecimatorReachesGivesWhereItStopped) {
    PhantomSpec spec = phantom_preset("sphere", {32, 32, 32});
    spec.noise_sigma = 0.2;
    const auto grid = phantom_scan_grid(spec);
    const Mesh mesh = mesh_to_budget(*grid, at_iso(0.5), 4).mesh;
    EXPECT_GT(mesh.triangles.size(), 4u);
    EXPECT_TRUE(judge_with_cgal(mesh).clean());
}

TEST(MeshBudgetTest, SameMeshForAnyThreadCount) {
    PhantomSpec spec = phantom_preset("cube-minus-sphere", {48, 48, 48});
    spec.noise_sigma = 0.2;  // rejected collapses of every kind
    const auto grid = phantom_scan_grid(spec);
    const std::size_t budget = triangles_at(*grid, 0.5, kBudgetBaseError) / 2;
    const auto mesh_on = [&](int threads) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        return mesh_to_budget(*grid, at_iso(0.5), budget).mesh;
    };
    const Mesh one = mesh_on(1), two = mesh_on(2);
    EXPECT_EQ(one.vertices, two.vertices);
    EXPECT_EQ(one.triangles, two.triangles);
}

TEST(MeshBudgetTest, ZeroBudgetAndOpenBoundaryAreRefused) {
    const auto grid = phantom_scan_grid(phantom_preset("sphere", {16, 16, 16}));
    EXPECT_THROW(mesh_to_budget(*grid, at_iso(0.5), 0), UsageError);
    MeshOptions open = at_iso(0.5);
    open.open_boundary = true;
    EXPECT_THROW(mesh_to_budget(*grid, open, 100), UsageError);
}

}  // namespace
}  // namespace vdbmesh::test
