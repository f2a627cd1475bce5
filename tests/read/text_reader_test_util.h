#pragma once
// Helpers for the text-header reader tests (OpenQVis, MetaImage, NRRD): every sample of a
// source, files written byte for byte, zlib/gzip compression, header warnings, and FormatError
// checks.

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh::test {

/// All samples of @a source, x fastest, through the generic VolumeReader.
inline std::vector<float> read_all_samples(VolumeSource source) {
    VolumeReader reader(std::move(source));
    std::vector<float> samples(static_cast<std::size_t>(reader.header().voxel_count()));
    reader.read_slices(reader.header().dims[2], samples.data());
    return samples;
}

inline void write_file(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Deflate-compressed @a bytes: zlib-wrapped (MetaImage CompressedData) or gzip (NRRD).
inline std::string compress_bytes(const std::string& bytes, bool gzip) {
    z_stream stream{};
    EXPECT_EQ(deflateInit2(&stream, Z_BEST_COMPRESSION, Z_DEFLATED, gzip ? 31 : 15, 8, Z_DEFAULT_STRATEGY), Z_OK);
    std::string out(deflateBound(&stream, static_cast<uLong>(bytes.size())) + 32, '\0');
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    stream.avail_in = static_cast<uInt>(bytes.size());
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = static_cast<uInt>(out.size());
    EXPECT_EQ(deflate(&stream, Z_FINISH), Z_STREAM_END);
    out.resize(stream.total_out);
    deflateEnd(&stream);
    return out;
}

/// Whether one of the header's warnings contains @a part.
inline bool has_warning(const VolumeHeader& h, const std::string& part) {
    return std::any_of(h.warnings.begin(), h.warnings.end(),
                       [&](const std::string& w) { return w.find(part) != std::string::npos; });
}

/// Expects @a call to throw a FormatError whose message names @a field.
inline void expect_format_error(const std::function<void()>& call, const std::string& field) {
    try {
        call();
        ADD_FAILURE() << "no FormatError (expected one naming \"" << field << "\")";
    } catch (const FormatError& error) {
        EXPECT_NE(std::string(error.what()).find(field), std::string::npos)
            << "message does not name \"" << field << "\": " << error.what();
    }
}

/// Feeds every prefix of @a text to @a parse: each must parse or throw FormatError, nothing else.
inline void expect_prefixes_fail_cleanly(const std::string& text, const std::function<void(std::string_view)>& parse) {
    for (std::size_t length = 0; length <= text.size(); ++length) {
        try {
            parse(std::string_view(text).substr(0, length));
        } catch (const FormatError&) {
        } catch (const std::exception& error) {
            ADD_FAILURE() << "prefix of " << length << " bytes threw a non-FormatError: " << error.what();
        }
    }
}

}  // namespace vdbmesh::test
