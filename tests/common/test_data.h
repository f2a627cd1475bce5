#pragma once
// The one helper through which tests and benchmarks find data: ../shared/data beside the
// repository (or $VDBMESH_DATA_DIR), and the repository's own testdata/.
// When the shared folder is missing a test skips, unless VDBMESH_REQUIRE_DATA=1 (CI), when it fails.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "shared_data_dir.h"  // shared_data_dir()

namespace vdbmesh::test {

/// True when VDBMESH_REQUIRE_DATA=1: missing data is a failure, not a skip.
bool data_required();
/// True when VDBMESH_FULL=1: the long cases on whole scans run too (minutes each; the default
/// suite keeps every guarantee on every staged scan and checks the figures on crops and phantoms).
bool full_run();
/// A file of the repository's testdata/ folder.
std::filesystem::path testdata(const std::string& relative);

/// A fresh empty folder under the system temp dir, removed with everything in it on destruction.
class ScratchDir {
public:
    ScratchDir();
    ~ScratchDir();
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

}  // namespace vdbmesh::test

/// Declares `var` as ../shared/data/<relative>; skips the test (or fails it under
/// VDBMESH_REQUIRE_DATA=1) when the file is missing.
#define VDBMESH_SHARED_DATA(var, relative)                                                         \
    const std::filesystem::path var = ::vdbmesh::test::shared_data_dir() / (relative);             \
    if (::vdbmesh::test::shared_data_dir().empty() || !std::filesystem::exists(var)) {             \
        if (::vdbmesh::test::data_required()) {                                                    \
            FAIL() << "shared data missing: " << (relative) << " (VDBMESH_REQUIRE_DATA=1)";        \
        } else {                                                                                   \
            GTEST_SKIP() << "shared data missing: " << (relative);                                 \
        }                                                                                          \
    }

/// Skips a long whole-scan case unless VDBMESH_FULL=1 (a skip, not a failure, under VDBMESH_REQUIRE_DATA=1 too).
#define VDBMESH_FULL_ONLY()                                                                        \
    if (!::vdbmesh::test::full_run()) GTEST_SKIP() << "a long whole-scan case: runs with VDBMESH_FULL=1"
