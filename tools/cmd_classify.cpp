// `vdbmesh classify SAMPLE --class NAME=REF ...`: the class whose reference solid is most
// similar to the sample (least energy after alignment, include/vdbmesh/points.h).

#include <iostream>
#include <limits>
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

namespace {

struct ClassifyCommandOptions {
    std::string sample;
    std::vector<std::string> classes;
    SolidOptions solid;
    SimilarityOptions sim;
    bool json = false;
    CommonOptions common;
};

void run_classify(ClassifyCommandOptions& o) {
    std::vector<std::pair<std::string, std::string>> classes;
    for (const std::string& c : o.classes) {
        const auto eq = c.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == c.size())
            throw UsageError("--class: expected NAME=POINTS_FILE, got \"" + c + "\"");
        const std::string name = c.substr(0, eq);
        for (const auto& named : classes)
            if (named.first == name) throw UsageError("--class: expected each NAME once, got \"" + name + "\" twice");
        classes.emplace_back(name, c.substr(eq + 1));
    }
    const ThreadLimit limit(o.common);
    std::unique_ptr<RbfField> sample_field;
    const PointCloud sample = load_solid(o.sample, o.solid, &sample_field);
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    std::string best;
    double best_energy = std::numeric_limits<double>::infinity();
    for (const auto& [name, path] : classes) {
        std::unique_ptr<RbfField> field;
        const PointCloud ref = load_solid(path, o.solid, &field);
        const SimilarityResult r = compare_solids(sample, *sample_field, ref, *field, o.sim);
        nlohmann::ordered_json j = similarity_json(r);
        j["class"] = name;
        j["reference"] = path;
        list.push_back(j);
        if (!o.json && !o.common.quiet) std::cerr << "  " << name << ": energy " << r.energy << "\n";
        if (r.energy < best_energy) best_energy = r.energy, best = name;
    }
    if (o.json) {
        nlohmann::ordered_json j;
        j["sample"] = o.sample;
        j["class"] = best;
        j["energy"] = best_energy;
        j["classes"] = list;
        std::cout << detail::json_text(j) << "\n";
    } else {
        std::cout << best << "\n";
    }
}

}  // namespace

void add_classify_command(CLI::App& command, CommandResult& result) {
    auto o = std::make_shared<ClassifyCommandOptions>();
    command.add_option("SAMPLE", o->sample, "The points of the solid to classify")->required();
    command.add_option("--class", o->classes, "NAME=POINTS: a class and its reference solid (repeat)")->required();
    add_solid_options(command, o->solid, o->sim);
    command.add_flag("--json", o->json, "Every class's energy and transform, and the winner, as one JSON object");
    add_common_options(command, o->common);
    command.callback([o, &result] {
        run_classify(*o);
        result.status = kSuccess;
    });
}

}  // namespace vdbmesh::cli
