// An installed vdbmesh used from outside: a sphere phantom written as a NIfTI scan, read,
// converted to a grid, meshed by Dual Marching Cubes, checked and written as STL. Prints the
// figures; exits 1 unless the mesh has triangles and is clean (closed, manifold, outward).

// The OpenVDB-free public headers first: none of them may pull in OpenVDB.
#include "vdbmesh/analysis.h"
#include "vdbmesh/atomic_file.h"
#include "vdbmesh/compare.h"
#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/read.h"
#include "vdbmesh/volume_stats.h"
#include "vdbmesh/write_volume.h"
#ifdef OPENVDB_OPENVDB_HAS_BEEN_INCLUDED
#error "a public header that promises to be OpenVDB-free includes OpenVDB"
#endif

#include "vdbmesh/grid.h"

#include <filesystem>
#include <iostream>

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    try {
        const fs::path folder = fs::path(argc > 1 ? argv[1] : fs::temp_directory_path().string()) / "consumer-data";
        fs::create_directories(folder);

        const vdbmesh::PhantomSpec sphere = vdbmesh::phantom_preset("sphere", {48, 48, 48});
        vdbmesh::VolumeHeader header;
        header.dims = sphere.dims;
        header.type = vdbmesh::SampleType::f32;
        vdbmesh::write_volume(folder / "sphere.nii", header,
                              [&](std::int64_t z, float* slice) { vdbmesh::fill_phantom_slice(sphere, z, slice); });

        const auto reader = vdbmesh::open_volume(folder / "sphere.nii");
        vdbmesh::ConvertOptions convert;
        convert.iso = 0.5;
        const openvdb::FloatGrid::Ptr grid = vdbmesh::convert_to_grid(*reader, convert);

        vdbmesh::MeshOptions options;
        options.iso = 0.5;
        options.error = 0.25;
        const vdbmesh::MeshResult result = vdbmesh::mesh_grid(*grid, options);
        vdbmesh::write_mesh(result.mesh, folder / "sphere.stl");
        const vdbmesh::MeshAnalysis analysis = vdbmesh::analyze_mesh(vdbmesh::read_mesh(folder / "sphere.stl"));

        std::cout << "vdbmesh_consumer: " << analysis.triangles << " triangles, closed " << analysis.closed
                  << ", clean " << analysis.is_clean() << ", " << result.report.phases.size() << " phases, "
                  << result.report.total_seconds() << " s\n";
        return analysis.triangles > 0 && analysis.closed && analysis.is_clean() ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "vdbmesh_consumer: " << e.what() << "\n";
        return 1;
    }
}
