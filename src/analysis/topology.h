#pragma once
// Private: the combinatorial checks of analyze_mesh() (edges, vertex fans, components).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "vdbmesh/mesh.h"

namespace vdbmesh::detail {

struct Topology {
    std::size_t referenced_vertices = 0;
    std::size_t edges = 0;
    std::size_t boundary_edges = 0;
    std::size_t boundary_loops = 0;
    std::size_t nonmanifold_edges = 0;
    std::size_t misoriented_edges = 0;
    std::size_t nonmanifold_vertices = 0;
    std::size_t components = 0;
    /// For each triangle its component, numbered in order of first appearance.
    std::vector<std::uint32_t> component_of_triangle;
};

/// Requires valid indices (check_indices). Self-loop edges of repeated-vertex faces are skipped.
Topology analyze_topology(const Mesh& mesh);

}  // namespace vdbmesh::detail
