#pragma once
/// @file labels.h
/// @brief Segmentations: label maps (0 = background, 1..N = structures) and their name tables
/// in, one closed, manifold, outward mesh per label out, the walls between two labels shared
/// (OpenVDB-free). Issue 31.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "vdbmesh/mesh.h"
#include "vdbmesh/read.h"

namespace vdbmesh {

/// One row of a label table.
struct LabelEntry {
    std::string name;
    std::optional<std::array<std::uint8_t, 3>> color;  ///< RGB, when the table gives one
};

/// Label value -> name (and colour). Read from the `value name [more]` text of the MRIcron atlases
/// (aal.nii.txt), FreeSurfer lookup tables (`value name R G B A`) and ITK-SNAP label files
/// (`value R G B A visible mesh "name"`); `#` starts a comment.
using LabelTable = std::map<std::uint32_t, LabelEntry>;

/// Parses a label table. Throws FormatError (file, line, expected, got) on a malformed line.
LabelTable read_label_table(const std::filesystem::path& path);

/// The table beside a scan, if there is one: `<file>.txt` (aal.nii.txt beside aal.nii.gz:
/// the name without .gz), `<stem>.txt`, `<stem>.lut`, `<stem>_LUT.txt`, `<stem>.label`.
std::optional<std::filesystem::path> find_label_table(const std::filesystem::path& scan);

/// The largest label value we take (labels are stored as 16 bits).
constexpr std::uint32_t kMaxLabel = 65535;

/// A label map held densely (x fastest), with the header it came from.
struct LabelVolume {
    VolumeHeader header;
    std::vector<std::uint16_t> labels;
    std::uint16_t at(std::int64_t x, std::int64_t y, std::int64_t z) const {
        return labels[std::size_t((z * header.dims[1] + y) * header.dims[0] + x)];
    }
};

/// Reads all samples of @a reader as labels. Throws FormatError naming the file when a sample
/// is not an integer in 0..kMaxLabel.
LabelVolume read_label_volume(SliceReader& reader);

/// Voxels of one label value.
struct LabelCount {
    std::uint32_t value = 0;
    std::uint64_t voxels = 0;
};

/// The labels of a scan (streamed slab by slab, background 0 included), ascending, or nothing when
/// it is not a label map: a sample that is not an integer in 0..kMaxLabel, or more than
/// @a max_distinct distinct values.
std::optional<std::vector<LabelCount>> count_labels(SliceReader& reader, std::size_t max_distinct,
                                                    const std::function<void(double)>& progress = {});

/// Counts per label of a volume in memory (ascending, 0 included).
std::vector<LabelCount> count_labels(const LabelVolume& volume);

/// Parses "all" or a list "3,5,10-12" of label values; throws UsageError naming --labels.
/// An empty result means all.
std::vector<std::uint32_t> parse_label_list(const std::string& text);

/// How the label mesher works.
struct LabelMeshOptions {
    std::vector<std::uint32_t> labels;  ///< the labels to mesh; empty: all but 0. Others count as background.
    int smoothing_iterations = 16;      ///< constrained smoothing passes (0: the voxel faces)
    /// Each vertex stays within this distance (voxels, per axis, 0 < d <= 2) of its voxel corner:
    /// 1 lets a one-voxel step flatten out (0.45, inside the cube between the 8 voxel centres,
    /// leaves 15% of an AAL mask's normals over 30 degrees off). Crossings are kept out by the
    /// exact hold-back, not by the distance.
    double max_offset = 1.0;
};

/// The multi-label surface: every wall between two different labels once, as triangles whose
/// normal points from sides[t][0] (inside) to sides[t][1] (outside); 0 is the background.
struct LabelSurface {
    Mesh mesh;                                            ///< world coordinates
    std::vector<std::array<std::uint16_t, 2>> sides;      ///< per triangle: {inside label, outside label}
    std::vector<std::uint32_t> labels;                    ///< the labels meshed, ascending
    std::uint64_t relabelled_voxels = 0;                  ///< voxels changed to make every label manifold
    std::uint64_t vertices_held_back = 0;                 ///< vertices kept short of their smoothed place
    int hold_back_rounds = 0;                             ///< rounds of the crossing check that held vertices back
    std::vector<std::pair<std::string, double>> phases;   ///< name, seconds
};

/// @brief The dual (SurfaceNets-style) multi-label mesh of @a volume: one vertex per boundary voxel
/// corner and per manifold sheet through it, smoothed within LabelMeshOptions::max_offset of the
/// corner, each label's volume then put back to its voxel count (smallest moves along the volume
/// gradients); a check with exact predicates keeps vertices back (toward their unsmoothed place)
/// where a triangle would cross another or degenerate. Every label's mesh (label_mesh()) is closed,
/// manifold and outward; walls are shared. Deterministic for any thread count.
LabelSurface mesh_labels(const LabelVolume& volume, const LabelMeshOptions& options = {},
                         const std::function<void(double)>& progress = {});

/// The closed mesh of one label: its walls, oriented out of it, with only the vertices it uses.
Mesh label_mesh(const LabelSurface& surface, std::uint32_t label);

/// label_mesh() of every label of @a surface, in its order, in one pass over the surface.
std::vector<Mesh> label_meshes(const LabelSurface& surface);

/// Volume, area and centroid of one label's mesh.
struct LabelMeasure {
    std::uint32_t value = 0;
    std::uint64_t voxels = 0;       ///< voxels of the label in the map
    double voxel_volume = 0;        ///< voxels x the volume of one voxel
    double volume = 0;              ///< enclosed by its mesh
    double area = 0;
    std::array<double, 3> centroid{};  ///< of the solid
    std::size_t triangles = 0;
};

/// Measures every label of @a surface (in its order) against the voxel counts of @a volume.
std::vector<LabelMeasure> measure_labels(const LabelSurface& surface, const LabelVolume& volume);

}  // namespace vdbmesh
