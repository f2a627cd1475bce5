// analyze_mesh_stream() (check --memory, issue 28) against analyze_mesh() on the mesh read whole:
// the same figures, bit for bit, in every format, with runs small enough that every sort goes
// through its temporary file in many runs; and a limit too small refused with the smallest
// that works.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "test_data.h"
#include "smallest_limit.h"
#include "test_meshes.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh {
namespace {

/// Records per run: small enough that the meshes below sort in dozens of runs.
constexpr std::size_t kTinyRuns = 97;

/// Every figure both report, compared exactly: the streaming check sums the same triangles in
/// the same blocks, so even the integrals agree to the bit.
void expect_same_figures(const MeshAnalysis& whole, const MeshAnalysis& stream) {
    EXPECT_EQ(stream.triangles, whole.triangles);
    EXPECT_EQ(stream.vertices, whole.vertices);
    EXPECT_EQ(stream.unreferenced_vertices, whole.unreferenced_vertices);
    EXPECT_EQ(stream.edges, whole.edges);
    EXPECT_EQ(stream.boundary_edges, whole.boundary_edges);
    EXPECT_EQ(stream.boundary_loops, whole.boundary_loops);
    EXPECT_EQ(stream.nonmanifold_edges, whole.nonmanifold_edges);
    EXPECT_EQ(stream.nonmanifold_vertices, whole.nonmanifold_vertices);
    EXPECT_EQ(stream.misoriented_edges, whole.misoriented_edges);
    EXPECT_EQ(stream.components, whole.components);
    EXPECT_EQ(stream.euler_characteristic, whole.euler_characteristic);
    EXPECT_EQ(stream.genus, whole.genus);
    EXPECT_EQ(stream.closed, whole.closed);
    EXPECT_EQ(stream.repeated_vertex_faces, whole.repeated_vertex_faces);
    EXPECT_EQ(stream.zero_area_faces, whole.zero_area_faces);
    EXPECT_EQ(stream.degenerate_faces, whole.degenerate_faces);
    EXPECT_EQ(stream.area, whole.area);
    EXPECT_EQ(stream.volume, whole.volume);
    EXPECT_EQ(stream.centroid, whole.centroid);
    EXPECT_EQ(stream.inertia, whole.inertia);
    EXPECT_EQ(stream.outward, whole.outward);
    EXPECT_EQ(stream.min_angle_deg, whole.min_angle_deg);
    EXPECT_EQ(stream.small_angle_share, whole.small_angle_share);
    // Not counted in bounded mode: the clean verdict is the rest's.
    EXPECT_EQ(stream.self_intersecting_pairs, 0u);
    MeshAnalysis without_intersections = whole;
    without_intersections.self_intersecting_pairs = 0;
    EXPECT_EQ(stream.is_clean(), without_intersections.is_clean());
}

/// The cube with every defect the check counts: a hole (one triangle gone), a flipped
/// triangle, a fin on an edge (three faces on it), a repeated-vertex face, a zero-area face,
/// an unused vertex, and a second component: two tetrahedra sharing one vertex (two fans).
Mesh broken_mesh() {
    Mesh mesh = test::cube();
    mesh.triangles.erase(mesh.triangles.begin() + 5);       // a hole: {0, 5, 4} gone
    std::swap(mesh.triangles[2][1], mesh.triangles[2][2]);  // {4, 5, 7} flipped
    mesh.vertices.push_back({0.5f, -1, 0.5f});              // 8: the fin's tip
    mesh.triangles.push_back({0, 1, 8});                    // a third face on edge 0-1
    mesh.triangles.push_back({3, 3, 7});                    // repeated vertex
    mesh.vertices.push_back({2, 2, 2});                     // 9: collinear with 0 and 7
    mesh.triangles.push_back({0, 7, 9});                    // zero area
    mesh.vertices.push_back({-5, -5, -5});                  // 10: unused
    const Mesh tetra = test::tetrahedron();
    std::uint32_t shared = 0;  // the first tetrahedron's corner (1, 0, 0) is the second's (0, 0, 0)
    for (const float x : {4.0f, 5.0f}) {
        const auto base = std::uint32_t(mesh.vertices.size());
        std::array<std::uint32_t, 4> index{};
        for (std::uint32_t k = 0; k < 4; ++k) {
            if (k == 0 && shared != 0) {
                index[k] = shared;
                continue;
            }
            const auto& v = tetra.vertices[k];
            index[k] = std::uint32_t(mesh.vertices.size());
            mesh.vertices.push_back({v[0] + x, v[1], v[2]});
        }
        for (const auto& t : tetra.triangles) mesh.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
        shared = base + 1;
    }
    return mesh;
}

/// Writes @a mesh as @a name, checks it both ways and compares; returns the stream's result.
StreamCheck check_both(const Mesh& mesh, const test::ScratchDir& dir, const std::string& name, bool ascii,
                       std::size_t run_records = kTinyRuns) {
    const std::filesystem::path file = dir / name;
    write_mesh(mesh, file, {ascii, false});
    const StreamCheck stream = analyze_mesh_stream(file, {test::kPlenty, run_records});
    SCOPED_TRACE(name);
    expect_same_figures(analyze_mesh(read_mesh(file)), stream.analysis);
    return stream;
}

TEST(AnalyzeStreamTest, EveryFormatGivesTheWholeChecksFiguresInManyRuns) {
    const test::ScratchDir dir;
    for (const bool ascii : {false, true}) {
        const std::string kind = ascii ? "ascii" : "binary";
        for (const auto& [label, mesh] : {std::pair<std::string, Mesh>{"cube", test::cube()}, {"torus", test::torus(40, 24)},
                                          {"broken", broken_mesh()}}) {
            for (const char* extension : {".ply", ".stl", ".obj"}) {
                const StreamCheck check = check_both(mesh, dir, label + "_" + kind + extension, ascii);
                if (mesh.triangles.size() > 3 * kTinyRuns) EXPECT_GT(check.sorted_runs, 2u) << label << extension;
            }
        }
    }
}

TEST(AnalyzeStreamTest, BrokenMeshShowsEachDefect) {
    const test::ScratchDir dir;
    const MeshAnalysis r = check_both(broken_mesh(), dir, "broken.ply", false).analysis;
    EXPECT_FALSE(r.closed);
    EXPECT_EQ(r.boundary_edges, 8u);       // the hole's 3, the fin's 2, the zero-area face's 3
    EXPECT_EQ(r.nonmanifold_edges, 2u);    // 0-1 (the fin), 3-7 (the repeated-vertex face)
    EXPECT_EQ(r.misoriented_edges, 4u);    // 4-7, 7-5 (the flipped face), 0-1, 3-7
    EXPECT_EQ(r.repeated_vertex_faces, 1u);
    EXPECT_EQ(r.zero_area_faces, 1u);
    EXPECT_EQ(r.unreferenced_vertices, 1u);
    EXPECT_EQ(r.components, 2u);
    EXPECT_EQ(r.nonmanifold_vertices, 3u);  // 0 and 7 (the zero-area face hangs off them), the tetrahedra's shared corner
    EXPECT_FALSE(r.is_clean());
}

TEST(AnalyzeStreamTest, IntegralsAgreeBitForBitAcrossTheSummingBlocks) {
    // 2 x 128 x 80 = 20480 triangles: more than one block of 16384 (moments.h).
    const test::ScratchDir dir;
    const MeshAnalysis r = check_both(test::torus(128, 80), dir, "torus.ply", false, 4096).analysis;
    EXPECT_TRUE(r.is_clean());
    EXPECT_EQ(r.genus, 1);
}

TEST(AnalyzeStreamTest, SameFiguresForAnyThreadCount) {
    const test::ScratchDir dir;
    write_mesh(test::torus(40, 24), dir / "torus.stl");
    const StreamCheck many = analyze_mesh_stream(dir / "torus.stl", {test::kPlenty, kTinyRuns});
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    expect_same_figures(many.analysis, analyze_mesh_stream(dir / "torus.stl", {test::kPlenty, kTinyRuns}).analysis);
}

TEST(AnalyzeStreamTest, RealScanMeshGivesTheWholeChecksFigures) {
    VDBMESH_SHARED_DATA(zipper, "pointcloud_stanford_bunny_scans/reconstruction/bun_zipper.ply");
    const StreamCheck stream = analyze_mesh_stream(zipper, {test::kPlenty, 20000});
    expect_same_figures(analyze_mesh(read_mesh(zipper)), stream.analysis);
    EXPECT_GT(stream.sorted_runs, 10u);
    EXPECT_GT(stream.analysis.boundary_loops, 0u);  // the zippered scan has holes
}

TEST(AnalyzeStreamTest, LimitTooSmallIsRefusedWithTheSmallestThatWorks) {
    const test::ScratchDir dir;
    write_mesh(test::torus(40, 24), dir / "torus.ply");
    const auto analyze = [&](std::uint64_t limit) { return analyze_mesh_stream(dir / "torus.ply", {limit, 0}); };
    const std::uint64_t smallest = test::smallest_limit_named(analyze);
    ASSERT_NE(smallest, 0u);
    EXPECT_TRUE(analyze(smallest).analysis.is_clean());
}

TEST(AnalyzeStreamTest, BadFileIsTheReadersFormatError) {
    const test::ScratchDir dir;
    write_mesh(test::cube(), dir / "cube.ply", {true, false});
    std::filesystem::resize_file(dir / "cube.ply", std::filesystem::file_size(dir / "cube.ply") - 10);
    EXPECT_THROW(analyze_mesh_stream(dir / "cube.ply", {test::kPlenty, 0}), FormatError);
    EXPECT_THROW(analyze_mesh_stream(dir / "missing.stl", {test::kPlenty, 0}), FormatError);
}

/// Sets an environment variable for the test's life.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        ::setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (old_) ::setenv(name_, old_->c_str(), 1);
        else ::unsetenv(name_);
    }

private:
    const char* name_;
    std::optional<std::string> old_;
};

TEST(AnalyzeStreamTest, TemporaryFilesGoToTmpdirAndLeaveNothing) {
    const test::ScratchDir dir, temp;
    write_mesh(test::torus(40, 24), dir / "torus.stl");
    {
        const ScopedEnv tmpdir("TMPDIR", temp.path().string());
        EXPECT_GT(analyze_mesh_stream(dir / "torus.stl", {test::kPlenty, kTinyRuns}).sorted_runs, 2u);
    }
    EXPECT_TRUE(std::filesystem::is_empty(temp.path()));
    const ScopedEnv tmpdir("TMPDIR", (temp / "missing").string());
    try {
        analyze_mesh_stream(dir / "torus.stl", {test::kPlenty, kTinyRuns});
        FAIL() << "no temporary file, yet no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find((temp / "missing").string()), std::string::npos) << e.what();
    }
    // Everything in one run needs no file.
    EXPECT_EQ(analyze_mesh_stream(dir / "torus.stl", {test::kPlenty, 0}).sorted_runs, 0u);
}

}  // namespace
}  // namespace vdbmesh
