// The spill of bricked contouring (dc_spill.h). A triangle's vertices lie in its node or in a
// neighbour (keys name grid points at most a node away), so resolving the triangles of the
// nodes in z-major order needs the vertices of three layers of nodes at most: each node's
// table is loaded before the nodes that can refer to it are resolved and dropped once every node
// that can refer to it is done. The nodes of a run (one z-layer, a bounded number of triangles)
// are resolved in parallel from tables loaded beforehand, read-only meanwhile.

#include "mesh/dc_spill.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <tuple>

#include "mesh/dc_key_index.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

using KeyedTriangle = std::array<std::uint64_t, 3>;


}  // namespace

/// The vertices of the nodes near the one being resolved, by key.
class IfcSpill::Tables {
public:
    Tables(const IfcSpill& spill, const Foreign* foreign) : spill_(spill), foreign_(foreign) {
        for (std::size_t n = 0; n < spill.nodes_.size(); ++n) by_origin_[ifc_z_major(spill.nodes_[n].origin)] = n;
    }

    struct Table {
        openvdb::Coord origin;
        std::uint64_t first_vertex;
        std::vector<std::array<float, 3>> positions;
        std::unique_ptr<IfcKeyIndex> index;
    };

    /// Loads the tables of @a nodes and of the nodes next to them: every table their
    /// triangles can name. The tables not loaded yet are made in parallel.
    void load_around(const NodeRecord* nodes, std::size_t count) {
        std::vector<openvdb::Coord> missing;
        for (std::size_t n = 0; n < count; ++n)
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const openvdb::Coord node = nodes[n].origin.offsetBy(dx * kNodeVoxels, dy * kNodeVoxels, dz * kNodeVoxels);
                        if (loaded_.emplace(ifc_z_major(node), nullptr).second) missing.push_back(node);
                    }
        std::vector<std::unique_ptr<Table>> made(missing.size());
        tbb::parallel_for(std::size_t{0}, missing.size(), [&](std::size_t m) { made[m] = table_of(missing[m]); });
        for (std::size_t m = 0; m < missing.size(); ++m) {
            if (made[m]) loaded_[ifc_z_major(missing[m])] = std::move(made[m]);
            else loaded_.erase(ifc_z_major(missing[m]));  // no node there
        }
    }

    /// The vertex @a key names: its number (before unused ones are dropped) and position,
    /// from the tables loaded (load_around()); @a last is the caller's table last used.
    std::pair<std::uint64_t, const std::array<float, 3>*> find(std::uint64_t key, const Table*& last) const {
        const openvdb::Coord node = ifc_node_of(ifc_key_point(key));
        if (!last || last->origin != node) {
            const auto it = loaded_.find(ifc_z_major(node));
            last = it == loaded_.end() ? nullptr : it->second.get();
        }
        const std::uint32_t index = last ? last->index->find(key) : IfcKeyIndex::kMissing;
        if (index == IfcKeyIndex::kMissing) throw Error("contouring: a triangle refers to a missing vertex");
        return {last->first_vertex + index, &last->positions[index]};
    }

    /// Drops the tables no node at or after z-layer @a z can refer to.
    void drop_below(int z) {
        for (auto it = loaded_.begin(); it != loaded_.end() && std::get<0>(it->first) < z - kNodeVoxels;) it = loaded_.erase(it);
    }

private:
    /// The table of the node at @a node, from the spill or another rank's; null when neither
    /// holds that node.
    std::unique_ptr<Table> table_of(const openvdb::Coord& node) const {
        const auto key = ifc_z_major(node);
        const auto record = by_origin_.find(key);
        const auto other = foreign_ ? foreign_->find(key) : Foreign::const_iterator();
        if (record == by_origin_.end() && (!foreign_ || other == foreign_->end())) return nullptr;
        auto table = std::make_unique<Table>();
        table->origin = node;
        std::vector<VertexRecord> vertices;
        if (record != by_origin_.end()) {
            const NodeRecord& r = spill_.nodes_[record->second];
            vertices = spill_.read<VertexRecord>(r.vertex_offset, r.vertex_count);
            table->first_vertex = r.first_vertex;
        } else {
            vertices = other->second.vertices;
            table->first_vertex = other->second.first_vertex;
        }
        std::vector<std::uint64_t> keys(vertices.size());
        table->positions.resize(vertices.size());
        for (std::size_t v = 0; v < vertices.size(); ++v) {
            keys[v] = vertices[v].key;
            table->positions[v] = vertices[v].position;
        }
        table->index = std::make_unique<IfcKeyIndex>(keys);
        return table;
    }

    const IfcSpill& spill_;
    const Foreign* foreign_;
    std::map<std::tuple<int, int, int>, std::size_t> by_origin_;
    std::map<std::tuple<int, int, int>, std::unique_ptr<Table>> loaded_;
};

void IfcSpill::append(IfcNodeOutput&& node) {
    NodeRecord record;
    record.origin = node.origin;
    std::vector<VertexRecord> vertices;
    std::vector<KeyedTriangle> triangles;
    for (const IfcBlockOutput& block : node.blocks) {
        for (const IfcVertex& v : block.vertices) vertices.push_back({v.key, v.position});
        triangles.insert(triangles.end(), block.triangles.begin(), block.triangles.end());
    }
    for (const IfcVertex& v : node.coarse) vertices.push_back({v.key, v.position});
    node = IfcNodeOutput();
    record.vertex_offset = file_.size();
    record.vertex_count = vertices.size();
    write(vertices);
    record.triangle_offset = file_.size();
    record.triangle_count = triangles.size();
    write(triangles);
    nodes_.push_back(record);
}

std::string IfcSpill::records_bytes() const {
    const std::uint64_t count = nodes_.size();
    std::string bytes(sizeof(count) + count * sizeof(NodeRecord), '\0');
    std::memcpy(bytes.data(), &count, sizeof(count));
    std::memcpy(bytes.data() + sizeof(count), nodes_.data(), count * sizeof(NodeRecord));
    return bytes;
}

RankPart IfcSpill::part() const {
    auto header = std::make_shared<const std::string>(records_bytes());
    RankPart part;
    part.size = header->size() + file_.size();
    part.read = [this, header](std::uint64_t offset, std::size_t bytes, char* into) {
        if (offset < header->size()) {
            const std::size_t from_header = std::min<std::uint64_t>(bytes, header->size() - offset);
            std::memcpy(into, header->data() + offset, from_header);
            into += from_header, offset += from_header, bytes -= from_header;
        }
        if (bytes > 0) file_.read(offset - header->size(), into, bytes);
    };
    return part;
}

void IfcSpill::Receiver::begin(int rank, std::uint64_t size) {
    if (left_ != 0) throw Error("bricks: rank " + std::to_string(rank_) + " sent a truncated part");
    rank_ = rank;
    left_ = size;
    header_.clear();
    header_size_ = 0;
    if (size == 0) throw Error("bricks: rank " + std::to_string(rank) + " sent an empty part");
}

void IfcSpill::Receiver::piece(const char* bytes, std::size_t count) {
    if (count > left_) throw Error("bricks: rank " + std::to_string(rank_) + " sent more than its part");
    left_ -= count;
    std::uint64_t node_count = 0;
    while (count > 0 && (header_size_ == 0 || header_.size() < header_size_)) {
        // The count first, then the records it announces.
        const std::size_t wanted = header_size_ == 0 ? sizeof(node_count) - header_.size() : header_size_ - header_.size();
        const std::size_t taken = std::min(wanted, count);
        header_.append(bytes, taken);
        bytes += taken, count -= taken;
        if (header_size_ == 0 && header_.size() == sizeof(node_count)) {
            std::memcpy(&node_count, header_.data(), sizeof(node_count));
            header_size_ = sizeof(node_count) + node_count * sizeof(NodeRecord);
        }
        if (header_size_ != 0 && header_.size() == header_size_) take_header();
    }
    if (count > 0) spill_.file_.append(bytes, count);
    if (left_ == 0 && (header_size_ == 0 || header_.size() < header_size_))
        throw Error("bricks: rank " + std::to_string(rank_) + " sent a truncated part");
}

void IfcSpill::Receiver::take_header() {
    std::uint64_t count = 0;
    std::memcpy(&count, header_.data(), sizeof(count));
    base_ = spill_.file_.size();
    for (std::uint64_t n = 0; n < count; ++n) {
        NodeRecord node;
        std::memcpy(&node, header_.data() + sizeof(count) + n * sizeof(NodeRecord), sizeof(NodeRecord));
        node.vertex_offset += base_;
        node.triangle_offset += base_;
        spill_.nodes_.push_back(node);
    }
}

void IfcSpill::resolve(const Foreign* foreign, bool with_corners, Used& used, const ResolvedRun& take) const {
    using Numbers = std::array<std::uint32_t, 3>;
    const std::size_t record_bytes = resolved_record_bytes(with_corners);
    auto resolve_node = [&](const Tables& tables, const NodeRecord& node, std::vector<char>& batch) {
        const Tables::Table* last = nullptr;
        const std::vector<KeyedTriangle> triangles = read<KeyedTriangle>(node.triangle_offset, node.triangle_count);
        batch.resize(triangles.size() * record_bytes);
        char* at = batch.data();
        for (const KeyedTriangle& t : triangles) {
            Numbers numbers;
            Corners corners;
            for (int k = 0; k < 3; ++k) {
                const auto [number, position] = tables.find(t[k], last);
                used.mark(number);
                numbers[k] = std::uint32_t(number);
                corners[k] = *position;
            }
            std::memcpy(at, &numbers, sizeof(numbers));
            if (with_corners) std::memcpy(at + sizeof(numbers), &corners, sizeof(corners));
            at += record_bytes;
        }
    };
    // Runs of nodes of one z-layer holding at most this many triangles (one node more when a
    // single node holds more): their resolved triangles are held until appended.
    constexpr std::uint64_t kRunTriangles = std::uint64_t{1} << 19;
    Tables tables(*this, foreign);
    std::vector<std::vector<char>> batches;
    for (std::size_t first = 0; first < nodes_.size();) {
        std::size_t end = first + 1;
        std::uint64_t triangles = nodes_[first].triangle_count;
        while (end < nodes_.size() && nodes_[end].origin.z() == nodes_[first].origin.z() &&
               triangles + nodes_[end].triangle_count <= kRunTriangles)
            triangles += nodes_[end++].triangle_count;
        tables.drop_below(nodes_[first].origin.z());
        tables.load_around(nodes_.data() + first, end - first);
        batches.resize(end - first);
        tbb::parallel_for(std::size_t{0}, end - first, [&](std::size_t n) { resolve_node(tables, nodes_[first + n], batches[n]); });
        take(batches);
        first = end;
    }
}

void IfcSpill::emit(MeshStreamSink& sink, bool mirrored) {
    std::sort(nodes_.begin(), nodes_.end(), [](const NodeRecord& a, const NodeRecord& b) { return ifc_node_before(a.origin, b.origin); });
    std::uint64_t vertex_count = 0, triangle_count = 0;
    for (NodeRecord& node : nodes_) {
        node.first_vertex = vertex_count;
        vertex_count += node.vertex_count;
        triangle_count += node.triangle_count;
    }
    if (vertex_count >= IfcKeyIndex::kMissing) throw Error("contouring: more than 2^32 vertices");
    // One pass resolves every triangle's keys (the costly part), marking the vertices used (the
    // weld drops the others) and keeping the triangles resolved in a second file, read back in
    // order once the used vertices are counted and written.
    const bool with_corners = sink.needs_corners();
    const std::size_t record_bytes = resolved_record_bytes(with_corners);
    MeshRangeSink* ranges = sink.ranges();
    if (ranges && write_ranges_every_vertex_used(*ranges, with_corners, mirrored, vertex_count, triangle_count)) return;
    TempFile resolved("for the bricks' resolved triangles", held_);
    Used used(vertex_count);
    resolve(nullptr, with_corners, used, appended_to(resolved));
    const std::uint64_t used_count = used.count();
    if (ranges) {
        write_ranges(*ranges, used, resolved, with_corners, mirrored, used_count, triangle_count);
        return;
    }
    sink.begin(used_count, triangle_count);
    for (const NodeRecord& node : nodes_) {
        const std::vector<VertexRecord> vertices = read<VertexRecord>(node.vertex_offset, node.vertex_count);
        for (std::size_t v = 0; v < vertices.size(); ++v) {
            if (used.used(node.first_vertex + v)) sink.vertex(vertices[v].position);
        }
    }
    constexpr std::uint64_t kBatch = 1 << 16;
    std::vector<char> batch;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<Corners> corners;
    for (std::uint64_t first = 0; first < triangle_count; first += kBatch) {
        const std::uint64_t count = std::min(kBatch, triangle_count - first);
        batch.resize(count * record_bytes);
        resolved.read(first * record_bytes, batch.data(), batch.size());
        decode_resolved(batch.data(), std::size_t(count), with_corners, mirrored, &used, triangles, corners);
        for (std::size_t t = 0; t < triangles.size(); ++t) sink.triangle(triangles[t], with_corners ? corners[t] : Corners{});
    }
}

}  // namespace vdbmesh::detail
