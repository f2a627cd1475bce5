// Blocks' cells as bytes (dc_block_bytes.h). Plain memory images of trivially copyable parts:
// the bytes go between ranks of one run of one program, never into a file.

#include "mesh/dc_block_bytes.h"

#include <cstdint>
#include <cstring>
#include <memory>
#include <type_traits>
#include <utility>

#include "vdbmesh/byte_codec.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

static_assert(std::is_trivially_copyable_v<IfcCell>);
static_assert(std::is_trivially_copyable_v<Qef3>);
static_assert(std::is_trivially_copyable_v<openvdb::Coord>);

/// Writes a block's fields (block_fields()) as bytes.
class ByteWriter {
public:
    explicit ByteWriter(std::string& out) : out_(out) {}
    template <typename T>
    void value(const T& v) {
        append_value(out_, v);
    }
    template <typename T>
    void vector(const std::vector<T>& values) {
        append_value(out_, std::uint64_t(values.size()));
        append_values(out_, values);
    }
    void leaves(const IfcLeaves& leaves) {
        value(leaves.level);
        value(leaves.cell);
        vector(leaves.cells);
    }
    void parts(const std::unique_ptr<IfcBlockCells::Parts>& parts) {
        value(bool(parts));
        if (!parts) return;
        leaves(*parts);
        value(parts->clipped_faces);
    }

private:
    std::string& out_;
};

/// Reads what ByteWriter wrote, field by field.
class ByteReader {
public:
    explicit ByteReader(const std::string& in) : in_(in) {}
    bool done() const { return at_ == in_.size(); }
    template <typename T>
    void value(T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        take(&v, sizeof(T));  // a memory image, padding included: written again, the same bytes
    }
    template <typename T>
    void vector(std::vector<T>& values) {
        std::uint64_t count = 0;
        value(count);
        if (count > (in_.size() - at_) / sizeof(T)) fail();
        values.resize(count);
        take(values.data(), count * sizeof(T));
    }
    void leaves(IfcLeaves& leaves) {
        value(leaves.level);
        value(leaves.cell);
        vector(leaves.cells);
    }
    void parts(std::unique_ptr<IfcBlockCells::Parts>& parts) {
        bool present = false;
        value(present);
        if (!present) return;
        parts = std::make_unique<IfcBlockCells::Parts>();
        leaves(*parts);
        value(parts->clipped_faces);
    }

private:
    void take(void* into, std::size_t bytes) {
        if (bytes > in_.size() - at_) fail();
        std::memcpy(into, in_.data() + at_, bytes);
        at_ += bytes;
    }
    [[noreturn]] static void fail() { throw Error("blocks' cells from another rank: the bytes end early (a different program?)"); }

    const std::string& in_;
    std::size_t at_ = 0;
};

/// Every field of @a block, in the one order both ways (@a Io: ByteWriter or ByteReader).
template <typename Io, typename Block>
void block_fields(Io& io, Block& block) {
    io.leaves(block);
    io.value(block.root_leaf);
    io.value(block.root_qef);
    io.parts(block.parts);
    io.value(block.sampled);
    io.value(block.inside_rows);
    io.vector(block.crossings);
    io.value(block.split_decided);
    io.value(block.was_split);
}

}  // namespace

std::string ifc_blocks_bytes(const IfcCellGrid& cells, const std::vector<std::size_t>& blocks) {
    std::string bytes;
    ByteWriter out(bytes);
    for (const std::size_t b : blocks) {
        out.value(cells.origins[b]);
        out.value(bool(cells.blocks[b]));
        if (cells.blocks[b]) block_fields(out, std::as_const(*cells.blocks[b]));
    }
    return bytes;
}

std::string ifc_blocks_bytes(const IfcCellGrid& cells, const IfcOriginFilter& take) {
    std::vector<std::size_t> taken;
    for (std::size_t b = 0; b < cells.origins.size(); ++b) {
        if (take(cells.origins[b])) taken.push_back(b);
    }
    return ifc_blocks_bytes(cells, taken);
}

void append_ifc_blocks(const std::string& bytes, IfcCellGrid& cells) {
    ByteReader in(bytes);
    while (!in.done()) {
        openvdb::Coord origin;
        in.value(origin);
        bool built = false;
        in.value(built);
        cells.origins.push_back(origin);
        cells.blocks.emplace_back();
        if (built) block_fields(in, cells.block_for_writing(cells.blocks.size() - 1));
    }
}

}  // namespace vdbmesh::detail
