#pragma once
/// @file lattice.h
/// @brief Periodic lattices (triply periodic minimal surfaces, a body-centred strut lattice) as
/// per-leaf level-set fields for build_shared_tree(): `vdbmesh lattice`. OpenVDB-free.
///
/// Sample (i, j, k) sits at world (i, j, k) * voxel. The lattice is intersected with the box
/// [box_min, box_min + box] (and with a clip solid) so that the surface is closed. When period / voxel is a
/// whole number P, the phase is taken from (i mod P) so that periods repeat bit for bit and
/// the shared tree stores each distinct leaf once; otherwise nothing repeats exactly.

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "vdbmesh/openvdb_fwd.h"
#include "vdbmesh/shared_tree.h"

namespace vdbmesh {

enum class LatticeKind { gyroid, schwarz_p, diamond, bcc_struts };

/// "gyroid", "schwarz-p", "diamond", "bcc"; @throw UsageError naming the choices.
LatticeKind parse_lattice_kind(const std::string& name);

struct LatticeOptions {
    LatticeKind kind = LatticeKind::gyroid;
    double period = 1.0;                ///< world units
    std::optional<double> thickness;    ///< sheet thickness (TPMS) or strut diameter (bcc), world units
    std::optional<double> level;        ///< solid TPMS: the region where the (normalised) function < level
    std::array<double, 3> box{1, 1, 1}; ///< world units: the box's size
    std::array<double, 3> box_min{0, 0, 0};  ///< world units: the box's minimum corner
    double voxel = 0.1;                 ///< world units
    double band = 3.0;                  ///< narrow band half-width in voxels
};

/// Checks the options (@throw UsageError naming the option, expected and actual values).
void check_lattice_options(const LatticeOptions& options);

/// The lattice as a level-set field; with @a clip (a level set with the same voxel size, no
/// translation, alive as long as the field), intersected with it.
std::unique_ptr<LeafField> make_lattice_field(const LatticeOptions& options, const openvdb::FloatGrid* clip = nullptr);

/// A narrow-band level set (voxel size @a voxel, half-width @a band_voxels + 1) of a closed
/// mesh, for make_lattice_field()'s clip. @throw UsageError when the mesh is empty.
std::shared_ptr<openvdb::FloatGrid> clip_level_set(const Mesh& solid, double voxel, double band_voxels);

/// The lattice's level-set value at world point @a p before box and clip (for tests).
double lattice_value(const LatticeOptions& options, const std::array<double, 3>& p);

}  // namespace vdbmesh
