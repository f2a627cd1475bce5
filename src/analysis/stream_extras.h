#pragma once
// Private: the bounded check's one pass over a mesh (analyze_stream.cpp), open to what else a
// caller gathers on the way (the bounded measure: each triangle's corners and vertices, the
// components), and fed either from a file or record by record (a bricked mesh as it is made).

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vdbmesh/analysis.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/program_memory.h"

namespace vdbmesh::detail {

/// Hears each triangle as the check reads it; see make_stream_checker().
class StreamExtras {
public:
    virtual ~StreamExtras() = default;
    /// Each triangle's corners, in the file's order.
    virtual void corners(const std::array<std::array<float, 3>, 3>& corners) = 0;
    /// Each triangle's vertex numbers, in the file's order (for STL, after the weld).
    virtual void vertices(const std::array<std::uint32_t, 3>& triangle) = 0;
    /// Each vertex's component (StreamTopology::take_components()), once the topology is counted.
    virtual void components(std::vector<std::uint32_t> components) = 0;
    /// Bytes held whatever the mesh's size (buffers), for the memory plan.
    virtual std::uint64_t held_bytes() const = 0;
};

/// The check's pass, given records as read_mesh_records() gives them; finish() after the last.
class StreamCheckRecords : public MeshRecordVisitor {
public:
    virtual StreamCheck finish() = 0;
};

/// A check of the mesh named @a name (for messages) within options.memory_bytes; @a extras (if
/// set, outliving the checker) hears each triangle and gets the components, and its held
/// bytes and StreamTopology::kComponentBytesPerVertex are planned for. Records of an OBJ file
/// need plan_vertices() first (its vertices are not announced).
std::unique_ptr<StreamCheckRecords> make_stream_checker(const std::string& name, const StreamCheckOptions& options,
                                                        StreamExtras* extras = nullptr);

/// Counts an OBJ file's vertices (a first pass); nothing for any other file.
std::optional<std::uint64_t> obj_vertex_count(const std::filesystem::path& path);

/// The least limit a PLY-like stream of no vertices needs, with @a extra_bytes held besides.
std::uint64_t least_stream_bytes(std::uint64_t extra_bytes);

/// Tells @a checker the vertices an OBJ file holds (obj_vertex_count()).
void plan_vertices(StreamCheckRecords& checker, std::uint64_t vertices);

}  // namespace vdbmesh::detail
