// Points on a phantom's exact surface (phantom_surface_points): each shape is described, in its
// own frame, by whole analytic pieces that cover its surface (cube faces, a sphere, a cylinder's
// side and caps, a torus), its edges (curves) and its corners. A piece may cover more than the
// surface (the cube-minus-sphere's faces include the discs the ball removes, its sphere the caps
// outside the cube): a point drawn on it is kept only where the exact signed distance is zero,
// so the points kept are uniform by area on the surface itself.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

#include "phantom_field.h"
#include "vdbmesh/error.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh {

namespace {

using Vec3 = std::array<double, 3>;
constexpr double kPi = 3.14159265358979323846;

/// A point drawn on a piece is on the surface when its exact distance is below this: the
/// pieces lie on the surface up to the rounding of a rotation of coordinates of ~100 voxels
/// (1e-13), and a point off it is off by more than this except within 1e-9 voxel of a cut.
constexpr double kOnSurfaceVoxels = 1e-9;

/// The share of the points spread along the edges (where a shape has any).
constexpr double kEdgeShare = 0.1;

/// Attempts per face point before giving up: the pieces are at least 30% surface for every
/// valid spec (cube-minus-sphere at its largest hole), so this is never reached in practice.
constexpr std::size_t kAttemptsPerPoint = 64;

/// A piece of surface in the shape's frame: its area and a map of the unit square onto it that
/// is uniform by area.
struct Patch {
    double area;
    std::function<Vec3(double, double)> point;
};

/// An edge in the shape's frame: its length and a map of [0, 1] onto it uniform by length.
struct Curve {
    double length;
    std::function<Vec3(double)> point;
};

struct Pieces {
    std::vector<Patch> patches;
    std::vector<Curve> edges;
    std::vector<Vec3> corners;
};

/// SplitMix64 (Steele, Lea and Flood 2014): a seeded stream of uniform numbers in [0, 1).
class Uniforms {
public:
    double next() {
        std::uint64_t h = (state_ += 0x9E3779B97F4A7C15ull);
        h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
        h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
        return static_cast<double>((h ^ (h >> 31)) >> 11) * 0x1.0p-53;
    }

private:
    std::uint64_t state_ = 29;
};

/// A point whose coordinate @a axis is @a normal and the next two (cyclically) @a u and @a v.
Vec3 on_axis(int axis, double normal, double u, double v) {
    Vec3 p{};
    p[axis] = normal;
    p[(axis + 1) % 3] = u;
    p[(axis + 2) % 3] = v;
    return p;
}

void add_sphere(Pieces& pieces, double r) {
    pieces.patches.push_back({4 * kPi * r * r, [r](double a, double b) {
                                  const double z = 1 - 2 * a, s = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * kPi * b;
                                  return Vec3{r * s * std::cos(phi), r * s * std::sin(phi), r * z};
                              }});
}

/// The cube [-h, h]^3: six faces, twelve edges, eight corners.
void add_cube(Pieces& pieces, double h) {
    for (int axis = 0; axis < 3; ++axis) {
        for (const double side : {-h, h}) {
            pieces.patches.push_back({4 * h * h, [=](double a, double b) { return on_axis(axis, side, (2 * a - 1) * h, (2 * b - 1) * h); }});
            for (const double other : {-h, h})  // the edge along axis + 1 at (side, ., other)
                pieces.edges.push_back({2 * h, [=](double t) { return on_axis(axis, side, (2 * t - 1) * h, other); }});
        }
    }
    for (const double x : {-h, h})
        for (const double y : {-h, h})
            for (const double z : {-h, h}) pieces.corners.push_back({x, y, z});
}

/// A circle of radius @a r in the plane where coordinate @a axis is @a normal.
Curve circle(int axis, double normal, double r) {
    return {2 * kPi * r, [=](double t) { return on_axis(axis, normal, r * std::cos(2 * kPi * t), r * std::sin(2 * kPi * t)); }};
}

/// The cylinder about z of radius @a r, |z| <= @a hh: its side, two caps and two rims.
void add_cylinder(Pieces& pieces, double r, double hh) {
    pieces.patches.push_back({2 * kPi * r * 2 * hh, [=](double a, double b) {
                                  return Vec3{r * std::cos(2 * kPi * a), r * std::sin(2 * kPi * a), (2 * b - 1) * hh};
                              }});
    for (const double z : {-hh, hh}) {
        pieces.patches.push_back({kPi * r * r, [=](double a, double b) {
                                      const double s = r * std::sqrt(a);
                                      return Vec3{s * std::cos(2 * kPi * b), s * std::sin(2 * kPi * b), z};
                                  }});
        pieces.edges.push_back(circle(2, z, r));
    }
}

/// The torus in the xy-plane: the angle round the tube has density R + r cos(v), drawn by
/// inverting its distribution function (R v + r sin v) / (2 pi R) by bisection (monotone as r < R).
void add_torus(Pieces& pieces, double major, double minor) {
    pieces.patches.push_back({4 * kPi * kPi * major * minor, [=](double a, double b) {
                                  double low = 0, high = 2 * kPi;
                                  for (int step = 0; step < 60; ++step) {
                                      const double v = 0.5 * (low + high);
                                      ((major * v + minor * std::sin(v)) / (2 * kPi * major) < b ? low : high) = v;
                                  }
                                  const double v = 0.5 * (low + high), u = 2 * kPi * a, ring = major + minor * std::cos(v);
                                  return Vec3{ring * std::cos(u), ring * std::sin(u), minor * std::sin(v)};
                              }});
}

Pieces pieces_of(const PhantomSpec& spec) {
    Pieces pieces;
    switch (spec.shape) {
        case PhantomShape::sphere: add_sphere(pieces, spec.radius); break;
        case PhantomShape::cube: add_cube(pieces, spec.side / 2); break;
        case PhantomShape::cylinder: add_cylinder(pieces, spec.radius, spec.height / 2); break;
        case PhantomShape::torus: add_torus(pieces, spec.radius, spec.tube_radius); break;
        case PhantomShape::cube_minus_sphere: {
            const double h = spec.side / 2, rho2 = spec.hole_radius * spec.hole_radius - h * h;
            add_cube(pieces, h);
            add_sphere(pieces, spec.hole_radius);
            if (rho2 > 0)  // the circles where the ball cuts the faces
                for (int axis = 0; axis < 3; ++axis)
                    for (const double side : {-h, h}) pieces.edges.push_back(circle(axis, side, std::sqrt(rho2)));
            break;
        }
    }
    return pieces;
}

}  // namespace

std::vector<std::array<double, 3>> phantom_surface_points(const PhantomSpec& spec, std::size_t count) {
    const detail::PhantomField field(spec);
    const Pieces pieces = pieces_of(spec);
    std::vector<Vec3> points;
    points.reserve(count);
    const auto keep = [&](const Vec3& shape_point) {
        const Vec3 p = field.to_volume(shape_point);
        if (points.size() < count && std::abs(field.signed_distance(p[0], p[1], p[2])) <= kOnSurfaceVoxels) points.push_back(p);
    };
    for (const Vec3& corner : pieces.corners) keep(corner);

    double edge_length = 0;
    for (const Curve& edge : pieces.edges) edge_length += edge.length;
    const double edge_points = std::floor(kEdgeShare * static_cast<double>(count));
    for (const Curve& edge : pieces.edges) {
        const auto n = static_cast<std::size_t>(std::llround(edge_points * edge.length / edge_length));
        for (std::size_t i = 0; i < n; ++i) keep(edge.point((static_cast<double>(i) + 0.5) / static_cast<double>(n)));
    }

    double area = 0;
    for (const Patch& patch : pieces.patches) area += patch.area;
    Uniforms uniforms;
    const std::size_t face_points = count - points.size();
    for (std::size_t attempt = 0; points.size() < count; ++attempt) {
        if (attempt == kAttemptsPerPoint * face_points)
            throw Error("phantom: could not draw " + std::to_string(face_points) + " points on the surface");
        double pick = uniforms.next() * area;
        std::size_t i = 0;
        while (i + 1 < pieces.patches.size() && pick >= pieces.patches[i].area) pick -= pieces.patches[i++].area;
        const double a = uniforms.next(), b = uniforms.next();
        keep(pieces.patches[i].point(a, b));
    }
    return points;
}

}  // namespace vdbmesh
