#pragma once
// Private: the cut of a closed mesh by a plane from its triangles one at a time (shared seed
// 002, chapter 3: cross-sections of the solid), for section_mesh() (a mesh in memory) and
// SectionStream (a mesh read as a stream, issue 28). Each triangle that straddles the plane
// gives one segment between the crossing points of its two straddling edges; a vertex on the
// plane counts as above it (a symbolic perturbation), so each crossing edge of a closed,
// oriented mesh starts exactly one segment and ends exactly one, and the segments chain into
// closed loops. A segment runs from the edge that goes down through the plane to the edge that
// goes up (in the triangle's order), which makes outer loops counter-clockwise seen from the
// normal's side.

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "vdbmesh/section.h"

namespace vdbmesh::detail {

/// An edge named by its ends: two vertex numbers, smaller first, then four zero words (a mesh
/// with vertex numbers), or the bits of the two positions, smaller first (an STL stream, whose
/// corners are not numbered). Its first end is the one the crossing point is measured from, so
/// both triangles of the edge give the same bits.
using EdgeName = std::array<std::uint32_t, 6>;

/// A directed piece of the cut: from the crossing point of one edge to that of another.
struct CutSegment {
    EdgeName from, to;
    std::array<double, 3> start;  ///< where `from` crosses the plane
    bool operator<(const CutSegment& o) const { return from < o.from; }
};

/// A triangle's corners and its edges' names: edge k joins corner k and corner k + 1 (mod 3);
/// first_end[k] is the corner that is the first end of its name.
struct CutTriangle {
    std::array<std::array<float, 3>, 3> corners;
    std::array<EdgeName, 3> edges;
    std::array<int, 3> first_end;
};

/// The names of a triangle's edges from its vertex numbers.
CutTriangle numbered_triangle(const std::array<std::uint32_t, 3>& vertices, const std::array<std::array<float, 3>, 3>& corners);
/// The names of a triangle's edges from its corners' positions.
CutTriangle positioned_triangle(const std::array<std::array<float, 3>, 3>& corners);

/// Adds to @a segments the segment @a triangle gives (if it straddles @a plane).
void cut_triangle(const Plane& plane, const CutTriangle& triangle, std::vector<CutSegment>& segments);

/// The names an error message gives an edge: "(3, 7)" or "(x y z)-(x y z)".
std::string edge_text(const EdgeName& edge, bool numbered);

/// @a segments (sorted here) chained into closed loops of crossing points.
/// @throw Error naming the first crossing edge (edge_text()) with no or two continuations.
std::vector<std::vector<std::array<double, 3>>> chain_loops(std::vector<CutSegment> segments, bool numbered);

}  // namespace vdbmesh::detail
