#pragma once
// `vdbmesh mesh --labels all|LIST`: a label map to one mesh per label (issue 31).

#include <string>
#include <vector>

#include "common_options.h"
#include "label_input.h"

namespace vdbmesh::cli {

struct LabelMeshRequest {
    std::vector<std::string> inputs;
    std::string output;        ///< DIR/ (one file per label), FILE.ply (label pairs), FILE.glb|.gltf
    std::string format = "stl";  ///< of the files in DIR/
    bool ascii = false;
    bool json = false;
    int smooth_iterations = 16;
    ReadFlags read;
    LabelFlags label;
    CommonOptions common;
};

/// Meshes and writes; returns the exit status (0).
int run_label_mesh(const LabelMeshRequest& request);

}  // namespace vdbmesh::cli
