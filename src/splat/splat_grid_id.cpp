// splat_grid_id(): what identifies the .vdb a splat tree was fitted to, from its header and
// topology alone (see SplatGridId), and the words for what differs.

#include <openvdb/openvdb.h>

#include <cstring>
#include <system_error>

#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/splats.h"

namespace vdbmesh {
namespace {

/// FNV-1a, 64 bits: a fingerprint, not a defence against a forger.
class Fnv1a {
public:
    template <typename T>
    void add(const T& value) {
        unsigned char bytes[sizeof(T)];
        std::memcpy(bytes, &value, sizeof(T));
        for (unsigned char b : bytes) hash_ = (hash_ ^ b) * 0x100000001B3ull;
    }
    std::uint64_t value() const { return hash_; }

private:
    std::uint64_t hash_ = 0xCBF29CE484222325ull;
};

std::uint64_t topology_hash(const GridRegionSource& source, const openvdb::FloatGrid& description) {
    Fnv1a hash;
    for (const NodeWeight& node : source.nodes()) {
        for (std::int32_t v : node.origin) hash.add(v);
        hash.add(node.active_voxels);
    }
    const openvdb::Mat4d matrix = description.transform().baseMap()->getAffineMap()->getMat4();
    for (int row = 0; row < 4; ++row)
        for (int column = 0; column < 4; ++column) hash.add(matrix(row, column));
    hash.add(description.background());
    return hash.value();
}

}  // namespace

SplatGridId splat_grid_id(const std::filesystem::path& path, const GridRegionSource& source) {
    const auto description = source.description();
    SplatGridId id;
    std::error_code error;
    id.file_bytes = std::filesystem::file_size(path, error);
    if (error) throw Error(path.string() + ": cannot read its size: " + error.message());
    if (const auto checksum = description->getMetadata<openvdb::StringMetadata>(kMetaChecksum)) id.checksum = checksum->value();
    // Without a stated checksum, a rewrite in place with the same size and topology shows only
    // in the modification time (a copy then refits: the safe side).
    if (id.checksum.empty()) id.modified = std::filesystem::last_write_time(path).time_since_epoch().count();
    id.topology = topology_hash(source, *description);
    return id;
}

std::string splat_grid_difference(const SplatGridId& fitted, const SplatGridId& grid) {
    const auto stated = [](const std::string& checksum) { return checksum.empty() ? std::string("none") : checksum; };
    if (fitted.checksum != grid.checksum)
        return "the grid it was fitted to states checksum " + stated(fitted.checksum) + ", this one " + stated(grid.checksum);
    if (fitted.file_bytes != grid.file_bytes)
        return "the grid it was fitted to was " + std::to_string(fitted.file_bytes) + " bytes, this one is " +
               std::to_string(grid.file_bytes);
    if (fitted.topology != grid.topology) return "another topology, transform or background";
    if (fitted.modified != grid.modified) return "the grid states no checksum and was modified since it was fitted";
    return "";
}

}  // namespace vdbmesh
