// decimate_mesh(): quadric edge collapse (M. Garland and P. Heckbert, SIGGRAPH 1997) that keeps a
// closed manifold mesh closed, manifold, oriented and free of self-intersections.
//
// The collapses are made in rounds. Each round takes the cheapest edges (about as many as
// collapses are still wanted) and picks among them, in order of cost, those whose ends lie in the
// star of no edge picked before (as meshoptimizer locks vertices). Those are checked in parallel
// against the mesh as it was at the start of the round, then applied in order of cost. No collapse
// of the round changes what another's checks read (its ends' rings, its star) but for the new
// triangles of two collapses: those crossings are found in parallel too, between the new stars as
// the checks built them, and a plan crossing one applied before it waits. So the result does not
// depend on the thread count. Each collapse is checked where it changes the mesh, on the float
// coordinates that will be written:
// - topology: the link condition (the ends' neighbours in common are exactly the two opposite
//   corners; T. K. Dey et al., "Topology preserving edge contraction", 1999), which keeps a
//   closed 2-manifold one;
// - geometry: no triangle of the new star is degenerate (exact collinearity) or turns by more
//   than kMaxTurnDegrees, and no component's enclosed volume changes sign (a nearly flat speck
//   can turn inside out while each triangle turns little; checked in the sequential apply, on
//   each component's volume kept up to date by the collapses' changes);
// - intersections: most collapses are cleared without a test between triangles, when all the
//   triangles near them and their new ones face a common direction (the proof is at
//   intersection_free()): the grids' cells keep what their triangles have in common. The others:
//   each new triangle against the others of the star and against the triangles the grids find
//   near it (one of all triangles, rebuilt once a quarter of them has moved, and one of those
//   moved since, rebuilt each round), with the exact tests of `vdbmesh check`; a plane that
//   certainly separates the two triangles (vdbmesh/separating_plane.h) spares most of them.
//   The same holds for the crossings between two new stars of a round.
// The mesh is held as a corner table (each corner's opposite corner across its edge), flat arrays
// throughout. The Decimator is declared in process/decimator.h, its parts defined by job in
// decimate_corner_table.cpp, decimate_costs.cpp, decimate_checks.cpp and decimate_rounds.cpp.
#include <string>

#include "process/decimator.h"
#include "vdbmesh/error.h"
#include "vdbmesh/geometry.h"
#include "vdbmesh/process.h"

namespace vdbmesh {
namespace {

void check_closed_manifold(const Mesh& mesh) {
    const detail::Topology topology = detail::analyze_topology(mesh);
    if (topology.boundary_edges || topology.nonmanifold_edges || topology.nonmanifold_vertices || topology.misoriented_edges) {
        throw Error("decimate: expected a closed, manifold, consistently oriented mesh, got " +
                    std::to_string(topology.boundary_edges) + " boundary edges, " + std::to_string(topology.nonmanifold_edges) +
                    " non-manifold edges, " + std::to_string(topology.nonmanifold_vertices) + " non-manifold vertices, " +
                    std::to_string(topology.misoriented_edges) + " misoriented edges");
    }
}

}  // namespace

Mesh decimate_mesh(const Mesh& mesh, const DecimateOptions& options, DecimateReport* report) {
    if (!(options.keep_fraction >= 0 && options.keep_fraction <= 1)) {
        throw UsageError("decimate: expected a share of triangles to keep in [0, 1], got " + std::to_string(options.keep_fraction));
    }
    if (!(options.max_error >= 0)) throw UsageError("decimate: expected a maximum error >= 0, got " + std::to_string(options.max_error));
    detail::check_indices(mesh);
    detail::decimation::Decimator decimator(mesh, options);
    if (!decimator.closed_manifold()) check_closed_manifold(mesh);  // throws, naming the faults
    DecimateReport local;
    Mesh result = decimator.run(local);
    if (report) *report = local;
    return result;
}

}  // namespace vdbmesh
