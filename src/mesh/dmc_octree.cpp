// The depth-3 octree of each leaf for Dual Marching Cubes (Schaefer and Warren 2004,
// section 3: octree generation by bottom-up merging under a QEF tolerance; the 4D QEF of the
// project source 000_*.txt, section 2.1.1).
//
// Values are scaled per leaf by the typical gradient magnitude at the isovalue (the median of
// |grad f| at voxels next to a crossing edge), so that f / G reads as a signed distance in
// voxels and the tolerance is in voxels. Every voxel gets two QEFs of its tangent hyperplane:
// one with the gradient of its whole neighbourhood, one with the feature-preserving tangent
// (dmc_tangent.h). Eight children merge into their parent when
//  - each child is a merged cell,
//  - where the parent's samples and their one-voxel ring do not straddle the isovalue, it
//    merges with no further test: its vertex is its centre, with the mean of the 8 samples
//    around it (the trilinear value there, on its samples' side). Such cells must merge too:
//    a surface cell next to voxels makes dual cells at every voxel corner between them, and
//    its surface keeps the voxels' resolution there;
//  - the RMS residual of the parent's QEF of either kind is at most the tolerance (noisy
//    scans merge by the first, sharp edges and corners by the second),
//  - no sample of the parent and its ring belongs to a sign component that the leaf's block
//    encloses (a speck or a pore: dmc_enclosed_components.h),
//  - the surface inside the parent (with its ring) is a single disc: inside and outside
//    samples each form one 6-connected component, and so do they on the block's boundary
//    shell (one crossing loop), which also keeps the signs at edge midpoints, face centres
//    and the centre consistent with the corners,
//  - no sample within one voxel lies outside the scanned box.
// The vertex is the minimiser of the QEF that fitted the parent alone, the smooth one first;
// a parent only the feature-preserving QEF fits holds an edge or corner, and its vertex comes
// from that QEF with the one-voxel ring where that fits too (the ring sees the faces beyond
// the cell). Tangent fits, the octree's main cost, are then made only around feature cells.

#include "mesh/dmc_octree.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>

#include "mesh/dmc_enclosed_components.h"
#include "mesh/dmc_qef.h"
#include "mesh/dmc_single_sheet.h"
#include "mesh/dmc_tangent.h"

namespace vdbmesh::detail {

namespace {

constexpr int kLevels = 4;  // cells of 1, 2, 4, 8 voxels

/// Only samples within this many voxels (scaled value) of the isovalue enter the QEFs. Far
/// from the surface the density saturates (a CT's material plateaus, a phantom's ramp ends):
/// the graph's tangent planes there are flat and would pull vertices to the plateau's kink
/// instead of the surface's edges and corners.
constexpr double kQefBand = 3.0;

int cells_per_axis(int level) { return kLeafDim >> level; }
int cell_index(int level, int cx, int cy, int cz) {
    const int n = cells_per_axis(level);
    return (cx * n + cy) * n + cz;
}

/// A cube of samples of a SampleBlock: local minimum corner and edge length.
struct SampleCube {
    int x, y, z, n;
};

bool has_sign_change(const SampleBlock& block, const SampleCube& cube) {
    const bool first = block.inside[std::size_t(SampleBlock::index(cube.x, cube.y, cube.z))];
    for (int i = 0; i < cube.n; ++i) {
        for (int j = 0; j < cube.n; ++j) {
            for (int k = 0; k < cube.n; ++k) {
                if (block.inside[std::size_t(SampleBlock::index(cube.x + i, cube.y + j, cube.z + k))] != first) return true;
            }
        }
    }
    return false;
}

bool has_outside_scan(const SampleBlock& block, const SampleCube& cube) {
    for (int i = 0; i < cube.n; ++i) {
        for (int j = 0; j < cube.n; ++j) {
            for (int k = 0; k < cube.n; ++k) {
                if (std::isinf(block.at(cube.x + i, cube.y + j, cube.z + k))) return true;
            }
        }
    }
    return false;
}

/// Median of |grad s| (s the signed value) at voxels of the leaf next to a crossing edge; 0
/// when the leaf holds no crossing.
double typical_gradient(const SampleBlock& block) {
    std::vector<double> magnitudes;
    for (int x = 0; x < kLeafDim; ++x) {
        for (int y = 0; y < kLeafDim; ++y) {
            for (int z = 0; z < kLeafDim; ++z) {
                const bool in = block.inside[std::size_t(SampleBlock::index(x, y, z))];
                if (block.inside[std::size_t(SampleBlock::index(x + 1, y, z))] == in &&
                    block.inside[std::size_t(SampleBlock::index(x, y + 1, z))] == in &&
                    block.inside[std::size_t(SampleBlock::index(x, y, z + 1))] == in &&
                    block.inside[std::size_t(SampleBlock::index(x - 1, y, z))] == in &&
                    block.inside[std::size_t(SampleBlock::index(x, y - 1, z))] == in &&
                    block.inside[std::size_t(SampleBlock::index(x, y, z - 1))] == in) {
                    continue;
                }
                const double gx = block.at(x + 1, y, z) - block.at(x - 1, y, z);
                const double gy = block.at(x, y + 1, z) - block.at(x, y - 1, z);
                const double gz = block.at(x, y, z + 1) - block.at(x, y, z - 1);
                const double g = 0.5 * std::sqrt(gx * gx + gy * gy + gz * gz);
                if (std::isfinite(g)) magnitudes.push_back(g);
            }
        }
    }
    if (magnitudes.empty()) return 0.0;
    std::nth_element(magnitudes.begin(), magnitudes.begin() + std::ptrdiff_t(magnitudes.size() / 2), magnitudes.end());
    return magnitudes[magnitudes.size() / 2];
}

/// Which gradients a QEF is built from: the plane of each sample's whole neighbourhood
/// (sample_gradient), or the feature-preserving tangent (sample_tangent). On a noisy scan the
/// planes of the best-fitting halves jump from sample to sample, and the ring's planes see
/// the noise beyond the cell: requiring those to fit left 88% of the bunny CT's triangles at
/// error 0.25; the smooth planes of the cell alone measure how far its surface is from flat.
enum QefKind { kSmooth = 0, kSharp = 1 };

/// Per level, the QEFs of one kind, computed on first use.
struct QefCache {
    std::array<std::vector<Qef4>, kLevels> qef;  ///< valid where ready is set
    std::array<std::vector<std::uint8_t>, kLevels> ready;
};

/// Scratch space for one leaf's fit.
struct LeafFit {
    SampleBlock block;
    std::array<QefCache, 2> cache;                      ///< by QefKind
    std::array<std::vector<std::uint8_t>, kLevels> ok;  ///< cell is merged or holds no surface
    std::array<std::vector<std::uint8_t>, kLevels> merged;
    std::array<std::vector<CellVertex>, kLevels> vertex;
    std::array<bool, kBlockSamples> enclosed;  ///< per sample: in a component the block encloses
    LeafFit() {
        for (int l = 0; l < kLevels; ++l) {
            const std::size_t cells = std::size_t(1) << (3 * (3 - l));
            for (QefCache& c : cache) {
                c.qef[std::size_t(l)].resize(cells);
                c.ready[std::size_t(l)].resize(cells);
            }
            ok[std::size_t(l)].resize(cells);
            merged[std::size_t(l)].resize(cells);
            vertex[std::size_t(l)].resize(cells);
        }
    }
};

/// The @a kind QEF of voxel (x, y, z) of the leaf, values scaled by 1 / @a scale and made
/// positive inside; computed on first use (tangent fits are the octree's main cost, and many
/// voxels' QEFs are never needed).
const Qef4& voxel_qef(const DmcGrid& grid, double scale, LeafFit& fit, QefKind kind, int x, int y, int z) {
    QefCache& cache = fit.cache[std::size_t(kind)];
    const std::size_t index = std::size_t(cell_index(0, x, y, z));
    Qef4& q = cache.qef[0][index];
    if (cache.ready[0][index]) return q;
    cache.ready[0][index] = 1;
    const SampleBlock& b = fit.block;
    auto s = [&](int x, int y, int z) { return (grid.inside_above ? b.at(x, y, z) - grid.iso : grid.iso - b.at(x, y, z)) / scale; };
    q = Qef4();
    const double f = s(x, y, z);
    if (!(std::abs(f) < kQefBand)) return q;
    Neighbourhood around;
    for (int n = 0; n < 27; ++n) around[std::size_t(n)] = s(x + n / 9 - 1, y + n / 3 % 3 - 1, z + n % 3 - 1);
    const std::optional<Point3d> g = kind == kSmooth ? sample_gradient(around) : sample_tangent(around);
    if (g) q.add_sample({double(x), double(y), double(z)}, f, *g);
    return q;
}

/// The @a kind QEF of the level-@a level cell (cx, cy, cz): the sum of its children's,
/// computed on first use.
const Qef4& cell_qef(const DmcGrid& grid, double scale, LeafFit& fit, QefKind kind, int level, int cx, int cy, int cz) {
    if (level == 0) return voxel_qef(grid, scale, fit, kind, cx, cy, cz);
    QefCache& cache = fit.cache[std::size_t(kind)];
    const std::size_t index = std::size_t(cell_index(level, cx, cy, cz));
    Qef4& qef = cache.qef[std::size_t(level)][index];
    if (cache.ready[std::size_t(level)][index]) return qef;
    cache.ready[std::size_t(level)][index] = 1;
    qef = Qef4();
    for (int c = 0; c < 8; ++c) {
        qef.add(cell_qef(grid, scale, fit, kind, level - 1, 2 * cx + (c & 1), 2 * cy + ((c >> 1) & 1), 2 * cz + (c >> 2)));
    }
    return qef;
}

/// @a qef plus the placement QEFs of the voxels of the one-voxel ring @a ring around the cell,
/// where it lies in the leaf: a cell next to an edge or corner then sees the planes of the
/// faces beyond it, so its vertex goes onto the feature (or the self-check splits the cell).
Qef4 with_ring(const DmcGrid& grid, double scale, LeafFit& fit, const SampleCube& ring, const Qef4& qef) {
    Qef4 result = qef;
    for (int i = 0; i < ring.n; ++i) {
        for (int j = 0; j < ring.n; ++j) {
            for (int k = 0; k < ring.n; ++k) {
                const int x = ring.x + i, y = ring.y + j, z = ring.z + k;
                const bool on_ring = i == 0 || j == 0 || k == 0 || i == ring.n - 1 || j == ring.n - 1 || k == ring.n - 1;
                if (!on_ring || x < 0 || y < 0 || z < 0 || x >= kLeafDim || y >= kLeafDim || z >= kLeafDim) continue;
                result.add(voxel_qef(grid, scale, fit, kSharp, x, y, z));
            }
        }
    }
    return result;
}

/// Whether @a cube holds a sample of a sign component that the leaf's block encloses
/// (dmc_enclosed_components.h): merging there could make its surface vanish.
bool holds_enclosed(const LeafFit& fit, const SampleCube& cube) {
    for (int i = 0; i < cube.n; ++i) {
        for (int j = 0; j < cube.n; ++j) {
            for (int k = 0; k < cube.n; ++k) {
                if (fit.enclosed[std::size_t(SampleBlock::index(cube.x + i, cube.y + j, cube.z + k))]) return true;
            }
        }
    }
    return false;
}

/// Tries to merge the level-@a level cell (cx, cy, cz) of the leaf.
void try_merge(const DmcGrid& grid, double error, double scale, int level, int cx, int cy, int cz, LeafFit& fit) {
    const int size = 1 << level;
    const int index = cell_index(level, cx, cy, cz);
    auto& ok = fit.ok[std::size_t(level)][std::size_t(index)];
    auto& merged = fit.merged[std::size_t(level)][std::size_t(index)];
    ok = 0;
    merged = 0;
    for (int c = 0; c < 8; ++c) {
        const int child = cell_index(level - 1, 2 * cx + (c & 1), 2 * cy + ((c >> 1) & 1), 2 * cz + (c >> 2));
        if (!fit.ok[std::size_t(level - 1)][std::size_t(child)]) return;
    }
    const SampleCube ring = {cx * size - 1, cy * size - 1, cz * size - 1, size + 2};
    if (has_outside_scan(fit.block, ring)) return;
    if (!has_sign_change(fit.block, ring)) {
        const double c = cx * size + 0.5 * (size - 1), cyy = cy * size + 0.5 * (size - 1), cz2 = cz * size + 0.5 * (size - 1);
        const int h = size / 2;
        double sum = 0.0;
        for (int k = 0; k < 8; ++k) sum += fit.block.at(cx * size + h - 1 + (k & 1), cy * size + h - 1 + ((k >> 1) & 1), cz * size + h - 1 + (k >> 2));
        const openvdb::Coord origin = fit.block.origin;
        fit.vertex[std::size_t(level)][std::size_t(index)] = {{origin.x() + c, origin.y() + cyy, origin.z() + cz2}, sum / 8.0};
        ok = 1;
        merged = 1;
        return;
    }
    if (!(scale > 0.0)) return;
    // The cheap topology test first: the QEFs then fit only cells that may merge.
    if (!single_sheet(fit.block, ring.x, ring.y, ring.z, ring.n) || holds_enclosed(fit, ring)) return;
    const Point3d lo = {cx * size - 0.5, cy * size - 0.5, cz * size - 0.5};
    const Point3d hi = {lo[0] + size, lo[1] + size, lo[2] + size};
    auto fitted = [&](const Qef4& qef) -> std::optional<Qef4::Solution> {
        if (qef.count() == 0) return std::nullopt;
        const Qef4::Solution solution = qef.solve(lo, hi);
        if (std::sqrt(solution.error / qef.count()) > error) return std::nullopt;
        return solution;
    };
    std::optional<Qef4::Solution> own = fitted(cell_qef(grid, scale, fit, kSmooth, level, cx, cy, cz));
    std::optional<Qef4::Solution> sharp;
    if (!own) {
        own = fitted(cell_qef(grid, scale, fit, kSharp, level, cx, cy, cz));
        if (!own) return;
        sharp = fitted(with_ring(grid, scale, fit, ring, cell_qef(grid, scale, fit, kSharp, level, cx, cy, cz)));
    }
    const Qef4::Solution& solution = sharp ? *sharp : *own;
    const openvdb::Coord origin = fit.block.origin;
    const double value = grid.inside_above ? grid.iso + solution.value * scale : grid.iso - solution.value * scale;
    fit.vertex[std::size_t(level)][std::size_t(index)] = {
        {origin.x() + solution.position[0], origin.y() + solution.position[1], origin.z() + solution.position[2]}, value};
    ok = 1;
    merged = 1;
}

/// Key of the level-@a level cell whose minimum voxel is @a min_offset in LeafOctree::built_key.
std::uint16_t cell_key(int level, int min_offset) { return std::uint16_t((level << 9) | min_offset); }

/// Writes every merged cell into @a octree's built cells, and makes the largest ones its cells.
void record_cells(const LeafFit& fit, LeafOctree& octree) {
    octree = LeafOctree();
    for (int l = 1; l < kLevels; ++l) {
        const int n = cells_per_axis(l), size = 1 << l;
        for (int cx = 0; cx < n; ++cx) {
            for (int cy = 0; cy < n; ++cy) {
                for (int cz = 0; cz < n; ++cz) {
                    const std::size_t index = std::size_t(cell_index(l, cx, cy, cz));
                    if (!fit.merged[std::size_t(l)][index]) continue;
                    octree.built_key.push_back(cell_key(l, leaf_offset(cx * size, cy * size, cz * size)));
                    octree.built_vertex.push_back(fit.vertex[std::size_t(l)][index]);
                }
            }
        }
    }
    if (octree.built_key.empty()) return;
    octree.level.assign(512, 0);
    octree.expand(0, 0, 0, kLeafDim, kLevels);
}

void build_leaf_octree(const DmcGrid& grid, std::size_t leaf, double error, LeafFit& fit, LeafOctree& octree) {
    load_sample_block(grid, leaf, fit.block);
    const double scale = typical_gradient(fit.block);
    fit.enclosed = enclosed_components(fit.block);
    for (QefCache& cache : fit.cache) {
        for (auto& ready : cache.ready) std::fill(ready.begin(), ready.end(), std::uint8_t(0));
    }
    std::fill(fit.ok[0].begin(), fit.ok[0].end(), std::uint8_t(1));
    for (int level = 1; level < kLevels; ++level) {
        const int n = cells_per_axis(level);
        for (int cx = 0; cx < n; ++cx) {
            for (int cy = 0; cy < n; ++cy) {
                for (int cz = 0; cz < n; ++cz) try_merge(grid, error, scale, level, cx, cy, cz, fit);
            }
        }
    }
    record_cells(fit, octree);
}

}  // namespace

void LeafOctree::expand(int x0, int y0, int z0, int extent, int below) {
    std::vector<std::pair<std::uint16_t, CellVertex>> added;
    for (int l = below - 1; l >= 1; --l) {
        const int size = 1 << l;
        for (int x = x0; x < x0 + extent; x += size) {
            for (int y = y0; y < y0 + extent; y += size) {
                for (int z = z0; z < z0 + extent; z += size) {
                    const int min = leaf_offset(x, y, z);
                    if (level[std::size_t(min)] != 0) continue;  // inside a larger cell
                    const std::uint16_t key = cell_key(l, min);
                    const auto it = std::lower_bound(built_key.begin(), built_key.end(), key);
                    if (it == built_key.end() || *it != key) continue;
                    for (int i = 0; i < size; ++i) {
                        for (int j = 0; j < size; ++j) {
                            for (int k = 0; k < size; ++k) level[std::size_t(leaf_offset(x + i, y + j, z + k))] = std::uint8_t(l);
                        }
                    }
                    added.emplace_back(std::uint16_t(min), built_vertex[std::size_t(it - built_key.begin())]);
                }
            }
        }
    }
    if (added.empty()) return;
    for (std::size_t i = 0; i < merged_min.size(); ++i) added.emplace_back(merged_min[i], merged_vertex[i]);
    std::sort(added.begin(), added.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    merged_min.resize(added.size());
    merged_vertex.resize(added.size());
    for (std::size_t i = 0; i < added.size(); ++i) std::tie(merged_min[i], merged_vertex[i]) = added[i];
}

void LeafOctree::split_cell(int offset) {
    const int l = level_at(offset);
    if (l == 0) return;
    const int x = offset >> 6, y = (offset >> 3) & 7, z = offset & 7;
    const int size = 1 << l, mask = ~(size - 1);
    const int mx = x & mask, my = y & mask, mz = z & mask;
    const auto it = std::lower_bound(merged_min.begin(), merged_min.end(), std::uint16_t(leaf_offset(mx, my, mz)));
    merged_vertex.erase(merged_vertex.begin() + (it - merged_min.begin()));
    merged_min.erase(it);
    for (int i = 0; i < size; ++i) {
        for (int j = 0; j < size; ++j) {
            for (int k = 0; k < size; ++k) level[std::size_t(leaf_offset(mx + i, my + j, mz + k))] = 0;
        }
    }
    expand(mx, my, mz, size, l);
}

std::vector<LeafOctree> build_leaf_octrees(const DmcGrid& grid, double error) {
    std::vector<LeafOctree> octrees(grid.leaves.size());
    if (!(error > 0.0)) return octrees;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.leaves.size()), [&](const auto& range) {
        auto fit = std::make_unique<LeafFit>();
        for (std::size_t leaf = range.begin(); leaf != range.end(); ++leaf) {
            build_leaf_octree(grid, leaf, error, *fit, octrees[leaf]);
        }
    });
    return octrees;
}

}  // namespace vdbmesh::detail
