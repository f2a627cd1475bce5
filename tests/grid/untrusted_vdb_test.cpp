// Corrupt and truncated .vdb files: OpenVDB's reader crashes or allocates without bound on some
// of them; reading must instead throw a FormatError naming the file.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

using test::ScratchDir;

std::vector<char> read_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

void write_bytes(const std::filesystem::path& path, const std::vector<char>& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// nucleon.dat converted at iso 80, as `vdbmesh convert` writes it.
std::filesystem::path write_nucleon_vdb(const std::filesystem::path& scan, const ScratchDir& dir) {
    ConvertOptions options;
    options.iso = 80;
    const auto path = dir / "nucleon.vdb";
    write_vdb(*convert_to_grid(*open_volume(scan), options), path);
    return path;
}

/// Reading @a path either works or throws a FormatError naming it; false when it threw anything else.
bool reads_or_names_the_file(const std::filesystem::path& path) {
    try {
        describe_vdb_file(path);
        return true;
    } catch (const FormatError& e) {
        return std::string(e.what()).find(path.string()) == 0;
    } catch (...) {
        return false;
    }
}

/// nucleon.vdb with the byte that makes OpenVDB's reader corrupt its heap in bloscFromStream
/// (glibc then aborts: "malloc(): corrupted top size").
std::filesystem::path write_vdb_that_crashes_openvdb(const std::filesystem::path& scan, const ScratchDir& dir) {
    const auto path = write_nucleon_vdb(scan, dir);
    std::vector<char> bytes = read_bytes(path);
    EXPECT_GT(bytes.size(), 4270u);
    bytes.at(4270) = static_cast<char>(0xDB);
    write_bytes(path, bytes);
    return path;
}

TEST(UntrustedVdbTest, AByteThatCrashedOpenVdbsReaderIsAFormatError) {
    VDBMESH_SHARED_DATA(scan, "openqvis_nucleon_sim/nucleon.dat");
    ScratchDir dir;
    const auto path = write_vdb_that_crashes_openvdb(scan, dir);
    EXPECT_THROW(describe_vdb_file(path), FormatError);
    EXPECT_THROW(read_vdb(path), FormatError);
}

/// Where the SIGABRT handler below leaves its mark (a path fixed before it is installed).
std::string* abort_marker = nullptr;
void mark_abort(int) {
    const int fd = ::open(abort_marker->c_str(), O_CREAT | O_WRONLY, 0644);  // async-signal-safe
    if (fd >= 0) ::close(fd);
}

// The child that reads the file first used to keep the parent's signal handlers: a host's
// crash handler ran in it (libFuzzer wrote a crash report for each corrupt file), and a host's
// SIGALRM handler would have swallowed the alarm that ends a reader stuck in a loop.
TEST(UntrustedVdbTest, TheReadingChildDoesNotRunTheHostsSignalHandlers) {
    VDBMESH_SHARED_DATA(scan, "openqvis_nucleon_sim/nucleon.dat");
    ScratchDir dir;
    const auto path = write_vdb_that_crashes_openvdb(scan, dir);
    std::string marker = (dir / "abort-handler-ran").string();
    abort_marker = &marker;
    struct sigaction host {}, previous {};
    host.sa_handler = mark_abort;
    ASSERT_EQ(::sigaction(SIGABRT, &host, &previous), 0);
    try {
        read_vdb(path);
        ADD_FAILURE() << "a corrupt file was read";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("crashed"), std::string::npos) << e.what();
    }
    ::sigaction(SIGABRT, &previous, nullptr);
    abort_marker = nullptr;
    EXPECT_FALSE(std::filesystem::exists(marker)) << "the host's SIGABRT handler ran in the reading child";
}

TEST(UntrustedVdbTest, FourByteMutationsNeverCrash) {
    VDBMESH_SHARED_DATA(scan, "openqvis_nucleon_sim/nucleon.dat");
    ScratchDir dir;
    const auto original = read_bytes(write_nucleon_vdb(scan, dir));
    const auto path = dir / "mutated.vdb";
    for (std::size_t at = 0; at + 4 <= original.size(); at += original.size() / 41) {
        std::vector<char> bytes = original;
        for (std::size_t i = at; i < at + 4; ++i) bytes[i] = static_cast<char>(~bytes[i]);
        write_bytes(path, bytes);
        EXPECT_TRUE(reads_or_names_the_file(path)) << "bytes " << at << ".." << at + 3 << " inverted";
    }
}

TEST(UntrustedVdbTest, TruncatedFilesAreFormatErrors) {
    VDBMESH_SHARED_DATA(scan, "openqvis_nucleon_sim/nucleon.dat");
    ScratchDir dir;
    const auto original = read_bytes(write_nucleon_vdb(scan, dir));
    const auto path = dir / "cut.vdb";
    for (const std::size_t size : {200, 1000, 4000}) {  // 200 bytes: OpenVDB asked for 11-17 GB
        write_bytes(path, std::vector<char>(original.begin(), original.begin() + static_cast<long>(size)));
        EXPECT_THROW(read_vdb(path), FormatError) << size << " bytes";
    }
}

// Cut inside the 65-byte header, OpenVDB read "0 grid(s)" and `info` exited 0.
TEST(UntrustedVdbTest, AFileCutInsideTheHeaderIsAFormatError) {
    ScratchDir dir;
    const auto whole = dir / "whole.vdb";
    write_vdb(*openvdb::FloatGrid::create(0.0f), whole);
    const auto original = read_bytes(whole);
    ASSERT_GE(original.size(), 65u);
    const auto path = dir / "cut.vdb";
    for (const std::size_t size : {0, 8, 30, 50, 64}) {
        write_bytes(path, std::vector<char>(original.begin(), original.begin() + static_cast<long>(size)));
        try {
            describe_vdb_file(path);
            ADD_FAILURE() << size << " bytes read without an error";
        } catch (const FormatError& e) {
            EXPECT_NE(std::string(e.what()).find("size"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
        }
    }
    EXPECT_NO_THROW(describe_vdb_file(whole));
}

TEST(UntrustedVdbTest, AGridChangedAfterWritingFailsItsChecksum) {
    ScratchDir dir;
    const auto grid = openvdb::FloatGrid::create(-1.0f);
    grid->tree().setValue(openvdb::Coord(1, 2, 3), 5.0f);
    grid->tree().setValue(openvdb::Coord(40, 2, 3), 7.0f);
    write_vdb(*grid, dir / "ours.vdb");
    EXPECT_EQ(read_vdb(dir / "ours.vdb")->tree().getValue(openvdb::Coord(40, 2, 3)), 7.0f);
    // Another program changes one value and keeps our metadata, checksum included.
    openvdb::io::File in((dir / "ours.vdb").string());
    in.open();
    const auto changed = openvdb::gridPtrCast<openvdb::FloatGrid>(in.getGrids()->front());
    in.close();
    ASSERT_TRUE(changed->getMetadata<openvdb::StringMetadata>(kMetaChecksum));
    changed->tree().setValue(openvdb::Coord(40, 2, 3), 7.5f);
    openvdb::io::File((dir / "changed.vdb").string()).write({changed});
    EXPECT_THROW(read_vdb(dir / "changed.vdb"), FormatError);
    EXPECT_THROW(describe_vdb_file(dir / "changed.vdb"), FormatError);
}

}  // namespace
}  // namespace vdbmesh
