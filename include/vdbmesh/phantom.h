#pragma once
/// @file phantom.h
/// @brief Synthetic test volumes ("phantoms") with an exactly known surface: the analytic
/// shapes of table 3.1 of the DMC coursework (sphere, cube, cylinder, cube minus sphere)
/// plus a torus and rotated shapes, as a smooth 0..1 density whose 0.5 isosurface is the
/// exact shape, with optional deterministic noise.
///
/// Everything here is in voxel index coordinates: voxel (i, j, k) sits at the point (i, j, k),
/// lengths are in voxels, areas in voxels^2 and volumes in voxels^3.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vdbmesh/read.h"

namespace vdbmesh {

/// The geometry of a phantom (centred on PhantomSpec::centre, rotated by rotation_degrees).
enum class PhantomShape {
    sphere,             ///< ball of `radius`
    cube,               ///< axis-aligned cube of edge `side`
    cylinder,           ///< axis along z, `radius`, `height`, flat caps
    cube_minus_sphere,  ///< cube of edge `side` with a concentric ball of `hole_radius` removed
    torus,              ///< in the xy-plane: `radius` from the centre to the tube's axis, `tube_radius`
};

/// A phantom: its shape, size, blur and noise. The defaults are the sphere of table 3.1.
struct PhantomSpec {
    PhantomShape shape = PhantomShape::sphere;
    std::array<std::int64_t, 3> dims{128, 128, 128};  ///< samples along x, y, z
    std::optional<std::array<double, 3>> centre;      ///< shape centre (voxels); default: volume centre (dims-1)/2
    double radius = 40;         ///< sphere and cylinder radius, torus major radius
    double tube_radius = 12;    ///< torus minor radius (< radius)
    double side = 80;           ///< cube edge length
    double height = 120;        ///< cylinder height
    double hole_radius = 50;    ///< cube_minus_sphere: radius of the removed ball, < side / sqrt(2)
    /// Rotation of the shape about its centre, in degrees: first about x, then y, then z
    /// (world = Rz * Ry * Rx * shape). Zero for the axis-aligned shapes of table 3.1.
    std::array<double, 3> rotation_degrees{0, 0, 0};
    double blur = 5;            ///< w of s(v, w): half-width of the density ramp (voxels); 0 gives a step
    double noise_sigma = 0;     ///< standard deviation of the added Gaussian noise (density units)
    std::uint64_t seed = 1;     ///< noise seed: the same seed gives the same samples, bit for bit

    std::array<double, 3> centre_or_default() const;
};

/// Names of the presets: "sphere", "cube", "cylinder", "cube-minus-sphere" (table 3.1),
/// "torus" and "rotated-cube".
std::vector<std::string> phantom_preset_names();

/// The preset @a name for a volume of @a dims: table 3.1's sizes (given for 128^3), all
/// lengths scaled by min(dims) / 128; blur 5 voxels, no noise. Throws UsageError for an
/// unknown name.
PhantomSpec phantom_preset(const std::string& name, const std::array<std::int64_t, 3>& dims);

/// Throws UsageError when @a spec is not a valid phantom (non-positive dims or lengths,
/// torus tube_radius >= radius, cube_minus_sphere hole_radius >= side / sqrt(2), blur < 0,
/// noise_sigma < 0, non-finite values).
void validate_phantom(const PhantomSpec& spec);

/// The coursework's blur function s(v, w): 1 for v < -w, (w - v) / (2w) for -w <= v < w,
/// 0 for v >= w. For w = 0 it is the step 1 / 0 with s(0, 0) = 0.5.
double phantom_blur(double v, double w);

/// Exact Euclidean signed distance (voxels) from (x, y, z) to the shape's surface: negative
/// inside, positive outside. Ignores the volume's bounds.
double phantom_signed_distance(const PhantomSpec& spec, double x, double y, double z);

/// The noise-free density s(signed distance, blur) at (x, y, z): its 0.5 isosurface is the
/// exact surface.
double phantom_density(const PhantomSpec& spec, double x, double y, double z);

/// The sample stored for voxel (i, j, k): the density plus noise_sigma times a standard
/// normal variate that depends only on (seed, i, j, k).
float phantom_sample(const PhantomSpec& spec, std::int64_t i, std::int64_t j, std::int64_t k);

/// Fills slice @a z (dims[0] * dims[1] floats, x fastest) with phantom_sample(), in
/// parallel; the result does not depend on the thread count.
void fill_phantom_slice(const PhantomSpec& spec, std::int64_t z, float* slice);

/// @a count points on the shape's exact surface, in voxel index coordinates, the same for the
/// same arguments: every corner (the cube's eight), a tenth of @a count evenly spaced along the
/// edges by length (the cube's twelve, the cylinder's rims, the circles where cube-minus-sphere's
/// ball cuts the faces), and the rest drawn uniformly by area on the faces. The reference a
/// mesh's distance from the surface is measured from (`compare --phantom`): points taken from
/// a mesh and projected onto the surface would miss its corners and edges.
std::vector<std::array<double, 3>> phantom_surface_points(const PhantomSpec& spec, std::size_t count);

/// Exact area of the shape's surface (voxels^2), ignoring the volume's bounds.
double phantom_area(const PhantomSpec& spec);
/// Exact volume enclosed by the surface (voxels^3), ignoring the volume's bounds.
double phantom_volume(const PhantomSpec& spec);

/// The stored value that stands for density 1 when a phantom is written as @a type: 255 for
/// u8, 127 for i8, 1000 for the 16- and 32-bit integers (a CT-like range), 1 for floats.
/// Writing with value_scale = 1 / full_scale stores density * full_scale, so a reader that
/// applies the scale sees the density again and iso 0.5 is the surface.
double phantom_full_scale(SampleType type);

}  // namespace vdbmesh
