// The splat tree's file: a header, 12 bytes a node in breadth-first order, then the weights of
// the childless nodes (little-endian).
//
//   header  "VDBSPLT2", u32 node count, u32 the root's child count, f32 x 3 box minimum,
//           f32 box extent, f64 isovalue, u8 inside (0 above, 1 below), f32 tolerance;
//           the grid fitted (SplatGridId): u64 file bytes, u64 topology hash, i64 modified,
//           u8 checksum length, the checksum's characters
//   node    u16 x 3 centre (65535 steps over the box's extent), u16 radius (steps of twice
//           that, rounded up and widened by the centre's rounding), u8 x 2 octahedral normal,
//           u8 cone (steps of pi / 255, rounded up and widened by the normals' rounding),
//           u8 child count (the root's is in the header)
//   weight  u16 per childless node, in node order (at most 1944 edges cross an 8^3 cube, the
//           largest childless node): an inner node's weight is the sum of its children's
//
// The levels follow from the order (the root's children are level 11, each child one below
// its parent).

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include "vdbmesh/atomic_file.h"
#include "vdbmesh/byte_codec.h"
#include "vdbmesh/error.h"
#include "vdbmesh/splats.h"

namespace vdbmesh {
namespace {

constexpr char kMagic[8] = {'V', 'D', 'B', 'S', 'P', 'L', 'T', '2'};
/// Up to the checksum's characters.
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 12 + 4 + 8 + 1 + 4 + 8 + 8 + 8 + 1;
constexpr std::size_t kWeightBytes = 2;
constexpr std::size_t kNodeBytes = 12;
constexpr double kPi = 3.14159265358979323846;
constexpr double kSteps = 65535;


/// The box the centres are quantised over: its minimum and its largest edge.
struct QuantBox {
    std::array<float, 3> min{};
    float extent = 1;
    double step() const { return extent / kSteps; }
};

QuantBox centre_box(const std::vector<SplatNode>& nodes) {
    QuantBox box;
    if (nodes.empty()) return box;
    std::array<float, 3> lo = nodes[0].centre, hi = nodes[0].centre;
    for (const SplatNode& n : nodes)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], n.centre[a]);
            hi[a] = std::max(hi[a], n.centre[a]);
        }
    box.min = lo;
    box.extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-6f});
    return box;
}

/// A whole number of steps (already rounded) as 16 bits.
std::uint16_t steps16(double steps) { return static_cast<std::uint16_t>(std::clamp(steps, 0.0, kSteps)); }

void put_node(std::string& out, const SplatNode& n, const QuantBox& box) {
    const double step = box.step();
    for (int a = 0; a < 3; ++a) detail::append_value(out, steps16(std::round((n.centre[a] - box.min[a]) / step)));
    // Rounded centres move by up to half a step on each axis: the radius grows by that much.
    detail::append_value(out, steps16(std::ceil((n.radius + step * std::sqrt(3.0) / 2) / (2 * step))));
    const auto code = detail::encode_splat_normal(n.normal);
    detail::append_value(out, code[0]);
    detail::append_value(out, code[1]);
    const double cone = std::ceil((n.cone + 2 * detail::kSplatNormalRounding) / (kPi / 255));
    detail::append_value(out, static_cast<std::uint8_t>(std::min(cone, 255.0)));
    detail::append_value(out, static_cast<std::uint8_t>(std::min<std::uint32_t>(n.child_count, 255)));
}

/// The file's bytes in one read (a huge tree's file is a hundred megabytes or more).
std::string read_all(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw Error(path.string() + ": cannot open for reading");
    std::string bytes(static_cast<std::size_t>(in.tellg()), '\0');
    in.seekg(0);
    if (!in.read(bytes.data(), std::streamsize(bytes.size()))) throw Error(path.string() + ": cannot read it");
    return bytes;
}

/// The nodes' quantised fields (12 bytes each from @a at), decoded in parallel: each node's
/// bytes are its own. Children, levels and weights follow (link_children()).
void decode_nodes(std::vector<SplatNode>& nodes, const std::string& in, std::size_t at, const QuantBox& box) {
    const double step = box.step();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes.size(), 4096), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            SplatNode& n = nodes[i];
            std::size_t from = at + kNodeBytes * i;
            for (int a = 0; a < 3; ++a) n.centre[a] = static_cast<float>(box.min[a] + detail::read_value<std::uint16_t>(in, from) * step);
            n.radius = static_cast<float>(detail::read_value<std::uint16_t>(in, from) * 2 * step);
            std::array<std::uint8_t, 2> code{};
            code[0] = detail::read_value<std::uint8_t>(in, from);
            code[1] = detail::read_value<std::uint8_t>(in, from);
            n.normal = detail::decode_splat_normal(code);
            n.cone = static_cast<float>(detail::read_value<std::uint8_t>(in, from) * kPi / 255);
            n.child_count = detail::read_value<std::uint8_t>(in, from);
        }
    });
}

/// Sets each node's first child, child count (the root's from the header) and level from the
/// breadth-first order, and each childless node's weight from the weights after the nodes
/// (at @a weights_at, in node order); throws when the counts do not add up to the nodes or the
/// file's size to the weights. One pass: the nodes of a huge tree are hundreds of megabytes.
void link_children(std::vector<SplatNode>& nodes, std::uint32_t root_children, const std::string& in,
                   std::size_t weights_at, const std::string& file) {
    nodes[0].child_count = root_children;
    nodes[0].level = kSplatRootLevel;
    std::uint64_t next = 1;
    std::size_t at = weights_at;
    const auto size_error = [&](std::size_t childless) {
        return FormatError(file, "size", std::to_string(weights_at + kWeightBytes * childless) + " bytes for " +
                           std::to_string(nodes.size()) + " nodes and the weights of " + std::to_string(childless) +
                           " childless ones", std::to_string(in.size()));
    };
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        SplatNode& n = nodes[i];
        if (i >= next) throw FormatError(file, "node " + std::to_string(i), "a child of an earlier node", "none");
        if (n.child_count != 0 && n.level == 0)
            throw FormatError(file, "node " + std::to_string(i) + " child count", "0 at level 0", std::to_string(n.child_count));
        n.first_child = static_cast<std::uint32_t>(next);
        next += n.child_count;
        if (next > nodes.size())
            throw FormatError(file, "node " + std::to_string(i) + " child count", "children within the " +
                              std::to_string(nodes.size()) + " nodes", std::to_string(n.child_count));
        for (std::uint32_t c = 0; c < n.child_count; ++c) nodes[n.first_child + c].level = std::uint8_t(n.level - 1);
        if (n.child_count != 0) continue;
        if (at + kWeightBytes > in.size()) {
            const auto childless = std::count_if(nodes.begin(), nodes.end(), [](const SplatNode& m) { return m.child_count == 0; });
            throw size_error(std::size_t(childless));
        }
        n.weight = detail::read_value<std::uint16_t>(in, at);
    }
    if (next != nodes.size())
        throw FormatError(file, "child counts", "a total of " + std::to_string(nodes.size() - 1), std::to_string(next - 1));
    if (at != in.size()) throw size_error((at - weights_at) / kWeightBytes);
}

/// Sums the childless nodes' weights up the tree (children follow their parents in
/// breadth-first order, so a backward walk meets children first).
void sum_weights(std::vector<SplatNode>& nodes) {
    for (std::size_t i = nodes.size(); i-- > 0;) {
        SplatNode& n = nodes[i];
        if (n.child_count == 0) continue;
        std::uint64_t sum = 0;
        for (std::uint32_t c = n.first_child; c < n.first_child + n.child_count; ++c) sum += nodes[c].weight;
        n.weight = std::uint32_t(std::min<std::uint64_t>(sum, UINT32_MAX));
    }
}

void put_grid_id(std::string& out, const SplatGridId& id) {
    detail::append_value(out, id.file_bytes);
    detail::append_value(out, id.topology);
    detail::append_value(out, id.modified);
    const std::string checksum = id.checksum.substr(0, 255);
    detail::append_value(out, static_cast<std::uint8_t>(checksum.size()));
    out += checksum;
}

}  // namespace

namespace detail {

std::array<std::uint8_t, 2> encode_splat_normal(const std::array<float, 3>& normal) {
    const double l1 = std::abs(normal[0]) + std::abs(normal[1]) + std::abs(normal[2]);
    double u = l1 > 0 ? normal[0] / l1 : 0, v = l1 > 0 ? normal[1] / l1 : 0;
    if (normal[2] < 0) {
        const double fu = (1 - std::abs(v)) * (u >= 0 ? 1 : -1), fv = (1 - std::abs(u)) * (v >= 0 ? 1 : -1);
        u = fu;
        v = fv;
    }
    const auto byte = [](double x) { return static_cast<std::uint8_t>(std::lround((x + 1) * 127.5)); };
    return {byte(u), byte(v)};
}

std::array<float, 3> decode_splat_normal(const std::array<std::uint8_t, 2>& code) {
    double u = code[0] / 127.5 - 1, v = code[1] / 127.5 - 1;
    const double z = 1 - std::abs(u) - std::abs(v);
    if (z < 0) {
        const double fu = (1 - std::abs(v)) * (u >= 0 ? 1 : -1), fv = (1 - std::abs(u)) * (v >= 0 ? 1 : -1);
        u = fu;
        v = fv;
    }
    const double length = std::sqrt(u * u + v * v + z * z);
    return {float(u / length), float(v / length), float(z / length)};
}

}  // namespace detail

void write_splat_file(const SplatTree& tree, const std::filesystem::path& path) {
    const QuantBox box = centre_box(tree.nodes);
    std::string out;
    out.reserve(kHeaderBytes + kNodeBytes * tree.nodes.size());
    out.append(kMagic, sizeof(kMagic));
    detail::append_value(out, static_cast<std::uint32_t>(tree.nodes.size()));
    detail::append_value(out, static_cast<std::uint32_t>(tree.nodes.empty() ? 0 : tree.nodes[0].child_count));
    for (float m : box.min) detail::append_value(out, m);
    detail::append_value(out, box.extent);
    detail::append_value(out, tree.iso);
    detail::append_value(out, static_cast<std::uint8_t>(tree.inside == Inside::below));
    detail::append_value(out, static_cast<float>(tree.tolerance));
    put_grid_id(out, tree.grid);
    for (const SplatNode& n : tree.nodes) put_node(out, n, box);
    for (const SplatNode& n : tree.nodes)
        if (n.child_count == 0) detail::append_value(out, static_cast<std::uint16_t>(std::min<std::uint32_t>(n.weight, UINT16_MAX)));
    AtomicFile file(path);
    std::ofstream stream(file.temp_path(), std::ios::binary);
    stream.write(out.data(), std::streamsize(out.size()));
    stream.close();
    if (!stream) throw Error(path.string() + ": cannot write the splat file");
    file.commit();
}

SplatTree read_splat_file(const std::filesystem::path& path) {
    const std::string file = path.string();
    const std::string in = read_all(path);
    if (in.size() < kHeaderBytes || std::memcmp(in.data(), kMagic, sizeof(kMagic)) != 0)
        throw FormatError(file, "header", "a splat file starting with VDBSPLT2", in.size() < kHeaderBytes ? "a shorter file" : "other bytes");
    std::size_t at = sizeof(kMagic);
    const auto count = detail::read_value<std::uint32_t>(in, at);
    const auto root_children = detail::read_value<std::uint32_t>(in, at);
    const std::size_t checksum_chars = std::uint8_t(in[kHeaderBytes - 1]);
    const std::uint64_t nodes_end = kHeaderBytes + checksum_chars + kNodeBytes * std::uint64_t(count);
    if (in.size() < nodes_end)
        throw FormatError(file, "size", "at least " + std::to_string(nodes_end) + " bytes for " + std::to_string(count) + " nodes",
                          std::to_string(in.size()));
    QuantBox box;
    for (float& m : box.min) m = detail::read_value<float>(in, at);
    box.extent = detail::read_value<float>(in, at);
    SplatTree tree;
    tree.iso = detail::read_value<double>(in, at);
    const auto inside = detail::read_value<std::uint8_t>(in, at);
    if (inside > 1) throw FormatError(file, "inside", "0 or 1", std::to_string(inside));
    tree.inside = inside ? Inside::below : Inside::above;
    tree.tolerance = detail::read_value<float>(in, at);
    tree.grid.file_bytes = detail::read_value<std::uint64_t>(in, at);
    tree.grid.topology = detail::read_value<std::uint64_t>(in, at);
    tree.grid.modified = detail::read_value<std::int64_t>(in, at);
    at += 1;
    tree.grid.checksum = in.substr(at, checksum_chars);
    at += checksum_chars;
    if (!(box.extent > 0)) throw FormatError(file, "box extent", "> 0", std::to_string(box.extent));
    tree.nodes.resize(count);
    decode_nodes(tree.nodes, in, at, box);
    if (count != 0) {
        link_children(tree.nodes, root_children, in, std::size_t(nodes_end), file);
        sum_weights(tree.nodes);
    } else if (in.size() != nodes_end) {
        throw FormatError(file, "size", std::to_string(nodes_end) + " bytes for no nodes", std::to_string(in.size()));
    }
    return tree;
}

}  // namespace vdbmesh
