#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "test_data.h"

namespace vdbmesh::cli {
namespace {

/// The README's command list: the rows "| `vdbmesh <name>` | <summary> |" of its
/// "## Commands" section, name -> summary.
std::map<std::string, std::string> readme_commands() {
    std::ifstream in(std::string(VDBMESH_SOURCE_DIR) + "/README.md");
    std::map<std::string, std::string> commands;
    std::string line;
    bool in_section = false;
    while (std::getline(in, line)) {
        if (line.rfind("## ", 0) == 0) in_section = line == "## Commands";
        const std::string prefix = "| `vdbmesh ";
        if (!in_section || line.rfind(prefix, 0) != 0) continue;
        const auto name_end = line.find('`', prefix.size());
        const auto summary_begin = line.find("| ", name_end) + 2;
        const auto summary_end = line.rfind(" |");
        if (name_end == std::string::npos || summary_end <= summary_begin) continue;
        commands[line.substr(prefix.size(), name_end - prefix.size())] = line.substr(summary_begin, summary_end - summary_begin);
    }
    return commands;
}

std::string capture_help(const std::vector<std::string>& args) {
    testing::internal::CaptureStdout();
    EXPECT_EQ(run(args), kSuccess);
    return testing::internal::GetCapturedStdout();
}

}  // namespace

TEST(CliTest, HelpSucceeds) { EXPECT_EQ(run({"--help"}), kSuccess); }

/// The exit status and what went to stderr.
std::pair<int, std::string> run_capturing_stderr(const std::vector<std::string>& args) {
    testing::internal::CaptureStderr();
    const int status = run(args);
    return {status, testing::internal::GetCapturedStderr()};
}

TEST(CliTest, UnknownSubcommandIsUsageErrorNamingIt) {
    const auto [status, message] = run_capturing_stderr({"frobnicate"});
    EXPECT_EQ(status, kUsageError);
    EXPECT_NE(message.find("unknown command \"frobnicate\""), std::string::npos) << message;
    EXPECT_NE(message.find("mesh"), std::string::npos) << message;  // the commands are listed
}

// Issue 10, point 6: messages that name the option and the value as given.
TEST(CliTest, BadNumbersAreReportedAsGiven) {
    const auto [nan_status, nan_message] = run_capturing_stderr({"mesh", "in.nii", "--iso", "1", "--error", "nan", "-o", "out.stl"});
    EXPECT_EQ(nan_status, kUsageError);
    EXPECT_NE(nan_message.find("--error"), std::string::npos) << nan_message;
    EXPECT_NE(nan_message.find("nan"), std::string::npos) << nan_message;
    const auto [bytes_status, bytes_message] =
        run_capturing_stderr({"info", "in.raw", "--raw-dims", "2,2,2", "--header-bytes", "-1", "-q"});
    EXPECT_EQ(bytes_status, kUsageError);
    EXPECT_NE(bytes_message.find("--header-bytes"), std::string::npos) << bytes_message;
    EXPECT_NE(bytes_message.find("got -1"), std::string::npos) << bytes_message;
    EXPECT_EQ(bytes_message.find("18446744073709551615"), std::string::npos) << bytes_message;
    // CLI11's own range checks printed DBL_MAX in 309 digits.
    for (const std::vector<std::string>& args : {std::vector<std::string>{"mesh", "in.nii", "--iso", "1", "--threads", "-1", "-o", "out.stl"},
                                                 std::vector<std::string>{"compare", "--phantom", "sphere", "--samples", "0", "-q"}}) {
        const auto [status, message] = run_capturing_stderr(args);
        EXPECT_EQ(status, kUsageError) << args[3];
        EXPECT_LT(message.size(), 200u) << message;
        EXPECT_NE(message.find(args[0] == "mesh" ? "--threads" : "--samples"), std::string::npos) << message;
    }
}

// Issue 10, point 6: raw-only options without --raw-dims were ignored silently.
TEST(CliTest, RawOptionsWithoutRawDimsAreRefused) {
    for (const char* flag : {"--spacing", "--raw-type", "--raw-endian", "--header-bytes"}) {
        const std::string value = std::string(flag) == "--spacing" ? "1,1,2" : std::string(flag) == "--raw-type" ? "u16"
                                  : std::string(flag) == "--raw-endian"                                  ? "big"
                                                                                                          : "16";
        const auto [status, message] = run_capturing_stderr({"info", test::testdata("sphere_phantom.nii.gz").string(), flag, value, "-q"});
        EXPECT_EQ(status, kUsageError) << flag;
        EXPECT_NE(message.find(flag), std::string::npos) << message;
        EXPECT_NE(message.find("--raw-dims"), std::string::npos) << message;
    }
}

// Issue 10, point 6: a 5 MB bad value was echoed whole.
TEST(CliTest, AHugeBadValueIsNotEchoedWhole) {
    const std::string huge(5 << 20, 'x');
    for (const std::vector<std::string>& args : {std::vector<std::string>{"mesh", "in.nii", "--iso", huge, "-o", "out.stl"},
                                                 std::vector<std::string>{"mesh", "in.nii", "--iso", "1", "--error", huge, "-o", "out.stl"},
                                                 std::vector<std::string>{huge}}) {
        const auto [status, message] = run_capturing_stderr(args);
        EXPECT_EQ(status, kUsageError);
        EXPECT_LT(message.size(), 1000u) << message.substr(0, 200);
        EXPECT_NE(message.find("bytes in all"), std::string::npos) << message.substr(0, 600);
    }
}

TEST(CliTest, NoSubcommandIsUsageError) { EXPECT_EQ(run({}), kUsageError); }

TEST(CliTest, SubcommandHelpSucceeds) {
    for (const CommandEntry& entry : kCommands) EXPECT_EQ(run({entry.name, "--help"}), kSuccess) << entry.name;
}

// --help says what the program does and lists every registered command with its summary.
TEST(CliTest, HelpListsEveryRegisteredCommand) {
    const std::string help = capture_help({"--help"});
    EXPECT_NE(help.find("tomography"), std::string::npos) << help;
    EXPECT_EQ(help.find("point cloud"), std::string::npos) << help;  // no point cloud input exists
    for (const CommandEntry& entry : kCommands) {
        EXPECT_NE(help.find(entry.name), std::string::npos) << entry.name;
        EXPECT_NE(help.find(entry.summary), std::string::npos) << entry.summary;
    }
}

// The README's command list is the registry (tools/commands.h): every registered command
// appears with its summary, and nothing else does.
TEST(CliTest, ReadmeListsExactlyTheRegisteredCommands) {
    const std::map<std::string, std::string> listed = readme_commands();
    ASSERT_FALSE(listed.empty()) << "README.md has no \"## Commands\" table";
    std::map<std::string, std::string> registered;
    for (const CommandEntry& entry : kCommands) registered[entry.name] = entry.summary;
    for (const auto& [name, summary] : registered) {
        const auto it = listed.find(name);
        ASSERT_NE(it, listed.end()) << "README.md does not list `vdbmesh " << name << "`";
        EXPECT_EQ(it->second, summary) << "README.md's summary of `vdbmesh " << name << "` differs from tools/commands.h";
    }
    for (const auto& [name, summary] : listed) {
        EXPECT_TRUE(registered.count(name)) << "README.md lists `vdbmesh " << name << "`, which tools/commands.h does not register";
    }
}

}  // namespace vdbmesh::cli
