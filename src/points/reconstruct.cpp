// Sampling the RBF field into a sparse grid and the whole reconstruction pipeline.

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>

#include "points_internal.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/points.h"
#include "vdbmesh/union_find.h"

namespace vdbmesh {

namespace {

/// Connected components of a mesh by shared vertices; drops those with |volume| below
/// @a fraction of the largest. Returns how many were dropped.
std::size_t drop_small_components(Mesh& mesh, double fraction, const std::function<bool(const Vec3d&)>& near_points) {
    const std::size_t nv = mesh.vertices.size();
    detail::UnionFind sets(nv);
    for (const auto& t : mesh.triangles) sets.unite(t[0], t[1]), sets.unite(t[0], t[2]);
    std::map<std::uint32_t, double> volume;
    std::map<std::uint32_t, std::pair<std::size_t, std::size_t>> support;  // vertices near the points, all
    for (std::size_t v = 0; v < nv; ++v) {
        auto& s = support[sets.find(std::uint32_t(v))];
        const auto& p = mesh.vertices[v];
        s.first += near_points({p[0], p[1], p[2]});
        ++s.second;
    }
    for (const auto& t : mesh.triangles) {
        const auto& p = mesh.vertices[t[0]];
        const auto& q = mesh.vertices[t[1]];
        const auto& r = mesh.vertices[t[2]];
        const double v = (double(p[0]) * (double(q[1]) * r[2] - double(q[2]) * r[1]) -
                          double(p[1]) * (double(q[0]) * r[2] - double(q[2]) * r[0]) +
                          double(p[2]) * (double(q[0]) * r[1] - double(q[1]) * r[0])) / 6.0;
        volume[sets.find(t[0])] += v;
    }
    if (volume.empty()) return 0;
    double largest = 0;
    for (const auto& [root, v] : volume) largest = std::max(largest, std::abs(v));
    std::size_t dropped = 0;
    std::map<std::uint32_t, bool> keep;
    for (const auto& [root, v] : volume) {
        // Small, or mostly away from the points (cavities the field made inside the solid).
        const auto& sup = support[root];
        keep[root] = std::abs(v) >= fraction * largest && 2 * sup.first >= sup.second;
        dropped += !keep[root];
    }
    if (!dropped) return 0;
    std::vector<std::uint32_t> remap(nv, std::uint32_t(-1));
    Mesh out;
    for (const auto& t : mesh.triangles) {
        if (!keep[sets.find(t[0])]) continue;
        std::array<std::uint32_t, 3> u;
        for (int k = 0; k < 3; ++k) {
            if (remap[t[k]] == std::uint32_t(-1)) {
                remap[t[k]] = std::uint32_t(out.vertices.size());
                out.vertices.push_back(mesh.vertices[t[k]]);
            }
            u[k] = remap[t[k]];
        }
        out.triangles.push_back(u);
    }
    mesh.vertices = std::move(out.vertices);
    mesh.triangles = std::move(out.triangles);
    return dropped;
}

/// Reorders the points along a Morton (Z-order) curve of a 2^21 grid over their box, so that
/// neighbours in space are neighbours in memory (the k-d tree queries and the spanning tree).
void sort_spatially(PointCloud& cloud) {
    const std::size_t n = cloud.points.size();
    Vec3d lo = cloud.points[0], hi = lo;
    for (const Vec3d& p : cloud.points)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-300});
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t code = 0;
        for (int a = 0; a < 3; ++a) {
            const auto q = std::uint64_t(std::clamp((cloud.points[i][a] - lo[a]) / extent, 0.0, 1.0) * 2097151.0);
            code |= detail::spread_bits(q) << a;
        }
        keys[i] = {code, std::uint32_t(i)};
    }
    std::sort(keys.begin(), keys.end());
    PointCloud out;
    out.scan_view = cloud.scan_view;
    out.points.resize(n);
    if (cloud.has_normals()) out.normals.resize(n);
    if (!cloud.scan.empty()) out.scan.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t j = keys[i].second;
        out.points[i] = cloud.points[j];
        if (cloud.has_normals()) out.normals[i] = cloud.normals[j];
        if (!cloud.scan.empty()) out.scan[i] = cloud.scan[j];
    }
    cloud = std::move(out);
}

/// Sets the values (not the active states) of the cube of @a n voxels at local @a min in @a leaf.
void fill_cube(openvdb::FloatTree::LeafNodeType& leaf, const openvdb::Coord& min, int n, float value) {
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y)
            for (int z = 0; z < n; ++z) leaf.setValueOnly(min.offsetBy(x, y, z), value);
}

/// Samples one 8^3 block (@a leaf, voxel @a h) coarse to fine: 4^3 cubes, then 2^3 cells,
/// then voxels, each level evaluated in one batch; a cube or cell whose centre value is farther
/// from 0 than the field can fall over its half diagonal (slope @a lipschitz) plus the band is
/// filled with +-background. Returns whether any voxel is within the band (active).
bool sample_block(const RbfField& field, openvdb::FloatTree::LeafNodeType& leaf, double h, double background, double lipschitz,
                  std::vector<Vec3d>& positions, std::vector<double>& values) {
    const openvdb::Coord o = leaf.origin();
    auto at = [&](double x, double y, double z) { return Vec3d{(o[0] + x) * h, (o[1] + y) * h, (o[2] + z) * h}; };
    std::vector<openvdb::Coord> corners;  // local minima of the cubes of the current level
    for (int x = 0; x < 8; x += 4)
        for (int y = 0; y < 8; y += 4)
            for (int z = 0; z < 8; z += 4) corners.emplace_back(x, y, z);
    // Cubes of side 4 then 2: refine those the surface may cross.
    for (const int side : {4, 2}) {
        positions.clear();
        const double centre = 0.5 * (side - 1);
        for (const openvdb::Coord& c : corners) positions.push_back(at(c[0] + centre, c[1] + centre, c[2] + centre));
        field.values(positions, values);
        std::vector<openvdb::Coord> finer;
        const double decided = lipschitz * 0.5 * (side - 1) * std::sqrt(3.0) * h + background;
        for (std::size_t i = 0; i < corners.size(); ++i) {
            if (std::abs(values[i]) > decided) {
                fill_cube(leaf, corners[i], side, values[i] < 0 ? -float(background) : float(background));
                continue;
            }
            const int half = side / 2;
            for (int x = 0; x < side; x += half)
                for (int y = 0; y < side; y += half)
                    for (int z = 0; z < side; z += half) finer.push_back(corners[i].offsetBy(x, y, z));
        }
        corners.swap(finer);
    }
    // The voxels of the cells left (corners are now single voxels).
    positions.clear();
    for (const openvdb::Coord& c : corners) positions.push_back(at(c[0], c[1], c[2]));
    field.values(positions, values);
    bool any = false;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        const bool on = std::abs(values[i]) < background;
        leaf.setValueOnly(corners[i], float(std::clamp(values[i], -background, background)));
        if (on) {
            leaf.setValueOn(corners[i]);
            any = true;
        }
    }
    return any;
}

}  // namespace

std::shared_ptr<openvdb::FloatGrid> sample_field(const RbfField& field, const SampleOptions& options) {
    openvdb::initialize();
    const Vec3d lo = field.box_min(), hi = field.box_max();
    const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const double h = options.voxel > 0 ? options.voxel : longest / 1.2 / 256.0;
    if (!(options.band >= 1)) throw UsageError("sample: the band must be at least 1 voxel");
    const double background = options.band * h;
    const double lipschitz = 1.5;  // the blended field's slope is about 1 near the surface
    const double reach = options.reach > 0 ? options.reach : 0.06 * longest / 1.2;
    auto grid = openvdb::FloatGrid::create(float(background));
    grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    // The blocks (8^3 voxels, OpenVDB's leaf nodes) covering the field's box.
    std::array<int, 3> first, count;
    for (int a = 0; a < 3; ++a) {
        first[a] = int(std::floor(lo[a] / h / 8.0));
        count[a] = int(std::floor(hi[a] / h / 8.0)) - first[a] + 1;
    }
    const std::size_t nblocks = std::size_t(count[0]) * std::size_t(count[1]) * std::size_t(count[2]);
    auto block_index = [&](int x, int y, int z) { return (std::size_t(x) * std::size_t(count[1]) + std::size_t(y)) * std::size_t(count[2]) + std::size_t(z); };
    auto origin_of = [&](std::size_t b) {
        const int z = int(b % std::size_t(count[2])), y = int(b / std::size_t(count[2]) % std::size_t(count[1])),
                  x = int(b / (std::size_t(count[1]) * std::size_t(count[2])));
        return openvdb::Coord((first[0] + x) * 8, (first[1] + y) * 8, (first[2] + z) * 8);
    };
    const double block_radius = 3.5 * std::sqrt(3.0) * h;
    // Near blocks (within reach of the points): the field decides. 0 far, 1 near.
    std::vector<signed char> near(nblocks, 0);
    std::vector<float> coarse(nblocks, 0.0f);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nblocks, 64), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<Vec3d> centres;
        std::vector<std::size_t> blocks;
        std::vector<double> values;
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            const openvdb::Coord o = origin_of(b);
            const Vec3d centre{(o[0] + 3.5) * h, (o[1] + 3.5) * h, (o[2] + 3.5) * h};
            if (field.distance_to_points(centre) > reach + block_radius) continue;
            near[b] = 1;
            centres.push_back(centre);
            blocks.push_back(b);
        }
        field.values(centres, values);
        for (std::size_t i = 0; i < blocks.size(); ++i) coarse[blocks[i]] = float(values[i]);
    });
    // Far blocks: connected groups (6-neighbours) take the sign most of the near blocks around
    // them have; a group touching the box's side is outside.
    std::vector<signed char> sign(nblocks, 0);  // far: -1 inside, +1 outside
    {
        std::vector<int> label(nblocks, -1);
        std::vector<std::size_t> queue;
        for (std::size_t seed = 0; seed < nblocks; ++seed) {
            if (near[seed] || label[seed] >= 0) continue;
            queue.assign(1, seed);
            label[seed] = int(seed);
            bool boundary = false;
            long vote = 0;
            for (std::size_t q = 0; q < queue.size(); ++q) {
                const std::size_t b = queue[q];
                const int z = int(b % std::size_t(count[2])), y = int(b / std::size_t(count[2]) % std::size_t(count[1])),
                          x = int(b / (std::size_t(count[1]) * std::size_t(count[2])));
                const int nbr[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z}, {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
                for (const auto& c : nbr) {
                    if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= count[0] || c[1] >= count[1] || c[2] >= count[2]) {
                        boundary = true;
                        continue;
                    }
                    const std::size_t m = block_index(c[0], c[1], c[2]);
                    if (near[m]) {
                        vote += coarse[m] < 0 ? -1 : 1;
                    } else if (label[m] < 0) {
                        label[m] = int(seed);
                        queue.push_back(m);
                    }
                }
            }
            const signed char s = (boundary || vote >= 0) ? 1 : -1;
            for (std::size_t b : queue) sign[b] = s;
        }
    }
    using Leaf = openvdb::FloatTree::LeafNodeType;
    std::vector<std::unique_ptr<Leaf>> leaves(nblocks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nblocks, 16), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<Vec3d> positions;
        std::vector<double> values;
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            if (!near[b]) continue;
            const double f = coarse[b];
            if (std::abs(f) > lipschitz * block_radius + background) {
                sign[b] = f < 0 ? -1 : 1;
                continue;
            }
            const openvdb::Coord o = origin_of(b);
            auto leaf = std::make_unique<Leaf>(o, float(background), false);
            const bool any = sample_block(field, *leaf, h, background, lipschitz, positions, values);
            if (any) {
                leaves[b] = std::move(leaf);
            } else {
                sign[b] = f < 0 ? -1 : 1;
            }
        }
    });
    openvdb::FloatTree& tree = grid->tree();
    // Near blocks without a surface become constant leaves, not tiles: mesh_grid() left
    // boundary edges where inside level-1 tiles met leaves of this grid (seen on the bunny).
    for (std::size_t b = 0; b < nblocks; ++b) {
        if (leaves[b]) {
            tree.addLeaf(leaves[b].release());
        } else if (near[b]) {
            tree.addLeaf(new Leaf(origin_of(b), sign[b] < 0 ? -float(background) : float(background), false));
        } else if (sign[b] < 0) {
            tree.addTile(1, origin_of(b), -float(background), false);
        }
    }
    return grid;
}

Reconstruction reconstruct(PointCloud cloud, const ReconstructOptions& options) {
    Reconstruction result;
    ReconstructReport& report = result.report;
    auto clock = std::chrono::steady_clock::now();
    auto phase = [&](const std::string& name) {
        const auto now = std::chrono::steady_clock::now();
        report.phases.emplace_back(name, std::chrono::duration<double>(now - clock).count());
        clock = now;
    };
    auto progress = [&](double f) {
        if (options.progress) options.progress(f);
    };
    report.input_points = cloud.points.size();
    if (cloud.points.size() < 10) throw Error("reconstruct: need at least 10 points, got " + std::to_string(cloud.points.size()));
    sort_spatially(cloud);
    phase("sort");
    report.outliers = remove_outliers(cloud, 8, options.outlier_factor);
    report.outliers += remove_small_clusters(cloud, options.min_cluster);
    phase("outliers");
    progress(0.05);
    estimate_normals(cloud, options.normals);
    phase("normals");
    progress(0.15);
    Vec3d lo = cloud.points[0], hi = cloud.points[0];
    for (const Vec3d& p : cloud.points)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const double voxel = options.sample.voxel > 0 ? options.sample.voxel : longest / 256.0;
    report.voxel = voxel;
    if (options.cluster >= 0) {
        const double cell = options.cluster > 0 ? options.cluster : voxel;
        cloud = points_detail::average_per_cell(cloud, cell);
        phase("cluster");
    }
    report.used_points = cloud.points.size();
    progress(0.25);
    const RbfField field(cloud, options.rbf);
    report.leaves = field.leaves();
    report.fitted_points = field.fitted_points();
    phase("fit");
    progress(0.45);
    SampleOptions sample = options.sample;
    sample.voxel = voxel;
    result.grid = sample_field(field, sample);
    phase("sample");
    progress(0.75);
    MeshOptions mesh;
    mesh.iso = 0;
    mesh.inside = Inside::below;
    mesh.error = options.mesh_error;
    MeshResult meshed = mesh_grid(*result.grid, mesh);
    result.mesh = std::move(meshed.mesh);
    report.mesh_fallbacks = meshed.report.fallbacks;
    phase("mesh");
    if (options.min_component > 0) {
        const double near = 8.0 * field.spacing();
        report.dropped_components = drop_small_components(result.mesh, options.min_component, [&](const Vec3d& p) {
            return field.distance_to_points(p) <= near;
        });
    }
    progress(1.0);
    return result;
}

Vec3d Similarity::apply(const Vec3d& x) const {
    Vec3d y;
    for (int r = 0; r < 3; ++r)
        y[r] = scale * (rotation[3 * r] * x[0] + rotation[3 * r + 1] * x[1] + rotation[3 * r + 2] * x[2]) + translation[r];
    return y;
}

}  // namespace vdbmesh
