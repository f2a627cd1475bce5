#pragma once
/// @file points.h
/// @brief Point clouds to solids (issue 13): reading points (.xyz/.pts, PLY, Stanford .conf
/// range-scan sets), normals by PCA oriented by a minimum spanning tree or towards each
/// scanner, adaptive decimation, the partition-of-unity RBF field (polyharmonic r^3 with a
/// linear polynomial per leaf of an overlapping binary partition, Carr et al. 2001
/// off-surface constraints), its sampling into a sparse grid (negative inside) meshed by DC (mesher.h),
/// and the similarity of two solids (coarse PCA alignment, Levenberg-Marquardt on scale,
/// rotation and translation). OpenVDB-free: the grid is only declared (openvdb_fwd.h).

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/openvdb_fwd.h"

namespace vdbmesh {

using Vec3d = std::array<double, 3>;

/// Points on the surface of a solid, with normals (outward) when known.
struct PointCloud {
    std::vector<Vec3d> points;
    std::vector<Vec3d> normals;          ///< empty, or one unit normal per point
    std::vector<std::uint32_t> scan;     ///< range-scan sets: the scan of each point; else empty
    /// Range-scan sets: per scan, the unit direction from the surface towards the scanner in
    /// world coordinates (the scan frame's +z: a Cyberware scanner looks down its -z axis).
    std::vector<Vec3d> scan_view;
    bool has_normals() const { return !normals.empty(); }
};

/// Reads .xyz/.pts/.txt (x y z [nx ny nz] per line; '#' comments), .ply (ASCII or binary;
/// x, y, z and optional nx, ny, nz of the vertex element; other elements such as Cyberware
/// range_grid are ignored) or a Stanford .conf range-scan set (`bmesh FILE tx ty tz qx qy qz qw`:
/// each scan's points p go to R(q)^-1 p + t, the convention that aligns the Stanford bunny
/// scans with bun_zipper.ply; `camera` lines are ignored).
/// @throw FormatError naming the file, the line or field, what was expected and what was found.
PointCloud read_points(const std::filesystem::path& path);

/// The files the .conf range-scan set @a conf names, in order, through nested .conf files (each
/// listed, then its own), without reading a scan: what read_points() reads besides @a conf.
/// @throw FormatError as read_points() for a malformed line, a cycle or too deep a nesting.
std::vector<std::filesystem::path> conf_scan_files(const std::filesystem::path& conf);

/// Writes x y z [nx ny nz] lines (for tests and tools).
void write_points_xyz(const PointCloud& cloud, const std::filesystem::path& path);

struct NormalOptions {
    int neighbours = 16;  ///< k of the k-nearest-neighbour PCA
};

/// Fills cloud.normals by PCA over the k nearest neighbours, oriented towards the scanner for
/// range-scan sets, otherwise by propagation over the minimum spanning tree of the k-nearest
/// graph weighted by 1 - |n_i . n_j| (Hoppe et al. 1992), each component started from its
/// highest point with an upward (+z) normal. Keeps normals the cloud already has.
void estimate_normals(PointCloud& cloud, const NormalOptions& options = {});

/// Drops isolated points: those whose mean distance to their k nearest neighbours exceeds
/// the median of that mean by more than @a factor times the median. Returns how many were dropped.
std::size_t remove_outliers(PointCloud& cloud, int neighbours = 8, double factor = 4.0);

/// Drops clusters of stray points: the components of the graph linking each point to those of
/// its k nearest neighbours closer than @a radius_factor times the median nearest-neighbour
/// distance, when they hold fewer than @a min_fraction of all points. Returns how many went.
std::size_t remove_small_clusters(PointCloud& cloud, double min_fraction = 0.01, int neighbours = 8, double radius_factor = 6.0);

struct DecimateOptions {
    double fraction = 0.0;      ///< the fraction of points to remove, in [0, 1)
    std::uint64_t seed = 1;     ///< the same seed and input give the same result
    int neighbours = 16;        ///< k of the PCA variation and of the local density
    int min_per_leaf = 20;      ///< never fewer points than this left in a leaf
    int leaf_points = 200;      ///< decimate_points() only: the leaves of its own partition
};

/// Adaptive decimation (the method's chapter 2.4) of a cloud on its own: each point's
/// importance is its normal variation (PCA surface variation) over its density relative to its
/// leaf (a median partition into leaves of at most leaf_points); leaves lose points with
/// probabilities from their total importance, and within a leaf the least important points
/// are the likeliest to go. Normals are kept where present and not needed. reconstruct()
/// decimates instead the leaves of the RBF partition (RbfOptions::decimate), as the method does.
PointCloud decimate_points(const PointCloud& cloud, const DecimateOptions& options);

struct RbfOptions {
    int leaf_min = 30;            ///< N1: leaves hold N1 to 2*N1 points (plus the overlap)
    double overlap = 0.05;        ///< the overlap of two siblings, a fraction of the parent's extent
    double off_surface = 0.0;     ///< Carr's off-surface distance; 0: half the median point spacing
    /// Within this distance of the points the field is the blended local fits; beyond twice
    /// it, Hoppe's signed distance to the tangent planes of the 8 nearest points of the cloud
    /// averaged per cell of 8 median spacings (a coarse shape, where a few wrong normals are
    /// outvoted); blended in between. 0: twice the median point spacing.
    double trust = 0.0;
    int off_every = 2;            ///< an off-surface constraint at every this many points (alternately outside and inside)
    /// Adaptive decimation after the partition, before the fits (chapter 2.4; leaf_points is not
    /// used: the leaves are the partition's). A point chosen leaves every leaf holding it and
    /// is merged into its nearest kept point (their mean: on scans that averages noise away).
    /// The fits get fewer centres; the field still knows every point (distance_to_points()).
    DecimateOptions decimate;
};

/// The partition-of-unity RBF field of a cloud with normals: negative inside, roughly a
/// signed distance near the surface; away from the points (RbfOptions::trust) it becomes
/// Hoppe's signed tangent-plane distance, so that the local fits' extrapolation cannot make
/// spurious solids.
class RbfField {
public:
    RbfField(const PointCloud& cloud, const RbfOptions& options = {});
    ~RbfField();
    RbfField(RbfField&&) noexcept;
    RbfField& operator=(RbfField&&) noexcept;

    double value(const Vec3d& p) const;
    /// The values at many points at once (the same numbers as value(), faster: each local fit
    /// is evaluated for all the points it covers together).
    void values(const std::vector<Vec3d>& points, std::vector<double>& out) const;
    Vec3d gradient(const Vec3d& p) const;  ///< by central differences
    Vec3d box_min() const;                 ///< where the field is defined
    Vec3d box_max() const;
    std::size_t leaves() const;
    double spacing() const;                ///< the median nearest-neighbour distance of the cloud
    std::size_t fitted_points() const;     ///< points that are centres of some leaf's fit
    double distance_to_points(const Vec3d& p) const;  ///< to the nearest point of the cloud

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

struct SampleOptions {
    double voxel = 0.0;    ///< 0: a 1/256 of the longest side of the points' box
    double band = 3.0;     ///< half-width in voxels of the band sampled exactly
    /// The field is trusted only this far from the points (gaps narrower than twice this are
    /// closed); beyond, inside or outside by flood fill. 0: 6% of the longest side of the points' box.
    double reach = 0.0;
    std::function<void(double)> progress;
};

/// Samples @a field into a sparse grid (negative inside, background = +band): coarse values
/// per 8^3 block everywhere in the field's box, exact voxels only in the blocks the surface
/// may cross. Gaps in the points are closed by the field itself.
std::shared_ptr<openvdb::FloatGrid> sample_field(const RbfField& field, const SampleOptions& options);

struct ReconstructOptions {
    NormalOptions normals;
    double outlier_factor = 4.0;  ///< remove_outliers(); 0: keep every point
    double min_cluster = 0.01;    ///< remove_small_clusters() fraction; 0: keep every cluster
    double cluster = 0.0;         ///< average the points per cell of this side first; 0: the voxel; < 0: no clustering
    RbfOptions rbf;
    SampleOptions sample;
    double mesh_error = 0.0;      ///< the mesher's (DC) error tolerance in voxels
    double min_component = 0.01;  ///< drop mesh components with |volume| below this fraction of the largest; 0: keep all
    std::function<void(double)> progress;
};

struct ReconstructReport {
    std::size_t input_points = 0, outliers = 0, used_points = 0, leaves = 0;
    std::size_t fitted_points = 0;  ///< used points left in some leaf's fit after decimation
    double voxel = 0;
    std::size_t dropped_components = 0;
    std::vector<std::string> mesh_fallbacks;  ///< MeshReport::fallbacks of the mesher
    std::vector<std::pair<std::string, double>> phases;  ///< name, seconds
};

struct Reconstruction {
    Mesh mesh;
    std::shared_ptr<openvdb::FloatGrid> grid;  ///< the sampled field
    ReconstructReport report;
};

/// The whole pipeline: outliers, normals, averaging per cell, the RBF field (decimated per
/// leaf), sampling, DC.
Reconstruction reconstruct(PointCloud cloud, const ReconstructOptions& options = {});

/// A similarity transform y = scale * R x + t.
struct Similarity {
    double scale = 1.0;
    std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  ///< row-major, det +1
    Vec3d translation{0, 0, 0};
    Vec3d apply(const Vec3d& x) const;
};

struct SimilarityResult {
    double energy = 0;        ///< mean squared field value / size^2 after alignment: 0 for the same solid
    Similarity transform;     ///< maps the sample's points onto the reference solid
    double coarse_energy = 0; ///< the same before the Levenberg-Marquardt refinement
    double forward_energy = 0, reverse_energy = 0;  ///< compare_solids(): each direction (energy is their mean)
    int iterations = 0;
};

struct SimilarityOptions {
    std::size_t max_points = 2000;  ///< sample points used (evenly chosen)
    int iterations = 50;
    bool allow_scale = true;
};

/// How alike the solid sampled by @a sample is to the one whose field is @a reference
/// (built from @a reference_cloud): coarse alignment by centroid, size and principal axes with
/// every sign choice, then Levenberg-Marquardt on scale, rotation and translation minimising
/// the sum of squared field values of the transformed sample points.
SimilarityResult compare_to(const PointCloud& sample, const PointCloud& reference_cloud, const RbfField& reference,
                            const SimilarityOptions& options = {});

/// The symmetric similarity: compare_to() of @a a against @a b, then the energy of b's points
/// taken back by the inverse transform in a's field; energy is the mean of the two directions
/// (a sample cannot look alike by covering only part of the reference).
SimilarityResult compare_solids(const PointCloud& a, const RbfField& field_a, const PointCloud& b, const RbfField& field_b,
                                const SimilarityOptions& options = {});

}  // namespace vdbmesh
