#include "cli.h"

#include <algorithm>
#include <iostream>

#include "commands.h"
#include "vdbmesh/error.h"

namespace vdbmesh::cli {

int run(const std::vector<std::string>& args) {
    CLI::App app{"vdbmesh: tomography (CT, MRI, micro-CT) to clean triangle meshes, through sparse OpenVDB grids",
                 "vdbmesh"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "vdbmesh 0.1.0");
    CommandResult result;
    for (const CommandEntry& entry : kCommands) entry.add(*app.add_subcommand(entry.name, entry.summary), result);

    // CLI11 would say only "A subcommand is required" for a word that is not a command.
    if (!args.empty() && !args.front().empty() && args.front()[0] != '-' &&
        std::none_of(std::begin(kCommands), std::end(kCommands), [&](const CommandEntry& e) { return args.front() == e.name; })) {
        std::cerr << "vdbmesh: unknown command \"" << args.front() << "\"; the commands are:";
        for (const CommandEntry& entry : kCommands) std::cerr << " " << entry.name;
        std::cerr << " (vdbmesh --help)\n";
        return kUsageError;
    }
    // CLI11 wants the arguments reversed when given as a vector.
    std::vector<std::string> reversed(args.rbegin(), args.rend());
    try {
        app.parse(reversed);
    } catch (const CLI::Success& done) {  // --help, --version
        return app.exit(done);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return kUsageError;
    } catch (const UsageError& e) {
        std::cerr << "vdbmesh: " << e.what() << "\n";
        return kUsageError;
    } catch (const std::exception& e) {
        std::cerr << "vdbmesh: error: " << e.what() << "\n";
        return kRuntimeError;
    }
    return result.status;
}

}  // namespace vdbmesh::cli
