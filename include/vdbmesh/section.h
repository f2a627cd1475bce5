#pragma once
/// @file section.h
/// @brief Cross-sections of the solid a closed mesh bounds: the cut by a plane as nested closed
/// loops, with its area, perimeter, centroid and second moments (OpenVDB-free; `vdbmesh section`).

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "vdbmesh/mesh.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh {

/// The points x with dot(normal, x) == offset; normal is a unit vector (make_plane()).
struct Plane {
    std::array<double, 3> normal{0, 0, 1};
    double offset = 0;
};

/// @brief The plane through the points whose coordinate @a axis (0 x, 1 y, 2 z) is @a value.
Plane axis_plane(int axis, double value);

/// @brief The plane dot(normal / |normal|, x) == @a offset.
/// @throw UsageError when @a normal is zero or not finite, or @a offset not finite.
Plane make_plane(const std::array<double, 3>& normal, double offset);

/// One closed polyline of a section (its last point joins its first).
struct SectionLoop {
    std::vector<std::array<double, 3>> points;  ///< in world coordinates, on the plane
    /// Signed, in the plane's (u, v) frame: positive for an outer boundary (counter-clockwise
    /// seen from the side the normal points to), negative for a hole.
    double area = 0;
    double perimeter = 0;
    int depth = 0;    ///< loops enclosing it: 0 outermost; odd depths are holes
    int parent = -1;  ///< index of the innermost loop enclosing it, -1 when none
};

/// The section of a solid by one plane. In-plane coordinates are (u, v) = (dot(u_axis, x),
/// dot(v_axis, x)), a right-handed frame with cross(u_axis, v_axis) = plane.normal: for the
/// plane z = c it is (x, y), for x = c (y, z), for y = c (z, x).
struct Section {
    Plane plane;
    std::array<double, 3> u_axis{}, v_axis{};
    std::vector<SectionLoop> loops;  ///< largest |area| first; parents before their children
    double area = 0;       ///< of the material: outer loops minus holes
    double perimeter = 0;  ///< of all loops
    std::array<double, 3> centroid{};  ///< of the material's area (world); the plane's point nearest the origin when area is 0
    /// Second moments of the material's area about the centroid, in the (u, v) frame:
    /// [integral of v^2, integral of u^2, integral of u v] (world units^4).
    std::array<double, 3> second_moments{};
    std::size_t holes() const;  ///< loops of odd depth
};

/// @brief The section of the solid bounded by @a mesh with @a plane. A vertex exactly on the
/// plane counts as lying on the side the normal points to, so every crossing of the surface
/// with the plane is a proper polyline even through vertices and edges lying in the plane.
/// @throw Error when the mesh is not closed and consistently oriented along the cut (a crossing
/// edge that does not belong to exactly one triangle on each side), or has a missing vertex.
Section section_mesh(const Mesh& mesh, const Plane& plane);

/// @brief section_mesh() for each of several planes, of a mesh given record by record and never
/// held (`section --memory`, issue 28): each triangle is cut by every plane as it comes and
/// only the segments are kept (a plane's cut is small beside the mesh). Held: 64 MiB for the
/// program, 12 bytes a vertex of a PLY or OBJ file (its positions; an STL's facets carry
/// theirs), 96 bytes a segment. The same sections, bit for bit, as section_mesh() on the mesh
/// read whole, but for an STL stream, whose edges are named by their ends' positions (the
/// crossing points and the loops' first points may differ to rounding). Feed it as
/// read_mesh_records() does (or a bricked mesher's stream), then finish().
class SectionStream final : public MeshRecordVisitor {
public:
    /// @a name (the file) for messages; @a memory_bytes the limit.
    SectionStream(std::string name, std::vector<Plane> planes, std::uint64_t memory_bytes);
    ~SectionStream() override;
    /// For an OBJ file: the vertices it holds, before any record (they are not announced).
    /// @throw UsageError naming the smallest limit that works when the positions do not fit.
    void plan_vertices(std::uint64_t vertices);
    void announced(std::uint64_t vertices, std::uint64_t faces) override;
    void vertex(const std::array<float, 3>& position) override;
    void triangle(const std::array<std::uint32_t, 3>& triangle) override;
    void facet(const std::array<std::array<float, 3>, 3>& corners) override;
    /// The sections, one a plane in the order given.
    /// @throw Error as section_mesh() for a mesh not closed where a plane cuts it.
    std::vector<Section> finish();
    /// The least limit of any stream: the program and 1 MiB of segments.
    static std::uint64_t least_bytes();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// @brief SectionStream over the file @a path (read_mesh_records(); an OBJ file is read twice,
/// first to count its vertices).
std::vector<Section> section_mesh_stream(const std::filesystem::path& path, const std::vector<Plane>& planes, std::uint64_t memory_bytes);

}  // namespace vdbmesh
