// .vdb files in and out through OpenVDB's io::File (the format is OpenVDB's own, see
// openvdb/io/Archive.h). Writes go through CheckedOutput; every OpenVDB exception becomes a
// FormatError or Error naming the file.

#include "vdb_file.h"

#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>

#include "grid_checksum.h"
#include "vdbmesh/checked_output.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdb_probe.h"

namespace vdbmesh {

namespace {

/// OpenVDB's archive writer aimed at a stream of ours: io::File writes the same bytes through
/// a stream of its own whose failures it never reports.
class VdbStreamWriter : public openvdb::io::Archive {
public:
    void write_to(std::ostream& out, const openvdb::GridCPtrVec& grids) const {
        Archive::write(out, grids, /*seekable=*/true);
    }
};

std::string hex(std::uint64_t value) {
    std::ostringstream text;
    text << std::hex << std::setw(16) << std::setfill('0') << value;
    return text.str();
}

/// Where the archive header holds its file id, a random UUID as 36 characters: after the
/// magic number (8 bytes), the file format and library versions (3 x 4) and the offsets flag (1).
constexpr std::streamoff kUuidOffset = 8 + 3 * 4 + 1;

/// A file id made from the grid's checksum, in the UUID's text form: the same grid gives the
/// same file, byte for byte (OpenVDB draws a new random id on every write).
std::string file_id(std::uint64_t checksum) {
    const std::string digits = hex(checksum) + hex(checksum * 0x9E3779B97F4A7C15ull + 1);
    return digits.substr(0, 8) + "-" + digits.substr(8, 4) + "-" + digits.substr(12, 4) + "-" + digits.substr(16, 4) + "-" +
           digits.substr(20, 12);
}

/// Throws FormatError when a float grid of @a path carries a checksum that its content no longer matches.
void verify_checksums(const std::filesystem::path& path, const openvdb::GridPtrVec& grids) {
    for (const openvdb::GridBase::Ptr& grid : grids) {
        const auto floats = openvdb::gridPtrCast<openvdb::FloatGrid>(grid);
        const auto stored = grid->getMetadata<openvdb::StringMetadata>(kMetaChecksum);
        if (!floats || !stored) continue;
        const std::string actual = hex(detail::grid_checksum(*floats));
        if (stored->value() != actual)
            throw FormatError(path.string(), std::string(kMetaChecksum) + " of grid \"" + grid->getName() + "\"",
                              stored->value() + " (written by vdbmesh)",
                              actual + ": the file was changed or damaged after it was written");
    }
}

}  // namespace

namespace detail {

/// The smallest .vdb file: magic (8 bytes), file version (4), library version (4 + 4), the
/// grid-offsets flag (1), the UUID (36), the file's metadata count (4) and grid count (4).
constexpr std::uintmax_t kVdbHeaderBytes = 65;

void require_vdb_header(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw FormatError(path.string(), "file", "an existing .vdb file", "nothing readable at that path");
    // OpenVDB reads a header cut short as a file of no grids, without a word.
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (!ec && bytes < kVdbHeaderBytes) {
        throw FormatError(path.string(), "size",
                          "at least " + std::to_string(kVdbHeaderBytes) +
                              " bytes (the header: magic, file and library versions, offsets flag, UUID, metadata and grid counts)",
                          std::to_string(bytes) + " bytes (a truncated file)");
    }
}

openvdb::GridPtrVecPtr read_vdb_grids(const std::filesystem::path& path) {
    openvdb::initialize();
    require_vdb_header(path);
    probe_vdb_in_child(path);
    openvdb::GridPtrVecPtr grids;
    try {
        openvdb::io::File file(path.string());
        file.open(/*delayLoad=*/false);
        grids = file.getGrids();
        file.close();
    } catch (const std::exception& e) {  // OpenVDB throws its own exceptions, std::bad_alloc on absurd sizes ...
        throw FormatError(path.string(), std::string("not a readable .vdb file (") + e.what() + ")");
    }
    verify_checksums(path, *grids);
    return grids;
}

}  // namespace detail

void write_vdb(const openvdb::FloatGrid& grid, const std::filesystem::path& path) {
    openvdb::initialize();
    CheckedOutput out(path);
    try {
        const std::uint64_t checksum = detail::grid_checksum(grid);
        openvdb::MetaMap metadata(grid);
        metadata.insertMeta(kMetaChecksum, openvdb::StringMetadata(hex(checksum)));
        // A shallow copy sharing the tree, with the checksum added to its metadata.
        VdbStreamWriter().write_to(out.stream(), openvdb::GridCPtrVec{grid.copyGridReplacingMetadata(metadata)});
        const std::string id = file_id(checksum);
        out.stream().seekp(kUuidOffset);
        out.stream().write(id.data(), std::streamsize(id.size()));
        out.stream().seekp(0, std::ios::end);
    } catch (const openvdb::Exception& e) {
        throw Error(path.string() + ": cannot write the .vdb file (" + e.what() + ")");
    }
    out.commit();
}

openvdb::FloatGrid::Ptr read_vdb(const std::filesystem::path& path) {
    // The file's values are read once, by children (vdb_regions.cpp); its topology twice.
    const openvdb::FloatGrid::Ptr grid = detail::read_first_float_grid(path);
    verify_checksums(path, openvdb::GridPtrVec{grid});
    return grid;
}

std::optional<double> stored_isovalue(const openvdb::FloatGrid& grid) {
    if (auto value = grid.getMetadata<openvdb::DoubleMetadata>(kMetaIsovalue)) return value->value();
    if (auto value = grid.getMetadata<openvdb::FloatMetadata>(kMetaIsovalue)) return value->value();
    return std::nullopt;
}

std::optional<std::pair<double, double>> band_isovalues(const openvdb::FloatGrid& grid) {
    if (const std::optional<double> iso = stored_isovalue(grid)) return std::make_pair(*iso, *iso);
    if (auto range = grid.getMetadata<openvdb::Vec2DMetadata>(kMetaIsoRange))
        return std::make_pair(range->value()[0], range->value()[1]);
    return std::nullopt;
}

std::optional<openvdb::CoordBBox> stored_scan_box(const openvdb::FloatGrid& grid) {
    const auto min = grid.getMetadata<openvdb::Vec3IMetadata>(kMetaScanMin);
    const auto max = grid.getMetadata<openvdb::Vec3IMetadata>(kMetaScanMax);
    if (!min || !max) return std::nullopt;
    return openvdb::CoordBBox(openvdb::Coord(min->value()), openvdb::Coord(max->value()));
}

}  // namespace vdbmesh
