// TempFile (temp_file.h): on disk and held in memory, the bytes appended come back from any
// offset, across the in-memory chunks' borders (8 MiB) and the disk's writes alike.

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "vdbmesh/error.h"
#include "vdbmesh/temp_file.h"

namespace vdbmesh::detail {
namespace {

/// 20 MiB in pieces of uneven sizes, each byte a function of its offset.
std::vector<char> pattern() {
    std::vector<char> bytes(std::size_t{20} << 20);
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = char((i * 2654435761u) >> 13);
    return bytes;
}

void expect_round_trip(TempFile::Held held) {
    const std::vector<char> bytes = pattern();
    TempFile file("for the test", held);
    for (std::size_t at = 0, piece = 1; at < bytes.size(); piece = piece * 7 % 3000001 + 1) {
        const std::size_t taken = std::min(piece, bytes.size() - at);
        file.append(bytes.data() + at, taken);
        at += taken;
    }
    ASSERT_EQ(file.size(), bytes.size());
    // Reads that start, end or cross at the chunks' borders (8 MiB), and the whole.
    const std::uint64_t chunk = std::uint64_t{8} << 20;
    for (const auto& [offset, count] : std::vector<std::pair<std::uint64_t, std::size_t>>{
             {0, 1}, {chunk - 1, 2}, {chunk - 5, 10}, {chunk, 100}, {2 * chunk - 3, 4}, {1, bytes.size() - 1}, {0, bytes.size()}}) {
        std::vector<char> back(count);
        file.read(offset, back.data(), count);
        EXPECT_EQ(std::string(back.begin(), back.end()), std::string(bytes.begin() + std::ptrdiff_t(offset), bytes.begin() + std::ptrdiff_t(offset + count)))
            << "offset " << offset << ", " << count << " bytes";
    }
}

TEST(TempFileTest, OnDiskGivesBackWhatWasAppended) { expect_round_trip(TempFile::Held::on_disk); }

TEST(TempFileTest, InMemoryGivesBackWhatWasAppendedAcrossItsChunks) { expect_round_trip(TempFile::Held::in_memory); }

TEST(TempFileTest, InMemoryReadBeyondTheEndIsAnError) {
    TempFile file("for the test", TempFile::Held::in_memory);
    file.append("abc", 3);
    char back[4];
    EXPECT_THROW(file.read(1, back, 3), Error);
}

}  // namespace
}  // namespace vdbmesh::detail
