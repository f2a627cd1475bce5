// The spill's output written by every rank together (dc_spill.h, emit_on_ranks(); docs/scale.md,
// "Assembly on every rank"). A vertex's number in the file is its node's place in z-major order
// and the used vertices before it, so each rank needs, besides its own nodes: every node's
// counts (one allgather of a few numbers a node), the vertices of the other ranks' nodes beside
// its own (its triangles name them: one exchange of the border nodes' records), and which
// vertices any rank's triangles use (one or-reduction of a bit a vertex). Each rank then formats
// its own nodes' records into local files, the ranks learn each other's byte counts (another
// allgather: an ASCII record's length depends on its numbers), and each copies its bytes to
// their places in the file rank 0 made.

#include <algorithm>
#include <cstring>
#include <set>

#include "mesh/dc_key_index.h"
#include "mesh/dc_spill.h"
#include "vdbmesh/byte_codec.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

/// What every rank learns of each node: where it is, its counts, and later its bytes.
struct NodeSummary {
    std::int32_t origin[3];
    std::uint64_t vertex_count, triangle_count;
};
struct NodeBytes {
    std::uint64_t vertex_bytes, triangle_bytes;
};


/// A node of the whole mesh: its owner and its place among the owner's nodes.
struct GlobalNode {
    openvdb::Coord origin;
    int owner = 0;
    std::size_t index = 0;  ///< among the owner's nodes, in z-major order
};

/// Every rank's nodes (each rank's list z-major), merged into z-major order.
std::vector<GlobalNode> merged_nodes(const std::vector<std::vector<NodeSummary>>& each) {
    std::vector<GlobalNode> all;
    for (std::size_t q = 0; q < each.size(); ++q)
        for (std::size_t n = 0; n < each[q].size(); ++n)
            all.push_back({openvdb::Coord(each[q][n].origin[0], each[q][n].origin[1], each[q][n].origin[2]), int(q), n});
    std::sort(all.begin(), all.end(), [](const GlobalNode& a, const GlobalNode& b) { return ifc_node_before(a.origin, b.origin); });
    return all;
}

/// Copies @a count bytes at @a from of @a local to @a to of @a sink's file, a piece at a time.
void copy_to_sink(const TempFile& local, std::uint64_t from, std::uint64_t count, std::uint64_t to, MeshRangeSink& sink) {
    constexpr std::uint64_t kPiece = std::uint64_t{16} << 20;
    std::vector<char> piece(std::size_t(std::min(kPiece, count)));
    for (std::uint64_t done = 0; done < count;) {
        const std::size_t bytes = std::size_t(std::min<std::uint64_t>(piece.size(), count - done));
        local.read(from + done, piece.data(), bytes);
        sink.write_at(to + done, piece.data(), bytes);
        done += bytes;
    }
}

}  // namespace

IfcSpill::Foreign IfcSpill::swap_borders(const std::map<std::tuple<int, int, int>, std::pair<int, std::uint64_t>>& owners,
                                         const RankCollectives& ranks) const {
    // A node goes to each other rank owning one of its 26 neighbours: that rank's triangles
    // may name its vertices (keys name grid points at most a node away).
    std::vector<std::string> to_each(std::size_t(ranks.ranks));
    for (const NodeRecord& node : nodes_) {
        std::set<int> readers;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const auto it = owners.find(ifc_z_major(node.origin.offsetBy(dx * kNodeVoxels, dy * kNodeVoxels, dz * kNodeVoxels)));
                    if (it != owners.end() && it->second.first != ranks.rank) readers.insert(it->second.first);
                }
        if (readers.empty()) continue;
        const std::vector<VertexRecord> vertices = read<VertexRecord>(node.vertex_offset, node.vertex_count);
        const NodeSummary summary{{node.origin.x(), node.origin.y(), node.origin.z()}, node.vertex_count, 0};
        for (const int q : readers) {
            to_each[std::size_t(q)].append(reinterpret_cast<const char*>(&summary), sizeof(summary));
            append_values(to_each[std::size_t(q)], vertices);
        }
    }
    Foreign foreign;
    for (const std::string& message : ranks.exchange(to_each)) {
        for (std::size_t at = 0; at < message.size();) {
            NodeSummary summary;
            std::memcpy(&summary, message.data() + at, sizeof(summary));
            at += sizeof(summary);
            const std::size_t bytes = summary.vertex_count * sizeof(VertexRecord);
            if (at + bytes > message.size()) throw Error("bricks: a rank sent a truncated border node");
            const auto key = ifc_z_major(openvdb::Coord(summary.origin[0], summary.origin[1], summary.origin[2]));
            ForeignNode& node = foreign[key];
            node.first_vertex = owners.at(key).second;
            node.vertices = values_of<VertexRecord>(message.substr(at, bytes));
            at += bytes;
        }
    }
    return foreign;
}

void IfcSpill::emit_on_ranks(MeshRangeSink& sink, bool with_corners, bool mirrored, const RankCollectives& ranks) {
    std::sort(nodes_.begin(), nodes_.end(), [](const NodeRecord& a, const NodeRecord& b) { return ifc_node_before(a.origin, b.origin); });
    std::vector<NodeSummary> mine;
    for (const NodeRecord& node : nodes_) mine.push_back({{node.origin.x(), node.origin.y(), node.origin.z()}, node.vertex_count, node.triangle_count});
    std::vector<std::vector<NodeSummary>> each;
    for (const std::string& bytes : ranks.allgather(bytes_of(mine))) each.push_back(values_of<NodeSummary>(bytes));
    const std::vector<GlobalNode> all = merged_nodes(each);

    // Every node's first vertex number, as one spill of all would number them (emit()).
    std::map<std::tuple<int, int, int>, std::pair<int, std::uint64_t>> owners;  // z-major origin -> rank, first vertex
    std::uint64_t vertex_count = 0, triangle_count = 0;
    for (const GlobalNode& node : all) {
        const NodeSummary& summary = each[std::size_t(node.owner)][node.index];
        owners[ifc_z_major(node.origin)] = {node.owner, vertex_count};
        if (node.owner == ranks.rank) nodes_[node.index].first_vertex = vertex_count;
        vertex_count += summary.vertex_count;
        triangle_count += summary.triangle_count;
    }
    if (vertex_count >= IfcKeyIndex::kMissing) throw Error("contouring: more than 2^32 vertices");

    const Foreign foreign = swap_borders(owners, ranks);
    TempFile resolved("for the bricks' resolved triangles", held_);
    Used used(vertex_count);
    resolve(&foreign, with_corners, used, appended_to(resolved));
    ranks.or_words(used.words());
    const std::uint64_t used_count = used.count();
    const std::string header = sink.header(used_count, triangle_count);
    const std::string footer = sink.footer();

    // This rank's records formatted into two local files.
    TempFile vertex_text("for this rank's vertices", held_), triangle_text("for this rank's triangles", held_);
    std::vector<NodeBytes> my_bytes(nodes_.size());
    format_records(Records::vertices, sink, &used, &resolved, with_corners, mirrored, [&](std::size_t n, const std::string& bytes) {
        vertex_text.append(bytes.data(), bytes.size());
        my_bytes[n].vertex_bytes = bytes.size();
    });
    format_records(Records::triangles, sink, &used, &resolved, with_corners, mirrored, [&](std::size_t n, const std::string& bytes) {
        triangle_text.append(bytes.data(), bytes.size());
        my_bytes[n].triangle_bytes = bytes.size();
    });

    // Each node's place in the file: the header, every node's vertices, every node's triangles.
    std::vector<std::vector<NodeBytes>> bytes_each;
    for (const std::string& bytes : ranks.allgather(bytes_of(my_bytes))) bytes_each.push_back(values_of<NodeBytes>(bytes));
    std::uint64_t vertices_end = header.size();
    for (const GlobalNode& node : all) vertices_end += bytes_each[std::size_t(node.owner)][node.index].vertex_bytes;
    std::uint64_t vertex_at = header.size(), triangle_at = vertices_end, my_vertex_at = 0, my_triangle_at = 0;

    const std::string made = ranks.rank == 0 ? sink.open("") : std::string();
    const std::string shared = ranks.from_rank0(made);
    bool written = false;
    try {
        if (ranks.rank != 0) sink.open(shared);
        for (const GlobalNode& node : all) {
            const NodeBytes& bytes = bytes_each[std::size_t(node.owner)][node.index];
            if (node.owner == ranks.rank) {
                copy_to_sink(vertex_text, my_vertex_at, bytes.vertex_bytes, vertex_at, sink);
                copy_to_sink(triangle_text, my_triangle_at, bytes.triangle_bytes, triangle_at, sink);
                my_vertex_at += bytes.vertex_bytes, my_triangle_at += bytes.triangle_bytes;
            }
            vertex_at += bytes.vertex_bytes, triangle_at += bytes.triangle_bytes;
        }
        if (ranks.rank == 0) {
            sink.write_at(0, header.data(), header.size());
            sink.write_at(triangle_at, footer.data(), footer.size());
        }
        written = true;
    } catch (...) {
        // Every rank learns that one failed, so that none waits and rank 0 removes the file.
        ranks.all(false);
        sink.close(false);
        throw;
    }
    const bool everyone = ranks.all(written);
    sink.close(everyone);
    if (!everyone) throw Error("bricks: another rank failed to write its part of the mesh");
}

}  // namespace vdbmesh::detail
