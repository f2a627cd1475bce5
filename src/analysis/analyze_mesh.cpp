// Placeholder until mesh analysis lands.
namespace vdbmesh::detail { int analysis_placeholder = 0; }
