#pragma once
// `vdbmesh measure --labels all|LIST`: per label volume, area and centroid of its mesh, with the
// voxel volume beside it, as a table, CSV or JSON (issue 31).

#include <string>
#include <vector>

#include "common_options.h"
#include "label_input.h"

namespace vdbmesh::cli {

struct LabelMeasureRequest {
    std::vector<std::string> inputs;
    bool json = false;
    bool csv = false;
    ReadFlags read;
    LabelFlags label;
    CommonOptions common;
};

void run_label_measure(const LabelMeasureRequest& request);

}  // namespace vdbmesh::cli
