#include "view/mesh_request.h"

#include <cmath>
#include <map>
#include <sstream>

#include "vdbmesh/error.h"

namespace vdbmesh::view {

namespace {

const std::map<std::string, MeshLevel> kLevels = {{"coarse", MeshLevel::coarse}, {"full", MeshLevel::full}, {"region", MeshLevel::region}};
const std::map<std::string, MeshMethod> kMethods = {
    {"dc", MeshMethod::dc}, {"mc", MeshMethod::mc}, {"openvdb", MeshMethod::openvdb}};

template <typename Value>
Value named(const std::map<std::string, Value>& names, const std::string& parameter, const std::string& text) {
    const auto found = names.find(text);
    if (found != names.end()) return found->second;
    std::string expected;
    for (const auto& [name, value] : names) expected += (expected.empty() ? "" : "|") + name;
    throw UsageError(parameter + ": expected " + expected + ", got \"" + text + "\"");
}

/// x0,y0,z0,x1,y1,z1 as a box of whole voxels, each max above its min.
IndexBox index_box(const std::array<double, 6>& values, const std::string& text) {
    IndexBox box;
    for (int a = 0; a < 3; ++a) {
        const double lo = values[a], hi = values[a + 3];
        if (lo != std::floor(lo) || hi != std::floor(hi) || !(hi > lo) || std::fabs(lo) > 1e9 || std::fabs(hi) > 1e9)
            throw UsageError("box: expected whole voxels x0,y0,z0,x1,y1,z1 with each max above its min, got \"" + text + "\"");
        box.min[a] = std::int32_t(lo);
        box.max[a] = std::int32_t(hi);
    }
    return box;
}

}  // namespace

double number_param(const std::string& parameter, const std::string& text) {
    std::size_t used = 0;
    double value = NAN;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || !std::isfinite(value)) {
        throw UsageError(parameter + ": expected a finite number, got \"" + text + "\"");
    }
    return value;
}

std::string MeshRequest::key() const {
    std::ostringstream key;
    key.precision(17);
    key << int(level) << ' ' << int(options.method) << ' ' << options.iso << ' ' << options.error << ' '
        << options.adaptivity;
    if (level == MeshLevel::region)
        for (int a = 0; a < 3; ++a) key << ' ' << box.min[a] << ' ' << box.max[a];
    return key.str();
}

MeshRequest parse_mesh_request(const ParamLookup& param, double default_iso) {
    MeshRequest request;
    if (auto level = param("level")) request.level = named(kLevels, "level", *level);
    if (auto method = param("method")) request.options.method = named(kMethods, "method", *method);
    request.options.iso = default_iso;
    if (auto iso = param("iso")) request.options.iso = number_param("iso", *iso);
    if (auto error = param("error")) request.options.error = number_param("error", *error);
    if (auto adaptivity = param("adaptivity")) request.options.adaptivity = number_param("adaptivity", *adaptivity);
    if (auto most = param("max_triangles")) {
        const double value = number_param("max_triangles", *most);
        if (value < 0) throw UsageError("max_triangles: expected a count >= 0, got \"" + *most + "\"");
        request.max_triangles = std::size_t(value);
    }
    const auto box = param("box");
    if (box && request.level != MeshLevel::region) throw UsageError("box: only with level=region");
    if (request.level == MeshLevel::region) {
        const std::array<double, 6> values = number_params<6>(param, "box");  // throws when absent
        request.box = index_box(values, *box);
    }
    return request;
}

}  // namespace vdbmesh::view
