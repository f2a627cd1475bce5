// The finest splats of one 8^3 cell: the isosurface's crossings of the grid edges in each
// 2^3-voxel cube, fitted by least squares (the plane of least squared distances, from the
// crossings' covariance), then merged up to the cell (levels 1 and 2).

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

#include "splat/splat_build.h"

namespace vdbmesh::splat {
namespace {

constexpr int kCell = 8;             // voxels per cell edge (a VDB leaf)
constexpr int kFine = 2;             // voxels per finest cube edge
constexpr int kPad = kCell + 3;      // samples read per axis: one beyond each side for gradients
constexpr double kCrossingMargin = 1e-3;  // as the meshers: no crossing on a sample

struct Crossing {
    Eigen::Vector3d point;    // index space
    Eigen::Vector3d outward;  // unit: the field's gradient, turned to point out of the object
};

/// The samples of the cube [origin - 1, origin + 9]^3, and which of the closed cube's are
/// inside; one thread's, loaded cell after cell.
class CellSamples {
public:
    void load(const openvdb::FloatGrid& grid, const openvdb::Coord& origin, const SampleRule& rule) {
        rule_ = &rule;
        origin_ = Eigen::Vector3d(origin.x(), origin.y(), origin.z());
        read_values(grid, origin);
        const openvdb::CoordBBox padded(origin.offsetBy(-1), origin.offsetBy(kPad - 2));
        if (!rule.scan_box || rule.scan_box->isInside(padded)) {
            in_scan_.fill(true);  // the common case: no sample outside the scan box
        } else {
            std::array<std::array<bool, kPad>, 3> in_scan_axis;
            for (int a = 0; a < 3; ++a)
                for (int l = 0; l < kPad; ++l)
                    in_scan_axis[a][l] = origin[a] + l - 1 >= rule.scan_box->min()[a] && origin[a] + l - 1 <= rule.scan_box->max()[a];
            for (int z = 0; z < kPad; ++z)
                for (int y = 0; y < kPad; ++y)
                    for (int x = 0; x < kPad; ++x)
                        in_scan_[index(x, y, z)] = in_scan_axis[0][x] && in_scan_axis[1][y] && in_scan_axis[2][z];
        }
        for (int z = 1; z <= kCell + 1; ++z)
            for (int y = 1; y <= kCell + 1; ++y) {
                std::uint16_t row = 0;
                for (int x = 1; x <= kCell + 1; ++x) {
                    const std::size_t i = index(x, y, z);
                    const bool inside = in_scan_[i] && (rule.inside_above ? value_[i] > rule.iso : value_[i] < rule.iso);
                    row |= std::uint16_t(inside) << (x - 1);
                }
                inside_rows_[z - 1][y - 1] = row;
            }
    }

    /// Padded coordinates (0 is origin - 1); z fastest, as in a leaf's buffer.
    static std::size_t index(int x, int y, int z) { return (static_cast<std::size_t>(x) * kPad + y) * kPad + z; }

    /// Which samples of the closed cube's row (padded y and z, 1 .. 9) are inside: bit x - 1
    /// for padded x.
    std::uint16_t inside_row(int y, int z) const { return inside_rows_[z - 1][y - 1]; }

    /// The crossing on the edge from padded sample @a p along @a axis, as the meshers place it.
    Crossing crossing(const std::array<int, 3>& p, int axis) const {
        std::array<int, 3> q = p;
        ++q[axis];
        const std::size_t a = index(p[0], p[1], p[2]), b = index(q[0], q[1], q[2]);
        double t = 0.5;  // an end outside the scan box: the surface closes at the midpoint
        if (in_scan_[a] && in_scan_[b])
            t = std::clamp((rule_->iso - value_[a]) / (double(value_[b]) - value_[a]), kCrossingMargin, 1 - kCrossingMargin);
        Crossing c;
        c.point = origin_ + Eigen::Vector3d(p[0] - 1, p[1] - 1, p[2] - 1);
        c.point[axis] += t;
        const Eigen::Vector3d gradient = (1 - t) * gradient_at(p) + t * gradient_at(q);
        const Eigen::Vector3d outward = rule_->inside_above ? Eigen::Vector3d(-gradient) : gradient;
        c.outward = outward.normalized();
        return c;
    }

private:
    /// The values of the padded cube, leaf by leaf: the 8^3 leaves (or tiles) it overlaps, the
    /// cell's own and its neighbours one leaf away (the same values an accessor would give).
    void read_values(const openvdb::FloatGrid& grid, const openvdb::Coord& origin) {
        const auto accessor = grid.getConstAccessor();
        for (int lz = -1; lz <= 1; ++lz)
            for (int ly = -1; ly <= 1; ++ly)
                for (int lx = -1; lx <= 1; ++lx) {
                    const int d[3] = {lx, ly, lz};
                    // The padded coordinates (0..kPad-1) this leaf covers on each axis.
                    int lo[3], hi[3];
                    for (int a = 0; a < 3; ++a) {
                        lo[a] = std::max(0, d[a] * kCell + 1);
                        hi[a] = std::min(kPad - 1, d[a] * kCell + kCell);
                    }
                    const openvdb::Coord leaf_origin = origin + openvdb::Coord(lx * kCell, ly * kCell, lz * kCell);
                    const auto* leaf = accessor.probeConstLeaf(leaf_origin);
                    if (!leaf) {
                        const float tile = accessor.getValue(leaf_origin);
                        for (int x = lo[0]; x <= hi[0]; ++x)
                            for (int y = lo[1]; y <= hi[1]; ++y)
                                std::fill_n(&value_[index(x, y, lo[2])], hi[2] - lo[2] + 1, tile);
                        continue;
                    }
                    const float* data = leaf->buffer().data();  // loads a delayed leaf once
                    for (int x = lo[0]; x <= hi[0]; ++x)
                        for (int y = lo[1]; y <= hi[1]; ++y) {
                            const int ox = x - 1 - lx * kCell, oy = y - 1 - ly * kCell, oz = lo[2] - 1 - lz * kCell;
                            // A run along z, contiguous in both (LeafNode::coordToOffset).
                            std::copy_n(data + ((ox << 6) | (oy << 3) | oz), hi[2] - lo[2] + 1, &value_[index(x, y, lo[2])]);
                        }
                }
    }

    /// Central differences (one-sided at the padding's faces).
    Eigen::Vector3d gradient_at(const std::array<int, 3>& p) const {
        Eigen::Vector3d g;
        for (int axis = 0; axis < 3; ++axis) {
            std::array<int, 3> lo = p, hi = p;
            lo[axis] = std::max(p[axis] - 1, 0);
            hi[axis] = std::min(p[axis] + 1, kPad - 1);
            g[axis] = (sample(hi) - sample(lo)) / (hi[axis] - lo[axis]);
        }
        return g;
    }

    /// A sample's value for gradients: outside the scan box, one unit on the outside side.
    double sample(const std::array<int, 3>& p) const {
        const std::size_t i = index(p[0], p[1], p[2]);
        if (in_scan_[i]) return value_[i];
        return rule_->inside_above ? rule_->iso - 1 : rule_->iso + 1;
    }

    const SampleRule* rule_ = nullptr;
    Eigen::Vector3d origin_;
    // Every element is written by load(): no initialisation per cell.
    std::array<float, kPad * kPad * kPad> value_;
    std::array<bool, kPad * kPad * kPad> in_scan_;
    std::array<std::array<std::uint16_t, kCell + 1>, kCell + 1> inside_rows_;
};

/// The crossings of the closed 8^3 cube, and for each finest (2^3) cube the crossings in
/// its closed cube: an edge on a face or line shared by finest cubes belongs to each.
struct CellCrossings {
    static constexpr int kCubes = kCell / kFine;
    /// The edges of a closed finest cube: 2 x 3 x 3 along each axis.
    static constexpr int kCubeEdges = 3 * kFine * (kFine + 1) * (kFine + 1);
    /// The edges of the closed cell: 8 x 9 x 9 along each axis.
    static constexpr int kCellEdges = 3 * kCell * (kCell + 1) * (kCell + 1);
    struct CubeCrossings {
        std::array<std::uint16_t, kCubeEdges> index;
        int count = 0;
    };
    std::array<Crossing, kCellEdges> all;
    int count = 0;
    std::array<CubeCrossings, kCubes * kCubes * kCubes> by_cube;

    void clear() {
        count = 0;
        for (CubeCrossings& cube : by_cube) cube.count = 0;
    }
};

/// The finest cubes along one axis holding local sample coordinate @a l (0..8): l / 2, and the
/// cube below too when l is on a shared face.
int cubes_holding(int l, std::array<int, 2>& out) {
    int n = 0;
    if (l < kCell) out[n++] = l / kFine;
    if (l % kFine == 0 && l > 0) out[n++] = l / kFine - 1;
    return n;
}

/// Files the crossing @a index, on the edge from padded sample @a p along @a axis, under
/// each finest cube whose closed cube holds the edge.
void file_crossing(const std::array<int, 3>& p, int axis, std::uint16_t index, CellCrossings& crossings) {
    std::array<std::array<int, 2>, 3> cubes{};
    std::array<int, 3> count{};
    for (int a = 0; a < 3; ++a) {
        if (a == axis) {
            cubes[a][0] = (p[a] - 1) / kFine;
            count[a] = 1;
        } else {
            count[a] = cubes_holding(p[a] - 1, cubes[a]);
        }
    }
    constexpr int n = CellCrossings::kCubes;
    for (int i = 0; i < count[0]; ++i)
        for (int j = 0; j < count[1]; ++j)
            for (int k = 0; k < count[2]; ++k) {
                auto& cube = crossings.by_cube[(cubes[2][k] * n + cubes[1][j]) * n + cubes[0][i]];
                cube.index[cube.count++] = index;
            }
}

/// Every crossed edge with both ends in the closed cube [origin, origin + 8]^3, z-major by its
/// first end, then by axis. Row by row: an edge along x is crossed where neighbouring bits of
/// a row differ, along y or z where the bits of neighbouring rows do.
void cell_crossings(const CellSamples& samples, CellCrossings& crossings) {
    crossings.clear();
    constexpr std::uint16_t kEdgesAlongX = (1u << kCell) - 1;  // from x = 1 .. 8
    for (int z = 1; z <= kCell + 1; ++z)
        for (int y = 1; y <= kCell + 1; ++y) {
            const std::uint16_t row = samples.inside_row(y, z);
            const std::uint16_t crossed[3] = {
                std::uint16_t((row ^ (row >> 1)) & kEdgesAlongX),
                std::uint16_t(y <= kCell ? row ^ samples.inside_row(y + 1, z) : 0),
                std::uint16_t(z <= kCell ? row ^ samples.inside_row(y, z + 1) : 0)};
            for (unsigned any = crossed[0] | crossed[1] | crossed[2]; any != 0; any &= any - 1) {
                const int bit = __builtin_ctz(any);
                const std::array<int, 3> p{bit + 1, y, z};
                for (int axis = 0; axis < 3; ++axis) {
                    if (!(crossed[axis] >> bit & 1)) continue;
                    const auto index = static_cast<std::uint16_t>(crossings.count);
                    crossings.all[crossings.count++] = samples.crossing(p, axis);
                    file_crossing(p, axis, index, crossings);
                }
            }
        }
}

std::array<float, 3> floats(const Eigen::Vector3d& v) {
    return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

/// The least-squares splat of @a cube's crossings (at least one): centre their mean, normal
/// the direction of least variance, oriented by the gradients (their sum alone where the
/// points do not span a plane), radius reaching the farthest point.
BuildNode fit_splat(const CellCrossings& crossings, const CellCrossings::CubeCrossings& cube,
                    const std::array<std::int32_t, 3>& origin) {
    const auto point = [&](int i) -> const Crossing& { return crossings.all[cube.index[i]]; };
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(), outward = Eigen::Vector3d::Zero();
    for (int i = 0; i < cube.count; ++i) {
        centre += point(i).point;
        outward += point(i).outward;
    }
    centre /= double(cube.count);
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (int i = 0; i < cube.count; ++i) covariance += (point(i).point - centre) * (point(i).point - centre).transpose();
    Eigen::Vector3d normal = outward.norm() > 0 ? outward.normalized() : Eigen::Vector3d::UnitZ();
    if (cube.count >= 3) {
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
        eigen.computeDirect(covariance);  // closed form for 3 x 3: several times the iterative solver's speed
        // A plane needs two directions of spread; collinear crossings keep the gradient.
        if (eigen.eigenvalues()[1] > 1e-6 * (1 + eigen.eigenvalues()[2])) {
            const Eigen::Vector3d least = eigen.eigenvectors().col(0);
            normal = least.dot(outward) < 0 ? -least : least;
        }
    }
    double radius = 0;
    for (int i = 0; i < cube.count; ++i) radius = std::max(radius, (point(i).point - centre).norm());
    BuildNode node;
    node.centre = floats(centre);
    node.normal = floats(normal);
    node.radius = static_cast<float>(radius * (1 + 1e-6) + 1e-6);  // float centre: stay covering
    node.weight = static_cast<std::uint32_t>(cube.count);
    node.origin = origin;
    return node;
}

/// Nodes of one level of a cell: at most one per finest cube.
struct CellLevel {
    std::array<BuildNode, CellCrossings::kCubes * CellCrossings::kCubes * CellCrossings::kCubes> node;
    int count = 0;
};

/// Merges the nodes of @a below (cubes of size/2, z-major) into @a parents, cubes of @a size
/// inside the cell; @a kept: the children not collapsed into a coplanar parent.
void merge_level(const CellLevel& below, CellLevel& kept, CellLevel& parents, const std::array<std::int32_t, 3>& cell,
                 int size, double tolerance) {
    kept.count = parents.count = 0;
    for (int z = 0; z < kCell; z += size)
        for (int y = 0; y < kCell; y += size)
            for (int x = 0; x < kCell; x += size) {
                const std::array<std::int32_t, 3> origin{cell[0] + x, cell[1] + y, cell[2] + z};
                std::array<BuildNode, 8> children;
                std::uint32_t count = 0;
                for (int i = 0; i < below.count; ++i) {
                    const BuildNode& n = below.node[i];
                    if (n.origin[0] - origin[0] >= 0 && n.origin[0] - origin[0] < size && n.origin[1] - origin[1] >= 0 &&
                        n.origin[1] - origin[1] < size && n.origin[2] - origin[2] >= 0 && n.origin[2] - origin[2] < size)
                        children[count++] = n;
                }
                if (count == 0) continue;
                BuildNode parent = merge_children(children.data(), count, origin);
                if (coplanar_within(parent, children.data(), count, tolerance)) {
                    parent.child_count = 0;
                } else {
                    parent.first_child = std::uint32_t(kept.count);
                    std::copy(children.begin(), children.begin() + count, kept.node.begin() + kept.count);
                    kept.count += int(count);
                }
                parents.node[parents.count++] = parent;
            }
}

/// One thread's working memory for fit_cell() (about 110 KB: reused, not allocated per cell).
struct CellScratch {
    CellSamples samples;
    CellCrossings crossings;
    CellLevel finest, middle, leaf;
    CellLevel finest_kept, middle_kept;  // the children not collapsed
};

}  // namespace

void fit_cell(const openvdb::FloatGrid& grid, const openvdb::Coord& origin, const SampleRule& rule, double tolerance,
              CellNodes& nodes) {
    nodes.finest.clear();
    nodes.middle.clear();
    nodes.leaf.reset();
    thread_local CellScratch scratch;
    scratch.samples.load(grid, origin, rule);
    CellCrossings& crossings = scratch.crossings;
    cell_crossings(scratch.samples, crossings);
    if (crossings.count == 0) return;
    const std::array<std::int32_t, 3> cell{origin.x(), origin.y(), origin.z()};
    CellLevel& finest = scratch.finest;
    finest.count = 0;
    for (int z = 0; z < kCell; z += kFine)
        for (int y = 0; y < kCell; y += kFine)
            for (int x = 0; x < kCell; x += kFine) {
                constexpr int n = CellCrossings::kCubes;
                const auto& cube = crossings.by_cube[((z / kFine) * n + y / kFine) * n + x / kFine];
                if (cube.count == 0) continue;
                finest.node[finest.count++] = fit_splat(crossings, cube, {cell[0] + x, cell[1] + y, cell[2] + z});
            }
    merge_level(finest, scratch.finest_kept, scratch.middle, cell, 2 * kFine, tolerance);
    merge_level(scratch.middle, scratch.middle_kept, scratch.leaf, cell, kCell, tolerance);
    const auto assign = [](std::vector<BuildNode>& out, const CellLevel& level) {
        out.assign(level.node.begin(), level.node.begin() + level.count);
    };
    assign(nodes.finest, scratch.finest_kept);
    assign(nodes.middle, scratch.middle_kept);
    nodes.leaf = scratch.leaf.node[0];
}

CellNodes fit_cell(const openvdb::FloatGrid& grid, const openvdb::Coord& origin, const SampleRule& rule, double tolerance) {
    CellNodes nodes;
    fit_cell(grid, origin, rule, tolerance, nodes);
    return nodes;
}

}  // namespace vdbmesh::splat
