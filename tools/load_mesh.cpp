// The input of the mesh-consuming subcommands: a mesh file or a scan meshed in memory.

#include "load_mesh.h"

#include <map>

#include "load_grid.h"
#include "option_checks.h"
#include "work_limits.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid_filter.h"
#include "vdbmesh/mesh_io.h"

namespace vdbmesh::cli {

namespace {
const std::map<std::string, Inside> kSides = {{"above", Inside::above}, {"below", Inside::below}};
}

void add_mesh_input_options(CLI::App& command, MeshInputOptions& options) {
    options.grid_only = {
        command.add_option("--iso", options.iso, "Isovalue for a scan or .vdb input (default for a .vdb: the stored one)"),
        command.add_option("--inside", options.inside, "Scan or .vdb input: which side of the isovalue is the object: above|below")
            ->transform(CLI::CheckedTransformer(kSides, CLI::ignore_case)),
        command.add_option("--error", options.error,
                           "Scan or .vdb input: the dc mesher's tolerated error in voxels (0: no simplification; above 0 with --memory)")
            ->check(kFiniteNonNegative)
            ->capture_default_str(),
        command.add_flag("--refine", options.refine,
                         "Scan or .vdb input: move the vertices onto the isosurface of the triquadratic interpolant "
                         "(sub-voxel accuracy on smooth solids)"),
    };
    add_read_flags(command, options.read);
}

bool is_mesh_input(const std::vector<std::string>& inputs, const MeshInputOptions& options) {
    if (!is_mesh_file(inputs.front())) return false;
    if (inputs.size() > 1) throw UsageError("a mesh input takes no further input files");
    for (const CLI::Option* option : options.grid_only) refuse_unless(option, false, "for a scan or .vdb input, got the mesh " + inputs.front());
    options.read.refuse_for("the mesh " + inputs.front());
    return true;
}

namespace {

/// The grid's conversion: band 1 (what the dc mesher reads).
ConvertOptions band_one() {
    ConvertOptions convert;
    convert.band = 1;
    return convert;
}

/// The dc mesher at --error for the isovalue and side the input gave.
MeshOptions mesher_options(const MeshInputOptions& options, double iso, Inside inside) {
    MeshOptions mesh;
    mesh.iso = iso;
    mesh.inside = inside;
    mesh.error = options.error;
    return mesh;
}

}  // namespace

Mesh load_mesh(const std::vector<std::string>& inputs, const MeshInputOptions& options, const std::string& purpose) {
    if (is_mesh_input(inputs, options)) return read_mesh(inputs.front());
    const GridInput loaded = load_grid(inputs, options.iso, options.read, purpose, band_one(), options.iso_option, options.inside);
    Mesh result = mesh_grid(*loaded.grid, mesher_options(options, loaded.iso, loaded.inside)).mesh;
    if (result.triangles.empty()) throw no_surface_error(inputs.front(), *loaded.grid, {loaded.iso, loaded.iso}, "");
    if (options.refine) refine_to_isosurface(result, *loaded.grid, loaded.iso);
    return result;
}

namespace {

/// Hands the bricked mesh on as a file of it would be read.
class RecordsSink final : public MeshStreamSink {
public:
    explicit RecordsSink(MeshRecordVisitor& visitor) : visitor_(visitor) {}
    void begin(std::uint64_t vertex_count, std::uint64_t triangle_count) override {
        triangles = triangle_count;
        try {
            visitor_.announced(vertex_count, triangle_count);
        } catch (const UsageError& e) {
            throw UsageError(std::string(e.what()) + " (of half the limit beside the program: a mesh made by bricks is handed over " +
                             "while the mesher reads its spill back, which holds the other half; --memory twice that less 64M)");
        }
    }
    void vertex(const std::array<float, 3>& position) override { visitor_.vertex(position); }
    void triangle(const std::array<std::uint32_t, 3>& t, const std::array<std::array<float, 3>, 3>&) override { visitor_.triangle(t); }
    std::uint64_t triangles = 0;

private:
    MeshRecordVisitor& visitor_;
};

}  // namespace

std::uint64_t grid_stream_share(std::uint64_t memory_bytes, std::uint64_t least_stream_bytes, const std::string& verb,
                                const std::string& input) {
    // The program is counted once: the rest is halved.
    const std::uint64_t program = kProgramBytes;
    const std::uint64_t share = memory_bytes < program ? memory_bytes : program + (memory_bytes - program) / 2;
    if (share >= least_stream_bytes) return share;
    constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
    const std::string least = std::to_string((2 * least_stream_bytes - program + kMiB - 1) / kMiB) + "M";
    throw UsageError("--memory: " + std::to_string(memory_bytes / kMiB) + "M is too small to " + verb + " the mesh of " + input +
                     " as it is made by bricks: half the limit beside the program goes to the stream, which needs at least " +
                     std::to_string((least_stream_bytes + kMiB - 1) / kMiB) + "M and about 12 bytes for each of the mesh's vertices; "
                     "the smallest limit that could work is " + least);
}

void stream_grid_mesh(const std::vector<std::string>& inputs, const MeshInputOptions& options, const std::string& purpose,
                      std::uint64_t memory_bytes, MeshRecordVisitor& visitor) {
    if (options.refine) throw UsageError("--memory: --refine moves the vertices of the whole mesh, which --memory never holds; leave it out");
    const GridRegionsInput opened =
        open_grid_regions(inputs, options.iso, options.read, purpose, band_one(), options.iso_option, options.inside);
    BrickOptions bricks;
    bricks.memory_bytes = memory_bytes;
    RecordsSink sink(visitor);
    mesh_bricks_to_stream(*opened.source, mesher_options(options, opened.iso, opened.inside), bricks, sink);
    if (sink.triangles == 0) throw no_surface_error(inputs.front(), *opened.source->description(), {opened.iso, opened.iso}, "");
}

}  // namespace vdbmesh::cli
