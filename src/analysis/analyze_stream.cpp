// analyze_mesh_stream(): `vdbmesh check --memory` (issue 28). One pass over the file's records
// (read_mesh_records()) sums what each triangle gives alone (class, angles, integrals, in the
// blocks of mesh_integrals()) and hands its vertex numbers to StreamTopology, whose sorts count
// the rest; STL corners are first numbered by StreamWeld. Memory: the process's own
// (kBaselineBytes), what is held per vertex, and the sorts alive at once, which share what is
// left: two for PLY and OBJ (the topology's), three for STL (the weld's merge feeding them).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>

#include "analysis/block_reduce.h"
#include "analysis/moments.h"
#include "analysis/report_parts.h"
#include "analysis/stream_extras.h"
#include "analysis/stream_topology.h"
#include "analysis/stream_weld.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/parse_util.h"

namespace vdbmesh {
namespace {

constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
/// The process besides the plan (stream_extras.h).
constexpr std::uint64_t kBaselineBytes = kProgramBytes;
/// The least a sort is given.
constexpr std::uint64_t kMinSortBytes = kMiB;
constexpr int kIndexedSorts = 2, kStlSorts = 3;
/// The positions of a PLY or OBJ file's vertices while it is read (after, the topology's 8.25).
constexpr double kPositionBytesPerVertex = 12;

using Position = std::array<float, 3>;

/// The memory plan for one limit: what is left for each of @a sorts sorts once @a per_vertex
/// bytes for each of @a vertices vertices (and @a extra bytes) are held; a usage error naming
/// the smallest limit that works when that is less than kMinSortBytes.
std::uint64_t sort_bytes(const std::string& verb, const std::string& name, std::uint64_t limit, int sorts, double per_vertex, std::uint64_t vertices,
                         std::uint64_t extra) {
    const std::uint64_t held = kBaselineBytes + extra + std::uint64_t(std::ceil(per_vertex * double(vertices)));
    const std::uint64_t needed = held + std::uint64_t(sorts) * kMinSortBytes;
    if (limit < needed) {
        std::ostringstream text;
        text << "--memory: " << limit / kMiB << "M is too small to " << verb << " " << name << ", which needs "
             << (kBaselineBytes + extra) / kMiB << " MiB for the program, ";
        if (vertices > 0) text << per_vertex << " bytes for each of its " << vertices << " vertices, ";
        text << "and at least " << kMinSortBytes / kMiB << " MiB for each of " << sorts
             << " sorts; the smallest limit that works is " << (needed + kMiB - 1) / kMiB << "M";
        throw UsageError(text.str());
    }
    return (limit - held) / std::uint64_t(sorts);
}

/// Records of @a record_bytes in one run of a sort given @a bytes (or the tests' run size).
std::size_t run_records(const StreamCheckOptions& options, std::uint64_t bytes, std::size_t record_bytes) {
    return options.run_records > 0 ? options.run_records : std::size_t(bytes / record_bytes);
}

/// What each triangle gives alone: its class, its angles, its share of the integrals.
class FaceSums {
public:
    /// @a ids: equal where two corners are the same vertex.
    void add(const std::array<std::uint32_t, 3>& ids, const std::array<Position, 3>& corners) {
        const auto point = [&](int k) { return detail::Point3{corners[k][0], corners[k][1], corners[k][2]}; };
        if (triangles_ == 0) reference_ = point(0);
        ++triangles_;
        const detail::FaceClass face = detail::classify_face(ids, {point(0), point(1), point(2)});
        ++class_counts_[std::size_t(face)];
        if (face == detail::FaceClass::kRegular) {
            for (const double angle : detail::triangle_angles(corners[0], corners[1], corners[2])) {
                angles_.add(angle, angle < detail::kSmallAngleDeg);
            }
        }
        const auto relative = [&](int k) {
            return detail::Vec{corners[k][0] - reference_[0], corners[k][1] - reference_[1], corners[k][2] - reference_[2]};
        };
        detail::add_triangle(relative(0), relative(1), relative(2), block_);
        if (triangles_ % detail::kMomentsBlock == 0) close_block();
    }
    std::uint64_t triangles() const { return triangles_; }
    void report(MeshAnalysis& report) {
        close_block();
        report.triangles = triangles_;
        detail::add_faces(class_counts_, angles_, report);
        if (triangles_ > 0) detail::add_integrals(detail::integrals_from(total_, reference_), report);
    }

private:
    void close_block() {
        total_.add(block_);
        block_ = {};
    }
    std::uint64_t triangles_ = 0;
    std::array<std::size_t, 3> class_counts_{};
    detail::ValueStats angles_;
    detail::Vec reference_{};
    detail::Moments total_, block_;
};

/// The one pass over the records.
class StreamChecker final : public detail::StreamCheckRecords {
public:
    StreamChecker(std::string name, StreamCheckOptions options, detail::StreamExtras* extras)
        : name_(std::move(name)), options_(std::move(options)), extras_(extras) {}

    /// A PLY or OBJ file of @a vertices vertices: the plan, before any record. Held per vertex:
    /// the positions while reading, then the topology's union-finds (and the components kept).
    void plan_indexed(std::uint64_t vertices) {
        const double per_vertex = std::max(kPositionBytesPerVertex, topology_bytes_per_vertex());
        const std::uint64_t bytes = sort_bytes(verb(), name_, options_.memory_bytes, kIndexedSorts, per_vertex, vertices, extra_bytes());
        positions_.reserve(vertices);
        topology_.emplace(run_records(options_, bytes, sizeof(detail::StreamTopology::EdgeUse)));
        if (extras_) topology_->keep_components();
    }
    void announced(std::uint64_t vertices, std::uint64_t faces) override {
        if (!topology_ && !weld_ && vertices > 0) plan_indexed(vertices);
        announced_faces_ = faces;
    }
    void vertex(const Position& position) override {
        if (positions_.size() == positions_.capacity()) {  // an OBJ file that grew since its vertices were counted
            throw FormatError(name_, "vertices", std::to_string(positions_.size()) + " (as counted first)", "more");
        }
        positions_.push_back(position);
    }
    void triangle(const std::array<std::uint32_t, 3>& t) override {
        const std::array<Position, 3> corners{positions_[t[0]], positions_[t[1]], positions_[t[2]]};
        faces_.add(t, corners);
        topology_->add(t);
        if (extras_) extras_->corners(corners), extras_->vertices(t);
        report_reading();
    }
    void facet(const std::array<Position, 3>& corners) override {
        if (!weld_) {
            const std::uint64_t bytes = sort_bytes(verb(), name_, options_.memory_bytes, kStlSorts, 0, 0, extra_bytes());
            weld_.emplace(run_records(options_, bytes, sizeof(std::array<std::uint32_t, 5>)));
        }
        const auto same = [&](int i, int j) { return std::memcmp(corners[i].data(), corners[j].data(), sizeof(Position)) == 0; };
        faces_.add({0, same(1, 0) ? 0u : 1u, same(2, 0) ? 0u : (same(2, 1) ? 1u : 2u)}, corners);
        weld_->add(corners);
        if (extras_) extras_->corners(corners);
        report_reading();
    }

    StreamCheck finish() override {
        if (!topology_ && !weld_) plan_indexed(0);  // no record at all
        StreamCheck result;
        MeshAnalysis& report = result.analysis;
        std::uint64_t vertices = positions_.size();
        std::vector<Position>().swap(positions_);
        if (weld_) {
            vertices = weld_->number_vertices();
            show_progress(kReadShare + kWeldShare / 2);
            const std::uint64_t bytes =
                sort_bytes(verb(), name_, options_.memory_bytes, kStlSorts, topology_bytes_per_vertex(), vertices, extra_bytes());
            topology_.emplace(run_records(options_, bytes, sizeof(detail::StreamTopology::EdgeUse)));
            if (extras_) topology_->keep_components();
            weld_->triangles([&](const std::array<std::uint32_t, 3>& t) {
                topology_->add(t);
                if (extras_) extras_->vertices(t);
            });
            result.sorted_runs += weld_->runs();
            show_progress(kReadShare + kWeldShare);
        }
        faces_.report(report);
        report.vertices = vertices;
        result.sorted_runs += topology_->runs();
        const double counted = weld_ ? kReadShare + kWeldShare : kReadShare;
        detail::add_topology(topology_->finish(vertices, [&](double share) { show_progress(counted + (1 - counted) * share); }), report);
        if (extras_) extras_->components(topology_->take_components());
        return result;
    }

private:
    // Shares of the work for the progress: reading (with the runs sorted on the way), the STL
    // weld's merges, the topology's merges.
    static constexpr double kReadShare = 0.6, kWeldShare = 0.15;

    void show_progress(double share) const {
        if (options_.progress) options_.progress(share);
    }
    /// The share of the faces read, when the header announced them (PLY, binary STL).
    void report_reading() const {
        const std::uint64_t read = faces_.triangles();
        if (announced_faces_ > 0 && read % 65536 == 0) show_progress(kReadShare * std::min(1.0, double(read) / double(announced_faces_)));
    }

    double topology_bytes_per_vertex() const {
        return detail::kTopologyBytesPerVertex + (extras_ ? detail::StreamTopology::kComponentBytesPerVertex : 0);
    }
    std::uint64_t extra_bytes() const { return extras_ ? extras_->held_bytes() : 0; }
    const char* verb() const { return extras_ ? "measure" : "check"; }

    std::string name_;
    StreamCheckOptions options_;
    detail::StreamExtras* extras_;
    std::vector<Position> positions_;
    FaceSums faces_;
    std::optional<detail::StreamTopology> topology_;
    std::optional<detail::StreamWeld> weld_;
    std::uint64_t announced_faces_ = 0;
};

/// Counts an OBJ file's vertices (its statements are read, nothing is kept).
struct VertexCounter final : MeshRecordVisitor {
    std::uint64_t vertices = 0;
    void vertex(const Position&) override { ++vertices; }
    void triangle(const std::array<std::uint32_t, 3>&) override {}
    void facet(const std::array<Position, 3>&) override {}
};

}  // namespace

namespace detail {

std::unique_ptr<StreamCheckRecords> make_stream_checker(const std::string& name, const StreamCheckOptions& options, StreamExtras* extras) {
    return std::make_unique<StreamChecker>(name, options, extras);
}

std::optional<std::uint64_t> obj_vertex_count(const std::filesystem::path& path) {
    if (to_lower(path.extension().string()) != ".obj") return std::nullopt;
    VertexCounter counter;
    read_mesh_records(path, counter);
    return counter.vertices;
}

std::uint64_t least_stream_bytes(std::uint64_t extra_bytes) { return kBaselineBytes + extra_bytes + kIndexedSorts * kMinSortBytes; }

void plan_vertices(StreamCheckRecords& checker, std::uint64_t vertices) { static_cast<StreamChecker&>(checker).plan_indexed(vertices); }

}  // namespace detail

StreamCheck analyze_mesh_stream(const std::filesystem::path& path, const StreamCheckOptions& options) {
    StreamChecker checker(path.string(), options, nullptr);
    if (const std::optional<std::uint64_t> vertices = detail::obj_vertex_count(path)) checker.plan_indexed(*vertices);
    read_mesh_records(path, checker);
    return checker.finish();
}

}  // namespace vdbmesh
