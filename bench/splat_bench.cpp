// vdbmesh_splat_bench: the splat hierarchy of a .vdb (issue 30) against its mesh: build time
// and file size of the tree, meshing time and PLY size of the mesh (the issue's "at most the
// meshing time, at most 1/10 of the PLY"), optionally with the grid tiled k x k x k.
//
//   vdbmesh_splat_bench GRID.vdb --iso V [--tile K] [--tolerance T] [--method dc|mc|none] [--error E] [--out DIR]
// (--method none: the tree alone, for grids whose mesh would not fit in memory.)
// Prints one JSON object. Figures and method: bench/README.md.

#include <openvdb/openvdb.h>
#include <tbb/global_control.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <string>

#include "vdbmesh/grid.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/splats.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// @a grid copied k^3 times, each copy shifted by the active box's size (its leaves moved,
/// the transform and metadata kept; the scan box grown to hold them all).
openvdb::FloatGrid::Ptr tiled(const openvdb::FloatGrid& grid, int k) {
    if (k == 1) return grid.deepCopy();
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    // Whole leaves: a multiple of 8 at least the box's size.
    const openvdb::Coord step((box.dim().x() + 7) & ~7, (box.dim().y() + 7) & ~7, (box.dim().z() + 7) & ~7);
    auto out = grid.copyWithNewTree();
    auto& tree = out->tree();
    for (int z = 0; z < k; ++z)
        for (int y = 0; y < k; ++y)
            for (int x = 0; x < k; ++x) {
                const openvdb::Coord shift(x * step.x(), y * step.y(), z * step.z());
                for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
                    auto* copy = new openvdb::FloatTree::LeafNodeType(*leaf);
                    copy->setOrigin(leaf->origin() + shift);
                    tree.addLeaf(copy);
                }
            }
    openvdb::FloatGrid::Ptr result = openvdb::gridPtrCast<openvdb::FloatGrid>(out);
    result->removeMeta(vdbmesh::kMetaScanMin);
    result->removeMeta(vdbmesh::kMetaScanMax);
    return result;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << "usage: vdbmesh_splat_bench GRID.vdb --iso V [--tile K] [--tolerance T] [--method dc|mc|none] [--error E] [--out DIR]\n";
        return 2;
    }
    const std::filesystem::path input = argv[1];
    double iso = 0, tolerance = 0.1, error = 0;
    int tile = 1;
    std::string method = "dc";
    std::filesystem::path out = std::filesystem::temp_directory_path();
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string name = argv[i], value = argv[i + 1];
        if (name == "--iso") iso = std::stod(value);
        else if (name == "--tile") tile = std::stoi(value);
        else if (name == "--tolerance") tolerance = std::stod(value);
        else if (name == "--method") method = value;
        else if (name == "--error") error = std::stod(value);
        else if (name == "--out") out = value;
        else {
            std::cerr << "unknown option " << name << "\n";
            return 2;
        }
    }
    openvdb::initialize();
    const auto grid = tiled(*vdbmesh::read_vdb(input), tile);

    nlohmann::json report;
    report["input"] = input.filename().string();
    report["tile"] = tile;
    report["iso"] = iso;
    report["active_voxels"] = grid->activeVoxelCount();

    vdbmesh::SplatOptions options;
    options.iso = iso;
    options.coplanar_tolerance = tolerance;
    auto start = std::chrono::steady_clock::now();
    const vdbmesh::SplatTree tree = vdbmesh::build_splat_tree(*grid, options);
    report["splat_seconds"] = seconds_since(start);
    report["splat_nodes"] = tree.nodes.size();
    report["splat_leaves"] = tree.leaf_count();
    const auto splat_path = out / "splat-bench.splat";
    vdbmesh::write_splat_file(tree, splat_path);
    report["splat_file_bytes"] = std::filesystem::file_size(splat_path);
    std::filesystem::remove(splat_path);

    if (method == "none") {
        std::cout << report.dump(2) << "\n";
        return 0;
    }
    vdbmesh::MeshOptions mesh_options;
    mesh_options.iso = iso;
    mesh_options.method = method == "mc" ? vdbmesh::MeshMethod::mc : vdbmesh::MeshMethod::dc;
    mesh_options.error = error;
    start = std::chrono::steady_clock::now();
    const vdbmesh::MeshResult mesh = vdbmesh::mesh_grid(*grid, mesh_options);
    report["mesh_method"] = method;
    report["mesh_error"] = error;
    report["mesh_seconds"] = seconds_since(start);
    report["triangles"] = mesh.mesh.triangles.size();
    const auto ply_path = out / "splat-bench.ply";
    vdbmesh::write_mesh(mesh.mesh, ply_path);
    report["ply_bytes"] = std::filesystem::file_size(ply_path);
    std::filesystem::remove(ply_path);
    report["time_ratio"] = report["splat_seconds"].get<double>() / report["mesh_seconds"].get<double>();
    report["size_ratio"] = double(report["splat_file_bytes"].get<std::uint64_t>()) / report["ply_bytes"].get<std::uint64_t>();
    std::cout << report.dump(2) << "\n";
    return 0;
}
