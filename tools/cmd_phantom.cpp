// Placeholder until `vdbmesh phantom` lands.
#include "commands.h"
#include "vdbmesh/error.h"

namespace vdbmesh::cli {
void add_phantom_command(CLI::App& command, CommandResult&) {
    command.callback([] { throw Error("not implemented yet"); });
}
}  // namespace vdbmesh::cli
