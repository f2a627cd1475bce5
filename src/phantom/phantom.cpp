// Placeholder until the phantom generator lands.
namespace vdbmesh::detail { int phantom_placeholder = 0; }
