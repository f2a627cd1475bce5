#pragma once
// The outputs of `vdbmesh mesh --labels` (issue 31): a folder with one file per label, one PLY
// with each face's label pair, or one glTF with a named mesh per label.

#include <array>
#include <string>
#include <vector>

#include "vdbmesh/labels.h"

namespace vdbmesh::cli {

/// A label's colour (RGB in [0, 1]): the table's, else one of a fixed palette.
std::array<double, 3> label_colour(std::uint32_t value, const LabelTable& table);

/// True when @a output names a folder: it ends with a slash or is an existing folder.
bool is_folder_output(const std::string& output);

/// `<value>_<name>.<extension>`, or `<value>.<extension>` when the table has no name for it.
std::string label_file_name(std::uint32_t value, const LabelTable& table, const std::string& extension);

/// Writes one mesh per label into folder @a output (made if missing) in @a format (stl|ply|obj);
/// returns the files written. Each file is written atomically.
std::vector<std::string> write_label_folder(const LabelSurface& surface, const LabelTable& table, const std::string& output,
                                            const std::string& format, bool ascii);

/// Binary little-endian PLY: vertices, then faces with `label_inside` and `label_outside`
/// (each wall once; the normal points from the inside label to the outside label).
void write_label_ply(const LabelSurface& surface, const std::string& path);

/// glTF 2.0 (.glb binary, .gltf with the buffer embedded): one mesh per label, named by the
/// table (else "label <value>"), coloured by the table (else a fixed palette).
void write_label_gltf(const LabelSurface& surface, const LabelTable& table, const std::string& path);

}  // namespace vdbmesh::cli
