// KeptRows (kept_rows.h). A run is one row's leaves and tiles in one node column:
//   leaves (uint32), tiles (uint32), then each leaf: origin (3 x int32), value mask (64 bytes),
//   the kind of its values (1 byte), its 512 values; then each tile: origin (3 x int32), value.
// Runs follow each other by row, then node row (y), then node column (x), so the runs of one
// node row across a range of x are one stretch of the file.

#include "kept_rows.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "vdbmesh/byte_codec.h"
#include "vdbmesh/grid_region.h"

namespace vdbmesh::detail {

namespace {

using MaskWord = Leaf::NodeMaskType::Word;

/// How a leaf's 512 values are kept.
enum class ValueKind : std::uint8_t { float32 = 0, uint16 = 1, int16 = 2 };

/// Whether every value of @a values is an integer of type T whose float has the same bits
/// (so -0 and NaN are kept as floats).
template <typename T>
bool holds_exactly(const float* values) {
    for (openvdb::Index n = 0; n < Leaf::SIZE; ++n) {
        const float v = values[n];
        if (!(v >= float(std::numeric_limits<T>::min()) && v <= float(std::numeric_limits<T>::max()))) return false;
        const float back = static_cast<float>(static_cast<T>(v));
        if (std::memcmp(&back, &v, sizeof v) != 0) return false;
    }
    return true;
}

template <typename T>
void append_narrowed(std::string& out, const float* values) {
    T narrow[Leaf::SIZE];
    for (openvdb::Index n = 0; n < Leaf::SIZE; ++n) narrow[n] = static_cast<T>(values[n]);
    append_values(out, narrow, Leaf::SIZE);
}

void append_leaf(std::string& out, const Leaf& leaf) {
    const openvdb::Coord origin = leaf.origin();
    for (int axis = 0; axis < 3; ++axis) append_value(out, std::int32_t(origin[axis]));
    const Leaf::NodeMaskType& mask = leaf.getValueMask();
    for (openvdb::Index w = 0; w < Leaf::NodeMaskType::WORD_COUNT; ++w) append_value(out, mask.getWord<MaskWord>(w));
    const float* values = leaf.buffer().data();
    if (holds_exactly<std::uint16_t>(values)) {
        append_value(out, ValueKind::uint16);
        append_narrowed<std::uint16_t>(out, values);
    } else if (holds_exactly<std::int16_t>(values)) {
        append_value(out, ValueKind::int16);
        append_narrowed<std::int16_t>(out, values);
    } else {
        append_value(out, ValueKind::float32);
        append_values(out, values, Leaf::SIZE);
    }
}

template <typename T>
void widen(const std::string& in, std::size_t& at, float* values) {
    T narrow[Leaf::SIZE];
    std::memcpy(narrow, in.data() + at, sizeof narrow);
    at += sizeof narrow;
    for (openvdb::Index n = 0; n < Leaf::SIZE; ++n) values[n] = static_cast<float>(narrow[n]);
}

openvdb::Coord read_origin(const std::string& in, std::size_t& at) {
    openvdb::Coord origin;
    for (int axis = 0; axis < 3; ++axis) origin[axis] = read_value<std::int32_t>(in, at);
    return origin;
}

std::unique_ptr<Leaf> read_leaf(const std::string& in, std::size_t& at) {
    auto leaf = std::make_unique<Leaf>(read_origin(in, at), 0.0f);
    Leaf::NodeMaskType mask;
    for (openvdb::Index w = 0; w < Leaf::NodeMaskType::WORD_COUNT; ++w) mask.getWord<MaskWord>(w) = read_value<MaskWord>(in, at);
    leaf->setValueMask(mask);
    float* values = leaf->buffer().data();
    switch (read_value<ValueKind>(in, at)) {
        case ValueKind::uint16: widen<std::uint16_t>(in, at, values); break;
        case ValueKind::int16: widen<std::int16_t>(in, at, values); break;
        case ValueKind::float32:
            std::memcpy(values, in.data() + at, Leaf::SIZE * sizeof(float));
            at += Leaf::SIZE * sizeof(float);
            break;
    }
    return leaf;
}

}  // namespace

KeptRows::KeptRows(int first_column, int columns_x, int columns_y)
    : first_column_(first_column), columns_x_(columns_x), columns_y_(columns_y) {}

int KeptRows::column(std::int64_t voxel) const { return floor_div(voxel, kNodeVoxels) - first_column_; }

void KeptRows::add(const ConvertedRow& row) {
    const std::size_t columns = std::size_t(columns_x_) * columns_y_;
    auto column_of = [&](const openvdb::Coord& origin) { return std::size_t(column(origin.y())) * columns_x_ + column(origin.x()); };
    // Leaves and tiles in order of node column (a counting sort, stable: block order within one).
    std::vector<std::uint32_t> leaves(columns + 1, 0), tiles(columns + 1, 0);
    for (const auto& leaf : row.leaves) ++leaves[column_of(leaf->origin()) + 1];
    for (const auto& tile : row.tiles) ++tiles[column_of(tile.first) + 1];
    std::vector<std::uint32_t> leaf_order(row.leaves.size()), tile_order(row.tiles.size());
    std::vector<std::uint32_t> next_leaf(leaves), next_tile(tiles);
    for (std::size_t c = 1; c <= columns; ++c) next_leaf[c] += next_leaf[c - 1], next_tile[c] += next_tile[c - 1];
    for (std::uint32_t i = 0; i < row.leaves.size(); ++i) leaf_order[next_leaf[column_of(row.leaves[i]->origin())]++] = i;
    for (std::uint32_t i = 0; i < row.tiles.size(); ++i) tile_order[next_tile[column_of(row.tiles[i].first)]++] = i;

    std::string bytes;
    std::size_t leaf_at = 0, tile_at = 0;
    std::uint64_t node_row_start = file_.size();
    for (std::size_t c = 0; c < columns; ++c) {
        if (c % columns_x_ == 0) {
            largest_stretch_ = std::max(largest_stretch_, file_.size() + bytes.size() - node_row_start);
            node_row_start = file_.size() + bytes.size();
        }
        runs_.push_back(file_.size() + bytes.size());
        append_value(bytes, leaves[c + 1]);
        append_value(bytes, tiles[c + 1]);
        for (std::uint32_t n = 0; n < leaves[c + 1]; ++n) append_leaf(bytes, *row.leaves[leaf_order[leaf_at++]]);
        for (std::uint32_t n = 0; n < tiles[c + 1]; ++n) {
            const auto& [origin, value] = row.tiles[tile_order[tile_at++]];
            for (int axis = 0; axis < 3; ++axis) append_value(bytes, std::int32_t(origin[axis]));
            append_value(bytes, value);
        }
    }
    largest_stretch_ = std::max(largest_stretch_, file_.size() + bytes.size() - node_row_start);
    file_.append(bytes.data(), bytes.size());
    rows_.push_back(row.z0);
}

std::vector<ConvertedRow> KeptRows::read(int first, int last, int x0, int x1, int y0, int y1) const {
    x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, columns_x_), y1 = std::min(y1, columns_y_);
    std::vector<ConvertedRow> rows;
    if (x0 >= x1 || y0 >= y1) return rows;
    std::string stretch;
    const auto begin = std::lower_bound(rows_.begin(), rows_.end(), first);
    for (auto z0 = begin; z0 != rows_.end() && *z0 <= last; ++z0) {
        const std::size_t row = std::size_t(z0 - rows_.begin());
        ConvertedRow& out = rows.emplace_back();
        out.z0 = *z0;
        for (int y = y0; y < y1; ++y) {
            const std::uint64_t from = runs_[run_index(row, x0, y)];
            const std::size_t end_run = run_index(row, x1 - 1, y) + 1;
            const std::uint64_t to = end_run < runs_.size() ? runs_[end_run] : file_.size();
            stretch.resize(to - from);
            file_.read(from, stretch.data(), stretch.size());
            std::size_t at = 0;
            for (int x = x0; x < x1; ++x) {
                const auto leaves = read_value<std::uint32_t>(stretch, at);
                const auto tiles = read_value<std::uint32_t>(stretch, at);
                for (std::uint32_t n = 0; n < leaves; ++n) out.leaves.push_back(read_leaf(stretch, at));
                for (std::uint32_t n = 0; n < tiles; ++n) {
                    const openvdb::Coord origin = read_origin(stretch, at);
                    out.tiles.emplace_back(origin, read_value<float>(stretch, at));
                }
            }
        }
    }
    return rows;
}

}  // namespace vdbmesh::detail
