#pragma once
// Private: the spill of bricked contouring (docs/dmc.md, "Bricks"): each node's keyed vertices
// and triangles appended to an unlinked temporary file as soon as its brick is meshed, then
// read back node by node in z-major order, keys resolved to vertex numbers, into a sink.

#include <cstdint>
#include <string>
#include <vector>

#include "vdbmesh/ranks.h"
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
    /// Every node appended, as a part another process's spill takes with a Receiver (a run
    /// over several ranks streams them to rank 0): the node records, then the file's bytes.
    RankPart part() const;
    /// Takes the parts of other spills into this one, as if their nodes were appended here.
    class Receiver;

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

    std::string records_bytes() const;

    TempFile file_{"for the bricks' spill"};
    std::vector<NodeRecord> nodes_;
};

/// Appends each part it receives to its spill: the header (the node count and records) held
/// until whole, the body written to the file as it comes.
class IfcSpill::Receiver final : public PartReceiver {
public:
    explicit Receiver(IfcSpill& spill) : spill_(spill) {}
    void begin(int rank, std::uint64_t size) override;
    void piece(const char* bytes, std::size_t count) override;

private:
    void take_header();

    IfcSpill& spill_;
    int rank_ = 0;
    std::uint64_t left_ = 0;      ///< of the part's bytes, still to come
    std::string header_;          ///< the part's count and records, while incomplete
    std::uint64_t header_size_ = 0;
    std::uint64_t base_ = 0;      ///< where the part's body starts in the spill's file
};

}  // namespace vdbmesh::detail
