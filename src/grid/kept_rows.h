#pragma once
// Private: the rows a scan's survey made (converter.h), kept in a temporary file so that a read
// by region costs a read of its own leaves, not another conversion of its slices (scan_regions.cpp).

#include <cstdint>
#include <vector>

#include "converter.h"
#include "vdbmesh/temp_file.h"

namespace vdbmesh::detail {

/// Rows of leaves and tiles on disk, grouped by 128^3 node column, so that a rectangle of node
/// columns over a range of rows is read as one stretch of the file per row and node row.
/// A leaf whose 512 values are all integers of 16 bits is kept in 2 bytes a value (CT scans:
/// half the disk and the reading); any other in its floats. What is read back has the bits
/// that were kept.
class KeptRows {
public:
    /// Node columns (x, y) from @a first_column on in both, @a columns_x x @a columns_y of them:
    /// every leaf the rows hold lies in one.
    KeptRows(int first_column, int columns_x, int columns_y);

    /// Appends row @a row.z0, above every row kept so far.
    void add(const ConvertedRow& row);

    /// The leaves and tiles of the rows with z0 in [@a first, @a last] in node columns
    /// [@a x0, @a x1) x [@a y0, @a y1) (indices of node columns, clipped to those kept), as rows.
    std::vector<ConvertedRow> read(int first, int last, int x0, int x1, int y0, int y1) const;

    /// The bytes read() holds besides the rows it returns: the largest stretch of one node row.
    std::uint64_t buffer_bytes() const { return largest_stretch_; }

    /// The node column index of voxel coordinate @a voxel (x or y).
    int column(std::int64_t voxel) const;

private:
    std::size_t run_index(std::size_t row, int x, int y) const { return (row * columns_y_ + y) * columns_x_ + x; }

    TempFile file_{"for the scan's surveyed rows"};
    int first_column_, columns_x_, columns_y_;
    std::vector<int> rows_;                ///< z0 of each row kept, increasing
    std::vector<std::uint64_t> runs_;      ///< per row, node row, node column: the offset of its run
    std::uint64_t largest_stretch_ = 0;
};

}  // namespace vdbmesh::detail
