// Replays a fuzz target without libFuzzer: runs LLVMFuzzerTestOneInput once on every file
// named on the command line or found in a folder named there, in name order. The normal
// test suite runs it over tests/fuzz/corpus/<parser>/, so the seeds and every crash
// reproducer kept there are checked on each build (an uncaught exception or a crash fails).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::vector<std::filesystem::path> input_files(int argc, char** argv) {
    std::vector<std::filesystem::path> files;
    for (int i = 1; i < argc; ++i) {
        const std::filesystem::path arg(argv[i]);
        if (!std::filesystem::is_directory(arg)) {
            files.push_back(arg);
            continue;
        }
        for (const auto& entry : std::filesystem::directory_iterator(arg))
            if (entry.is_regular_file()) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::vector<std::uint8_t> read_all(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

int main(int argc, char** argv) {
    const auto files = input_files(argc, argv);
    if (files.empty()) {
        std::fprintf(stderr, "usage: %s <corpus folder or file>... (no input found)\n", argv[0]);
        return 1;
    }
    for (const auto& file : files) {
        std::fprintf(stderr, "%s\n", file.string().c_str());
        const std::vector<std::uint8_t> bytes = read_all(file);
        LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
    }
    std::fprintf(stderr, "%zu inputs replayed\n", files.size());
    return 0;
}
