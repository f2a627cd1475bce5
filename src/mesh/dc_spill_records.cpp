// The spill's records formatted for a file (dc_spill.h, format_records() and write_ranges()).
// Formatting a mesh's records (an ASCII number's shortest form above all) is most of the
// spill's output once its keys are resolved, and it is serial in the order of the file; so runs
// of nodes are formatted in parallel in a pipeline whose last stage takes them in order, and
// the bytes are those of one thread. When every vertex is used (no scan measured has one
// unused), a triangle's numbers are known as soon as it is resolved: one process then formats
// the triangles as they are resolved, without the resolved file
// (write_ranges_every_vertex_used()).

#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <cstring>
#include <memory>

#include "mesh/dc_spill.h"

namespace vdbmesh::detail {

namespace {

/// Records (vertices or triangles) a run of nodes holds at most, unless one node holds more:
/// large enough to amortise a pipeline step, small enough to keep the runs in flight a few MB.
constexpr std::uint64_t kRunRecords = std::uint64_t{1} << 16;

/// A run of consecutive nodes and, once formatted, each one's bytes.
struct FormattedRun {
    std::size_t first = 0, end = 0;
    std::uint64_t resolved_at = 0;  ///< the first node's triangles' place in the resolved file
    std::vector<std::string> bytes;
};

/// Gathers bytes into writes of a few MB at consecutive offsets of @a sink's file.
class RangeWriter {
public:
    RangeWriter(MeshRangeSink& sink, std::string first) : sink_(sink), pending_(std::move(first)) {}
    void add(const std::string& bytes) {
        pending_ += bytes;
        if (pending_.size() >= kWriteBytes) flush();
    }
    void flush() {
        sink_.write_at(at_, pending_.data(), pending_.size());
        at_ += pending_.size();
        pending_.clear();
    }

private:
    static constexpr std::size_t kWriteBytes = std::size_t{4} << 20;
    MeshRangeSink& sink_;
    std::string pending_;
    std::uint64_t at_ = 0;
};

}  // namespace

void IfcSpill::decode_resolved(const char* records, std::size_t count, bool with_corners, bool mirrored, const Used* used,
                               std::vector<std::array<std::uint32_t, 3>>& triangles, std::vector<Corners>& corners) {
    using Numbers = std::array<std::uint32_t, 3>;
    const std::size_t record_bytes = resolved_record_bytes(with_corners);
    triangles.resize(count);
    corners.resize(with_corners ? count : 0);
    for (std::size_t t = 0; t < count; ++t) {
        Numbers numbers;
        std::memcpy(&numbers, records + t * record_bytes, sizeof(numbers));
        for (int k = 0; k < 3; ++k) triangles[t][std::size_t(k)] = used ? std::uint32_t(used->rank(numbers[std::size_t(k)])) : numbers[std::size_t(k)];
        if (with_corners) std::memcpy(&corners[t], records + t * record_bytes + sizeof(numbers), sizeof(Corners));
        if (mirrored) {
            std::swap(triangles[t][1], triangles[t][2]);
            if (with_corners) std::swap(corners[t][1], corners[t][2]);
        }
    }
}

IfcSpill::ResolvedRun IfcSpill::appended_to(TempFile& resolved) {
    return [&resolved](std::vector<std::vector<char>>& batches) {
        for (const std::vector<char>& batch : batches) resolved.append(batch.data(), batch.size());
    };
}

void IfcSpill::format_records(Records which, const MeshRangeSink& format, const Used* used, const TempFile* resolved, bool with_corners,
                              bool mirrored, const std::function<void(std::size_t, const std::string&)>& take) const {
    const std::size_t record_bytes = resolved_record_bytes(with_corners);
    auto records_of = [&](const NodeRecord& node) { return which == Records::vertices ? node.vertex_count : node.triangle_count; };

    auto format_vertices = [&](const NodeRecord& node, std::string& out) {
        const std::vector<VertexRecord> vertices = read<VertexRecord>(node.vertex_offset, node.vertex_count);
        std::vector<std::array<float, 3>> positions;
        positions.reserve(vertices.size());
        for (std::size_t v = 0; v < vertices.size(); ++v)
            if (!used || used->used(node.first_vertex + v)) positions.push_back(vertices[v].position);
        format.vertices(positions, out);
    };
    auto format_triangles = [&](const NodeRecord& node, std::uint64_t resolved_at, std::string& out) {
        std::vector<char> batch(std::size_t(node.triangle_count * record_bytes));
        if (!batch.empty()) resolved->read(resolved_at, batch.data(), batch.size());
        std::vector<std::array<std::uint32_t, 3>> triangles;
        std::vector<Corners> corners;
        decode_resolved(batch.data(), std::size_t(node.triangle_count), with_corners, mirrored, used, triangles, corners);
        format.triangles(triangles, corners, out);
    };

    std::size_t next = 0;
    std::uint64_t resolved_at = 0;
    auto next_run = [&](tbb::flow_control& control) -> std::shared_ptr<FormattedRun> {
        if (next == nodes_.size()) {
            control.stop();
            return nullptr;
        }
        auto run = std::make_shared<FormattedRun>();
        run->first = next;
        run->resolved_at = resolved_at;
        std::uint64_t records = 0;
        do {
            records += records_of(nodes_[next]);
            resolved_at += nodes_[next].triangle_count * record_bytes;
            ++next;
        } while (next < nodes_.size() && records + records_of(nodes_[next]) <= kRunRecords);
        run->end = next;
        return run;
    };
    auto format_run = [&](std::shared_ptr<FormattedRun> run) {
        run->bytes.resize(run->end - run->first);
        std::uint64_t at = run->resolved_at;
        for (std::size_t n = run->first; n < run->end; ++n) {
            const NodeRecord& node = nodes_[n];
            if (which == Records::vertices) {
                format_vertices(node, run->bytes[n - run->first]);
            } else {
                format_triangles(node, at, run->bytes[n - run->first]);
                at += node.triangle_count * record_bytes;
            }
        }
        return run;
    };
    auto take_run = [&](std::shared_ptr<FormattedRun> run) {
        for (std::size_t n = run->first; n < run->end; ++n) take(n, run->bytes[n - run->first]);
    };
    const std::size_t tokens = 2 * std::size_t(tbb::this_task_arena::max_concurrency());
    tbb::parallel_pipeline(tokens, tbb::make_filter<void, std::shared_ptr<FormattedRun>>(tbb::filter_mode::serial_in_order, next_run) &
                                       tbb::make_filter<std::shared_ptr<FormattedRun>, std::shared_ptr<FormattedRun>>(tbb::filter_mode::parallel, format_run) &
                                       tbb::make_filter<std::shared_ptr<FormattedRun>, void>(tbb::filter_mode::serial_in_order, take_run));
}

void IfcSpill::write_ranges(MeshRangeSink& sink, const Used& used, const TempFile& resolved, bool with_corners, bool mirrored,
                            std::uint64_t used_count, std::uint64_t triangle_count) const {
    const std::string header = sink.header(used_count, triangle_count);
    const std::string footer = sink.footer();
    sink.open("");
    try {
        RangeWriter writer(sink, header);
        auto write = [&](std::size_t, const std::string& bytes) { writer.add(bytes); };
        format_records(Records::vertices, sink, &used, &resolved, with_corners, mirrored, write);
        format_records(Records::triangles, sink, &used, &resolved, with_corners, mirrored, write);
        writer.add(footer);
        writer.flush();
    } catch (...) {
        sink.close(false);
        throw;
    }
    sink.close(true);
}

bool IfcSpill::write_ranges_every_vertex_used(MeshRangeSink& sink, bool with_corners, bool mirrored, std::uint64_t vertex_count,
                                              std::uint64_t triangle_count) const {
    const std::string header = sink.header(vertex_count, triangle_count);
    const std::string footer = sink.footer();
    sink.open("");
    Used used(vertex_count);
    try {
        RangeWriter writer(sink, header);
        format_records(Records::vertices, sink, nullptr, nullptr, with_corners, mirrored,
                       [&](std::size_t, const std::string& bytes) { writer.add(bytes); });
        std::vector<std::string> formatted;
        resolve(nullptr, with_corners, used, [&](std::vector<std::vector<char>>& batches) {
            formatted.resize(batches.size());
            const std::size_t record_bytes = resolved_record_bytes(with_corners);
            tbb::parallel_for(std::size_t{0}, batches.size(), [&](std::size_t n) {
                std::vector<std::array<std::uint32_t, 3>> triangles;
                std::vector<Corners> corners;
                decode_resolved(batches[n].data(), batches[n].size() / record_bytes, with_corners, mirrored, nullptr, triangles, corners);
                formatted[n].clear();
                sink.triangles(triangles, corners, formatted[n]);
            });
            for (const std::string& bytes : formatted) writer.add(bytes);
        });
        writer.add(footer);
        writer.flush();
    } catch (...) {
        sink.close(false);
        throw;
    }
    if (used.count() == vertex_count) {
        sink.close(true);
        return true;
    }
    sink.close(false);
    return false;
}

}  // namespace vdbmesh::detail
