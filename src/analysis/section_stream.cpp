// SectionStream: `vdbmesh section --memory` (issue 28). Each triangle is cut by every plane as
// it comes (section_cut.h), the same cut as section_mesh()'s; only the segments stay.
#include <sstream>

#include "analysis/section_cut.h"
#include "analysis/section_figures.h"
#include "analysis/stream_extras.h"
#include "vdbmesh/error.h"
#include "vdbmesh/section.h"

namespace vdbmesh {
namespace {

constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
constexpr double kPositionBytesPerVertex = 12;
/// A segment held (section_cut.h) and its loop point while the loops are chained.
constexpr std::uint64_t kBytesPerSegment = sizeof(detail::CutSegment) + 3 * sizeof(double);
/// The least room for the segments.
constexpr std::uint64_t kMinSegmentBytes = kMiB;

}  // namespace

struct SectionStream::Impl {
    std::string name;
    std::vector<Plane> planes;
    std::uint64_t memory_bytes = 0;
    std::uint64_t held_bytes = kProgramBytes;  ///< the program and the positions
    bool numbered = true;                                    ///< false for an STL stream
    std::vector<std::array<float, 3>> positions;
    std::vector<std::vector<detail::CutSegment>> segments;  ///< one list a plane
    std::uint64_t segment_count = 0;

    /// Refuses a limit that cannot hold @a vertices positions and the least room for segments.
    void plan(std::uint64_t vertices) {
        held_bytes = kProgramBytes + std::uint64_t(kPositionBytesPerVertex * double(vertices));
        if (memory_bytes >= held_bytes + kMinSegmentBytes) {
            positions.reserve(vertices);
            return;
        }
        std::ostringstream text;
        text << "--memory: " << memory_bytes / kMiB << "M is too small to section " << name << ", which needs "
             << kProgramBytes / kMiB << " MiB for the program, ";
        if (vertices > 0) text << kPositionBytesPerVertex << " bytes for each of its " << vertices << " vertices, ";
        text << "and at least " << kMinSegmentBytes / kMiB << " MiB for the cuts; the smallest limit that works is "
             << (held_bytes + kMinSegmentBytes + kMiB - 1) / kMiB << "M";
        throw UsageError(text.str());
    }
    void cut(const detail::CutTriangle& triangle) {
        for (std::size_t p = 0; p < planes.size(); ++p) {
            const std::size_t before = segments[p].size();
            detail::cut_triangle(planes[p], triangle, segments[p]);
            segment_count += segments[p].size() - before;
        }
        if (held_bytes + segment_count * kBytesPerSegment > memory_bytes) {
            throw UsageError("--memory: " + std::to_string(memory_bytes / kMiB) + "M is too small to section " + name + ": its cuts by " +
                             std::to_string(planes.size()) + " planes hold more than " + std::to_string(segment_count) +
                             " segments (" + std::to_string(kBytesPerSegment) + " bytes each) beside the rest (" +
                             std::to_string((held_bytes + kMiB - 1) / kMiB) + "M); fewer planes or a larger limit");
        }
    }
};

SectionStream::SectionStream(std::string name, std::vector<Plane> planes, std::uint64_t memory_bytes) : impl_(std::make_unique<Impl>()) {
    impl_->name = std::move(name);
    impl_->segments.resize(planes.size());
    impl_->planes = std::move(planes);
    impl_->memory_bytes = memory_bytes;
}
SectionStream::~SectionStream() = default;

void SectionStream::plan_vertices(std::uint64_t vertices) { impl_->plan(vertices); }
void SectionStream::announced(std::uint64_t vertices, std::uint64_t) {
    if (vertices > 0) impl_->plan(vertices);
}
void SectionStream::vertex(const std::array<float, 3>& position) {
    if (impl_->positions.size() == impl_->positions.capacity()) {  // an OBJ file that grew since its vertices were counted
        throw FormatError(impl_->name, "vertices", std::to_string(impl_->positions.size()) + " (as counted first)", "more");
    }
    impl_->positions.push_back(position);
}
void SectionStream::triangle(const std::array<std::uint32_t, 3>& t) {
    const auto& p = impl_->positions;
    impl_->cut(detail::numbered_triangle(t, {p[t[0]], p[t[1]], p[t[2]]}));
}
void SectionStream::facet(const std::array<std::array<float, 3>, 3>& corners) {
    impl_->numbered = false;
    impl_->cut(detail::positioned_triangle(corners));
}

std::vector<Section> SectionStream::finish() {
    std::vector<std::array<float, 3>>().swap(impl_->positions);
    std::vector<Section> sections;
    for (std::size_t p = 0; p < impl_->planes.size(); ++p) {
        sections.push_back(detail::section_from_loops(impl_->planes[p], detail::chain_loops(std::move(impl_->segments[p]), impl_->numbered)));
    }
    return sections;
}

std::uint64_t SectionStream::least_bytes() { return kProgramBytes + kMinSegmentBytes; }

std::vector<Section> section_mesh_stream(const std::filesystem::path& path, const std::vector<Plane>& planes, std::uint64_t memory_bytes) {
    SectionStream stream(path.string(), planes, memory_bytes);
    if (const std::optional<std::uint64_t> vertices = detail::obj_vertex_count(path)) stream.plan_vertices(*vertices);
    read_mesh_records(path, stream);
    return stream.finish();
}

}  // namespace vdbmesh
