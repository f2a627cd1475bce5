// Issue 32: every option of every subcommand (read from the registry, so a new option is
// covered without a change here) given NaN, infinity, 0, -1, a huge number and a word, on
// tiny inputs, by the vdbmesh program in a child process. No run may crash, hang or print
// raw bytes; a refusal exits 2 naming the option (or 1 naming the option or a file); a
// non-number never passes where a number is expected.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fcntl.h>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "commands.h"
#include "test_data.h"

extern char** environ;

namespace vdbmesh::cli {
namespace {

constexpr auto kRunLimit = std::chrono::seconds(60);  ///< a run still going after this has hung

struct Outcome {
    int status = 0;        ///< exit status; 128 + signal when killed by one
    bool served = false;   ///< `view` started serving (and was stopped)
    bool hung = false;
    std::string message;   ///< stderr
};

std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

/// Runs the program in @a folder with @a args; stops a `view` once it serves.
Outcome run_program(const std::filesystem::path& folder, std::vector<std::string> args) {
    args.insert(args.begin(), VDBMESH_BINARY);
    args.push_back("--quiet");
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    const std::string out = (folder / "stdout.txt").string(), err = (folder / "stderr.txt").string();
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&files, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const std::filesystem::path cwd = std::filesystem::current_path();
    std::filesystem::current_path(folder);
    pid_t child = 0;
    const int spawned = posix_spawn(&child, argv[0], &files, nullptr, argv.data(), environ);
    std::filesystem::current_path(cwd);
    posix_spawn_file_actions_destroy(&files);
    Outcome outcome;
    if (spawned != 0) {
        outcome.status = -1;
        return outcome;
    }
    const auto start = std::chrono::steady_clock::now();
    int status = 0;
    while (::waitpid(child, &status, WNOHANG) == 0) {
        outcome.served = read_file(out).find("serving") != std::string::npos;
        outcome.hung = std::chrono::steady_clock::now() - start > kRunLimit;
        if (outcome.served || outcome.hung) {
            ::kill(child, SIGTERM);
            ::waitpid(child, &status, 0);
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    outcome.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    outcome.message = read_file(err);
    return outcome;
}

/// Arguments with which each command succeeds on the tiny inputs, so that the option under test
/// is what a refusal is about.
const std::map<std::string, std::vector<std::string>> kValidArguments = {
    {"info", {"scan.nii"}},
    {"convert", {"scan.nii", "--iso", "0.5", "-o", "out.vdb"}},
    {"phantom", {"sphere", "--size", "8", "-o", "out.nii"}},
    {"mesh", {"scan.vdb", "-o", "out.stl"}},
    {"check", {"io.stl", "--ref", "io.stl", "--samples", "100"}},
    {"measure", {"io.stl"}},
    {"section", {"io.stl", "--plane", "z=8"}},
    {"reconstruct", {"p.xyz", "-o", "out.stl"}},
    {"similarity", {"p.xyz", "p.xyz", "--points", "64", "--iterations", "2"}},
    {"classify", {"p.xyz", "--class", "a=p.xyz", "--points", "64", "--iterations", "2"}},
    {"compare", {"--phantom", "sphere", "--size", "12", "--samples", "200", "--error", "0", "--adaptivity", "0"}},
    {"lattice", {"gyroid", "--period", "2", "--thickness", "0.5", "--box", "2", "--voxel", "0.5", "--measure"}},
    {"process", {"level.vdb", "--deposit", "0.25", "-o", "out.vdb"}},
    {"view", {"io.stl", "--no-open", "--port", "0"}},
};

const std::vector<std::string> kHostileValues = {"nan", "inf", "0", "-1", "1e300", "abc"};

/// Every option that takes a value, per command: its names ("-o", "--output").
std::map<std::string, std::vector<std::vector<std::string>>> options_of_every_command() {
    CLI::App app;
    CommandResult result;
    for (const CommandEntry& entry : kCommands) entry.add(*app.add_subcommand(entry.name, entry.summary), result);
    std::map<std::string, std::vector<std::vector<std::string>>> options;
    for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) {
        std::vector<CLI::App*> parts = {command};
        for (CLI::App* group : command->get_subcommands([](CLI::App* sub) { return sub->get_name().empty(); }))
            parts.push_back(group);
        for (CLI::App* part : parts) {
            for (const CLI::Option* option : part->get_options()) {
                if (!option->nonpositional() || option->get_expected_min() == 0) continue;  // positionals, flags
                std::vector<std::string> names;
                for (const std::string& s : option->get_snames()) names.push_back("-" + s);
                for (const std::string& l : option->get_lnames()) names.push_back("--" + l);
                options[command->get_name()].push_back(names);
            }
        }
    }
    return options;
}

bool names_any(const std::string& message, const std::vector<std::string>& names) {
    for (const std::string& name : names)
        if (message.find(name) != std::string::npos) return true;
    return false;
}

/// A run whose message names a file of @a folder (an input or an output).
bool names_a_file(const std::string& message) {
    for (const char* file : {"scan.nii", "scan.vdb", "io.stl", "p.xyz", "level.vdb", "out."})
        if (message.find(file) != std::string::npos) return true;
    return false;
}

TEST(OptionFuzz, EveryOptionOfEveryCommandRefusesHostileValuesCleanly) {
    const test::ScratchDir dir;
    ASSERT_EQ(run_program(dir.path(), {"phantom", "sphere", "--size", "16", "--type", "f32", "-o", "scan.nii"}).status, 0);
    ASSERT_EQ(run_program(dir.path(), {"convert", "scan.nii", "--iso", "0.5", "-o", "scan.vdb"}).status, 0);
    ASSERT_EQ(run_program(dir.path(), {"mesh", "scan.vdb", "-o", "io.stl"}).status, 0);
    ASSERT_EQ(run_program(dir.path(), {"lattice", "gyroid", "--period", "2", "--thickness", "0.5", "--box", "2", "--voxel",
                                       "0.25", "-o", "level.vdb"}).status,
              0);
    {
        std::ofstream points(dir / "p.xyz");
        for (int i = 0; i < 400; ++i) {
            const double z = 1 - (i + 0.5) / 200.0, r = std::sqrt(1 - z * z), a = i * 2.399963;
            points << 10 * r * std::cos(a) << " " << 10 * r * std::sin(a) << " " << 10 * z << "\n";
        }
    }
    const auto options = options_of_every_command();
    ASSERT_EQ(options.size(), kValidArguments.size());
    std::size_t runs = 0;
    for (const auto& [command, names_list] : options) {
        ASSERT_TRUE(kValidArguments.count(command)) << command;
        // The valid arguments succeed on their own.
        std::vector<std::string> valid = kValidArguments.at(command);
        valid.insert(valid.begin(), command);
        const Outcome baseline = run_program(dir.path(), valid);
        EXPECT_TRUE(baseline.status == 0 || baseline.served) << command << ": " << baseline.message;
        for (const std::vector<std::string>& names : names_list) {
            for (const std::string& value : kHostileValues) {
                std::vector<std::string> args = valid;
                const auto given = std::find_first_of(args.begin(), args.end(), names.begin(), names.end());
                if (given != args.end()) {
                    *(given + 1) = value;  // the valid value replaced
                } else {
                    args.push_back(names.back());
                    args.push_back(value);
                }
                const Outcome o = run_program(dir.path(), args);
                ++runs;
                const std::string what = command + " " + names.back() + " " + value + ": status " + std::to_string(o.status) +
                                         ", \"" + o.message.substr(0, 300) + "\"";
                EXPECT_FALSE(o.hung) << what;
                EXPECT_TRUE(o.served || (o.status >= 0 && o.status <= 3)) << "crash: " << what;
                if (o.status == 2) EXPECT_TRUE(names_any(o.message, names)) << what;
                if (o.status == 1) EXPECT_TRUE(names_any(o.message, names) || names_a_file(o.message)) << what;
                if (value == "nan" || value == "inf" || value == "1e300") EXPECT_NE(o.status, 0) << what;
                for (const char c : o.message)
                    EXPECT_TRUE(static_cast<unsigned char>(c) >= 0x20 || c == '\n') << "raw byte " << int(c) << ": " << what;
            }
        }
    }
    EXPECT_GT(runs, 500u);  // every command's options, six values each
}

}  // namespace
}  // namespace vdbmesh::cli
