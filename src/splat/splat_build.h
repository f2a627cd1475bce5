#pragma once
// Private: the nodes of a splat tree while it is built, in the grid's index space, and the
// two steps that make them: fitting the finest nodes of one 8^3 cell to its edge crossings
// (splat_cell.cpp) and merging children into their parent (splat_merge.cpp).

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "vdbmesh/splats.h"

namespace vdbmesh::splat {

/// A node under construction; children are a range of the level below's node vector.
struct BuildNode {
    std::array<float, 3> centre{};
    std::array<float, 3> normal{};
    float radius = 0;
    float cone = 0;
    std::uint32_t weight = 0;              ///< edge crossings below (saturated)
    std::array<std::int32_t, 3> origin{};  ///< min corner of the node's cube (index space)
    std::uint32_t first_child = 0;
    std::uint32_t child_count = 0;
};

/// How samples are read: which side is inside, and the scan box outside which every sample
/// is outside the object.
struct SampleRule {
    double iso = 0;
    bool inside_above = true;
    std::optional<openvdb::CoordBBox> scan_box;
};

/// The nodes of one 8^3 cell (levels 0, 1 and 2), the children of each level contiguous and
/// referring to the level below's vector. Empty when no edge in the cell's closed cube is crossed.
struct CellNodes {
    std::vector<BuildNode> finest;  ///< level 0
    std::vector<BuildNode> middle;  ///< level 1
    std::optional<BuildNode> leaf;  ///< level 2
};

/// Fits the cell of origin @a origin (a multiple of 8) and merges it up to level 2,
/// collapsing coplanar children within @a tolerance voxels, into @a nodes (their vectors
/// reused: no allocation once they have grown).
void fit_cell(const openvdb::FloatGrid& grid, const openvdb::Coord& origin, const SampleRule& rule, double tolerance,
              CellNodes& nodes);
CellNodes fit_cell(const openvdb::FloatGrid& grid, const openvdb::Coord& origin, const SampleRule& rule,
                   double tolerance);

/// The parent of @a count nodes at @a children: their crossing-weighted mean centre and normal,
/// a radius enclosing their discs, a cone enclosing their cones. first_child is left 0.
BuildNode merge_children(const BuildNode* children, std::uint32_t count, const std::array<std::int32_t, 3>& origin);

/// Flips the normals of @a count nodes at @a children that point away from their principal
/// direction (of the weighted sum of n n^T), so that normals known only up to sign (the
/// topology preview's) do not cancel in merge_children().
void align_normals(BuildNode* children, std::uint32_t count);

/// Whether @a parent may stand for its @a children: all childless and every child's disc within
/// @a tolerance voxels of the parent's plane.
bool coplanar_within(const BuildNode& parent, const BuildNode* children, std::uint32_t count, double tolerance);

/// The nodes of every level while they are built; levels[L] holds level L's nodes, each
/// one's children a range of levels[L - 1].
using Levels = std::vector<std::vector<BuildNode>>;

/// Every 8^3 cell of @a grid whose closed cube may hold a crossed edge by @a rule, z-major;
/// only those whose origin lies in @a within when given.
std::vector<openvdb::Coord> candidate_cells(const openvdb::FloatGrid& grid, const std::optional<openvdb::CoordBBox>& within,
                                            const SampleRule& rule);

/// Fits @a cells of @a grid (in parallel) and appends their nodes of levels 0 to 2 to @a levels.
void append_cells(Levels& levels, const openvdb::FloatGrid& grid, const std::vector<openvdb::Coord>& cells,
                  const SampleRule& rule, double tolerance);

/// Appends one cell's nodes to @a levels (its children's indices made the levels'; @a cell is
/// changed so).
void append_cell(Levels& levels, CellNodes& cell);

/// Builds levels[level] from levels[level - 1] (reordered so each parent's children are
/// contiguous); the root level takes every node below as a child. With @a unsigned_normals,
/// each parent's children are aligned first (align_normals()).
void merge_up(Levels& levels, int level, bool unsigned_normals = false);

/// Keeps the nodes of levels 0 to 2 within a number of bytes while cells are appended
/// (SplatOptions::max_bytes): past it, the finest level kept is dropped and the level above
/// made childless, down to leaf level. Pruning is decided between appends from the nodes'
/// count alone, and a pruned level stays pruned, so the result is the unbounded tree without
/// the levels under finest_kept().
class LevelPruning {
public:
    /// @a max_bytes 0: no bound.
    explicit LevelPruning(std::uint64_t max_bytes) : max_bytes_(max_bytes) {}
    /// Drops what the levels' last appends put under the finest level kept, then prunes further
    /// while the levels hold more than the bound. @throw Error when leaf level alone exceeds it.
    void fit(Levels& levels);
    int finest_kept() const { return finest_kept_; }

private:
    /// Drops the levels under finest_kept_ and makes its nodes from @a from on childless.
    void drop_below(Levels& levels, std::size_t from);
    std::uint64_t max_bytes_;
    int finest_kept_ = 0;
    std::size_t childless_up_to_ = 0;  ///< the finest kept level's nodes made childless so far
};

/// The tree of levels 0 to 2 (nodes of higher levels made by merge_up()), in the world space of
/// @a transform, with @a options' isovalue, side and tolerance; with @a pruning, pruned once
/// more to fit its bound with every level made, before the layout.
SplatTree assemble(Levels& levels, const openvdb::math::Transform& transform, const SplatOptions& options,
                   bool unsigned_normals = false, LevelPruning* pruning = nullptr);

/// The nodes breadth-first from levels[top][0] (the only node of that level), each node's
/// children contiguous, in world space by @a transform; in @a sources (when given) the level
/// and index in @a levels each came from.
std::vector<SplatNode> breadth_first(const Levels& levels, int top, const openvdb::math::Transform& transform,
                                     std::vector<std::pair<int, std::uint32_t>>* sources = nullptr);

/// The rule of @a grid's samples for @a options. @throw UsageError on a negative tolerance.
SampleRule sample_rule(const openvdb::FloatGrid& grid, const SplatOptions& options);

}  // namespace vdbmesh::splat
