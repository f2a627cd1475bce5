// find_dominance() (compare.h): which rows of a comparison beat each volumeToMesh row on every
// count, and in time, on rows made by hand so that each count decides one case.
#include <gtest/gtest.h>

#include <string>

#include "vdbmesh/compare.h"

namespace vdbmesh {
namespace {

/// A clean row with these figures (closed and outward: MeshAnalysis::is_clean()).
MeshComparison row(MeshMethod method, std::size_t triangles, double hausdorff, double small_angles, double seconds) {
    MeshComparison m;
    m.method = method;
    m.analysis.triangles = triangles;
    m.analysis.closed = true;
    m.analysis.outward = true;
    m.accuracy.distance.hausdorff = hausdorff;
    m.analysis.small_angle_share = small_angles;
    m.seconds = seconds;
    return m;
}

MeshComparison volume_to_mesh(double adaptivity, std::size_t triangles, double hausdorff, double small_angles, double seconds) {
    MeshComparison m = row(MeshMethod::openvdb, triangles, hausdorff, small_angles, seconds);
    m.adaptivity = adaptivity;
    return m;
}

TEST(FindDominanceTest, EachCountDecides) {
    Comparison c;
    c.meshes.push_back(volume_to_mesh(0.25, 1000, 1.0, 0.02, 1.0));  // 0
    c.meshes.push_back(row(MeshMethod::dc, 1000, 1.0, 0.02, 1.0));    // 1: ties on every count: dominates
    c.meshes.push_back(row(MeshMethod::dc, 1001, 0.5, 0.01, 0.5));    // 2: one triangle more
    c.meshes.push_back(row(MeshMethod::dc, 900, 1.01, 0.01, 0.5));    // 3: farther
    c.meshes.push_back(row(MeshMethod::dc, 900, 0.5, 0.021, 0.5));    // 4: more small angles
    c.meshes.push_back(row(MeshMethod::dc, 900, 0.5, 0.01, 1.2));     // 5: slower only
    MeshComparison defective = row(MeshMethod::dc, 900, 0.5, 0.01, 0.5);
    defective.analysis.self_intersecting_pairs = 1;
    c.meshes.push_back(defective);                                    // 6: not clean
    const std::vector<Dominance> d = find_dominance(c);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0].volume_to_mesh, 0u);
    EXPECT_EQ(d[0].with_time, (std::vector<std::size_t>{1}));
    EXPECT_EQ(d[0].every_count, (std::vector<std::size_t>{1, 5}));
    EXPECT_FALSE(d[0].closest);  // one dominates with time: no closest
}

TEST(FindDominanceTest, AtAdaptivityOneHalfAgainTheTimeIsAllowed) {
    Comparison c;
    c.meshes.push_back(volume_to_mesh(1, 1000, 3.0, 0.03, 1.0));
    c.meshes.push_back(row(MeshMethod::dc, 1000, 1.0, 0.01, 1.5));  // exactly 1.5x: allowed
    c.meshes.push_back(volume_to_mesh(0.25, 1000, 3.0, 0.03, 1.0));
    const std::vector<Dominance> d = find_dominance(c);
    ASSERT_EQ(d.size(), 2u);
    EXPECT_EQ(d[0].with_time, (std::vector<std::size_t>{1}));
    EXPECT_TRUE(d[1].with_time.empty());  // at 0.25 the same row is slower
    EXPECT_EQ(d[1].every_count, (std::vector<std::size_t>{1}));
    ASSERT_TRUE(d[1].closest);
    EXPECT_EQ(*d[1].closest, 1u);
    ASSERT_EQ(d[1].closest_loses.size(), 1u);
    EXPECT_EQ(std::string(d[1].closest_loses[0]), "time");
}

TEST(FindDominanceTest, TheClosestLosesTheFewestCountsOfQualityThenNotTimeThenIsTheFaster) {
    Comparison c;
    c.meshes.push_back(volume_to_mesh(0, 1000, 0.5, 0.004, 0.2));
    c.meshes.push_back(row(MeshMethod::dc, 1200, 0.6, 0.01, 0.1));   // triangles, hausdorff, angles
    c.meshes.push_back(row(MeshMethod::dc, 900, 0.6, 0.001, 0.4));   // hausdorff, time
    c.meshes.push_back(row(MeshMethod::mc, 1000, 0.6, 0.03, 0.1));   // hausdorff, angles
    c.meshes.push_back(row(MeshMethod::dc, 900, 0.4, 0.001, 0.3));   // time, but slower than the next
    c.meshes.push_back(row(MeshMethod::dc, 950, 0.4, 0.001, 0.25));  // time
    const std::vector<Dominance> d = find_dominance(c);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_TRUE(d[0].with_time.empty());
    ASSERT_TRUE(d[0].closest);
    EXPECT_EQ(*d[0].closest, 5u);

    // A row losing only on triangles, faster than every other: still behind one losing only on time.
    c.meshes.push_back(row(MeshMethod::dc, 1001, 0.4, 0.001, 0.01));
    EXPECT_EQ(*find_dominance(c)[0].closest, 5u);
    // One losing on nothing of quality and no slower dominates: no closest then.
    c.meshes.push_back(row(MeshMethod::dc, 1000, 0.5, 0.004, 0.2));
    EXPECT_EQ(find_dominance(c)[0].with_time, (std::vector<std::size_t>{7}));
    EXPECT_FALSE(find_dominance(c)[0].closest);
}

TEST(FindDominanceTest, NoVolumeToMeshRowsNoneToJudge) {
    Comparison c;
    c.meshes.push_back(row(MeshMethod::dc, 10, 0.1, 0, 0.1));
    EXPECT_TRUE(find_dominance(c).empty());
}

}  // namespace
}  // namespace vdbmesh
