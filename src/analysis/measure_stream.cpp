// MeshMeasureStream: `vdbmesh measure --memory` (issue 28). The bounded check's pass
// (analyze_stream.cpp) gives the figures; on the way each triangle's area and signed volume, and
// its first vertex, are spooled in file order (record_spool.h); once the topology has named each
// vertex's component, the spools are read back together and summed per component, numbered in
// order of first appearance as split_components() numbers them.
#include <cmath>
#include <limits>
#include <sstream>

#include "analysis/measure_parts.h"
#include "analysis/moments.h"
#include "analysis/record_spool.h"
#include "analysis/stream_extras.h"
#include "vdbmesh/error.h"
#include "vdbmesh/measure.h"

namespace vdbmesh {
namespace {

using Position = std::array<float, 3>;

struct TriangleSums {
    double area, volume;
};

class MeasureExtras final : public detail::StreamExtras {
public:
    void corners(const std::array<Position, 3>& corners) override {
        if (!started_) {
            started_ = true;
            reference_ = {corners[0][0], corners[0][1], corners[0][2]};
            box_min_.fill(std::numeric_limits<double>::infinity());
            box_max_.fill(-std::numeric_limits<double>::infinity());
        }
        std::array<detail::Vec, 3> p;
        for (int k = 0; k < 3; ++k) {
            for (int i = 0; i < 3; ++i) {
                box_min_[i] = std::min(box_min_[i], double(corners[k][i]));
                box_max_[i] = std::max(box_max_[i], double(corners[k][i]));
                p[k][i] = corners[k][i] - reference_[i];
            }
        }
        // The terms of detail::add_triangle() (a closed component's volume does not depend on
        // the reference point).
        const detail::Vec ab{p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        const detail::Vec ac{p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        const detail::Vec n = detail::cross(ab, ac);
        sums_.add({0.5 * std::sqrt(detail::dot(n, n)), detail::dot(p[0], detail::cross(p[1], p[2])) / 6});
    }
    void vertices(const std::array<std::uint32_t, 3>& triangle) override { first_vertices_.add(triangle[0]); }
    void components(std::vector<std::uint32_t> components) override { components_ = std::move(components); }
    std::uint64_t held_bytes() const override { return 2 * (detail::RecordSpool<TriangleSums>::kBufferBytes + detail::RecordSpool<std::uint32_t>::kBufferBytes); }

    void finish(MeshMeasure& measure) {
        if (!started_) return;
        measure.box_min = box_min_, measure.box_max = box_max_;
        // number[root]: the number + 1 of the component of that root once met.
        constexpr std::uint32_t kUnnumbered = 0;
        std::vector<std::uint32_t> number(components_.size(), kUnnumbered);
        for (std::uint64_t t = first_vertices_.size(); t > 0; --t) {
            const TriangleSums sums = sums_.next();
            std::uint32_t& n = number[components_[first_vertices_.next()]];
            if (n == kUnnumbered) {
                measure.components.emplace_back();
                n = std::uint32_t(measure.components.size());
            }
            ComponentMeasure& c = measure.components[n - 1];
            ++c.triangles;
            c.area += sums.area, c.volume += sums.volume;
        }
        detail::sort_components(measure.components);
    }

private:
    bool started_ = false;
    detail::Vec reference_{}, box_min_{}, box_max_{};
    detail::RecordSpool<TriangleSums> sums_;
    detail::RecordSpool<std::uint32_t> first_vertices_;
    std::vector<std::uint32_t> components_;
};

}  // namespace

struct MeshMeasureStream::Impl {
    MeasureExtras extras;
    std::unique_ptr<detail::StreamCheckRecords> checker;
};

MeshMeasureStream::MeshMeasureStream(const std::string& name, const StreamCheckOptions& options) : impl_(std::make_unique<Impl>()) {
    impl_->checker = detail::make_stream_checker(name, options, &impl_->extras);
}
MeshMeasureStream::~MeshMeasureStream() = default;
void MeshMeasureStream::plan_vertices(std::uint64_t vertices) { detail::plan_vertices(*impl_->checker, vertices); }
void MeshMeasureStream::announced(std::uint64_t vertices, std::uint64_t faces) { impl_->checker->announced(vertices, faces); }
void MeshMeasureStream::vertex(const std::array<float, 3>& position) { impl_->checker->vertex(position); }
void MeshMeasureStream::triangle(const std::array<std::uint32_t, 3>& triangle) { impl_->checker->triangle(triangle); }
void MeshMeasureStream::facet(const std::array<std::array<float, 3>, 3>& corners) { impl_->checker->facet(corners); }

std::uint64_t MeshMeasureStream::least_bytes() { return detail::least_stream_bytes(MeasureExtras().held_bytes()); }

MeshMeasure MeshMeasureStream::finish() {
    MeshMeasure measure;
    measure.report = impl_->checker->finish().analysis;
    detail::set_principal_frame(measure.report.inertia, measure);
    impl_->extras.finish(measure);
    return measure;
}

MeshMeasure measure_mesh_stream(const std::filesystem::path& path, const StreamCheckOptions& options) {
    MeshMeasureStream stream(path.string(), options);
    if (const std::optional<std::uint64_t> vertices = detail::obj_vertex_count(path)) stream.plan_vertices(*vertices);
    read_mesh_records(path, stream);
    return stream.finish();
}

}  // namespace vdbmesh
