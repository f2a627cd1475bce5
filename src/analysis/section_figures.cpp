// The figures of a section: each loop's signed area, first and second moments by Green's
// theorem over its edges (exact for the polygon), summed over the loops, so holes (clockwise,
// negative) subtract themselves; nesting by point-in-polygon tests against the larger loops.
#include "analysis/section_figures.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vdbmesh::detail {
namespace {

using Vec = std::array<double, 3>;
using Point2 = std::array<double, 2>;

double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// u along the coordinate axis after the normal's dominant one, made orthogonal to the normal;
/// v = normal x u.
void set_frame(Section& section) {
    const Vec& n = section.plane.normal;
    int dominant = 0;
    for (int k = 1; k < 3; ++k) {
        if (std::abs(n[k]) > std::abs(n[dominant])) dominant = k;
    }
    Vec u{0, 0, 0};
    u[(dominant + 1) % 3] = 1;
    const double along = dot(u, n);
    for (int k = 0; k < 3; ++k) u[k] -= along * n[k];
    const double length = std::sqrt(dot(u, u));
    for (double& x : u) x /= length;
    section.u_axis = u;
    section.v_axis = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
}

/// Integrals over a polygon's signed area of 1, x, y, x^2, y^2, xy (Green's theorem).
struct AreaMoments {
    double area = 0, x = 0, y = 0, xx = 0, yy = 0, xy = 0;
    void add(const AreaMoments& o) { area += o.area, x += o.x, y += o.y, xx += o.xx, yy += o.yy, xy += o.xy; }
};

AreaMoments polygon_moments(const std::vector<Point2>& polygon) {
    AreaMoments m;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const auto [x0, y0] = polygon[i];
        const auto [x1, y1] = polygon[(i + 1) % polygon.size()];
        const double c = x0 * y1 - x1 * y0;
        m.area += c / 2;
        m.x += c * (x0 + x1) / 6;
        m.y += c * (y0 + y1) / 6;
        m.xx += c * (x0 * x0 + x0 * x1 + x1 * x1) / 12;
        m.yy += c * (y0 * y0 + y0 * y1 + y1 * y1) / 12;
        m.xy += c * (x0 * y1 + 2 * x0 * y0 + 2 * x1 * y1 + x1 * y0) / 24;
    }
    return m;
}

double perimeter(const std::vector<Vec>& points) {
    double length = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec& a = points[i];
        const Vec& b = points[(i + 1) % points.size()];
        length += std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
    }
    return length;
}

/// Even-odd rule: a ray from @a p towards +x crosses the polygon an odd number of times.
bool contains(const std::vector<Point2>& polygon, const Point2& p) {
    bool inside = false;
    for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
        const Point2& a = polygon[i];
        const Point2& b = polygon[j];
        if ((a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])) inside = !inside;
    }
    return inside;
}

struct Box2 {
    Point2 lo, hi;
    bool contains(const Box2& o) const { return lo[0] <= o.lo[0] && lo[1] <= o.lo[1] && o.hi[0] <= hi[0] && o.hi[1] <= hi[1]; }
};

Box2 bounding_box(const std::vector<Point2>& polygon) {
    Box2 box{polygon[0], polygon[0]};
    for (const Point2& p : polygon) {
        for (int k = 0; k < 2; ++k) box.lo[k] = std::min(box.lo[k], p[k]), box.hi[k] = std::max(box.hi[k], p[k]);
    }
    return box;
}

/// Parents and depths; the loops are sorted by decreasing |area|, so a parent comes first.
void nest(const std::vector<std::vector<Point2>>& polygons, std::vector<SectionLoop>& loops) {
    std::vector<Box2> boxes;
    for (const auto& polygon : polygons) boxes.push_back(bounding_box(polygon));
    for (std::size_t i = 0; i < loops.size(); ++i) {
        for (std::size_t j = i; j-- > 0;) {  // the smallest enclosing loop is the last one found
            if (boxes[j].contains(boxes[i]) && contains(polygons[j], polygons[i][0])) {
                loops[i].parent = int(j);
                loops[i].depth = loops[j].depth + 1;
                break;
            }
        }
    }
}

}  // namespace

Section section_from_loops(const Plane& plane, std::vector<std::vector<Vec>> points) {
    Section section;
    section.plane = plane;
    set_frame(section);
    const Vec reference = points.empty() ? Vec{0, 0, 0} : points[0][0];
    const auto to_plane = [&](const Vec& p) {
        const Vec d{p[0] - reference[0], p[1] - reference[1], p[2] - reference[2]};
        return Point2{dot(d, section.u_axis), dot(d, section.v_axis)};
    };
    std::vector<std::vector<Point2>> polygons;
    std::vector<AreaMoments> moments;
    for (auto& loop : points) {
        std::vector<Point2> polygon;
        for (const Vec& p : loop) polygon.push_back(to_plane(p));
        moments.push_back(polygon_moments(polygon));
        polygons.push_back(std::move(polygon));
    }
    std::vector<std::size_t> order(points.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return std::abs(moments[a].area) > std::abs(moments[b].area);
    });
    AreaMoments total;
    std::vector<std::vector<Point2>> sorted_polygons;
    for (const std::size_t i : order) {
        SectionLoop loop;
        loop.area = moments[i].area;
        loop.perimeter = perimeter(points[i]);
        loop.points = std::move(points[i]);
        section.loops.push_back(std::move(loop));
        sorted_polygons.push_back(std::move(polygons[i]));
        total.add(moments[i]);
        section.perimeter += section.loops.back().perimeter;
    }
    nest(sorted_polygons, section.loops);
    section.area = total.area;
    // The centroid and the central moments in the frame, then the centroid in the world.
    Point2 centre{0, 0};
    if (total.area != 0) {
        centre = {total.x / total.area, total.y / total.area};
        section.second_moments = {total.yy - total.area * centre[1] * centre[1], total.xx - total.area * centre[0] * centre[0],
                                  total.xy - total.area * centre[0] * centre[1]};
        for (int k = 0; k < 3; ++k) section.centroid[k] = reference[k] + centre[0] * section.u_axis[k] + centre[1] * section.v_axis[k];
    } else {
        for (int k = 0; k < 3; ++k) section.centroid[k] = plane.offset * plane.normal[k];
    }
    return section;
}

}  // namespace vdbmesh::detail

namespace vdbmesh {

std::size_t Section::holes() const {
    return std::size_t(std::count_if(loops.begin(), loops.end(), [](const SectionLoop& loop) { return loop.depth % 2 == 1; }));
}

}  // namespace vdbmesh
