#include "cli.h"

#include <algorithm>
#include <iostream>
#include <memory>

#include "commands.h"
#include "option_checks.h"
#include "vdbmesh/error.h"

namespace vdbmesh::cli {

namespace {

/// The length of the valid UTF-8 sequence at @a i of @a text (no overlong forms), 0 if none.
std::size_t utf8_length(const std::string& text, std::size_t i) {
    const auto byte = [&](std::size_t k) { return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u; };
    const unsigned lead = byte(i);
    const std::size_t length = lead >= 0xf0 ? (lead <= 0xf4 ? 4 : 0) : lead >= 0xe0 ? 3 : lead >= 0xc2 ? 2 : 0;
    for (std::size_t k = 1; k < length; ++k)
        if ((byte(i + k) & 0xc0u) != 0x80u) return 0;
    return length;
}

/// @a text with control bytes and bytes that are not UTF-8 written as \xNN: a message quotes
/// what it found in a file, and a binary file's bytes would garble the terminal.
std::string printable(const std::string& text) {
    std::string shown;
    for (std::size_t i = 0; i < text.size();) {
        const auto c = static_cast<unsigned char>(text[i]);
        const std::size_t length = c >= 0x80 ? utf8_length(text, i) : (c >= 0x20 && c != 0x7f) || c == '\n' || c == '\t' ? 1 : 0;
        if (length == 0) {
            const char* hex = "0123456789abcdef";
            shown += std::string("\\x") + hex[c >> 4] + hex[c & 15];
            ++i;
        } else {
            shown.append(text, i, length);
            i += length;
        }
    }
    return shown;
}

/// @a message, cut after its first kShownBytes bytes (a bad value is echoed in the messages,
/// and a value of megabytes would bury the message itself), made printable().
std::string bounded(const std::string& message) {
    constexpr std::size_t kShownBytes = 400;
    if (message.size() <= kShownBytes) return printable(message);
    return printable(message.substr(0, kShownBytes)) + "... (" + std::to_string(message.size()) + " bytes in all)";
}

}  // namespace

int run(const std::vector<std::string>& args) {
    CLI::App app{"vdbmesh: tomography (CT, MRI, micro-CT) to clean triangle meshes, through sparse OpenVDB grids",
                 "vdbmesh"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "vdbmesh 0.1.0");
    CommandResult result;
    for (const CommandEntry& entry : kCommands)
        entry.add(*app.add_subcommand(std::make_shared<CheckedCommand>(entry.summary, entry.name, &app)), result);

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
