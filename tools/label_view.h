#pragma once
// `vdbmesh view MAP --labels all|LIST` (issue 31): the label map meshed per label for the page,
// which shows each label in its colour and lets each be switched off.

#include <string>
#include <vector>

#include "common_options.h"
#include "label_input.h"
#include "vdbmesh/view.h"

namespace vdbmesh::cli {

/// The map meshed (mesh_labels(), the labels of @a flags), every label's closed mesh one after
/// another in the source's mesh, the labels named and coloured by the table (else "label N"
/// and a fixed palette).
ViewSource label_view_source(const std::vector<std::string>& inputs, const ReadFlags& read, const LabelFlags& flags);

/// The figures of `check --json` for the page, summed over the labels' meshes analysed one by
/// one (their shared walls are not self-intersections): closed and manifold when every label's
/// mesh is; "labels": how many.
std::string label_figures(const Mesh& mesh, const std::vector<ViewLabel>& labels);

}  // namespace vdbmesh::cli
