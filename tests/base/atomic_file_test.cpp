// AtomicFile: any valid target name works, and SIGINT/SIGTERM/SIGHUP leave no temporary behind.

#include "vdbmesh/atomic_file.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include "test_data.h"

namespace vdbmesh {
namespace {

using test::ScratchDir;

void write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(AtomicFileTest, TargetNamesUpTo255CharactersWork) {
    ScratchDir dir;
    for (std::size_t length = 250; length <= 255; ++length) {
        const std::filesystem::path target = dir / (std::string(length - 4, 'n') + ".vdb");
        AtomicFile file(target);
        EXPECT_LE(file.temp_path().filename().string().size(), 255u);
        write_text(file.temp_path(), "complete");
        file.commit();
        EXPECT_EQ(read_text(target), "complete") << "name of " << length << " characters";
    }
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 6);
}

/// Runs @a make_temporary in a child process, ends the child with @a signal_number once the
/// temporary exists, and returns the temporary's path after checking the signal ended the child.
template <typename MakeTemporary>
std::filesystem::path temporary_left_by_signal(const std::filesystem::path& target, int signal_number,
                                               MakeTemporary make_temporary) {
    int ready[2];
    EXPECT_EQ(::pipe(ready), 0);
    const pid_t child = ::fork();
    if (child == 0) {
        AtomicFile file(target);
        make_temporary(file.temp_path());
        const std::string path = file.temp_path().string();
        (void)!::write(ready[1], path.c_str(), path.size());
        ::close(ready[1]);
        for (;;) ::pause();
    }
    ::close(ready[1]);
    std::string temp;
    char buffer[4096];
    for (ssize_t n; (n = ::read(ready[0], buffer, sizeof(buffer))) > 0;) temp.append(buffer, static_cast<std::size_t>(n));
    ::close(ready[0]);
    ::kill(child, signal_number);
    int status = 0;
    ::waitpid(child, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal_number) << "status " << status;
    return temp;
}

TEST(AtomicFileTest, SignalsRemoveTheTemporaryFile) {
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
        ScratchDir dir;
        write_text(dir / "out.vdb", "old");
        const std::filesystem::path temp = temporary_left_by_signal(
            dir / "out.vdb", signal_number, [](const std::filesystem::path& path) { write_text(path, "partial"); });
        ASSERT_FALSE(temp.empty());
        EXPECT_FALSE(std::filesystem::exists(temp)) << strsignal(signal_number);
        EXPECT_EQ(read_text(dir / "out.vdb"), "old");
    }
}

TEST(AtomicFileTest, SignalsRemoveATemporaryFolderOfFiles) {
    ScratchDir dir;
    const std::filesystem::path temp =
        temporary_left_by_signal(dir / "series", SIGTERM, [](const std::filesystem::path& path) {
            std::filesystem::create_directory(path);
            for (int i = 0; i < 300; ++i) write_text(path / ("slice" + std::to_string(i) + ".dcm"), "slice");
        });
    ASSERT_FALSE(temp.empty());
    EXPECT_FALSE(std::filesystem::exists(temp));
}

}  // namespace
}  // namespace vdbmesh
