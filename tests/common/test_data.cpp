#include "test_data.h"

#include <unistd.h>

#include <atomic>
#include <cstdlib>

namespace vdbmesh::test {

std::filesystem::path shared_data_dir() {
    if (const char* env = std::getenv("VDBMESH_DATA_DIR"); env && *env) {
        if (std::filesystem::is_directory(env)) return env;
        return {};
    }
    // The repository's checkout sits beside shared/ (the source folder is compiled in).
    for (std::filesystem::path dir = VDBMESH_SOURCE_DIR; !dir.empty(); dir = dir.parent_path()) {
        const auto candidate = dir.parent_path() / "shared" / "data";
        if (std::filesystem::is_directory(candidate)) return candidate;
        if (dir == dir.parent_path()) break;
    }
    return {};
}

bool data_required() {
    const char* env = std::getenv("VDBMESH_REQUIRE_DATA");
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
