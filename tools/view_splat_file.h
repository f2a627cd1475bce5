#pragma once
// `vdbmesh view scan.vdb --splats FILE`: the splat tree kept in a file, fitted once and viewed
// many times.

#include <filesystem>
#include <future>
#include <memory>
#include <optional>

#include "vdbmesh/splats.h"
#include "vdbmesh/view.h"

namespace vdbmesh::cli {

/// The splat tree of the .vdb at @a vdb (opened as @a regions) from @a file when it exists and
/// was fitted to this grid (then at its isovalue), else fitted at @a iso (the asked one, else
/// the stored one) and written to @a file through a temporary file.
/// @throw Error when @a file was fitted to another grid or is not a splat file (nothing is
/// written), UsageError when @a asked_iso differs from the file's or no isovalue is known.
/// @a read_ahead: read_splat_file(@a file) begun earlier (while the grid was opened), if any.
std::shared_ptr<const ViewSplats> view_splat_file(const std::filesystem::path& file, const std::filesystem::path& vdb,
                                                  const GridRegionSource& regions, std::optional<double> asked_iso,
                                                  std::optional<double> stored_iso, bool quiet,
                                                  std::future<SplatTree> read_ahead = {});

/// `vdbmesh view scan.splat`: the splat tree of @a file alone, without the grid it was fitted
/// to (the page shows the splats; meshes, the isovalue and close-ups need the grid). Throws
/// FormatError when @a file is not a splat file, UsageError when @a asked_iso differs from its
/// isovalue.
std::shared_ptr<const ViewSplats> view_splats_alone(const std::filesystem::path& file, std::optional<double> asked_iso,
                                                    bool quiet);

}  // namespace vdbmesh::cli
