#pragma once
/// @file compare.h
/// @brief Measuring meshers against the true isosurface of a grid (`vdbmesh compare`,
/// bench/; OpenVDB-free: the grid is only declared, openvdb_fwd.h): distance and normal deviation of a mesh to the surface the samples define, and
/// the same grid meshed by DC, Marching Cubes and volumeToMesh side by side.
///
/// The true surface is, for a scan, the isovalue surface of the grid's trilinear interpolant
/// (the surface every sample-based mesher approximates) and, for a phantom, the analytic
/// surface given by its exact signed distance. Everything is measured in index space, so
/// distances are in VOXELS (index units, whatever the spacing).

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "vdbmesh/analysis.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/openvdb_fwd.h"

namespace vdbmesh {

/// A signed distance in index space (voxels; negative inside), called concurrently.
using SignedDistance = std::function<double(double, double, double)>;

/// How meshes are measured.
struct AccuracyOptions {
    /// Points drawn uniformly by area on the mesh (mesh -> surface) and on the reference
    /// surface (surface -> mesh). The maxima are estimates of the one-sided Hausdorff distances.
    std::size_t samples = 100000;
    /// Analytic surface (phantoms). Empty: the trilinear isosurface of the grid.
    SignedDistance exact_signed_distance;
    /// Points on the analytic surface (index space, e.g. phantom_surface_points(), corners and
    /// edges included) for the surface -> mesh direction, in place of samples of the grid's
    /// Marching Cubes mesh projected onto it (which miss the corners). Only with
    /// exact_signed_distance.
    std::vector<std::array<double, 3>> exact_surface_points;
};

/// Angle between each triangle's normal and the true surface normal at its centroid, in degrees.
struct NormalDeviation {
    double mean_deg = 0;  ///< area-weighted mean
    double p95_deg = 0;   ///< area-weighted 95th percentile
};

/// How far a mesh is from the true surface, in voxels. distance: a = the mesh, b = the surface.
struct Accuracy {
    DistanceReport distance;
    NormalDeviation normals;
    /// Mesh samples for which no point of the trilinear isosurface was found within
    /// kIsosurfaceSearchVoxels (they count as that far away).
    std::size_t unresolved_samples = 0;
};

/// How far from a mesh point the trilinear isosurface is searched for (the reach of the
/// grid stage's search, trilinear_field.h).
inline constexpr double kIsosurfaceSearchVoxels = 4.0;

/// Distance (voxels) from @a index_point to the nearest point of {trilinear(grid) = iso} that
/// a projection finds: Newton steps along the normalised gradient of the interpolant, then
/// alternate re-projections from the foot of the point on the tangent plane (converging to
/// the nearest point where the surface is smooth); ray searches with bisection when Newton
/// does not converge. On a converted grid (scan box metadata) the true solid is, as the
/// meshers close it, {inside} cut by the scan box grown by half a voxel, with the samples
/// extended constantly beyond the last one: its faces count as surface where the last layer
/// of samples is inside. Empty when no surface point was found within kIsosurfaceSearchVoxels.
std::optional<double> distance_to_trilinear_isosurface(const openvdb::FloatGrid& grid, double iso,
                                                       const std::array<double, 3>& index_point,
                                                       Inside inside = Inside::above);

/// @a mesh (world coordinates, as mesh_grid() returns) moved to @a grid's index space.
Mesh to_index_space(const Mesh& mesh, const openvdb::FloatGrid& grid);

/// The true surface of a grid at an isovalue, against which any number of meshes are
/// measured. Built once: the reference samples for the surface -> mesh direction, either
/// AccuracyOptions::exact_surface_points or drawn uniformly by area on the grid's Marching
/// Cubes mesh and moved to the nearest point of the true surface (the trilinear isosurface cut
/// by the scan box as distance_to_trilinear_isosurface() says, or the exact one), so they lie
/// ON it. (A supersampled MC mesh would only approximate it, at 4x the triangles.)
class TrueSurface {
public:
    TrueSurface(const openvdb::FloatGrid& grid, double iso, Inside inside, AccuracyOptions options = {});
    /// Measures @a mesh, in world coordinates as mesh_grid() returns it.
    Accuracy measure(const Mesh& mesh) const;
    std::size_t reference_triangles() const { return reference_triangles_; }  ///< of the MC mesh sampled (0: none was)

private:
    const openvdb::FloatGrid& grid_;
    double iso_;
    Inside inside_;
    AccuracyOptions options_;
    std::vector<std::array<double, 3>> reference_points_;  ///< index space, on the true surface
    std::size_t reference_triangles_ = 0;
};

/// What compare_meshers() does.
struct CompareOptions {
    double iso = 0;
    Inside inside = Inside::above;
    std::vector<double> errors{0, 0.1, 0.25, 0.5};         ///< the default mesher (intersection-free DC), one mesh each
    /// DC with MeshOptions::sharp (`--sharp`) at each of these errors (> 0), one mesh each,
    /// after every other row.
    std::vector<double> sharp_errors;
    std::vector<double> adaptivities{0, 0.1, 0.25, 1};     ///< volumeToMesh, one mesh each
    /// Shares of triangles to keep: the default mesher's error-0 mesh decimated by
    /// decimate_mesh() (as `vdbmesh mesh --decimate`), one mesh each.
    std::vector<double> decimate_fractions;
    bool marching_cubes = true;                            ///< one MC mesh
    /// One mesh of the dual surface (MeshMethod::dual), after MC: `compare` makes it by default
    /// when an adaptivity is 0, the mesh of ours meant to meet volumeToMesh's there.
    bool dual = false;
    /// Per volumeToMesh mesh, mesh_to_budget() (mesh_budget.h) at its triangle count: the mesh
    /// of ours meant to beat it on every count. A budget whose route (budget_route.h) only makes
    /// and keeps meshes of the DC rows is not meshed again: its time is the sum of those rows'
    /// times, its mesh the one kept (`same_mesh_as`).
    bool budget_rows = true;
    AccuracyOptions accuracy;
    /// Called before each mesh with its index and the number of meshes.
    std::function<void(std::size_t index, std::size_t count)> progress;
};

/// One mesher's result.
struct MeshComparison {
    MeshMethod method = MeshMethod::dc;
    std::optional<double> error;       ///< DC
    bool sharp = false;                ///< DC with MeshOptions::sharp
    std::optional<double> adaptivity;  ///< volumeToMesh
    std::optional<double> decimate;    ///< the share of triangles kept by decimate_mesh()
    std::optional<std::size_t> budget; ///< mesh_to_budget()'s budget (its time is seconds, its report mesher)
    double seconds = 0;                ///< mesh_grid() wall time, the fastest of up to 3 runs under 0.2 s (with decimate: plus decimate_seconds)
    double decimate_seconds = 0;       ///< decimate_mesh() wall time
    MeshReport mesher;                 ///< what mesh_grid() reported (phases, fallbacks)
    MeshAnalysis analysis;             ///< analyze_mesh()
    Accuracy accuracy;
    /// The earlier run whose mesh is the same, vertex for vertex (DC at error 0 is Marching
    /// Cubes): its analysis and accuracy are taken over rather than measured again.
    std::optional<std::size_t> same_mesh_as;
};

/// Every mesher's result, in the order run.
struct Comparison {
    std::vector<MeshComparison> meshes;
    std::size_t reference_triangles = 0;  ///< of the MC mesh the reference samples come from (0: exact_surface_points)
};

/// Meshes @a grid with every setting (DC at each error, MC, volumeToMesh at each
/// adaptivity, the budget at each volumeToMesh mesh's triangle count, DC at error 0 decimated to
/// each fraction, in that order), one at a time in this
/// process, timing mesh_grid() (and decimate_mesh()) alone, and measures each result (once per
/// distinct mesh). Meshes are dropped once measured, but for the error-0 mesh that is decimated.
Comparison compare_meshers(const openvdb::FloatGrid& grid, const CompareOptions& options);

/// At adaptivity 1 a row of ours may take up to this many times volumeToMesh's time and still
/// dominate it (issue 29: the triangle budget "in at most 1.5x its time"); elsewhere 1.
inline constexpr double kAdaptivityOneTimeFactor = 1.5;

/// Which rows of a comparison dominate one volumeToMesh row (issue 29's figure): no more
/// triangles, no larger two-sided Hausdorff distance, no larger share of angles under 10
/// degrees, no defect (MeshAnalysis::is_clean()), and for with_time also no more time
/// (kAdaptivityOneTimeFactor times it at adaptivity 1). Indices into Comparison::meshes.
struct Dominance {
    std::size_t volume_to_mesh = 0;          ///< the volumeToMesh row
    std::vector<std::size_t> every_count;    ///< rows of ours beating it on every count but time
    std::vector<std::size_t> with_time;      ///< of those, the ones no slower
    /// When none dominates with time: the row of ours nearest to it (the fewest counts of
    /// quality lost, then not slower, then the faster), and the counts it loses on
    /// ("triangles", "hausdorff", "angles", "defects", "time"); empty when there is no row of ours.
    std::optional<std::size_t> closest;
    std::vector<const char*> closest_loses;
};

/// One Dominance per volumeToMesh row of @a comparison, in its order; every other row is ours.
std::vector<Dominance> find_dominance(const Comparison& comparison);

/// "dc", "mc" or "openvdb".
const char* method_name(MeshMethod method);

}  // namespace vdbmesh
