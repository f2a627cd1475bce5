// Meshers side by side against the true surface (`vdbmesh compare`, bench/): the two-sided
// distance of each mesh to the true isosurface (mesh samples projected onto it, reference
// samples measured exactly to the mesh), the deviation of its triangle normals from the true
// normal, its validity (analyze_mesh) and the time mesh_grid() took.

#include "vdbmesh/compare.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <utility>

#include "vdbmesh/analysis.h"
#include "vdbmesh/budget_route.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/mesh_budget.h"
#include "vdbmesh/process.h"
#include "vdbmesh/trilinear_field.h"

namespace vdbmesh {

static_assert(kIsosurfaceSearchVoxels == detail::kTrilinearSearchVoxels);

namespace {

using openvdb::Vec3d;

constexpr double kGradientStep = 1e-4;  ///< central differences of an exact signed distance (voxels)
constexpr double kPi = 3.14159265358979323846;

Vec3d numeric_gradient(const SignedDistance& f, const Vec3d& p) {
    const double h = kGradientStep;
    return Vec3d(f(p[0] + h, p[1], p[2]) - f(p[0] - h, p[1], p[2]), f(p[0], p[1] + h, p[2]) - f(p[0], p[1] - h, p[2]),
                 f(p[0], p[1], p[2] + h) - f(p[0], p[1], p[2] - h)) /
           (2 * h);
}

/// Points of the reference surface moved onto the analytic one: for an exact signed
/// distance d, p - d(p) grad d(p) is the closest surface point (two steps absorb the
/// finite-difference error).
void project_onto_exact(std::vector<std::array<double, 3>>& points, const SignedDistance& f) {
    tbb::parallel_for(std::size_t(0), points.size(), [&](std::size_t i) {
        Vec3d p(points[i][0], points[i][1], points[i][2]);
        for (int step = 0; step < 2; ++step) {
            const Vec3d g = numeric_gradient(f, p);
            if (!(g.length() > 0)) break;
            p -= g.unit() * f(p[0], p[1], p[2]);
        }
        points[i] = {p[0], p[1], p[2]};
    });
}

/// For a point beyond the last samples along an axis (in the half voxel where the meshers
/// close the surface) whose extended samples are inside, the nearest true surface is the
/// closing face: its outward normal. Zero otherwise.
Vec3d closing_face_normal(const std::optional<openvdb::CoordBBox>& box, const detail::TrilinearField& field,
                          double iso, Inside inside, const Vec3d& p) {
    if (!box) return Vec3d(0);
    Vec3d n(0);
    for (int a = 0; a < 3; ++a) {
        if (p[a] < box->min()[a]) n[a] = -1;
        if (p[a] > box->max()[a]) n[a] = 1;
    }
    if (n == Vec3d(0)) return n;
    const double value = field(p).value;
    if (!(inside == Inside::above ? value > iso : value < iso)) return Vec3d(0);
    return n.unit();
}

/// Points moved to the nearest point of the trilinear isosurface; the rare point with none
/// within the search radius (on no surface the projection can reach) is dropped.
void project_onto_isosurface(std::vector<std::array<double, 3>>& points, const openvdb::FloatGrid& grid, double iso,
                             Inside inside) {
    std::vector<std::optional<Vec3d>> moved(points.size());
    const auto box = stored_scan_box(grid);
    tbb::enumerable_thread_specific<detail::TrilinearField> fields([&] { return detail::TrilinearField(grid, box); });
    tbb::parallel_for(std::size_t(0), points.size(), [&](std::size_t i) {
        moved[i] = detail::closest_boundary_point(fields.local(), iso, inside == Inside::above,
                                                  Vec3d(points[i][0], points[i][1], points[i][2]));
    });
    points.clear();
    for (const auto& p : moved)
        if (p) points.push_back({(*p)[0], (*p)[1], (*p)[2]});
}

/// Area-weighted mean and 95th percentile of the angle between each triangle's normal and
/// @a true_normal at its centroid (a zero vector: the triangle is skipped).
template <class TrueNormal>
NormalDeviation normal_deviation(const Mesh& mesh, TrueNormal true_normal) {
    std::vector<std::pair<double, double>> angle_area(mesh.triangles.size(), {0.0, 0.0});
    tbb::parallel_for(std::size_t(0), mesh.triangles.size(), [&](std::size_t i) {
        const auto& t = mesh.triangles[i];
        const auto corner = [&](int k) {
            const auto& v = mesh.vertices[t[k]];
            return Vec3d(v[0], v[1], v[2]);
        };
        const Vec3d a = corner(0), b = corner(1), c = corner(2);
        const Vec3d cross = (b - a).cross(c - a);
        const double twice_area = cross.length();
        const Vec3d truth = true_normal((a + b + c) / 3.0);
        if (!(twice_area > 0) || !(truth.length() > 0)) return;
        const double cosine = std::clamp(cross.dot(truth) / (twice_area * truth.length()), -1.0, 1.0);
        angle_area[i] = {std::acos(cosine) * 180.0 / kPi, 0.5 * twice_area};
    });
    tbb::parallel_sort(angle_area.begin(), angle_area.end());
    double total = 0, weighted = 0;
    for (const auto& [angle, area] : angle_area) {
        total += area;
        weighted += angle * area;
    }
    NormalDeviation result;
    if (!(total > 0)) return result;
    result.mean_deg = weighted / total;
    double running = 0;
    for (const auto& [angle, area] : angle_area) {
        running += area;
        if (area > 0 && running >= 0.95 * total) {
            result.p95_deg = angle;
            break;
        }
    }
    return result;
}

/// Sizes and two 64-bit hashes of a mesh's vertex and index bytes: equal for the same mesh;
/// for two different meshes of the same sizes, equal with odds of about 2^-128.
struct MeshFingerprint {
    std::size_t vertices = 0, triangles = 0;
    std::uint64_t hash[2] = {0, 0};
    bool operator==(const MeshFingerprint& other) const {
        return vertices == other.vertices && triangles == other.triangles && hash[0] == other.hash[0] && hash[1] == other.hash[1];
    }
};

MeshFingerprint mesh_fingerprint(const Mesh& mesh) {
    MeshFingerprint f;
    f.vertices = mesh.vertices.size();
    f.triangles = mesh.triangles.size();
    // Two multiply-xorshift chains over the 32-bit words (coordinates as their bit patterns),
    // with different odd multipliers and seeds.
    std::uint64_t a = 0x243f6a8885a308d3ull, b = 0x13198a2e03707344ull;
    const auto add = [&](std::uint32_t word) {
        a = (a ^ word) * 0x9e3779b97f4a7c15ull;
        a ^= a >> 29;
        b = (b + word) * 0xc2b2ae3d27d4eb4full;
        b ^= b >> 31;
    };
    for (const auto& v : mesh.vertices) {
        for (const float c : v) {
            std::uint32_t bits;
            std::memcpy(&bits, &c, sizeof bits);
            add(bits);
        }
    }
    for (const auto& t : mesh.triangles)
        for (const std::uint32_t index : t) add(index);
    f.hash[0] = a;
    f.hash[1] = b;
    return f;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A mesher taking under this long is timed again, up to kTimedRuns runs in all, and the
/// fastest run counts: a run of a few hundredths of a second varies by about 10% from one run to
/// the next on a 2-core machine (the walnut's meshes, 0.04 s: DC 0.5 measured 0.046 and 0.048 s
/// in two runs of the same build), which decided comparisons of equal times either way.
constexpr double kRetimeBelowSeconds = 0.2;
constexpr int kTimedRuns = 3;

/// mesh_grid() of @a grid from its fastest run (see kRetimeBelowSeconds; every run makes the
/// same mesh), and that run's time.
std::pair<MeshResult, double> timed_mesh(const openvdb::FloatGrid& grid, const MeshOptions& options,
                                         std::optional<std::size_t> budget = std::nullopt) {
    double fastest = std::numeric_limits<double>::infinity();
    std::optional<MeshResult> kept;
    for (int run = 0; run < kTimedRuns && (run == 0 || fastest < kRetimeBelowSeconds); ++run) {
        const auto start = std::chrono::steady_clock::now();
        MeshResult result = budget ? mesh_to_budget(grid, options, *budget) : mesh_grid(grid, options);
        const double seconds = seconds_since(start);
        if (seconds < fastest) {
            fastest = seconds;
            kept = std::move(result);
        }
    }
    return {std::move(*kept), fastest};
}

/// The mesh of @a run (meshed, or for a decimate run the error-0 mesh decimated), with its
/// times and the mesher's report filled in. @a error0 keeps the error-0 mesh and its report
/// for the decimate runs after the first.
Mesh mesh_of(const openvdb::FloatGrid& grid, const CompareOptions& options, MeshComparison& run,
             std::optional<std::pair<MeshResult, double>>& error0) {
    MeshOptions mesh_options;
    mesh_options.method = run.method;
    mesh_options.iso = options.iso;
    mesh_options.inside = options.inside;
    mesh_options.error = run.error.value_or(0.0);
    mesh_options.sharp = run.sharp;
    mesh_options.adaptivity = run.adaptivity.value_or(0.0);
    if (run.budget == std::optional<std::size_t>(0)) return {};  // (volumeToMesh found no surface: nothing to meet)
    if (!run.decimate) {
        auto [result, seconds] = timed_mesh(grid, mesh_options, run.budget);
        run.seconds = seconds;
        run.mesher = std::move(result.report);
        return std::move(result.mesh);
    }
    if (!error0) error0.emplace(timed_mesh(grid, mesh_options));
    DecimateOptions decimate;
    decimate.keep_fraction = *run.decimate;
    const auto start = std::chrono::steady_clock::now();
    Mesh decimated = decimate_mesh(error0->first.mesh, decimate);
    run.decimate_seconds = seconds_since(start);
    run.seconds = error0->second + run.decimate_seconds;
    run.mesher = error0->first.report;
    return decimated;
}

/// The DC row (not sharp, not decimated, no budget) of @a error among the first @a count runs.
std::optional<std::size_t> dc_row(const std::vector<MeshComparison>& runs, std::size_t count, double error) {
    for (std::size_t k = 0; k < count; ++k) {
        const MeshComparison& r = runs[k];
        if (r.method == MeshMethod::dc && r.error == error && !r.sharp && !r.decimate && !r.budget) return k;
    }
    return std::nullopt;
}

/// The earlier DC row whose mesh the budget run @a i keeps, found without meshing: mesh_to_budget()'s
/// route (budget_route()) over the rows' triangle counts, when every mesh it makes is a row's and
/// it keeps one (no decimation). The run's time is then the sum of those rows' times
/// (mesh_to_budget() makes exactly those meshes, one after the other; each row's time is the
/// fastest of its runs, see kRetimeBelowSeconds) and its mesher report the kept row's. Empty
/// otherwise: the budget is meshed.
std::optional<std::size_t> budget_from_rows(std::vector<MeshComparison>& runs, std::size_t i) {
    MeshComparison& run = runs[i];
    if (!run.budget || *run.budget == 0) return std::nullopt;
    double seconds = 0;
    bool missing = false;
    const std::optional<double> kept = budget_route(*run.budget, [&](double error) -> std::size_t {
        const auto row = dc_row(runs, i, error);
        if (!row) {
            missing = true;
            return 0;  // (the route is dropped)
        }
        seconds += runs[*row].seconds;
        return runs[*row].analysis.triangles;
    });
    if (missing || !kept) return std::nullopt;
    const std::size_t row = *dc_row(runs, i, *kept);
    run.seconds = seconds;
    run.mesher = runs[row].mesher;
    return row;
}

}  // namespace

const char* method_name(MeshMethod method) {
    switch (method) {
        case MeshMethod::mc:
            return "mc";
        case MeshMethod::openvdb:
            return "openvdb";
        case MeshMethod::dc:
            return "dc";
        case MeshMethod::dual:
            return "dual";
    }
    return "unknown";
}

std::optional<double> distance_to_trilinear_isosurface(const openvdb::FloatGrid& grid, double iso,
                                                       const std::array<double, 3>& index_point, Inside inside) {
    const detail::TrilinearField field(grid, stored_scan_box(grid));
    const Vec3d p(index_point[0], index_point[1], index_point[2]);
    const auto q = detail::closest_boundary_point(field, iso, inside == Inside::above, p);
    if (!q) return std::nullopt;
    return (*q - p).length();
}

Mesh to_index_space(const Mesh& mesh, const openvdb::FloatGrid& grid) {
    Mesh moved = mesh;
    const openvdb::math::Transform& transform = grid.transform();
    tbb::parallel_for(std::size_t(0), moved.vertices.size(), [&](std::size_t i) {
        auto& v = moved.vertices[i];
        const Vec3d p = transform.worldToIndex(Vec3d(v[0], v[1], v[2]));
        v = {float(p[0]), float(p[1]), float(p[2])};
    });
    return moved;
}

TrueSurface::TrueSurface(const openvdb::FloatGrid& grid, double iso, Inside inside, AccuracyOptions options)
    : grid_(grid), iso_(iso), inside_(inside), options_(std::move(options)) {
    if (!options_.exact_surface_points.empty()) {
        if (!options_.exact_signed_distance) throw UsageError("TrueSurface: exact surface points need the exact signed distance");
        reference_points_ = std::move(options_.exact_surface_points);
        options_.exact_surface_points.clear();
        return;
    }
    MeshOptions mc;
    mc.method = MeshMethod::mc;
    mc.iso = iso;
    mc.inside = inside;
    const Mesh reference = to_index_space(mesh_grid(grid, mc).mesh, grid);
    reference_triangles_ = reference.triangles.size();
    if (reference.triangles.empty()) return;
    reference_points_ = sample_surface(reference, options_.samples);
    if (options_.exact_signed_distance)
        project_onto_exact(reference_points_, options_.exact_signed_distance);
    else
        project_onto_isosurface(reference_points_, grid, iso, inside);
}

Accuracy TrueSurface::measure(const Mesh& world_mesh) const {
    Accuracy result;
    const Mesh mesh = to_index_space(world_mesh, grid_);
    if (mesh.triangles.empty()) return result;
    const SignedDistance& exact = options_.exact_signed_distance;
    const auto box = stored_scan_box(grid_);
    tbb::enumerable_thread_specific<detail::TrilinearField> fields([&] { return detail::TrilinearField(grid_, box); });
    std::atomic<std::size_t> unresolved{0};
    const SignedDistance to_surface = exact ? exact : SignedDistance([&](double x, double y, double z) {
        const Vec3d p(x, y, z);
        const auto q = detail::closest_boundary_point(fields.local(), iso_, inside_ == Inside::above, p);
        if (q) return (*q - p).length();
        ++unresolved;
        return kIsosurfaceSearchVoxels;
    });
    result.distance = mesh_distance(mesh, to_surface, options_.samples, reference_points_);
    result.unresolved_samples = unresolved;
    const double outward = inside_ == Inside::above ? -1.0 : 1.0;  // the interpolant grows inwards when above
    result.normals = normal_deviation(mesh, [&](const Vec3d& p) {
        if (exact) return numeric_gradient(exact, p);
        const Vec3d face = closing_face_normal(box, fields.local(), iso_, inside_, p);
        if (face != Vec3d(0)) return face;
        return fields.local()(p).gradient * outward;
    });
    return result;
}

Comparison compare_meshers(const openvdb::FloatGrid& grid, const CompareOptions& options) {
    std::vector<MeshComparison> runs;
    const auto add_run = [&](MeshMethod method, std::optional<double> error, std::optional<double> adaptivity,
                             std::optional<double> decimate = std::nullopt) {
        MeshComparison run;
        run.method = method;
        run.error = error;
        run.adaptivity = adaptivity;
        run.decimate = decimate;
        runs.push_back(run);
    };
    for (double error : options.errors) add_run(MeshMethod::dc, error, std::nullopt);
    if (options.marching_cubes) add_run(MeshMethod::mc, std::nullopt, std::nullopt);
    if (options.dual) add_run(MeshMethod::dual, std::nullopt, std::nullopt);
    for (double adaptivity : options.adaptivities) add_run(MeshMethod::openvdb, std::nullopt, adaptivity);
    // (a budget run's count is its volumeToMesh mesh's, known once that one is made)
    std::vector<std::optional<std::size_t>> budget_of(runs.size());
    if (options.budget_rows) {
        for (std::size_t i = 0, count = runs.size(); i < count; ++i) {
            if (runs[i].method != MeshMethod::openvdb) continue;
            add_run(MeshMethod::dc, std::nullopt, std::nullopt);
            budget_of.push_back(i);
        }
    }
    for (double fraction : options.decimate_fractions) add_run(MeshMethod::dc, 0.0, std::nullopt, fraction);
    for (double error : options.sharp_errors) {  // last: the rows before keep their places
        add_run(MeshMethod::dc, error, std::nullopt);
        runs.back().sharp = true;
    }
    budget_of.resize(runs.size());

    const TrueSurface truth(grid, options.iso, options.inside, options.accuracy);
    std::vector<MeshFingerprint> fingerprints(runs.size());
    std::optional<std::pair<MeshResult, double>> error0;  // kept for the decimate runs
    for (std::size_t i = 0; i < runs.size(); ++i) {
        if (options.progress) options.progress(i, runs.size());
        MeshComparison& run = runs[i];
        if (budget_of[i]) run.budget = runs[*budget_of[i]].analysis.triangles;
        const std::optional<std::size_t> budget_row = budget_from_rows(runs, i);
        const Mesh mesh = budget_row ? Mesh() : mesh_of(grid, options, run, error0);
        fingerprints[i] = budget_row ? fingerprints[*budget_row] : mesh_fingerprint(mesh);
        for (std::size_t earlier = 0; earlier < i && !run.same_mesh_as; ++earlier)
            if (fingerprints[earlier] == fingerprints[i]) run.same_mesh_as = earlier;
        if (run.same_mesh_as) {
            run.analysis = runs[*run.same_mesh_as].analysis;
            run.accuracy = runs[*run.same_mesh_as].accuracy;
            continue;
        }
        run.analysis = analyze_mesh(mesh);
        run.accuracy = truth.measure(mesh);
    }
    if (options.progress) options.progress(runs.size(), runs.size());
    return {std::move(runs), truth.reference_triangles()};
}

}  // namespace vdbmesh
