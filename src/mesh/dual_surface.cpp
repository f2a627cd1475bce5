// The dual surface (dual_surface.h): the cells and their vertices (dual_surface_cells.cpp),
// the written coordinates, the proof (dual_surface_proof.cpp), then a quad per crossed grid
// edge, split for the better angles, in the blocks' order.

#include "mesh/dual_surface.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <string>

#include "mesh/dual_surface_cells.h"
#include "mesh/dual_surface_proof.h"
#include "mesh/mesh_phases.h"

namespace vdbmesh::detail {

namespace {

/// A point of index space as written: world space, rounded to float.
Point3 written(const openvdb::math::Transform& transform, const Point3& p) {
    const openvdb::Vec3d w = transform.indexToWorld(openvdb::Vec3d(p[0], p[1], p[2]));
    return {double(float(w[0])), double(float(w[1])), double(float(w[2]))};
}

DualPositions written_positions(const DualCells& cells, const openvdb::math::Transform& transform) {
    DualPositions positions;
    positions.at.resize(cells.vertex_count());
    positions.mean.resize(cells.vertex_count());
    positions.at_mean.assign(cells.vertex_count(), false);
    const auto& blocks = cells.blocks();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size()), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            const DualBlock& block = blocks[b];
            for (std::size_t v = 0; v < block.projected.size(); ++v) {
                positions.at[block.first + v] = written(transform, block.projected[v]);
                positions.mean[block.first + v] = written(transform, block.mean[v]);
            }
        }
    });
    return positions;
}

Mesh assemble(const DualCells& cells, const DualPositions& positions) {
    Mesh mesh;
    mesh.vertices.resize(positions.at.size());
    mesh.triangles.resize(2 * cells.quads().size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, positions.at.size(), 4096), [&](const auto& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            const Point3& p = positions.at[v];
            mesh.vertices[v] = {float(p[0]), float(p[1]), float(p[2])};
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.quads().size(), 4096), [&](const auto& range) {
        for (std::size_t q = range.begin(); q != range.end(); ++q) {
            const auto triangles = cells.quads()[q].triangles(positions.split_13[q]);
            mesh.triangles[2 * q] = triangles[0];
            mesh.triangles[2 * q + 1] = triangles[1];
        }
    });
    return mesh;
}

}  // namespace

Mesh dual_surface(const openvdb::FloatGrid& grid, const MeshOptions& options, MeshReport& report, DualProofFigures* figures) {
    PhaseClock clock;
    const SampleClassifier classifier(grid, options);
    const DualCells cells(grid, classifier);
    DualPositions positions = written_positions(cells, grid.transform());
    choose_splits(cells, positions);
    clock.lap(report, "vertices");
    if (options.progress) options.progress(0.3);
    const DualProofFigures proof = prove_no_crossings(cells, positions, report);
    if (options.progress) options.progress(0.8);
    clock.lap();
    Mesh mesh = assemble(cells, positions);
    clock.lap(report, "triangles");
    if (proof.moved > 0) report.fallbacks.push_back(std::to_string(proof.moved) + " vertices at their crossings' mean, where the proof found triangles crossing");
    if (proof.unresolved > 0) report.fallbacks.push_back(std::to_string(proof.unresolved) + " pairs of triangles still crossing with every vertex at its mean");
    if (figures) *figures = proof;
    if (options.progress) options.progress(1.0);
    return mesh;
}

}  // namespace vdbmesh::detail
