#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "point_shapes.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/points.h"

namespace vdbmesh {
namespace {

void write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

std::string error_of(const std::filesystem::path& path) {
    try {
        read_points(path);
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

TEST(ReadPoints, XyzWithAndWithoutNormals) {
    test::ScratchDir dir;
    write_text(dir / "a.xyz", "# comment\n0 0 0\n1 2 3\n\n4,5,6\n");
    const PointCloud a = read_points(dir / "a.xyz");
    ASSERT_EQ(a.points.size(), 3u);
    EXPECT_FALSE(a.has_normals());
    EXPECT_EQ(a.points[2][2], 6.0);
    write_text(dir / "b.pts", "0 0 0 0 0 2\n1 0 0 0 1 0\n");
    const PointCloud b = read_points(dir / "b.pts");
    ASSERT_TRUE(b.has_normals());
    EXPECT_DOUBLE_EQ(b.normals[0][2], 1.0);  // normalised
}

TEST(ReadPoints, BadXyzLinesNameFileLineAndField) {
    test::ScratchDir dir;
    write_text(dir / "bad.xyz", "0 0 0\n1 2\n");
    std::string e = error_of(dir / "bad.xyz");
    EXPECT_NE(e.find("bad.xyz"), std::string::npos) << e;
    EXPECT_NE(e.find("line 2"), std::string::npos) << e;
    EXPECT_NE(e.find("got 2 fields"), std::string::npos) << e;
    write_text(dir / "nan.xyz", "0 0 0\n1 x 3\n");
    e = error_of(dir / "nan.xyz");
    EXPECT_NE(e.find("line 2 field 2"), std::string::npos) << e;
    write_text(dir / "mixed.xyz", "0 0 0\n1 2 3 0 0 1\n");
    EXPECT_NE(error_of(dir / "mixed.xyz").find("line 2"), std::string::npos);
    write_text(dir / "empty.xyz", "# nothing\n");
    EXPECT_NE(error_of(dir / "empty.xyz").find("at least one point"), std::string::npos);
    EXPECT_NE(error_of(dir / "a.abc").find("does not exist"), std::string::npos);
}

TEST(ReadPoints, PlyAsciiWithExtraElementsAndBinary) {
    test::ScratchDir dir;
    // Cyberware-style: extra obj_info, a range_grid element after the vertices.
    write_text(dir / "a.ply",
               "ply\nformat ascii 1.0\nobj_info num_cols 2\nelement vertex 2\nproperty float x\nproperty float y\n"
               "property float z\nproperty float confidence\nelement range_grid 3\nproperty list uchar int vertex_indices\n"
               "end_header\n1 2 3 0.5\n4 5 6 0.5\n1 0\n0\n1 1\n");
    const PointCloud a = read_points(dir / "a.ply");
    ASSERT_EQ(a.points.size(), 2u);
    EXPECT_FLOAT_EQ(float(a.points[1][1]), 5.0f);
    // Binary little endian with normals and a face element before nothing else.
    std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                      "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const float v[2][6] = {{1, 2, 3, 0, 0, 1}, {4, 5, 6, 0, 1, 0}};
    for (const auto& row : v) {
        bin.append(reinterpret_cast<const char*>(row), sizeof row);
        bin.push_back(char(7));
    }
    write_text(dir / "b.ply", bin);
    const PointCloud b = read_points(dir / "b.ply");
    ASSERT_EQ(b.points.size(), 2u);
    ASSERT_TRUE(b.has_normals());
    EXPECT_FLOAT_EQ(float(b.points[1][2]), 6.0f);
    EXPECT_FLOAT_EQ(float(b.normals[1][1]), 1.0f);
    // Truncated binary: a clear error.
    write_text(dir / "c.ply", bin.substr(0, bin.size() - 10));
    const std::string e = error_of(dir / "c.ply");
    EXPECT_NE(e.find("c.ply"), std::string::npos) << e;
    EXPECT_NE(e.find("vertex 1"), std::string::npos) << e;
    write_text(dir / "d.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n");
    EXPECT_NE(error_of(dir / "d.ply").find("property z"), std::string::npos);
}

TEST(ReadPoints, ConfAppliesTheInverseRotationThenTheTranslation) {
    test::ScratchDir dir;
    write_text(dir / "s.xyz", "1 0 0\n0 0 1\n0 1 0\n");
    // 90 degrees about z: q = (0, 0, sin 45, cos 45). The points go to R(q)^-1 p + t.
    const double h = std::sqrt(0.5);
    write_text(dir / "set.conf", "camera 0 0 0 0 0 0 1\nbmesh s.xyz 0 0 0 0 0 0 1\nbmesh s.xyz 10 0 0 0 0 " + std::to_string(h) +
                                     " " + std::to_string(h) + "\n");
    const PointCloud c = read_points(dir / "set.conf");
    ASSERT_EQ(c.points.size(), 6u);
    ASSERT_EQ(c.scan.size(), 6u);
    ASSERT_EQ(c.scan_view.size(), 2u);
    EXPECT_NEAR(c.points[3][0], 10.0, 1e-9);  // (1,0,0) rotated by -90 degrees: (0,-1,0)
    EXPECT_NEAR(c.points[3][1], -1.0, 1e-9);
    EXPECT_NEAR(c.scan_view[1][2], 1.0, 1e-9);
    write_text(dir / "bad.conf", "bmesh s.xyz 0 0 0 0 0 1\n");
    EXPECT_NE(error_of(dir / "bad.conf").find("line 1"), std::string::npos);
    write_text(dir / "missing.conf", "bmesh nothere.ply 0 0 0 0 0 0 1\n");
    EXPECT_NE(error_of(dir / "missing.conf").find("nothere.ply"), std::string::npos);
}

// Issue 32: a .conf naming itself, or two naming each other, recursed until SIGSEGV.
TEST(ReadPoints, ConfCyclesAndDeepChainsAreRefusedNamingFileAndLine) {
    test::ScratchDir dir;
    write_text(dir / "s.xyz", "0 0 0\n1 0 0\n0 1 0\n");
    write_text(dir / "self.conf", "bmesh s.xyz 0 0 0 0 0 0 1\nbmesh self.conf 0 0 0 0 0 0 1\n");
    std::string e = error_of(dir / "self.conf");
    EXPECT_NE(e.find("self.conf: line 2"), std::string::npos) << e;
    EXPECT_NE(e.find("cycle"), std::string::npos) << e;
    write_text(dir / "a.conf", "bmesh b.conf 0 0 0 0 0 0 1\n");
    write_text(dir / "b.conf", "bmesh s.xyz 0 0 0 0 0 0 1\nbmesh a.conf 0 0 0 0 0 0 1\n");
    e = error_of(dir / "a.conf");
    EXPECT_NE(e.find("a.conf: line 1"), std::string::npos) << e;
    EXPECT_NE(e.find("b.conf: line 2"), std::string::npos) << e;
    EXPECT_NE(e.find("cycle"), std::string::npos) << e;
    // The same file by another name (a symbolic link) is the same file.
    std::filesystem::create_symlink(dir / "self.conf", dir / "link.conf");
    write_text(dir / "via.conf", "bmesh link.conf 0 0 0 0 0 0 1\n");
    write_text(dir / "self.conf", "bmesh via.conf 0 0 0 0 0 0 1\n");
    EXPECT_NE(error_of(dir / "via.conf").find("cycle"), std::string::npos);
    // A chain of distinct files deeper than the bound: refused, not followed.
    for (int i = 0; i < 40; ++i)
        write_text(dir / ("d" + std::to_string(i) + ".conf"), "bmesh d" + std::to_string(i + 1) + ".conf 0 0 0 0 0 0 1\n");
    write_text(dir / "d40.conf", "bmesh s.xyz 0 0 0 0 0 0 1\n");
    e = error_of(dir / "d0.conf");
    EXPECT_NE(e.find("nested at most 16 deep"), std::string::npos) << e.substr(0, 300);
    // A file named twice, not nested, is no cycle.
    write_text(dir / "twice.conf", "bmesh s.xyz 0 0 0 0 0 0 1\nbmesh s.xyz 1 0 0 0 0 0 1\n");
    write_text(dir / "outer.conf", "bmesh twice.conf 0 0 0 0 0 0 1\nbmesh twice.conf 5 0 0 0 0 0 1\n");
    EXPECT_EQ(read_points(dir / "outer.conf").points.size(), 12u);
}

TEST(ReadPoints, StanfordScansLineUpWithBunZipper) {
    VDBMESH_SHARED_DATA(conf, "pointcloud_stanford_bunny_scans/data/bun.conf");
    const PointCloud c = read_points(conf);
    EXPECT_EQ(c.points.size(), 362272u);
    EXPECT_EQ(c.scan_view.size(), 10u);
}

TEST(Normals, MstOrientsASphereOutward) {
    PointCloud c = test::sample_shape("sphere", 3000, 5);
    c.normals.clear();
    estimate_normals(c);
    ASSERT_TRUE(c.has_normals());
    std::size_t outward = 0;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        const auto& p = c.points[i];
        const auto& n = c.normals[i];
        outward += p[0] * n[0] + p[1] * n[1] + p[2] * n[2] > 0.9;
    }
    EXPECT_EQ(outward, c.points.size());
}

TEST(Normals, MstOrientsACubeMinusSphereOutward) {
    const PointCloud truth = test::sample_shape("cube_minus_sphere", 6000, 6);
    PointCloud c = truth;
    c.normals.clear();
    estimate_normals(c);
    std::size_t agree = 0;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        const auto& a = c.normals[i];
        const auto& b = truth.normals[i];
        agree += a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0;
    }
    EXPECT_GT(double(agree), 0.99 * double(c.points.size()));
}

TEST(Decimate, RemovesTheFractionRepeatablyAndKeepsTheMinimumPerLeaf) {
    const PointCloud c = test::sample_shape("torus", 20000, 7);
    DecimateOptions o;
    o.fraction = 0.3;
    o.seed = 42;
    const PointCloud a = decimate_points(c, o), b = decimate_points(c, o);
    EXPECT_EQ(a.points.size(), 14000u);
    EXPECT_EQ(a.points, b.points);
    o.seed = 43;
    EXPECT_NE(decimate_points(c, o).points, a.points);
    o.fraction = 0.95;
    o.min_per_leaf = 50;
    o.leaf_points = 200;
    const PointCloud d = decimate_points(c, o);
    EXPECT_GE(d.points.size(), 20000u / 200 * 50 / 2);  // leaves hold 100..200 points, each keeps 50
    EXPECT_THROW(decimate_points(c, DecimateOptions{1.0}), UsageError);
}

// Decimation inside the RBF partition: the points chosen leave every leaf holding them (and are
// merged into kept neighbours), so the fits lose the fraction asked for; the field stays a good
// sphere (radius 1: values at the points and at 1.1 and 0.9 along the normal).
TEST(Decimate, RbfFieldFitsFewerPointsAndStaysAccurate) {
    const PointCloud c = test::sample_shape("sphere", 8000, 8);
    RbfOptions o;
    o.decimate.fraction = 0.3;
    const RbfField decimated(c, o);
    EXPECT_NEAR(double(decimated.fitted_points()), 0.7 * 8000, 0.02 * 8000);  // the minimum per leaf may keep a few
    EXPECT_EQ(RbfField(c).fitted_points(), 8000u);
    double worst = 0;
    for (std::size_t i = 0; i < c.points.size(); i += 37) {
        const Vec3d& p = c.points[i];
        worst = std::max(worst, std::abs(decimated.value(p)));
        EXPECT_GT(decimated.value({1.1 * p[0], 1.1 * p[1], 1.1 * p[2]}), 0.0);
        EXPECT_LT(decimated.value({0.9 * p[0], 0.9 * p[1], 0.9 * p[2]}), 0.0);
    }
    EXPECT_LT(worst, 0.01);  // 1% of the radius: a tenth of the spacing's order (8000 points: about 0.04)
}

}  // namespace
}  // namespace vdbmesh
