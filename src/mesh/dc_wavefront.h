#pragma once
// Private: the contouring of one column of bricks, node layer after node layer
// (dc_wavefront.cpp; docs/dmc.md, "Bricks").

#include <openvdb/openvdb.h>

#include <functional>
#include <vector>

#include "mesh/dual_contouring.h"

namespace vdbmesh::detail {

/// The owned part of a column of bricks: whole nodes across x and y (voxels, inclusive).
struct IfcColumn {
    int min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

/// Contours the column's node layers from bottom to top. Held at any time: the samples of
/// the column's nodes and of one ring of nodes round it (a leaf more) in at most three node
/// layers and a leaf row, and the cells of two node layers and a block row. The ring's nodes are built (octree, coarse
/// merge, split) but not contoured; no node is built twice in one column.
class IfcColumnWavefront {
public:
    IfcColumnWavefront(const GridRegionSource& source, const SampleClassifier& classifier, const MeshOptions& options, const IfcColumn& column,
                       MeshReport& report);

    /// Calls @a consume with the nodes of each node layer @a first .. @a last (node z
    /// indices, z / kNodeVoxels) in turn, in z-major order within a layer.
    void run(int first, int last, const std::function<void(std::vector<IfcNodeOutput>&&)>& consume);

private:
    bool in_column(const openvdb::Coord& origin) const;
    void read(int z_begin, int z_end);
    void build(int layer);
    std::vector<IfcNodeOutput> contour(int layer);
    void drop_below(int cells_z, int samples_z);

    const GridRegionSource& source_;
    const SampleClassifier& classifier_;
    const MeshOptions& options_;
    const IfcColumn column_;
    MeshReport& report_;
    openvdb::FloatGrid::Ptr window_;
    IfcCellGrid cells_;
};

}  // namespace vdbmesh::detail
