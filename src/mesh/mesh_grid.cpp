// Placeholder until the mesher lands.
namespace vdbmesh::detail { int mesh_placeholder = 0; }
