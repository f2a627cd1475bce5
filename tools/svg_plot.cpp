// svg_plot(): a small line-chart writer (SVG 1.1 text, no dependency).

#include "svg_plot.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace vdbmesh::cli {
namespace {

constexpr double kWidth = 760, kHeight = 500;
constexpr double kLeft = 80, kRight = 170, kTop = 50, kBottom = 60;  // margins (legend on the right)
constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};

std::string escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '&') out += "&amp;";
        else if (c == '"') out += "&quot;";
        else out += c;
    }
    return out;
}

/// A "nice" step (1, 2 or 5 times a power of ten) giving about 5 ticks over [0, top].
double nice_step(double top) {
    const double rough = top / 5;
    const double power = std::pow(10.0, std::floor(std::log10(rough)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * power >= rough) return m * power;
    return 10 * power;
}

/// Maps data to pixels.
struct Axes {
    double log_min = 0, log_max = 1, y_max = 1;
    double px(double x) const {
        return kLeft + (std::log10(x) - log_min) / (log_max - log_min) * (kWidth - kLeft - kRight);
    }
    double py(double y) const { return kHeight - kBottom - y / y_max * (kHeight - kTop - kBottom); }
};

Axes fit_axes(const Plot& plot) {
    double x_min = std::numeric_limits<double>::infinity(), x_max = 0, y_max = 0;
    for (const auto& s : plot.series)
        for (const auto& p : s.points) {
            if (!(p.x > 0)) continue;
            x_min = std::min(x_min, p.x);
            x_max = std::max(x_max, p.x);
            y_max = std::max(y_max, p.y);
        }
    Axes axes;
    if (x_max > 0) {
        axes.log_min = std::floor(std::log10(x_min));
        axes.log_max = std::max(std::ceil(std::log10(x_max)), axes.log_min + 1);
    }
    axes.y_max = y_max > 0 ? std::ceil(y_max * 1.1 / nice_step(y_max * 1.1)) * nice_step(y_max * 1.1) : 1;
    return axes;
}

void draw_axes(std::ostringstream& svg, const Plot& plot, const Axes& axes) {
    const double x0 = kLeft, x1 = kWidth - kRight, y0 = kHeight - kBottom, y1 = kTop;
    svg << "<rect x=\"" << x0 << "\" y=\"" << y1 << "\" width=\"" << x1 - x0 << "\" height=\"" << y0 - y1
        << "\" fill=\"none\" stroke=\"#444\"/>\n";
    for (double e = axes.log_min; e <= axes.log_max + 1e-9; e += 1) {
        const double x = axes.px(std::pow(10.0, e));
        svg << "<line x1=\"" << x << "\" y1=\"" << y0 << "\" x2=\"" << x << "\" y2=\"" << y1
            << "\" stroke=\"#ddd\"/>\n<text x=\"" << x << "\" y=\"" << y0 + 18
            << "\" text-anchor=\"middle\">1e" << int(e) << "</text>\n";
    }
    const double step = nice_step(axes.y_max);
    for (double y = 0; y <= axes.y_max + 1e-12; y += step) {
        svg << "<line x1=\"" << x0 << "\" y1=\"" << axes.py(y) << "\" x2=\"" << x1 << "\" y2=\"" << axes.py(y)
            << "\" stroke=\"#ddd\"/>\n<text x=\"" << x0 - 6 << "\" y=\"" << axes.py(y) + 4
            << "\" text-anchor=\"end\">" << y << "</text>\n";
    }
    svg << "<text x=\"" << (x0 + x1) / 2 << "\" y=\"" << kHeight - 15 << "\" text-anchor=\"middle\">"
        << escape(plot.x_label) << "</text>\n";
    svg << "<text transform=\"translate(20," << (y0 + y1) / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
        << escape(plot.y_label) << "</text>\n";
    svg << "<text x=\"" << kWidth / 2 << "\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">" << escape(plot.title)
        << "</text>\n";
}

void draw_series(std::ostringstream& svg, const PlotSeries& series, const Axes& axes, std::size_t index) {
    const char* colour = kColours[index % (sizeof(kColours) / sizeof(kColours[0]))];
    svg << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\" points=\"";
    for (const auto& p : series.points)
        if (p.x > 0) svg << axes.px(p.x) << "," << axes.py(p.y) << " ";
    svg << "\"/>\n";
    for (const auto& p : series.points) {
        if (!(p.x > 0)) continue;
        svg << "<circle cx=\"" << axes.px(p.x) << "\" cy=\"" << axes.py(p.y) << "\" r=\"4\" fill=\"" << colour
            << "\"/>\n<text x=\"" << axes.px(p.x) + 6 << "\" y=\"" << axes.py(p.y) - 6 << "\" font-size=\"11\" fill=\""
            << colour << "\">" << escape(p.label) << "</text>\n";
    }
    const double y = kTop + 20 + 22 * double(index);
    svg << "<line x1=\"" << kWidth - kRight + 15 << "\" y1=\"" << y << "\" x2=\"" << kWidth - kRight + 45 << "\" y2=\""
        << y << "\" stroke=\"" << colour << "\" stroke-width=\"2\"/>\n<text x=\"" << kWidth - kRight + 52
        << "\" y=\"" << y + 4 << "\">" << escape(series.name) << "</text>\n";
}

}  // namespace

std::string svg_plot(const Plot& plot) {
    const Axes axes = fit_axes(plot);
    std::ostringstream svg;
    svg << std::setprecision(6);
    svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth
        << "\" height=\"" << kHeight << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    draw_axes(svg, plot, axes);
    for (std::size_t i = 0; i < plot.series.size(); ++i) draw_series(svg, plot.series[i], axes, i);
    svg << "</svg>\n";
    return svg.str();
}

}  // namespace vdbmesh::cli
