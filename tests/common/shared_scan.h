#pragma once
// Test helper: a real scan of the shared data (../shared/data) converted at its isovalue, as
// the guarantee and figure tests on real scans read them.

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "vdbmesh/scan_regions.h"

namespace vdbmesh::test {

struct SharedScan {
    std::string name;                 ///< the test's name
    std::vector<std::string> inputs;  ///< under ../shared/data: the scan, then further parts of a split raw scan
    double iso;
    /// For a headerless big-endian int16 scan: its dims.
    std::optional<std::array<std::int64_t, 3>> raw_i16_dims;
};

inline std::ostream& operator<<(std::ostream& out, const SharedScan& scan) { return out << scan.name; }

/// The real scans of the shared data the tests use, each with its isovalue.
const std::vector<SharedScan>& shared_scans();
/// The one of shared_scans() named @a name (throws when there is none).
const SharedScan& shared_scan(const std::string& name);

/// The scan converted at its isovalue into @a grid. Left empty when the data is missing and the
/// test skips (a failure when VDBMESH_REQUIRE_DATA=1): call it through ASSERT_NO_FATAL_FAILURE
/// and return when @a grid is empty.
void convert_shared_scan(const SharedScan& scan, openvdb::FloatGrid::Ptr& grid);

/// How to open the scan from its first slice into @a open, as convert_shared_scan() reads it.
/// Left empty when the data is missing (as above).
void open_shared_scan(const SharedScan& scan, OpenSlices& open);

/// The options convert_shared_scan() converts with (its isovalue).
ConvertOptions shared_scan_options(const SharedScan& scan);

}  // namespace vdbmesh::test
