#include "view/web_assets.h"

// VDBMESH_WEB_PAGE and VDBMESH_WEB_SCRIPT are the paths of the files, set by CMake, which
// also rebuilds this file when they change. The assembler copies their bytes in.
#define VDBMESH_EMBED(symbol, path)                                     \
    asm(".pushsection .rodata\n"                                        \
        ".global " #symbol "_begin\n" #symbol "_begin:\n"               \
        ".incbin \"" path "\"\n"                                        \
        ".global " #symbol "_end\n" #symbol "_end:\n"                   \
        ".popsection\n");                                               \
    extern "C" const char symbol##_begin[];                             \
    extern "C" const char symbol##_end[];

VDBMESH_EMBED(vdbmesh_web_page, VDBMESH_WEB_PAGE)
VDBMESH_EMBED(vdbmesh_web_script, VDBMESH_WEB_SCRIPT)

namespace vdbmesh::view {

namespace {

std::string_view embedded(const char* begin, const char* end) { return {begin, std::size_t(end - begin)}; }

}  // namespace

std::optional<WebAsset> web_asset(const std::string& path) {
    if (path == "/" || path == "/index.html") {
        return WebAsset{embedded(vdbmesh_web_page_begin, vdbmesh_web_page_end), "text/html; charset=utf-8"};
    }
    if (path == "/app.js") {
        // Not text/*, nor the bare application/javascript: Debian's cpp-httplib compresses
        // those on every request with Brotli at its highest quality when the browser accepts
        // it, 1.5 s and more for this script on a busy 2-core machine, the most of the page's
        // start (issue 30); over the loopback the bytes cost nothing.
        return WebAsset{embedded(vdbmesh_web_script_begin, vdbmesh_web_script_end), "application/javascript; charset=utf-8"};
    }
    return std::nullopt;
}

}  // namespace vdbmesh::view
