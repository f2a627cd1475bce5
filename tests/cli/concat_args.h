#pragma once
// Shared by the CLI tests: argument lists joined.

#include <string>
#include <vector>

namespace vdbmesh::cli {

/// @a a followed by @a b.
inline std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

}  // namespace vdbmesh::cli
