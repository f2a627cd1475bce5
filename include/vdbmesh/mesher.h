#pragma once
/// @file mesher.h
/// @brief Meshing a sparse grid: Dual Marching Cubes on the VDB tree, Marching Cubes, or
/// OpenVDB's volumeToMesh, all returning the same indexed, welded, oriented Mesh, with a
/// report of what the mesher did. OpenVDB-free: the grid is only declared (openvdb_fwd.h);
/// grid.h makes and reads grids.

#include <functional>
#include <string>
#include <vector>

#include "vdbmesh/mesh.h"
#include "vdbmesh/openvdb_fwd.h"

namespace vdbmesh {

enum class MeshMethod {
    dmc,      ///< Dual Marching Cubes on the leaf octrees (Schaefer and Warren 2004), adaptive by --error,
              ///< clean by a whole-mesh check-and-refine loop
    mc,       ///< Marching Cubes on the samples, vertices welded by grid edge
    openvdb,  ///< openvdb::tools::volumeToMesh, quads split along the shorter diagonal
    dc,       ///< intersection-free Dual Contouring on the leaf octrees (Ju and Udeshi 2006), Marching
              ///< Cubes in unit cells, adaptive by --error
};

/// Which side of the isovalue is the object.
enum class Inside {
    above,  ///< values above the isovalue (dense material in CT)
    below,  ///< values below it (level sets, --inside below)
};

struct MeshOptions {
    MeshMethod method = MeshMethod::dc;  ///< the default: clean by construction at any error
    double iso = 0.0;           ///< isovalue, in the grid's value units
    double error = 0.0;         ///< dc, dmc: error tolerance in voxels (0: no merging; dc: the dual mesh, dmc: equals MC)
    double adaptivity = 0.0;    ///< openvdb: volumeToMesh adaptivity in [0, 1]
    Inside inside = Inside::above;
    bool open_boundary = false; ///< leave the surface open where it meets the scan's box
    std::function<void(double)> progress;  ///< fraction done (0..1), may be empty
};

/// One step of a mesher and the wall time it took.
struct MeshPhase {
    std::string name;  ///< "mesh" (MC, volumeToMesh); DMC: "octree", "contour", "check"
    double seconds = 0;
};

/// What mesh_grid() did: the settings it ran with, where the time went, and anything it
/// did instead of what was asked.
struct MeshReport {
    MeshMethod method = MeshMethod::dmc;
    double iso = 0;
    double error = 0;
    double adaptivity = 0;
    Inside inside = Inside::above;
    bool open_boundary = false;
    std::vector<MeshPhase> phases;       ///< in the order run
    int refinement_rounds = 0;           ///< DMC safety-net rounds, 0 when none ran
    std::vector<std::string> fallbacks;  ///< anything the mesher fell back to, in words; empty when none
    double total_seconds() const;        ///< the sum of the phases
};

/// A mesh and how it was made.
struct MeshResult {
    Mesh mesh;
    MeshReport report;
};

/// Meshes @a grid at options.iso. The result is in world coordinates (the grid's
/// transform), triangles counter-clockwise seen from outside the object. Unless
/// open_boundary, the surface is closed where the object meets the edge of the scanned
/// box (kMetaScanMin/Max metadata; outside it counts as outside the object). The same
/// grid and options give the same mesh, whatever the thread count.
/// MeshMethod::openvdb meshes the grid's values as they are (no scan-box closing).
/// @throw UsageError for a non-finite iso, error < 0, adaptivity outside [0, 1], or
/// open_boundary with MeshMethod::openvdb.
MeshResult mesh_grid(const openvdb::FloatGrid& grid, const MeshOptions& options);

}  // namespace vdbmesh
