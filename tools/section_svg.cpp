// section_svg(): sections as SVG 1.1 text (no dependency).

#include "section_svg.h"

#include <algorithm>
#include <array>
#include <limits>
#include <sstream>

namespace vdbmesh::cli {
namespace {

constexpr double kMarginShare = 0.05;  ///< margin around each section, a share of the drawing's larger side

struct Extent {
    double u_min = std::numeric_limits<double>::infinity(), u_max = -u_min, v_min = u_min, v_max = -u_min;
    bool empty() const { return u_min > u_max; }
};

std::array<double, 2> in_plane(const Section& s, const std::array<double, 3>& p) {
    return {s.u_axis[0] * p[0] + s.u_axis[1] * p[1] + s.u_axis[2] * p[2],
            s.v_axis[0] * p[0] + s.v_axis[1] * p[1] + s.v_axis[2] * p[2]};
}

Extent extent(const Section& s) {
    Extent e;
    for (const SectionLoop& loop : s.loops) {
        for (const auto& p : loop.points) {
            const auto [u, v] = in_plane(s, p);
            e.u_min = std::min(e.u_min, u), e.u_max = std::max(e.u_max, u);
            e.v_min = std::min(e.v_min, v), e.v_max = std::max(e.v_max, v);
        }
    }
    return e;
}

/// One path of every loop of @a s, its top-left corner at (0, top) in the document.
void draw_section(const Section& s, const Extent& e, double margin, double top, std::ostringstream& out) {
    out << "<path fill=\"#c8d7e6\" fill-rule=\"evenodd\" stroke=\"#1f3b57\" stroke-width=\"" << margin / 10 << "\" d=\"";
    for (const SectionLoop& loop : s.loops) {
        for (std::size_t i = 0; i < loop.points.size(); ++i) {
            const auto [u, v] = in_plane(s, loop.points[i]);
            out << (i == 0 ? "M" : "L") << (u - e.u_min + margin) << " " << (top + margin + e.v_max - v) << " ";
        }
        out << "Z ";
    }
    out << "\"/>\n";
}

}  // namespace

std::string section_svg(const std::vector<Section>& sections, const std::vector<std::string>& labels) {
    std::vector<Extent> extents;
    double width = 0, height = 0, largest = 0;
    for (const Section& s : sections) {
        extents.push_back(extent(s));
        const Extent& e = extents.back();
        if (!e.empty()) largest = std::max({largest, e.u_max - e.u_min, e.v_max - e.v_min});
    }
    const double margin = largest > 0 ? kMarginShare * largest : 1;
    for (const Extent& e : extents) {
        width = std::max(width, e.empty() ? 0 : e.u_max - e.u_min);
        height += (e.empty() ? 0 : e.v_max - e.v_min) + 3 * margin;
    }
    width += 2 * margin;
    std::ostringstream out;
    out.precision(9);
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << width << "mm\" height=\"" << height
        << "mm\" viewBox=\"0 0 " << width << " " << height << "\">\n";
    double top = 0;
    for (std::size_t i = 0; i < sections.size(); ++i) {
        const Extent& e = extents[i];
        out << "<text x=\"" << margin << "\" y=\"" << top + 1.5 * margin << "\" font-size=\"" << margin
            << "\" font-family=\"sans-serif\">" << labels[i] << ": area " << sections[i].area << ", perimeter "
            << sections[i].perimeter << ", " << sections[i].loops.size() << " loops</text>\n";
        top += 2 * margin;
        if (!e.empty()) {
            draw_section(sections[i], e, margin, top - margin, out);
            top += e.v_max - e.v_min;
        }
        top += margin;
    }
    out << "</svg>\n";
    return out.str();
}

}  // namespace vdbmesh::cli
