#pragma once
/// @file mesh_range_file.h
/// @brief A mesh file that several ranks write together (mesher.h's MeshRangeSink): rank 0 makes
/// a temporary file beside the target (atomic_file.h), every rank writes its byte ranges into
/// it (a shared file system), and rank 0 renames it into place once all have written.

#include <filesystem>
#include <optional>
#include <string>

#include "vdbmesh/atomic_file.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh {

class MeshRangeFile : public MeshRangeSink {
public:
    /// The records of @a target's format (by extension; binary unless @a ascii).
    /// @throw UsageError for an unknown extension.
    MeshRangeFile(std::filesystem::path target, bool ascii);
    ~MeshRangeFile() override;

    std::string header(std::uint64_t vertex_count, std::uint64_t triangle_count) override;
    std::string footer() const override;
    void vertices(const std::vector<std::array<float, 3>>& positions, std::string& out) const override;
    void triangles(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                   const std::vector<std::array<std::array<float, 3>, 3>>& corners, std::string& out) const override;
    /// @throw Error naming the file when it cannot be made or opened.
    std::string open(const std::string& made) override;
    /// @throw Error naming the target when a write fails (a full disk).
    void write_at(std::uint64_t offset, const char* bytes, std::size_t count) override;
    void close(bool commit) override;

private:
    std::filesystem::path target_;
    MeshRecordFormat format_;
    std::optional<AtomicFile> made_;  ///< rank 0's
    int descriptor_ = -1;
};

}  // namespace vdbmesh
