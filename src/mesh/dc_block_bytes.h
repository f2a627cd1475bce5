#pragma once
// Private: blocks' cells as bytes, so that a rank can hand the cells it built at a border to
// the rank beyond it instead of that rank building them again (dc_wavefront.cpp; docs/scale.md,
// "Borders between ranks").

#include <string>
#include <vector>

#include "mesh/dual_contouring.h"

namespace vdbmesh::detail {

/// The blocks of @a cells whose origins @a take accepts (built or not), in origin order, with
/// everything a block holds: its leaves, the parts a split may take, what the contour reads of
/// its samples, and its split decision.
std::string ifc_blocks_bytes(const IfcCellGrid& cells, const IfcOriginFilter& take);
/// The same, of the blocks numbered @a blocks (indices into @a cells, in origin order).
std::string ifc_blocks_bytes(const IfcCellGrid& cells, const std::vector<std::size_t>& blocks);

/// The blocks ifc_blocks_bytes() wrote, as they were, appended to @a cells (whose origins then
/// need sorting unless the bytes' follow them). @throw Error on bytes it did not write.
void append_ifc_blocks(const std::string& bytes, IfcCellGrid& cells);
inline IfcCellGrid ifc_blocks_from_bytes(const std::string& bytes) {
    IfcCellGrid cells;
    append_ifc_blocks(bytes, cells);
    return cells;
}

}  // namespace vdbmesh::detail
