#include "shared_scan.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/read.h"

namespace vdbmesh::test {

void convert_shared_scan(const SharedScan& scan, openvdb::FloatGrid::Ptr& grid) {
    std::vector<std::filesystem::path> paths;
    for (const std::string& input : scan.inputs) {
        VDBMESH_SHARED_DATA(path, input);
        paths.push_back(path);
    }
    ReadOptions read;
    if (scan.raw_i16_dims) {
        read.raw_dims = *scan.raw_i16_dims;
        read.raw_type = SampleType::i16;
        read.raw_byte_order = ByteOrder::big;
        read.raw_more_files.assign(paths.begin() + 1, paths.end());
    }
    ConvertOptions convert;
    convert.iso = scan.iso;
    grid = convert_to_grid(*open_volume(paths.front(), read), convert);
}

}  // namespace vdbmesh::test
