// `vdbmesh similarity A B`: how alike two solids given by points are (the method's chapter
// 3.5), and the similarity transform taking A onto B.

#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "commands.h"
#include "common_options.h"
#include "points_commands.h"
#include "vdbmesh/error.h"
#include "vdbmesh/json_text.h"
#include "vdbmesh/points.h"

namespace vdbmesh::cli {

nlohmann::ordered_json similarity_json(const SimilarityResult& r) {
    nlohmann::ordered_json j;
    j["energy"] = r.energy;
    j["forward_energy"] = r.forward_energy;
    j["reverse_energy"] = r.reverse_energy;
    j["coarse_energy"] = r.coarse_energy;
    j["iterations"] = r.iterations;
    j["scale"] = r.transform.scale;
    j["rotation"] = r.transform.rotation;
    j["translation"] = r.transform.translation;
    return j;
}

PointCloud load_solid(const std::string& path, const SolidOptions& options, std::unique_ptr<RbfField>* field) {
    PointCloud cloud = read_points(path);
    try {
        remove_outliers(cloud, 8, 4.0);
        estimate_normals(cloud, {options.neighbours});
        if (field) *field = std::make_unique<RbfField>(cloud, RbfOptions{});
    } catch (const FormatError&) {
        throw;
    } catch (const Error& e) {  // "normals: need at least 3 points": say which file's
        throw Error(path + ": " + e.what());
    }
    return cloud;
}

namespace {

struct SimilarityCommandOptions {
    std::string a, b;
    SolidOptions solid;
    SimilarityOptions sim;
    bool json = false;
    CommonOptions common;
};

void run_similarity(SimilarityCommandOptions& o) {
    const ThreadLimit limit(o.common);
    std::unique_ptr<RbfField> field_a, field;
    const PointCloud a = load_solid(o.a, o.solid, &field_a);
    const PointCloud b = load_solid(o.b, o.solid, &field);
    const SimilarityResult r = compare_solids(a, *field_a, b, *field, o.sim);
    if (o.json) {
        std::cout << detail::json_text(similarity_json(r)) << "\n";
        return;
    }
    std::cout << std::setprecision(9) << "energy      " << r.energy << "  (mean squared field value / size^2, both ways; 0: the same solid)\n"
              << "scale       " << r.transform.scale << "\n"
              << "rotation    " << r.transform.rotation[0] << " " << r.transform.rotation[1] << " " << r.transform.rotation[2] << "\n"
              << "            " << r.transform.rotation[3] << " " << r.transform.rotation[4] << " " << r.transform.rotation[5] << "\n"
              << "            " << r.transform.rotation[6] << " " << r.transform.rotation[7] << " " << r.transform.rotation[8] << "\n"
              << "translation " << r.transform.translation[0] << " " << r.transform.translation[1] << " " << r.transform.translation[2] << "\n";
}

}  // namespace

void add_solid_options(CLI::App& command, SolidOptions& solid, SimilarityOptions& sim) {
    command.add_option("--neighbours", solid.neighbours, "k of the PCA normals (when the points have none)")->check(CLI::Range(3, 200));
    command.add_option("--points", sim.max_points, "Sample points used in the fit")->check(CLI::Range(16, 1000000));
    command.add_option("--iterations", sim.iterations, "Levenberg-Marquardt iterations at most")->check(CLI::Range(0, 10000));
    command.add_flag("!--no-scale", sim.allow_scale, "Fit rotation and translation only");
}

void add_similarity_command(CLI::App& command, CommandResult& result) {
    auto o = std::make_shared<SimilarityCommandOptions>();
    command.add_option("A", o->a, "The sample solid's points (.xyz/.pts, .ply, .conf)")->required();
    command.add_option("B", o->b, "The reference solid's points")->required();
    add_solid_options(command, o->solid, o->sim);
    command.add_flag("--json", o->json, "Energy and transform as one JSON object");
    add_common_options(command, o->common);
    command.callback([o, &result] {
        run_similarity(*o);
        result.status = kSuccess;
    });
}

}  // namespace vdbmesh::cli
