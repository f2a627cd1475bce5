#pragma once
// The page, built into the program: web/index.html and the bundle esbuild made of web/src
// at build time. Nothing is read from disk or fetched at run time.

#include <optional>
#include <string>
#include <string_view>

namespace vdbmesh::view {

struct WebAsset {
    std::string_view body;
    const char* content_type;
};

/// The file served at URL path @a path ("/" or "/index.html": the page; "/app.js": its
/// script); none for any other path.
std::optional<WebAsset> web_asset(const std::string& path);

}  // namespace vdbmesh::view
