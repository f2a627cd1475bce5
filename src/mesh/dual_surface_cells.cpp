// The dual surface's cells (dual_surface_cells.h): per block, the samples its cells read (the
// window DC's octree reads, load_ifc_samples()), each cell's configuration, and a vertex per
// edge group at the mean of the group's crossings (edge_crossing.h, as Marching Cubes places
// its vertices), then moved onto the cell's trilinear isosurface by Newton steps along the
// gradient, kept kDualInteriorMargin inside.

#include "mesh/dual_surface_cells.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "mesh/dc_block.h"
#include "mesh/dual_surface_groups.h"
#include "mesh/edge_crossing.h"
#include "mesh/mc_table.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

constexpr int kNewtonSteps = 3;

/// The trilinear interpolant of a cell's corner values @a f (corner c at (c & 1, c >> 1 & 1,
/// c >> 2)) at local position @a t, and its gradient.
double trilinear(const std::array<double, 8>& f, const Point3& t, Point3& gradient) {
    double value = 0;
    gradient = {0, 0, 0};
    for (unsigned c = 0; c < 8; ++c) {
        std::array<double, 3> w;
        for (int a = 0; a < 3; ++a) w[a] = (c >> a) & 1 ? t[a] : 1 - t[a];
        value += f[c] * w[0] * w[1] * w[2];
        for (int a = 0; a < 3; ++a) {
            const double sign = (c >> a) & 1 ? 1.0 : -1.0;
            gradient[a] += sign * f[c] * w[(a + 1) % 3] * w[(a + 2) % 3];
        }
    }
    return value;
}

Point3 clamped_into_cell(Point3 t) {
    for (double& x : t) x = std::clamp(x, kDualInteriorMargin, 1 - kDualInteriorMargin);
    return t;
}

/// The local position @a start moved onto the isosurface of the cell's interpolant by Newton
/// steps along the gradient, kept inside the cell; @a start where that does not get closer to
/// the isovalue (or a corner value is infinite: beyond the scan box).
Point3 projected_onto_isosurface(const std::array<double, 8>& f, double iso, const Point3& start) {
    for (double value : f)
        if (!std::isfinite(value)) return start;
    Point3 gradient;
    const double start_residual = std::abs(trilinear(f, start, gradient) - iso);
    Point3 t = start;
    double residual = start_residual;
    for (int step = 0; step < kNewtonSteps; ++step) {
        const double r = trilinear(f, t, gradient) - iso;
        const double norm2 = gradient[0] * gradient[0] + gradient[1] * gradient[1] + gradient[2] * gradient[2];
        if (!(norm2 > 0)) break;
        for (int a = 0; a < 3; ++a) t[a] -= r * gradient[a] / norm2;
        t = clamped_into_cell(t);
        residual = std::abs(trilinear(f, t, gradient) - iso);
    }
    return residual < start_residual ? t : start;
}

/// The vertices of the cell at (x, y, z) of the block at @a origin: per edge group, the mean
/// of its crossings and that mean on the isosurface.
void add_cell_vertices(const IfcSamples& samples, const openvdb::Coord& origin, int x, int y, int z, double iso, DualBlock& block) {
    const int cell = DualBlock::cell_index(x, y, z);
    const CellGroups& groups = cell_groups(block.grouping[cell]);
    std::array<double, 8> f;
    for (unsigned c = 0; c < 8; ++c) f[c] = samples.at(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2));
    std::array<Point3, 4> sum{};
    std::array<int, 4> count{};
    for (int e = 0; e < 12; ++e) {
        const int g = groups.of_edge[e];
        if (g < 0) continue;
        const unsigned c0 = kEdgeCorners[e][0], c1 = kEdgeCorners[e][1];
        const Point3 p0 = {double(c0 & 1), double((c0 >> 1) & 1), double(c0 >> 2)};
        const Point3 p1 = {double(c1 & 1), double((c1 >> 1) & 1), double(c1 >> 2)};
        const Point3 p = edge_crossing(p0, f[c0], p1, f[c1], iso);
        for (int a = 0; a < 3; ++a) sum[g][a] += p[a];
        ++count[g];
    }
    const Point3 corner = {double(origin.x() + x), double(origin.y() + y), double(origin.z() + z)};
    for (int g = 0; g < groups.count; ++g) {
        Point3 mean;
        for (int a = 0; a < 3; ++a) mean[a] = sum[g][a] / count[g];
        mean = clamped_into_cell(mean);
        const Point3 on_surface = projected_onto_isosurface(f, iso, mean);
        Point3 mean_at, projected_at;
        for (int a = 0; a < 3; ++a) {
            mean_at[a] = corner[a] + mean[a];
            projected_at[a] = corner[a] + on_surface[a];
        }
        block.mean.push_back(mean_at);
        block.projected.push_back(projected_at);
        block.vertex_cell.push_back(std::uint16_t(cell));
    }
}

/// Whether the face between a cell of configuration @a upper and the one below it along @a n
/// (configuration @a lower) is ambiguous (four crossings) with each cell's groups joining all
/// four into one polygon: the dual edge between their vertices would then be in four triangles.
bool joined_on_both_sides(unsigned lower, unsigned upper, int n) {
    const int u = (n + 1) % 3, w = (n + 2) % 3;
    const auto joined = [&](unsigned config, unsigned base) {
        const CellGroups& groups = cell_groups(config);
        const std::array<int, 4> edges = {cell_edge(base, u), cell_edge(base | (1u << w), u), cell_edge(base, w), cell_edge(base | (1u << u), w)};
        for (int e : edges)
            if (groups.of_edge[e] < 0 || groups.of_edge[e] != groups.of_edge[edges[0]]) return false;
        return true;
    };
    return joined(upper, 0) && joined(lower, 1u << n);
}

/// The ambiguous faces (inside corners on one diagonal) of a configuration: bit 2n + s for the
/// face at side s (0 below, 1 above) along axis n.
unsigned ambiguous_faces(unsigned config) {
    unsigned faces = 0;
    for (int n = 0; n < 3; ++n) {
        const int u = (n + 1) % 3, w = (n + 2) % 3;
        for (unsigned s = 0; s < 2; ++s) {
            const unsigned base = s << n;
            const bool c00 = (config >> base) & 1, c11 = (config >> (base | (1u << u) | (1u << w))) & 1;
            const bool c10 = (config >> (base | (1u << u))) & 1, c01 = (config >> (base | (1u << w))) & 1;
            if (c00 == c11 && c10 == c01 && c00 != c10) faces |= 1u << (2 * n + s);
        }
    }
    return faces;
}

/// The configuration whose groups the cell takes: its own, or its complement's (the same
/// crossed edges, every ambiguous face paired the other way) when its only ambiguous face is
/// joined on both sides and is the only ambiguous face of the cell across it too: both cells
/// then take their complements, so they still pair that face alike, and each splits its four
/// crossings in two (the complement's inside corners there, the face's outside ones, cannot
/// both reach the cell's interior when the face's inside corners do). Cells with more
/// ambiguous faces keep their own (the figures count what remains, docs/dmc.md).
unsigned grouping(const IfcSamples& samples, int x, int y, int z, unsigned config) {
    const unsigned faces = ambiguous_faces(config);
    if (faces == 0 || (faces & (faces - 1)) != 0) return config;
    const int bit = __builtin_ctz(faces), n = bit / 2, s = bit % 2;
    const int step = s == 0 ? -1 : 1;
    const unsigned other = samples.config(x + step * (n == 0), y + step * (n == 1), z + step * (n == 2));
    if (ambiguous_faces(other) != 1u << (2 * n + 1 - s)) return config;
    const bool joined = s == 0 ? joined_on_both_sides(other, config, n) : joined_on_both_sides(config, other, n);
    return joined ? 255 - config : config;
}

void make_block(openvdb::FloatGrid::ConstAccessor& accessor, const SampleClassifier& classifier, IfcSamples& samples, DualBlock& block) {
    samples.origin = block.origin;
    load_ifc_samples(accessor, classifier, samples);
    for (int x = 0; x < kBlockDim; ++x) {
        for (int y = 0; y < kBlockDim; ++y) {
            for (int z = 0; z < kBlockDim; ++z) {
                const int cell = DualBlock::cell_index(x, y, z);
                const unsigned config = samples.config(x, y, z);
                block.config[cell] = std::uint8_t(config);
                block.grouping[cell] = std::uint8_t(config == 0 || config == 255 ? config : grouping(samples, x, y, z, config));
                block.first_vertex[cell] = std::uint16_t(block.projected.size());
                if (config != 0 && config != 255) add_cell_vertices(samples, block.origin, x, y, z, classifier.iso(), block);
                for (int axis = 0; axis < 3; ++axis)
                    if (samples.crossed(x, y, z, axis)) block.crossed_edges.push_back(std::uint16_t(cell * 3 + axis));
            }
        }
    }
}

openvdb::Coord block_origin(const openvdb::Coord& cell) {
    constexpr int mask = ~(kBlockDim - 1);
    return openvdb::Coord(cell.x() & mask, cell.y() & mask, cell.z() & mask);
}

}  // namespace

DualCells::DualCells(const openvdb::FloatGrid& grid, const SampleClassifier& classifier) {
    std::vector<openvdb::Coord> origins = surface_blocks(grid, classifier);
    std::sort(origins.begin(), origins.end());
    blocks_.resize(origins.size());
    for (std::size_t b = 0; b < origins.size(); ++b) blocks_[b].origin = origins[b];
    make_vertices(grid, classifier);
    make_quads();
}

void DualCells::make_vertices(const openvdb::FloatGrid& grid, const SampleClassifier& classifier) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size()), [&](const auto& range) {
        auto accessor = grid.getConstAccessor();
        IfcSamples samples;  // the octree's window of samples, read as it reads them (dc_samples.cpp)
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            if (!block_may_hold_surface(accessor, classifier, blocks_[b].origin)) continue;
            make_block(accessor, classifier, samples, blocks_[b]);
        }
    });
    // Each vertex's star holds a quad per crossed edge of its group.
    for (DualBlock& block : blocks_) {
        block.first = star_first_.size() - 1;
        for (std::size_t v = 0; v < block.projected.size(); ++v) {
            const int cell = block.vertex_cell[v];
            const int group = int(v) - block.first_vertex[cell];
            star_first_.push_back(star_first_.back() + cell_groups(block.grouping[cell]).size[group]);
        }
    }
    if (vertex_count() > 0xffffffffu) throw Error("dual surface: more than 2^32 vertices");
}

void DualCells::make_quads() {
    std::size_t count = 0;
    for (DualBlock& block : blocks_) {
        block.first_quad = count;
        count += block.crossed_edges.size();
    }
    if (count > 0xffffffffu) throw Error("dual surface: more than 2^32 quads");
    quads_.resize(count);
    star_.resize(star_first_.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            const DualBlock& block = blocks_[b];
            std::array<const DualBlock*, 8> below;  // the blocks one step below along the axes of each bit
            for (unsigned d = 0; d < 8; ++d) below[d] = block_of(block.origin.offsetBy(-kBlockDim * int(d & 1), -kBlockDim * int((d >> 1) & 1), -kBlockDim * int(d >> 2)));
            for (std::size_t k = 0; k < block.crossed_edges.size(); ++k) {
                const int cell = block.crossed_edges[k] / 3;
                const openvdb::Coord voxel = block.origin.offsetBy(cell / (kBlockDim * kBlockDim), (cell / kBlockDim) % kBlockDim, cell % kBlockDim);
                std::array<std::uint8_t, 4> ranks;
                const std::size_t q = block.first_quad + k;
                quads_[q] = quad(voxel, block.crossed_edges[k] % 3, below, ranks);
                for (int c = 0; c < 4; ++c) star_[star_first_[quads_[q].vertex[c]] + ranks[c]] = std::uint32_t(q);
            }
        }
    });
}

DualCellVertices DualCells::cell_vertices(const openvdb::Coord& cell) const {
    const DualBlock* block = block_of(cell);
    if (!block) return {};
    const openvdb::Coord local = cell - block->origin;
    const int i = DualBlock::cell_index(local.x(), local.y(), local.z());
    return {std::uint32_t(block->first + block->first_vertex[i]), cell_groups(block->grouping[i]).count};
}

std::vector<DualCellVertices> DualCells::every_cell() const {
    std::vector<DualCellVertices> cells;
    for (const DualBlock& block : blocks_) {
        for (std::size_t v = 0; v < block.projected.size();) {
            const int cell = block.vertex_cell[v];
            const std::uint32_t count = cell_groups(block.grouping[cell]).count;
            cells.push_back({std::uint32_t(block.first + v), count});
            v += count;
        }
    }
    return cells;
}

const DualBlock* DualCells::block_of(const openvdb::Coord& cell) const {
    const openvdb::Coord origin = block_origin(cell);
    const auto it = std::lower_bound(blocks_.begin(), blocks_.end(), origin, [](const DualBlock& b, const openvdb::Coord& o) { return b.origin < o; });
    return it != blocks_.end() && it->origin == origin ? &*it : nullptr;
}

std::uint32_t DualCells::vertex(const DualBlock* block, const openvdb::Coord& cell, int edge, std::uint8_t& rank) const {
    if (!block) throw Error("dual surface: a crossed edge's cell has no block");
    const openvdb::Coord local = cell - block->origin;
    const int i = DualBlock::cell_index(local.x(), local.y(), local.z());
    const CellGroups& groups = cell_groups(block->grouping[i]);
    const int group = groups.of_edge[edge];
    if (group < 0) throw Error("dual surface: a crossed edge is not crossed in a cell round it");
    rank = groups.rank[edge];
    return std::uint32_t(block->first + block->first_vertex[i] + std::size_t(group));
}

DualQuad DualCells::quad(const openvdb::Coord& voxel, int axis, const std::array<const DualBlock*, 8>& below,
                         std::array<std::uint8_t, 4>& ranks) const {
    // Counter-clockwise round +axis (u x w = axis): the cells in quadrants (+,+), (-,+), (-,-), (+,-).
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    DualQuad quad;
    for (int q = 0; q < 4; ++q) {
        const int du = q == 1 || q == 2, dw = q == 2 || q == 3;
        openvdb::Coord cell = voxel;
        cell[u] -= du;
        cell[w] -= dw;
        const unsigned corner = (unsigned(du) << u) | (unsigned(dw) << w);  // the voxel's corner in that cell
        // The cell's block: this one, or one below along u or w where the voxel is on its face.
        const unsigned step = (du && (voxel[u] & (kBlockDim - 1)) == 0 ? 1u << u : 0u) | (dw && (voxel[w] & (kBlockDim - 1)) == 0 ? 1u << w : 0u);
        quad.vertex[q] = vertex(below[step], cell, cell_edge(corner, axis), ranks[q]);
    }
    // Seen from outside means round the direction from the inside end to the outside end.
    const openvdb::Coord local = voxel - below[0]->origin;
    if (!(below[0]->config[DualBlock::cell_index(local.x(), local.y(), local.z())] & 1u)) {
        std::swap(quad.vertex[1], quad.vertex[3]);
        std::swap(ranks[1], ranks[3]);
    }
    return quad;
}

openvdb::Coord DualCells::cell_of_vertex(std::uint32_t v) const {
    const auto it = std::upper_bound(blocks_.begin(), blocks_.end(), std::size_t(v), [](std::size_t i, const DualBlock& b) { return i < b.first; });
    const DualBlock& block = *(it - 1);
    const int cell = block.vertex_cell[v - block.first];
    return block.origin.offsetBy(cell / (kBlockDim * kBlockDim), (cell / kBlockDim) % kBlockDim, cell % kBlockDim);
}

}  // namespace vdbmesh::detail
