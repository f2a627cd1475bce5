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
    /// With @a below: the top two block rows of layer first - 1, as the rank below built them
    /// (prebuild_last_layer()).
    std::function<const std::string&()> rows_below;
    /// With @a above: the bottom two block rows of layer last + 1, as the rank above built them.
    std::function<const std::string&()> rows_above;
};

/// Contours the column's node layers from bottom to top. Held at any time: the samples of
/// the column's nodes and of one ring of nodes round it (a leaf more) in at most three node
/// layers and a leaf row, and the cells of two node layers and a block row. The ring's nodes are built (octree, coarse
/// merge, split) but not contoured; no node is built twice in one column, nor, with a cache,
/// in one process.
class IfcColumnWavefront {
public:
    /// With @a cache (may be null), the nodes it holds are taken from it rather than built, and
    /// the nodes built that a later column reads are kept in it. With @a release_memory (a
    /// memory limit), what a dropped layer frees goes back to the system at once; otherwise
    /// malloc keeps it for the next layer, which spares the page faults of taking it again.
    IfcColumnWavefront(const GridRegionSource& source, const SampleClassifier& classifier, const MeshOptions& options, const IfcColumn& column,
                       MeshReport& report, IfcNodeCache* cache, bool release_memory);

    /// Calls @a consume with the nodes of each node layer @a first .. @a last (node z
    /// indices, z / kNodeVoxels) in turn, in z-major order within a layer.
    /// With @a borders (may be null), as IfcColumnBorders says.
    void run(int first, int last, const std::function<void(std::vector<IfcNodeOutput>&&)>& consume, IfcColumnBorders* borders = nullptr);

    /// Builds layer @a layer (this column's last, under another rank's run) into the cache the
    /// wavefront was made with, ahead of run(), and returns its top two block rows for that rank.
    std::string prebuild_last_layer(int layer);

private:
    bool in_column(const openvdb::Coord& origin) const;
    void read(int z_begin, int z_end);
    void build(int layer);
    IfcCellGrid build_cells(int layer);
    void take_rows_above(const std::string& rows, int layer);
    void take_rows_below(const std::string& rows, int layer);
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
    const bool release_memory_;
    IfcCellGrid cells_;
    /// Blocks below this z are never decided by run() (a rank below: its cells come later).
    int decide_from_z_ = std::numeric_limits<int>::min();
};

}  // namespace vdbmesh::detail
