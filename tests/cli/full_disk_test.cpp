// Every writer on a full disk: the vdbmesh program runs with a file size limit (RLIMIT_FSIZE,
// SIGXFSZ ignored), so its writes fail past 16 KiB as they would on a full filesystem. The run
// must exit 1, leave the existing output as it was, and leave no temporary behind.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "test_data.h"

namespace vdbmesh {
namespace {

using test::ScratchDir;

constexpr rlim_t kDiskBytes = 16 * 1024;

/// Runs the vdbmesh program with @a args in @a folder, its files limited to kDiskBytes; returns its exit status.
int run_on_full_disk(const std::filesystem::path& folder, std::vector<std::string> args) {
    args.insert(args.begin(), VDBMESH_BINARY);
    args.push_back("-q");
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    const pid_t child = ::fork();
    if (child == 0) {
        const rlimit limit{kDiskBytes, kDiskBytes};
        ::signal(SIGXFSZ, SIG_IGN);
        if (::setrlimit(RLIMIT_FSIZE, &limit) != 0 || ::chdir(folder.c_str()) != 0) ::_exit(125);
        ::execv(argv[0], argv.data());
        ::_exit(126);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

int run_program(const std::filesystem::path& folder, const std::string& args) {
    return std::system(("cd '" + folder.string() + "' && '" VDBMESH_BINARY "' " + args + " -q").c_str());
}

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The names in @a folder, sorted.
std::vector<std::string> names_in(const std::filesystem::path& folder) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) names.push_back(entry.path().filename());
    std::sort(names.begin(), names.end());
    return names;
}

/// The words of @a command.
std::vector<std::string> words(const std::string& command) {
    std::istringstream in(command);
    return {std::istream_iterator<std::string>(in), {}};
}

/// A command line whose last word is the output file.
class FullDiskTest : public testing::TestWithParam<std::string> {};

TEST_P(FullDiskTest, FailsAndKeepsTheOldFile) {
    ScratchDir dir;
    ASSERT_EQ(run_program(dir.path(), "phantom sphere --size 64 -o in.nii"), 0);
    const std::vector<std::string> args = words(GetParam());
    const std::filesystem::path output = dir / args.back();
    { std::ofstream(output) << "old"; }
    const std::vector<std::string> before = names_in(dir.path());
    EXPECT_EQ(run_on_full_disk(dir.path(), args), 1);
    EXPECT_EQ(read_text(output), "old");
    EXPECT_EQ(names_in(dir.path()), before);
}

INSTANTIATE_TEST_SUITE_P(EveryWriter, FullDiskTest,
                         testing::Values("convert in.nii --iso 0.5 -o out.vdb", "mesh in.nii --iso 0.5 -o out.stl",
                                         "mesh in.nii --iso 0.5 --ascii -o out.ply", "mesh in.nii --iso 0.5 -o out.obj",
                                         "phantom sphere --size 64 -o out.nii", "phantom sphere --size 64 -o out.nrrd",
                                         "phantom sphere --size 64 -o out.mha", "phantom sphere --size 64 -o out.raw"));

TEST(FullDiskTest, DicomSeriesFailsAndLeavesNoFolder) {
    ScratchDir dir;
    EXPECT_EQ(run_on_full_disk(dir.path(), {"phantom", "sphere", "--dims", "128,128,4", "-o", "series/"}), 1);
    EXPECT_TRUE(names_in(dir.path()).empty());
}

}  // namespace
}  // namespace vdbmesh
