#pragma once
// Sections drawn to scale as SVG, for `vdbmesh section --svg`.

#include <string>
#include <vector>

#include "vdbmesh/section.h"

namespace vdbmesh::cli {

/// The sections as one standalone SVG document, one below the other, each seen from the side
/// its plane's normal points to (u to the right, v up) and labelled with its plane. One user
/// unit is one world unit, and the document's size is given in millimetres, so a scan in
/// millimetres prints at 1:1. Material is filled (holes by the even-odd rule), loops outlined.
std::string section_svg(const std::vector<Section>& sections, const std::vector<std::string>& labels);

}  // namespace vdbmesh::cli
