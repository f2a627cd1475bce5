#pragma once
/// @file temporary_registry.h
/// @brief Temporary outputs in progress, removed when SIGINT, SIGTERM or SIGHUP ends the process.

#include <filesystem>

namespace vdbmesh::detail {

/// Records @a path (a file, or a flat folder of files) as a temporary to delete should the
/// process be ended by SIGINT, SIGTERM or SIGHUP; on first use installs handlers for those
/// signals that are still at their default action (a program's own handlers are left alone).
/// The handler deletes every recorded temporary, then lets the signal end the process as it
/// would have. Returns a slot for forget_temporary(), or -1 when every slot is taken.
int remember_temporary(const std::filesystem::path& path);

/// Stops tracking the temporary in @a slot (it was renamed into place or deleted). -1 is a no-op.
void forget_temporary(int slot);

}  // namespace vdbmesh::detail
