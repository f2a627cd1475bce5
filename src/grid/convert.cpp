// Placeholder until conversion lands.
namespace vdbmesh::detail { int grid_placeholder = 0; }
