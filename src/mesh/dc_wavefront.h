#pragma once
// Private: the contouring of one column of bricks, node layer after node layer
// (dc_wavefront.cpp; docs/dmc.md, "Bricks").

#include <openvdb/openvdb.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "mesh/dc_node_cache.h"
#include "mesh/dual_contouring.h"

namespace vdbmesh::detail {

/// The owned part of a column of bricks: whole nodes across x and y (voxels, inclusive).
struct IfcColumn {
    int min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

/// Where a column's run of bricks meets another rank's run in the same column (mpirun): the
/// layer beyond is built by that rank, not again here, and the cells at the border are handed
/// over as bytes (dc_block_bytes.h; docs/scale.md, "Borders between ranks").
struct IfcColumnBorders {
    bool below = false;  ///< layer first - 1 is another rank's
    bool above = false;  ///< layer last + 1 is another rank's
    /// With @a below: called once layer first is built, with its bottom two block rows (as
    /// built, the bottom one not yet decided by the split).
    std::function<void(std::string)> first_layer_built;
    /// With @a above: the bottom two block rows of layer last + 1, as the rank above built them.
    std::function<const std::string&()> rows_above;
    /// With @a below: called with layer first's cells (all but its bottom block row decided)
    /// and the bottom block row of the layer above, for contour_deferred() at the end.
    std::function<void(const std::string&)> first_layer_left;
    /// Out, with @a above: the top block row of layer last, decided.
    std::string top_row;
};

/// Contours the column's node layers from bottom to top. Held at any time: the samples of
/// the column's nodes and of one ring of nodes round it (a leaf more) in at most three node
/// layers and a leaf row, and the cells of two node layers and a block row. The ring's nodes are built (octree, coarse
/// merge, split) but not contoured; no node is built twice in one column, nor, with a cache,
/// in one process.
class IfcColumnWavefront {
public:
    /// With @a cache (may be null), the nodes it holds are taken from it rather than built, and
    /// the nodes built that a later column reads are kept in it.
    IfcColumnWavefront(const GridRegionSource& source, const SampleClassifier& classifier, const MeshOptions& options, const IfcColumn& column,
                       MeshReport& report, IfcNodeCache* cache = nullptr);

    /// Calls @a consume with the nodes of each node layer @a first .. @a last (node z
    /// indices, z / kNodeVoxels) in turn, in z-major order within a layer.
    /// With @a borders (may be null), as IfcColumnBorders says: layer first is then left to
    /// contour_deferred().
    void run(int first, int last, const std::function<void(std::vector<IfcNodeOutput>&&)>& consume, IfcColumnBorders* borders = nullptr);

    /// Contours layer @a layer, left by run() to IfcColumnBorders::first_layer_left, once the top block
    /// row of the layer below (IfcColumnBorders::top_row of the rank below) has come.
    void contour_deferred(int layer, const std::string& deferred, const std::string& row_below,
                          const std::function<void(std::vector<IfcNodeOutput>&&)>& consume);

private:
    bool in_column(const openvdb::Coord& origin) const;
    void read(int z_begin, int z_end);
    void build(int layer);
    void take_rows_above(const std::string& rows, int layer);
    void split_where(const IfcOriginFilter& decide);
    std::string block_rows(int z_begin, int z_end) const;
    std::vector<IfcNodeOutput> contour(int layer);
    void drop_below(int cells_z, int samples_z);

    const GridRegionSource& source_;
    const SampleClassifier& classifier_;
    const MeshOptions& options_;
    const IfcColumn column_;
    MeshReport& report_;
    openvdb::FloatGrid::Ptr window_;
    IfcNodeCache* cache_;
    IfcCellGrid cells_;
    /// Blocks below this z are never decided by run() (a rank below: its cells come later).
    int decide_from_z_ = std::numeric_limits<int>::min();
};

}  // namespace vdbmesh::detail
