#pragma once
// Where the shared real data lives (../shared/data beside the repository, or
// $VDBMESH_DATA_DIR): the one finder, used by the tests (test_data.h) and bench/ (no gtest).

#include <filesystem>

namespace vdbmesh::test {

/// The shared data folder, or an empty path when it cannot be found.
std::filesystem::path shared_data_dir();

}  // namespace vdbmesh::test
