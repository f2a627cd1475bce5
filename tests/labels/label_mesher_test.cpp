// The multi-label mesher (labels.h): every label's mesh closed, manifold, outward and free of
// self-intersections, no crossings between labels, walls shared, volumes kept, judged by CGAL
// (label_judge.h) on synthetic maps built to hit the non-manifold configurations and on the
// AAL and JHU atlases (a crop here; the whole maps under VDBMESH_FULL=1).

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

#include <tbb/global_control.h>

#include "label_judge.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/labels.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

using test::judge_label_surface;

LabelVolume blank_volume(std::array<std::int64_t, 3> dims) {
    LabelVolume v;
    v.header.dims = dims;
    v.header.path = "synthetic";
    v.labels.assign(std::size_t(dims[0] * dims[1] * dims[2]), 0);
    return v;
}

std::uint16_t& at(LabelVolume& v, std::int64_t x, std::int64_t y, std::int64_t z) {
    return v.labels[std::size_t((z * v.header.dims[1] + y) * v.header.dims[0] + x)];
}

LabelVolume load_atlas(const std::filesystem::path& path) {
    auto reader = open_volume(path);
    return read_label_volume(*reader);
}

/// The box [lo, lo + size) of @a v (same spacing and affine).
LabelVolume crop(const LabelVolume& v, std::array<std::int64_t, 3> lo, std::array<std::int64_t, 3> size) {
    LabelVolume c = blank_volume(size);
    c.header.index_to_world = v.header.index_to_world;
    for (std::int64_t z = 0; z < size[2]; ++z)
        for (std::int64_t y = 0; y < size[1]; ++y)
            for (std::int64_t x = 0; x < size[0]; ++x) at(c, x, y, z) = v.at(lo[0] + x, lo[1] + y, lo[2] + z);
    return c;
}

bool full_run() {
    const char* full = std::getenv("VDBMESH_FULL");
    return full && std::string(full) == "1";
}

TEST(LabelMesherTest, TwoBoxesShareOneWall) {
    LabelVolume v = blank_volume({12, 10, 10});
    for (std::int64_t z = 2; z < 8; ++z)
        for (std::int64_t y = 2; y < 8; ++y)
            for (std::int64_t x = 2; x < 10; ++x) at(v, x, y, z) = x < 6 ? 1 : 2;
    const LabelSurface s = mesh_labels(v);
    EXPECT_EQ(s.labels, (std::vector<std::uint32_t>{1, 2}));
    EXPECT_EQ(s.relabelled_voxels, 0u);
    judge_label_surface(s, v, false);
    // The wall between them: 6 x 6 voxel faces, two triangles each, met by both labels.
    std::size_t shared = 0;
    for (const auto& sides : s.sides) shared += sides[0] != 0 && sides[1] != 0;
    EXPECT_EQ(shared, 72u);
}

/// Random labels (a few values, blobby and speckled) meet in every kind of corner: checkerboards,
/// diagonal voxels, three and more labels round an edge.
TEST(LabelMesherTest, RandomMapsAreManifoldAndFreeOfCrossings) {
    std::mt19937 random(31);
    for (int trial = 0; trial < 6; ++trial) {
        LabelVolume v = blank_volume({14, 13, 12});
        const int labels = 2 + trial % 4;
        for (std::uint16_t& l : v.labels) l = std::uint16_t(random() % std::uint32_t(labels + 1));
        SCOPED_TRACE("trial " + std::to_string(trial));
        const LabelSurface s = mesh_labels(v);
        judge_label_surface(s, v, false);
    }
}

TEST(LabelMesherTest, TheBackgroundAndUnlistedLabelsAreOutside) {
    LabelVolume v = blank_volume({10, 10, 10});
    for (std::int64_t x = 2; x < 8; ++x) at(v, x, 4, 4) = at(v, x, 5, 4) = std::uint16_t(x < 5 ? 3 : 7);
    LabelMeshOptions options;
    options.labels = {7, 9};  // 9 is not in the map: no mesh for it
    const LabelSurface s = mesh_labels(v, options);
    EXPECT_EQ(s.labels, (std::vector<std::uint32_t>{7}));
    for (const auto& sides : s.sides) EXPECT_TRUE(sides[0] == 7 || sides[1] == 7);
    judge_label_surface(s, v, false);
}

TEST(LabelMesherTest, SameBytesForAnyThreadCount) {
    std::mt19937 random(7);
    LabelVolume v = blank_volume({20, 18, 16});
    for (std::uint16_t& l : v.labels) l = std::uint16_t(random() % 3);
    const auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        return mesh_labels(v);
    };
    const LabelSurface one = run(1), two = run(2);
    EXPECT_EQ(one.mesh.vertices, two.mesh.vertices);
    EXPECT_EQ(one.mesh.triangles, two.mesh.triangles);
    EXPECT_EQ(one.sides, two.sides);
}

TEST(LabelMesherTest, AalCropIsCleanConformingAndKeepsVolumes) {
    VDBMESH_SHARED_DATA(path, "nifti_mricron_label_atlases/aal.nii.gz");
    const LabelVolume aal = load_atlas(path);
    // 48^3 voxels through the middle of the brain: deep structures and cortex, about 50 labels.
    const LabelVolume v = full_run() ? aal : crop(aal, {66, 84, 60}, {48, 48, 48});
    const LabelSurface s = mesh_labels(v);
    EXPECT_GE(s.labels.size(), full_run() ? 116u : 30u);
    const test::LabelJudgement j = judge_label_surface(s, v);
    RecordProperty("worst_volume_error", std::to_string(j.worst_volume_error));
}

TEST(LabelMesherTest, JhuIsCleanConformingAndKeepsVolumes) {
    VDBMESH_SHARED_DATA(path, "nifti_mricron_label_atlases/JHU-WhiteMatter-labels-1mm.nii.gz");
    const LabelVolume jhu = load_atlas(path);
    const LabelVolume v = full_run() ? jhu : crop(jhu, {60, 70, 50}, {60, 70, 50});
    const LabelSurface s = mesh_labels(v);
    EXPECT_GE(s.labels.size(), full_run() ? 48u : 10u);
    judge_label_surface(s, v);
}

TEST(LabelMesherTest, RefusesOffsetsOutOfRange) {
    LabelVolume v = blank_volume({4, 4, 4});
    at(v, 1, 1, 1) = 1;
    LabelMeshOptions options;
    for (const double offset : {0.0, -1.0, 2.5}) {
        options.max_offset = offset;
        EXPECT_THROW(mesh_labels(v, options), UsageError) << offset;
    }
}

}  // namespace
}  // namespace vdbmesh
