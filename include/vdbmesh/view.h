#pragma once
/// @file view.h
/// @brief `vdbmesh view`: what the page shows (a scan meshed on request, or a mesh file) and
/// the local HTTP server that serves the page, meshes as binary buffers and their figures.

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vdbmesh/background_control.h"
#include "vdbmesh/mesh.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/openvdb_fwd.h"
#include "vdbmesh/read.h"

namespace vdbmesh {

class GridRegionSource;
struct SharedSplatTree;
struct SplatTree;

/// Counts of samples in equal bins over [min, max].
struct ValueHistogram {
    double min = 0, max = 0;
    std::vector<std::uint64_t> counts;
};

/// A scan prepared for live re-meshing: grids that hold the surface at every isovalue of
/// [histogram.min, histogram.max].
struct ViewScan {
    /// Full resolution, in memory; null when the grid is read by region only (prepare_grid_regions()).
    std::shared_ptr<openvdb::FloatGrid> grid;
    /// Full resolution by region (always set): the splat tree and the meshes of regions read it.
    std::shared_ptr<const GridRegionSource> regions;
    std::shared_ptr<openvdb::FloatGrid> coarse;  ///< averaged over coarse_factor^3 blocks: the quick first mesh
    int coarse_factor = 1;
    ValueHistogram histogram;        ///< of the scan's samples
    double suggested_iso = 0;        ///< Otsu's threshold
    std::string suggested_reason;
};

/// Bins of ViewScan::histogram.
inline constexpr std::size_t kViewHistogramBins = 256;
/// The coarse grid has at most this many samples (the factor grows until it fits).
inline constexpr std::int64_t kCoarseSampleBudget = 2'000'000;

/// Reads a scan twice through readers made by @a open_reader: once for its statistics, once
/// into a grid over its whole value range; then averages the coarse grid.
ViewScan prepare_scan(const std::function<std::unique_ptr<VolumeReader>()>& open_reader);

/// A stored grid as it is: statistics and histogram of its samples inside its scan box (its
/// active box when it has none). Isovalues away from the one it was converted at may find
/// only part of the surface.
ViewScan prepare_grid(std::shared_ptr<openvdb::FloatGrid> grid);

/// prepare_grid() of a grid that is never held whole (a huge .vdb): its statistics, histogram
/// and coarse grid read in slabs about one node thick, one at a time. Without a stored scan box
/// the box is that of the source's nodes. With @a control, heeds it between reads and between the pieces of each slab's work (a
/// fraction of a second each): waits while it pauses, gives up (Error) once it stops.
ViewScan prepare_grid_regions(std::shared_ptr<const GridRegionSource> regions, const BackgroundControl* control = nullptr);

/// One label of a label map shown label by label: its closed mesh is a run of the
/// source's mesh (its triangles and its vertices one after another).
struct ViewLabel {
    std::uint32_t value = 0;
    std::string name;                  ///< from the label table, else "label <value>"
    std::array<double, 3> colour{};    ///< RGB in [0, 1]: the table's, else a fixed palette's
    std::size_t first_triangle = 0, triangles = 0;
    std::size_t first_vertex = 0, vertices = 0;
};

/// A lattice shown by its shared tree's splat hierarchy alone (never meshed, never expanded).
struct ViewLattice {
    std::shared_ptr<const SharedSplatTree> splats;
    double seconds = 0;                    ///< the splat hierarchy's build
    std::array<double, 3> box_min{}, box_max{};  ///< world units: what the page frames first
};

/// The splat tree of a scan at its initial isovalue, made before serving (`view --splats FILE`:
/// read from its file, or fitted and written there): the page shows it at once.
struct ViewSplats {
    std::shared_ptr<const SplatTree> tree;
    double seconds = 0;     ///< the fit's, or the file's reading
    std::string file;       ///< the splat file's name
    bool from_file = false; ///< read from the file (else fitted now and written to it)
    /// The topology preview (build_topology_preview(): a splat per leaf, no value read), shown
    /// until ViewSource::fit_splats has fitted the tree.
    bool preview = false;
    std::array<double, 3> box_min{}, box_max{};  ///< world units: the childless discs' box, what the page frames first
};

/// The box of @a splats' tree's childless discs into its box_min and box_max.
void set_splat_box(ViewSplats& splats);

/// The topology preview of @a regions at @a iso (what the page shows of a .vdb without a
/// splat file while its tree is fitted): seconds on a huge grid, no voxel value read.
std::shared_ptr<const ViewSplats> topology_preview_splats(const GridRegionSource& regions, double iso);

/// The splat tree of @a regions at @a iso (build_splat_tree() by region), its build within
/// @a max_bytes (SplatOptions::max_bytes; 0: no bound). Each read heeds @a control: waits
/// while it pauses, gives up (Error) once it stops.
std::shared_ptr<const ViewSplats> fit_view_splats(std::shared_ptr<const GridRegionSource> regions, double iso,
                                                  const BackgroundControl& control, std::uint64_t max_bytes = 0);

/// How `view --memory SIZE` shares SIZE (issue 28). Beside the program (kProgramBytes) the
/// rest R: a quarter for one close-up's read by region (and a full mesh's bricks), a quarter
/// for the page (its coarse grid and the meshes it keeps), half for the grid as opened (its
/// topology, a scan's survey, the topology preview: `opened`, what the process holds beyond the
/// program once they are made) and the splat tree once fitted. The fit runs before the page's
/// meshes and close-ups (they wait for the scan's preparation, which follows it), so while it
/// runs the tree being built may take all of R beside what is opened.
struct ViewMemoryPlan {
    std::uint64_t limit = 0;  ///< SIZE, bytes

    /// The least R: a close-up's read of at least kMinCloseUpBytes.
    static constexpr std::uint64_t kMinCloseUpBytes = std::uint64_t(64) << 20;
    /// The smallest SIZE before anything is opened.
    static std::uint64_t smallest_limit();
    /// The most one close-up may read (ViewServerOptions::region_read_bytes).
    std::uint64_t close_up_bytes() const;
    /// The splat tree's fit's bound (SplatOptions::max_bytes) with @a opened bytes held: what
    /// lets its build take at most R - opened and the tree it leaves (sizeof(SplatNode) a node)
    /// at most R / 2 - opened. 0 when nothing is left.
    std::uint64_t splat_tree_bytes(std::uint64_t opened) const;
    /// The smallest SIZE whose splat_tree_bytes(@a opened) holds @a tree_bytes.
    static std::uint64_t smallest_limit(std::uint64_t opened, std::uint64_t tree_bytes);

private:
    std::uint64_t rest() const;
};

/// What the page shows: a scan, a mesh, a label map's meshes, or a lattice's splats.
struct ViewSource {
    std::string name;                  ///< the input's file name, shown as the title
    std::shared_ptr<const ViewScan> scan;  ///< set for scans and .vdb grids
    std::shared_ptr<const Mesh> mesh;      ///< set for mesh files and label maps
    std::vector<ViewLabel> labels;     ///< set for label maps: the runs of @a mesh, ascending values
    std::shared_ptr<const ViewLattice> lattice;  ///< set for a lattice (then neither scan nor mesh)
    double initial_iso = 0;            ///< scans: the isovalue shown first
    /// Scans: a splat tree at initial_iso made before serving. Alone (scan, mesh and
    /// prepare_scan unset: `view scan.splat`, kind "splats"), the page shows these splats
    /// only; meshes, other isovalues and close-ups are refused (400: they need the grid).
    std::shared_ptr<const ViewSplats> splats;
    /// Set with @a splats (and @a scan null): prepares the scan (its histogram and coarse grid,
    /// a pass over every leaf of a huge .vdb) in the background while the page already shows
    /// the splats. Until it is done GET /api/info says "preparing" and /api/mesh answers 503.
    /// It starts when the page asks (GET /api/info?prepare=1, once its first splats are drawn),
    /// or 20 s after the server was made. The work heeds @a control's checkpoints: the server
    /// pauses it while the page's camera moves (POST /api/motion) and stops it when it is
    /// destroyed (the preparation should then give up soon).
    std::function<std::shared_ptr<const ViewScan>(const BackgroundControl& control)> prepare_scan;
    /// Set with a topology preview in @a splats (`view scan.vdb` without --splats): fits the
    /// tree at initial_iso; it runs before prepare_scan, in its thread and when it starts, and
    /// replaces the preview (GET /api/splats then serves the fitted tree, X-Splat-Kind fitted).
    /// It heeds @a control as prepare_scan does.
    std::function<std::shared_ptr<const ViewSplats>(const BackgroundControl& control)> fit_splats;
};

/// Meshes a grid as mesh_grid() does.
using GridMesher = std::function<MeshResult(const openvdb::FloatGrid&, const MeshOptions&)>;

struct ViewServerOptions {
    std::string host = "127.0.0.1";
    int port = 0;                            ///< 0: any free port
    /// Larger meshes are shown coarse until the user asks; a grid read by region is never
    /// meshed whole beyond it.
    std::size_t triangle_budget = 2'000'000;
    /// The most one close-up's read by region may hold (GridRegionSource::estimated_bytes()):
    /// a close-up beyond it is not offered, the page keeping its splats there.
    std::uint64_t region_read_bytes = std::uint64_t(1) << 30;
    /// The bound of a splat tree fitted at another isovalue than the initial one
    /// (SplatOptions::max_bytes), the one kept before it dropped first; 0: no bound, the last
    /// two kept (`view --memory`: a close-up's share).
    std::uint64_t other_splat_tree_bytes = 0;
    /// The figures of a mesh as a JSON object's text (GET /api/figures), e.g. what
    /// `vdbmesh check --json` prints; empty: none.
    std::function<std::string(const Mesh&)> mesh_figures;
    /// What meshes the scan: mesh_grid() when empty. A stand-in lets a test hold a request
    /// inside the mesher (a full mesh gives up through its options.progress).
    GridMesher mesher;
    /// POST /api/motion: how long the background work's pause lasts after moving=1 unless
    /// renewed (the page renews it every second while its camera moves), and after moving=0
    /// (the page's refined view drawn first).
    std::chrono::milliseconds motion_lease{3000};
    std::chrono::milliseconds resume_after_still{1000};
};

/// The HTTP server of `vdbmesh view`, bound on construction.
/// GET /                 the page; /app.js its script
/// GET /api/info         JSON: the input, its histogram and suggested isovalue (once prepared:
///                       "preparing" true until then, "prepare_error" if it failed; prepare=1
///                       starts the preparation: ViewSource::prepare_scan), the budget;
///                       for a label map its labels (value, name, colour, their runs of the mesh);
///                       with a tree made before serving, splats (file, from_file, preview, nodes,
///                       seconds, iso; preview true until the fit replaces the topology preview);
///                       for a lattice (kind "lattice") its box, placed and fitted subtrees;
///                       kind "splats" for a splat file alone (ViewSource::splats)
///                       (only /api/splats serves a lattice, without close-ups)
/// GET /api/mesh         binary: positions (float32 x 3V), normals (float32 x 3V), indices
///                       (uint32 x 3T); headers X-Vertices, X-Triangles, X-Seconds.
///                       Parameters: level=coarse|full|region, method=dc|mc|openvdb, iso, error,
///                       adaptivity; box=x0,y0,z0,x1,y1,z1 (index space, max exclusive) with
///                       level=region: the full mesh's triangles with a corner in the box, made
///                       from the nodes round it alone (the page's close-up). The full mesh of a grid read by
///                       region (a .vdb) is made only within the budget: over the estimate (the
///                       coarse mesh's triangles times the coarse factor squared) /api/mesh,
///                       /api/figures and /api/download answer 413 with X-Triangles (the
///                       estimate) and X-Estimated: 1
/// GET /api/figures      JSON: the analysis of the mesh of the same parameters (as `check`)
/// GET /api/download     the mesh of the same parameters as format=stl|ply|obj
/// GET /api/splats       binary: the splats a camera needs (centre, normal as float32 x 3,
///                       radius float32: 28 bytes each) of the scan's splat hierarchy at iso;
///                       headers X-Splats, X-Splat-Kind (preview: the topology preview; fitted),
///                       X-Level (finest level shown), X-Cut-Level (coarsest node
///                       shown for its children, -1: full detail), X-Complete, X-Tree-Nodes,
///                       X-Seconds (the tree's build). Parameters: iso, vp (16 numbers, world to
///                       clip, column-major), eye (3), focal (pixels per unit at w = 1), pixel, budget;
///                       closeup=N: where the view asks for more detail than the finest splats
///                       hold and triangles are cheaper (src/view/close_up.h), a box of at most
///                       about N triangles for level=region: X-Closeup-Box (x0,y0,z0,x1,y1,z1),
///                       X-Closeup-Triangles (estimated), X-Closeup-Splats (the last splats sent,
///                       inside the box: the triangles replace them)
/// POST /api/motion      the page's camera: moving=1 when it starts moving (and again at least
///                       every second while it moves), moving=0 once it has been still for a
///                       moment. The background work (ViewSource::fit_splats, prepare_scan)
///                       pauses at its next checkpoint while the camera moves and goes on
///                       resume_after_still after moving=0, or motion_lease after the last
///                       moving=1 when no moving=0 comes (a page gone mid-motion): the same
///                       results, later (ViewServerOptions). JSON: {"paused_ms": how long
///                       the pause now lasts}
class ViewServer {
public:
    /// @throw Error when the address cannot be bound (a port in use).
    ViewServer(ViewSource source, const ViewServerOptions& options);
    /// Binds at once and serves the page (/ and /app.js) while @a load makes the source in a
    /// thread: for an input whose reading takes seconds (a huge .vdb's topology and its splat
    /// file), so that the browser starts meanwhile. Every /api/ request waits for the source;
    /// when @a load throws they answer with its error (a usage error 400, else 500).
    /// @throw Error when the address cannot be bound.
    ViewServer(std::function<ViewSource()> load, const ViewServerOptions& options);
    /// Returns once the source is there; rethrows what @a load threw.
    void wait_until_loaded() const;
    ~ViewServer();
    ViewServer(const ViewServer&) = delete;
    ViewServer& operator=(const ViewServer&) = delete;

    int port() const;
    /// "http://HOST:PORT/".
    std::string address() const;
    /// Serves until stop() (called from another thread).
    void run();
    void stop();

private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace vdbmesh
