// Sampling the RBF field into a sparse grid and the whole reconstruction pipeline.

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>

#include "points_internal.h"
#include "vdbmesh/error.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/points.h"

namespace vdbmesh {

namespace {

/// Averages the points (and normals) that fall in one cell of a grid of side @a cell.
/// Deterministic: cells in key order, points in input order.
PointCloud cluster_points(const PointCloud& cloud, double cell) {
    using Key = std::array<std::int64_t, 3>;
    std::vector<std::pair<Key, std::uint32_t>> keyed(cloud.points.size());
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        Key k;
        for (int a = 0; a < 3; ++a) k[a] = std::int64_t(std::floor(cloud.points[i][a] / cell));
        keyed[i] = {k, std::uint32_t(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    PointCloud out;
    for (std::size_t i = 0; i < keyed.size();) {
        std::size_t j = i;
        Vec3d p{0, 0, 0}, nsum{0, 0, 0};
        while (j < keyed.size() && keyed[j].first == keyed[i].first) {
            const std::uint32_t m = keyed[j].second;
            for (int a = 0; a < 3; ++a) p[a] += cloud.points[m][a], nsum[a] += cloud.normals[m][a];
            ++j;
        }
        const double count = double(j - i);
        for (double& c : p) c /= count;
        const double len = std::sqrt(nsum[0] * nsum[0] + nsum[1] * nsum[1] + nsum[2] * nsum[2]);
        if (len > 1e-9 * count) {  // normals that cancel out: drop the cell
            for (double& c : nsum) c /= len;
            out.points.push_back(p);
            out.normals.push_back(nsum);
        }
        i = j;
    }
    return out;
}

/// Connected components of a mesh by shared vertices; drops those with |volume| below
/// @a fraction of the largest. Returns how many were dropped.
std::size_t drop_small_components(Mesh& mesh, double fraction) {
    const std::size_t nv = mesh.vertices.size();
    std::vector<std::uint32_t> parent(nv);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const auto& t : mesh.triangles) {
        const std::uint32_t a = find(t[0]), b = find(t[1]), c = find(t[2]);
        parent[b] = a;
        parent[find(c)] = find(a);
    }
    std::map<std::uint32_t, double> volume;
    for (const auto& t : mesh.triangles) {
        const auto& p = mesh.vertices[t[0]];
        const auto& q = mesh.vertices[t[1]];
        const auto& r = mesh.vertices[t[2]];
        const double v = (double(p[0]) * (double(q[1]) * r[2] - double(q[2]) * r[1]) -
                          double(p[1]) * (double(q[0]) * r[2] - double(q[2]) * r[0]) +
                          double(p[2]) * (double(q[0]) * r[1] - double(q[1]) * r[0])) / 6.0;
        volume[find(t[0])] += v;
    }
    if (volume.size() <= 1) return 0;
    double largest = 0;
    for (const auto& [root, v] : volume) largest = std::max(largest, std::abs(v));
    std::size_t dropped = 0;
    std::map<std::uint32_t, bool> keep;
    for (const auto& [root, v] : volume) {
        keep[root] = std::abs(v) >= fraction * largest;
        dropped += !keep[root];
    }
    if (!dropped) return 0;
    std::vector<std::uint32_t> remap(nv, std::uint32_t(-1));
    Mesh out;
    for (const auto& t : mesh.triangles) {
        if (!keep[find(t[0])]) continue;
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

}  // namespace

std::shared_ptr<openvdb::FloatGrid> sample_field(const RbfField& field, const SampleOptions& options) {
    openvdb::initialize();
    const Vec3d lo = field.box_min(), hi = field.box_max();
    const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const double h = options.voxel > 0 ? options.voxel : longest / 1.2 / 256.0;
    if (!(options.band >= 1)) throw UsageError("sample: the band must be at least 1 voxel");
    const double background = options.band * h;
    const double lipschitz = 2.0;  // the blended field's slope is about 1 near the surface
    auto grid = openvdb::FloatGrid::create(float(background));
    grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    openvdb::Coord cmin, cmax;
    for (int a = 0; a < 3; ++a) {
        cmin[a] = int(std::ceil(lo[a] / h)) & ~7;
        cmax[a] = int(std::floor(hi[a] / h));
    }
    std::vector<openvdb::Coord> blocks;
    for (int x = cmin[0]; x <= cmax[0]; x += 8)
        for (int y = cmin[1]; y <= cmax[1]; y += 8)
            for (int z = cmin[2]; z <= cmax[2]; z += 8) blocks.emplace_back(x, y, z);
    using Leaf = openvdb::FloatTree::LeafNodeType;
    std::vector<std::unique_ptr<Leaf>> leaves(blocks.size());
    std::vector<signed char> tile(blocks.size(), 0);  // -1 inside tile, +1 outside, 0 leaf
    auto inside_box = [&](const Vec3d& p) {
        for (int a = 0; a < 3; ++a)
            if (p[a] < lo[a] || p[a] > hi[a]) return false;
        return true;
    };
    std::atomic<std::size_t> done{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 16), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            const openvdb::Coord o = blocks[b];
            const Vec3d centre{(o[0] + 3.5) * h, (o[1] + 3.5) * h, (o[2] + 3.5) * h};
            const double f = field.value(centre);
            if (std::abs(f) > lipschitz * 3.5 * std::sqrt(3.0) * h + background) {
                tile[b] = f < 0 ? -1 : 1;
                continue;
            }
            auto leaf = std::make_unique<Leaf>(o, float(background), false);
            bool any = false;
            for (int sx = 0; sx < 8; sx += 4)
                for (int sy = 0; sy < 8; sy += 4)
                    for (int sz = 0; sz < 8; sz += 4) {
                        const Vec3d c{(o[0] + sx + 1.5) * h, (o[1] + sy + 1.5) * h, (o[2] + sz + 1.5) * h};
                        const double g = field.value(c);
                        if (std::abs(g) > lipschitz * 1.5 * std::sqrt(3.0) * h + background) {
                            const float v = g < 0 ? -float(background) : float(background);
                            for (int x = 0; x < 4; ++x)
                                for (int y = 0; y < 4; ++y)
                                    for (int z = 0; z < 4; ++z) leaf->setValueOnly(openvdb::Coord(sx + x, sy + y, sz + z), v);
                            continue;
                        }
                        for (int x = 0; x < 4; ++x)
                            for (int y = 0; y < 4; ++y)
                                for (int z = 0; z < 4; ++z) {
                                    const openvdb::Coord ijk(o[0] + sx + x, o[1] + sy + y, o[2] + sz + z);
                                    const Vec3d p{ijk[0] * h, ijk[1] * h, ijk[2] * h};
                                    double v = inside_box(p) ? field.value(p) : background;
                                    const bool on = std::abs(v) < background;
                                    v = std::clamp(v, -background, background);
                                    leaf->setValueOnly(openvdb::Coord(sx + x, sy + y, sz + z), float(v));
                                    if (on) {
                                        leaf->setValueOn(openvdb::Coord(sx + x, sy + y, sz + z));
                                        any = true;
                                    }
                                }
                    }
            if (any) {
                leaves[b] = std::move(leaf);
            } else {
                tile[b] = f < 0 ? -1 : 1;
            }
            const std::size_t d = ++done;
            (void)d;
        }
    });
    openvdb::FloatTree& tree = grid->tree();
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        if (leaves[b]) {
            tree.addLeaf(leaves[b].release());
        } else if (tile[b] < 0) {
            tree.addTile(1, blocks[b], -float(background), false);
        }
    }
    tree.prune();
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
    report.outliers = remove_outliers(cloud, 8, options.outlier_factor);
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
        cloud = cluster_points(cloud, cell);
        phase("cluster");
    }
    if (options.decimate > 0) {
        DecimateOptions d;
        d.fraction = options.decimate;
        d.seed = options.seed;
        d.neighbours = options.normals.neighbours;
        cloud = decimate_points(cloud, d);
        phase("decimate");
    }
    report.used_points = cloud.points.size();
    progress(0.25);
    const RbfField field(cloud, options.rbf);
    report.leaves = field.leaves();
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
    mesh.error = options.dmc_error;
    result.mesh = mesh_grid(*result.grid, mesh).mesh;
    phase("mesh");
    if (options.min_component > 0) report.dropped_components = drop_small_components(result.mesh, options.min_component);
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
