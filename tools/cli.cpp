#include "cli.h"

#include <algorithm>
#include <iostream>

#include "commands.h"
#include "vdbmesh/error.h"

namespace vdbmesh::cli {

namespace {

/// @a message, cut after its first kShownBytes bytes: a bad value is echoed in the messages,
/// and a value of megabytes would bury the message itself.
std::string bounded(const std::string& message) {
    constexpr std::size_t kShownBytes = 400;
    if (message.size() <= kShownBytes) return message;
    return message.substr(0, kShownBytes) + "... (" + std::to_string(message.size()) + " bytes in all)";
}

}  // namespace

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
        std::cerr << "vdbmesh: " << bounded("unknown command \"" + args.front() + "\"") << "; the commands are:";
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
        std::cerr << "vdbmesh: " << bounded(e.what()) << "\nRun with --help for more information.\n";
        return kUsageError;
    } catch (const UsageError& e) {
        std::cerr << "vdbmesh: " << bounded(e.what()) << "\n";
        return kUsageError;
    } catch (const std::exception& e) {
        std::cerr << "vdbmesh: error: " << bounded(e.what()) << "\n";
        return kRuntimeError;
    }
    return result.status;
}

}  // namespace vdbmesh::cli
