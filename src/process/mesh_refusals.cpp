// The refusals `vdbmesh mesh` and Python's mesh() share (mesh_refusals.h).

#include "vdbmesh/mesh_refusals.h"

#include <sstream>

namespace vdbmesh {

namespace {

/// @a name with @a value as @a style spells it: "--error 0" or "error=0" (a text @a value quoted in Python).
std::string option(OptionStyle style, const std::string& name, const std::string& value, bool text = false) {
    if (style == OptionStyle::command_line) return "--" + name + " " + value;
    return name + "=" + (text ? "\"" + value + "\"" : value);
}

const char* method_text(MeshMethod method) {
    switch (method) {
        case MeshMethod::dc: return "dc";
        case MeshMethod::mc: return "mc";
        case MeshMethod::openvdb: return "openvdb";
        case MeshMethod::dual: return "dual";
    }
    return "unknown";
}

std::string number(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

}  // namespace

std::string sharp_refusal(OptionStyle style, bool sharp, MeshMethod method, double error, bool budget) {
    if (!sharp) return {};
    const std::string only = (style == OptionStyle::command_line ? "--sharp" : "sharp=True") + std::string(": only ");
    if (method != MeshMethod::dc)
        return only + "with " + option(style, "method", "dc", true) + ", got " + option(style, "method", method_text(method), true);
    if (!(error > 0))
        return only + "with " + (style == OptionStyle::command_line ? "--error" : "error") + " above 0 (at 0 no cell merges), got " +
               option(style, "error", number(error));
    const std::string triangles = style == OptionStyle::command_line ? "--triangles" : "triangles";
    if (budget) return only + "without " + triangles + " (the budget's decimator keeps no feature), got " + triangles;
    return {};
}

std::string budget_refusal(OptionStyle style, std::uint64_t triangles, std::size_t got, const BudgetReport& report) {
    if (got == 0) return {};
    const std::string asked = option(style, "triangles", std::to_string(triangles)) + ": ";
    if (report.error == 0 && report.meshed_triangles < triangles)
        return asked + "the most accurate mesh there is (" + option(style, "error", "0") + ") has " +
               std::to_string(report.meshed_triangles) + " triangles; expected a budget of at most that many";
    if (got > triangles)
        return asked + "the decimation keeping the mesh closed, manifold and free of self-intersections stops at " +
               std::to_string(got) + " triangles (each further collapse would break a guarantee); expected a budget of at least that many";
    return {};
}

}  // namespace vdbmesh
