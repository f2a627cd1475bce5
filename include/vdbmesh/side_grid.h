#pragma once
/// @file side_grid.h
/// @brief A scan converted for meshing the object on either side of the isovalue, closed at
/// the scan's box by every method (the command line's `mesh --inside below` and the Python
/// module's inside="below" alike).

#include "vdbmesh/grid.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh {

/// Set, true, on a grid converted from negated samples (convert_for_side()).
inline constexpr const char* kMetaNegatedSamples = "vdbmesh_negated_samples";

/// A converted grid and how to mesh it.
struct SideGrid {
    openvdb::FloatGrid::Ptr grid;
    double iso = 0;                 ///< the isovalue to mesh grid at: minus the one asked when negated
    Inside inside = Inside::above;  ///< the side to mesh grid at: always above
    bool negated = false;           ///< grid holds the negated samples
};

/// @a source converted at @a options.iso for the object on @a side. convert_to_grid() closes
/// the band at the scan's box only for an object above the isovalue (beyond the box is outside
/// for it), so an object below is converted as the negated samples' object above -iso: the same
/// surface (edge crossings are symmetric in the sign), closed at the box by every method, and
/// marked kMetaNegatedSamples (its stored value range and isovalue are the negated ones).
SideGrid convert_for_side(SliceReader& source, const ConvertOptions& options, Inside side);

/// Whether @a grid holds negated samples (kMetaNegatedSamples): a value v of it, or an
/// isovalue, is -v in the scan's terms.
bool holds_negated_samples(const openvdb::FloatGrid& grid);

}  // namespace vdbmesh
