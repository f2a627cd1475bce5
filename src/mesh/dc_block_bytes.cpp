// Blocks' cells as bytes (dc_block_bytes.h). Plain memory images of trivially copyable parts:
// the bytes go between ranks of one run of one program, never into a file.

#include "mesh/dc_block_bytes.h"

#include <cstdint>
#include <cstring>
#include <type_traits>

#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

static_assert(std::is_trivially_copyable_v<IfcCell>);
static_assert(std::is_trivially_copyable_v<Qef3>);
static_assert(std::is_trivially_copyable_v<openvdb::Coord>);

class ByteWriter {
public:
    explicit ByteWriter(std::string& out) : out_(out) {}
    template <typename T>
    void put(const T& value) {
        static_assert(std::is_trivially_copyable_v<T>);
        out_.append(reinterpret_cast<const char*>(&value), sizeof(T));
    }
    template <typename T>
    void put_vector(const std::vector<T>& values) {
        put(std::uint64_t(values.size()));
        out_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    }
    void put_leaves(const IfcLeaves& leaves) {
        put(leaves.level);
        put(leaves.cell);
        put_vector(leaves.cells);
    }

private:
    std::string& out_;
};

class ByteReader {
public:
    explicit ByteReader(const std::string& in) : in_(in) {}
    bool done() const { return at_ == in_.size(); }
    template <typename T>
    void get(T& value) {
        static_assert(std::is_trivially_copyable_v<T>);
        take(&value, sizeof(T));
    }
    template <typename T>
    void get_vector(std::vector<T>& values) {
        std::uint64_t count = 0;
        get(count);
        if (count > (in_.size() - at_) / sizeof(T)) fail();
        values.resize(count);
        take(values.data(), count * sizeof(T));
    }
    void get_leaves(IfcLeaves& leaves) {
        get(leaves.level);
        get(leaves.cell);
        get_vector(leaves.cells);
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

void write_block(ByteWriter& out, const IfcBlockCells& block) {
    out.put_leaves(block);
    out.put(block.root_leaf);
    out.put(block.root_qef);
    out.put(bool(block.parts));
    if (block.parts) {
        out.put_leaves(*block.parts);
        out.put(block.parts->clipped_faces);
    }
    out.put(block.sampled);
    out.put(block.inside_rows);
    out.put_vector(block.crossings);
    out.put(block.split_decided);
    out.put(block.was_split);
}

void read_block(ByteReader& in, IfcBlockCells& block) {
    in.get_leaves(block);
    in.get(block.root_leaf);
    in.get(block.root_qef);
    bool has_parts = false;
    in.get(has_parts);
    if (has_parts) {
        block.parts = std::make_unique<IfcBlockCells::Parts>();
        in.get_leaves(*block.parts);
        in.get(block.parts->clipped_faces);
    }
    in.get(block.sampled);
    in.get(block.inside_rows);
    in.get_vector(block.crossings);
    in.get(block.split_decided);
    in.get(block.was_split);
}

}  // namespace

std::string ifc_blocks_bytes(const IfcCellGrid& cells, const std::vector<std::size_t>& blocks) {
    std::string bytes;
    ByteWriter out(bytes);
    for (const std::size_t b : blocks) {
        out.put(cells.origins[b]);
        out.put(bool(cells.blocks[b]));
        if (cells.blocks[b]) write_block(out, *cells.blocks[b]);
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
        in.get(origin);
        bool built = false;
        in.get(built);
        cells.origins.push_back(origin);
        cells.blocks.emplace_back();
        if (built) read_block(in, cells.block_for_writing(cells.blocks.size() - 1));
    }
}

}  // namespace vdbmesh::detail
