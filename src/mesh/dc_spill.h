#pragma once
// Private: the spill of bricked contouring (docs/dmc.md, "Bricks"): each node's keyed vertices
// and triangles appended to an unlinked temporary file as soon as its brick is meshed, then
// read back node by node in z-major order, keys resolved to vertex numbers, into a sink.

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "vdbmesh/mesher.h"
#include "vdbmesh/ranks.h"
#include "vdbmesh/temp_file.h"
#include "mesh/dual_contouring.h"

namespace vdbmesh::detail {

/// A node's place in z-major order, as a map key.
inline std::tuple<int, int, int> ifc_z_major(const openvdb::Coord& c) { return {c.z(), c.y(), c.x()}; }

class IfcSpill {
public:
    /// Its file, and the emit's, on disk (a memory limit) or held in memory (none).
    explicit IfcSpill(TempFile::Held held = TempFile::Held::on_disk) : held_(held), file_("for the bricks' spill", held) {}

    /// Writes @a node's vertices (its blocks' lists, then its coarse cells) and triangles, and
    /// frees them. Each node comes once, in any order.
    void append(IfcNodeOutput&& node);
    /// The mesh weld_ifc_nodes() makes of every node appended, into @a sink; with @a mirrored
    /// every triangle wound the other way (mesh_grid()'s rule for a mirroring transform). A
    /// sink with ranges() gets its records formatted in parallel and written in order.
    void emit(MeshStreamSink& sink, bool mirrored);
    /// emit() by every rank together (BrickOptions::collectives; docs/scale.md, "Assembly on
    /// every rank"): each rank's spill holds its own nodes; the ranks learn each other's node
    /// counts, swap the vertices of the nodes beside another rank's, resolve their own
    /// triangles, or together which vertices are used, and each writes its own nodes' records
    /// at their places in @a sink's shared file. The same bytes as emit() on one spill of all.
    void emit_on_ranks(MeshRangeSink& sink, bool with_corners, bool mirrored, const RankCollectives& ranks);
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
    class Used;
    struct ForeignNode;
    using Foreign = std::map<std::tuple<int, int, int>, ForeignNode>;
    /// A run of nodes resolved, in order: each node's triangles resolved (records of resolve());
    /// the callee may take the batches' bytes.
    using ResolvedRun = std::function<void(std::vector<std::vector<char>>& batches)>;
    using Corners = std::array<std::array<float, 3>, 3>;
    /// Bytes of resolve()'s record of a triangle: its three vertex numbers, then, @a
    /// with_corners, their positions.
    static std::size_t resolved_record_bytes(bool with_corners) {
        return sizeof(std::array<std::uint32_t, 3>) + (with_corners ? sizeof(Corners) : 0);
    }
    /// The @a count records of resolve() at @a records as triangles numbered among the used
    /// vertices (@a used; null: every vertex is) and, @a with_corners, their corners (else
    /// @a corners is left empty), wound the other way when @a mirrored.
    static void decode_resolved(const char* records, std::size_t count, bool with_corners, bool mirrored, const Used* used,
                                std::vector<std::array<std::uint32_t, 3>>& triangles, std::vector<Corners>& corners);
    /// Resolves the triangles of nodes_ (sorted, numbered), a run of nodes at a time, into
    /// @a take: each triangle its vertex numbers (before unused ones are dropped), then, @a
    /// with_corners, its corners; marks the vertices used in @a used. @a foreign: other ranks'
    /// nodes beside these, if any.
    void resolve(const Foreign* foreign, bool with_corners, Used& used, const ResolvedRun& take) const;
    /// A ResolvedRun that appends the runs to @a resolved, in order.
    static ResolvedRun appended_to(TempFile& resolved);
    /// The vertex records of the nodes beside other ranks' nodes, to each rank (emit_on_ranks()).
    Foreign swap_borders(const std::map<std::tuple<int, int, int>, std::pair<int, std::uint64_t>>& owners, const RankCollectives& ranks) const;

    /// Which records format_records() formats.
    enum class Records { vertices, triangles };
    /// Formats with @a format, for each node of nodes_ in order, its used vertices (@a used;
    /// null: all of them) or its triangles resolved into @a resolved (numbered among the used
    /// vertices; wound the other way when @a mirrored), and hands @a take each node's index and
    /// bytes in that order. Runs
    /// of nodes are formatted in parallel while the one before is taken (dc_spill_records.cpp).
    void format_records(Records which, const MeshRangeSink& format, const Used* used, const TempFile* resolved, bool with_corners,
                        bool mirrored, const std::function<void(std::size_t, const std::string&)>& take) const;
    /// emit()'s end into @a sink's file (one process): the header, then every node's records
    /// as format_records() gives them, at their places; the file committed when all are written.
    void write_ranges(MeshRangeSink& sink, const Used& used, const TempFile& resolved, bool with_corners, bool mirrored,
                      std::uint64_t used_count, std::uint64_t triangle_count) const;
    /// write_ranges() in one pass, for when every vertex is used (every scan measured): the
    /// vertices written first, the triangles formatted and written as they are resolved, without
    /// the resolved file. Returns false, the file removed, when a vertex turned out unused (the
    /// weld drops it, so the numbers change): emit() then takes the two passes.
    bool write_ranges_every_vertex_used(MeshRangeSink& sink, bool with_corners, bool mirrored, std::uint64_t vertex_count,
                                        std::uint64_t triangle_count) const;

    std::string records_bytes() const;

    TempFile::Held held_;
    TempFile file_;
    std::vector<NodeRecord> nodes_;
};

/// Which vertices some triangle uses, and each used one's number among them (rank()).
class IfcSpill::Used {
public:
    explicit Used(std::uint64_t count) : words_((count + 63) / 64, 0) {}
    /// Safe to call from several threads at once.
    void mark(std::uint64_t v) { __atomic_fetch_or(&words_[v / 64], std::uint64_t(1) << (v % 64), __ATOMIC_RELAXED); }
    bool used(std::uint64_t v) const { return (words_[v / 64] >> (v % 64)) & 1u; }
    /// Counts the used vertices; rank() answers after this.
    std::uint64_t count() {
        before_.resize(words_.size());
        std::uint64_t total = 0;
        for (std::size_t w = 0; w < words_.size(); ++w) {
            before_[w] = total;
            total += std::uint64_t(__builtin_popcountll(words_[w]));
        }
        return total;
    }
    /// The marks, a bit a vertex: or-ed over ranks by emit_on_ranks().
    std::vector<std::uint64_t>& words() { return words_; }
    /// The number of used vertices before @a v.
    std::uint64_t rank(std::uint64_t v) const {
        const std::uint64_t below = words_[v / 64] & ((std::uint64_t(1) << (v % 64)) - 1);
        return before_[v / 64] + std::uint64_t(__builtin_popcountll(below));
    }

private:
    std::vector<std::uint64_t> words_, before_;
};

/// Another rank's node beside this rank's (emit_on_ranks()): its number and its vertices.
struct IfcSpill::ForeignNode {
    std::uint64_t first_vertex = 0;
    std::vector<VertexRecord> vertices;
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
