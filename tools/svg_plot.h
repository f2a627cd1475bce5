#pragma once
// A line chart as SVG text: one polyline per series, each point labelled, log-scale x axis.
// Written for `vdbmesh compare --plot` (triangles against Hausdorff distance).

#include <string>
#include <vector>

namespace vdbmesh::cli {

struct PlotPoint {
    double x = 0, y = 0;
    std::string label;  ///< drawn beside the point
};

struct PlotSeries {
    std::string name;  ///< legend entry
    std::vector<PlotPoint> points;  ///< joined in this order
};

struct Plot {
    std::string title, x_label, y_label;
    std::vector<PlotSeries> series;
};

/// The chart as a standalone SVG document. x is drawn on a log10 scale (points with x <= 0
/// are left out), y linearly from 0; axes get ticks at powers of ten (x) and round steps (y).
std::string svg_plot(const Plot& plot);

}  // namespace vdbmesh::cli
