#pragma once
// Private: the spill of bricked contouring (docs/dmc.md, "Bricks"): each node's keyed vertices
// and triangles appended to an unlinked temporary file as soon as its brick is meshed, then
// read back node by node in z-major order, keys resolved to vertex numbers, into a sink.

#include <cstdint>
#include <string>
#include <vector>

#include "vdbmesh/temp_file.h"
#include "mesh/dual_contouring.h"

namespace vdbmesh::detail {

class IfcSpill {
public:

    /// Writes @a node's vertices (its blocks' lists, then its coarse cells) and triangles, and
    /// frees them. Each node comes once, in any order.
    void append(IfcNodeOutput&& node);
    /// The mesh weld_ifc_nodes() makes of every node appended, into @a sink; with @a mirrored
    /// every triangle wound the other way (mesh_grid()'s rule for a mirroring transform).
    void emit(MeshStreamSink& sink, bool mirrored);
    /// Every node appended, as bytes another process's spill takes with absorb() (a run over
    /// several ranks sends them to rank 0).
    std::string serialized() const;
    /// Takes the nodes of another spill's serialized() bytes, as if appended here.
    void absorb(const std::string& bytes);

    struct NodeRecord {
        openvdb::Coord origin;
        std::uint64_t vertex_offset = 0, vertex_count = 0;  ///< in the file: bytes, records
        std::uint64_t triangle_offset = 0, triangle_count = 0;
        std::uint64_t first_vertex = 0;  ///< its first vertex's number before unused ones are dropped
    };

private:
    struct VertexRecord {
        std::uint64_t key;
        std::array<float, 3> position;
    };
    template <typename T>
    void write(const std::vector<T>& records) {
        if (!records.empty()) file_.append(records.data(), records.size() * sizeof(T));
    }
    template <typename T>
    std::vector<T> read(std::uint64_t offset, std::uint64_t count) const {
        std::vector<T> records(count);
        if (count > 0) file_.read(offset, records.data(), count * sizeof(T));
        return records;
    }
    class Tables;

    TempFile file_{"for the bricks' spill"};
    std::vector<NodeRecord> nodes_;
};

}  // namespace vdbmesh::detail
