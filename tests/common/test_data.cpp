#include "test_data.h"

#include <unistd.h>

#include <atomic>
#include <cstdlib>

namespace vdbmesh::test {

bool data_required() {
    const char* env = std::getenv("VDBMESH_REQUIRE_DATA");
    return env && std::string(env) == "1";
}

bool full_run() {
    const char* env = std::getenv("VDBMESH_FULL");
    return env && std::string(env) == "1";
}

std::filesystem::path testdata(const std::string& relative) {
    return std::filesystem::path(VDBMESH_SOURCE_DIR) / "testdata" / relative;
}

ScratchDir::ScratchDir() {
    static std::atomic<unsigned> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("vdbmesh-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

}  // namespace vdbmesh::test
