#include "shared_data_dir.h"

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

}  // namespace vdbmesh::test
