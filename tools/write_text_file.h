#pragma once
// Text outputs of the subcommands (JSON reports, SVG pictures), written atomically.

#include <string>

namespace vdbmesh::cli {

/// Writes @a text to @a path through a temporary file and a rename; throws Error on failure.
void write_text_file(const std::string& path, const std::string& text);

}  // namespace vdbmesh::cli
