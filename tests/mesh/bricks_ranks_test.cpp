// Issue 28: ranks that write the file together (mesher.h's BrickOptions::collectives; docs/scale.md,
// "Assembly on every rank") give the bytes one process writes, in every format, here with each rank
// a thread of this process and the collectives a board they meet at (what MPI does between
// processes under mpirun: tests/ranks runs that too). One rank is one process writing the
// file's ranges itself (dc_spill_records.cpp: its records formatted in parallel, in order).

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <unistd.h>

#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "mesh/dc_polygons.h"
#include "mesh/dc_spill.h"
#include "phantom_grid.h"
#include "shared_scan.h"
#include "vdbmesh/grid_region.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/mesh_range_file.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/ranks.h"

namespace vdbmesh {
namespace {

/// Collective calls between threads: each call posts this rank's input, waits for every rank,
/// reads what it needs, and waits again before the board is reused. Messages (post, take) wait
/// in a mailbox.
class Board {
public:
    explicit Board(int ranks) : ranks_(ranks), posted_(std::size_t(ranks)), words_(std::size_t(ranks)) {}

    RankCollectives for_rank(int rank) {
        RankCollectives c;
        c.rank = rank, c.ranks = ranks_;
        c.allgather = [this, rank](const std::string& mine) {
            posted_[std::size_t(rank)] = {mine};
            wait();
            std::vector<std::string> all;
            for (const auto& p : posted_) all.push_back(p.front());
            wait();
            return all;
        };
        c.exchange = [this, rank](const std::vector<std::string>& to_each) {
            posted_[std::size_t(rank)] = to_each;
            wait();
            std::vector<std::string> from_each;
            for (const auto& p : posted_) from_each.push_back(p[std::size_t(rank)]);
            wait();
            return from_each;
        };
        c.or_words = [this, rank](std::vector<std::uint64_t>& words) {
            words_[std::size_t(rank)] = words;
            wait();
            for (const auto& theirs : words_)
                for (std::size_t w = 0; w < words.size(); ++w) words[w] |= theirs[w];
            wait();
        };
        c.from_rank0 = [this, rank](const std::string& text) {
            if (rank == 0) posted_[0] = {text};
            wait();
            const std::string value = posted_[0].front();
            wait();
            return value;
        };
        c.post = [this, rank](int to, int tag, std::string bytes) {
            std::lock_guard<std::mutex> lock(mutex_);
            mailbox_[{rank, to, tag}] = std::move(bytes);
            woken_.notify_all();
        };
        c.take = [this, rank](int from, int tag) {
            std::unique_lock<std::mutex> lock(mutex_);
            const std::tuple<int, int, int> key{from, rank, tag};
            woken_.wait(lock, [&] { return mailbox_.count(key) != 0; });
            std::string bytes = std::move(mailbox_[key]);
            mailbox_.erase(key);
            return bytes;
        };
        c.all = [this, rank](bool mine) {
            posted_[std::size_t(rank)] = {mine ? "1" : "0"};
            wait();
            bool every = true;
            for (const auto& p : posted_) every &= p.front() == "1";
            wait();
            return every;
        };
        return c;
    }

private:
    void wait() {
        std::unique_lock<std::mutex> lock(mutex_);
        const std::uint64_t generation = generation_;
        if (++arrived_ == ranks_) {
            arrived_ = 0, ++generation_;
            woken_.notify_all();
            return;
        }
        woken_.wait(lock, [&] { return generation_ != generation; });
    }

    int ranks_;
    std::vector<std::vector<std::string>> posted_;
    std::vector<std::vector<std::uint64_t>> words_;
    std::map<std::tuple<int, int, int>, std::string> mailbox_;  // from, to, tag
    std::mutex mutex_;
    std::condition_variable woken_;
    int arrived_ = 0;
    std::uint64_t generation_ = 0;
};

/// Nothing reaches this sink but its ranges() (every rank writes its part of the file).
class RangesOnlySink final : public MeshStreamSink {
public:
    RangesOnlySink(const std::filesystem::path& path, bool ascii) : file_(path, ascii), corners_(MeshStreamWriter::writes_corners(path)) {}
    void begin(std::uint64_t, std::uint64_t) override { ADD_FAILURE() << "a rank sent the mesh as a stream"; }
    void vertex(const std::array<float, 3>&) override {}
    void triangle(const std::array<std::uint32_t, 3>&, const std::array<std::array<float, 3>, 3>&) override {}
    bool needs_corners() const override { return corners_; }
    MeshRangeSink* ranges() override { return &file_; }

private:
    MeshRangeFile file_;
    bool corners_;
};

std::string bytes_of(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// @a ranks threads, each a rank meshing its bricks and writing its part of @a path.
void write_over_ranks(const openvdb::FloatGrid::Ptr& grid, const MeshOptions& options, const BrickShape& shape, int ranks,
                      const std::filesystem::path& path, bool ascii) {
    const std::unique_ptr<GridRegionSource> source = grid_regions_in_memory(grid);
    Board board(ranks);
    std::vector<std::thread> threads;
    for (int rank = 0; rank < ranks; ++rank) {
        threads.emplace_back([&, rank] {
            BrickOptions bricks{shape};
            bricks.rank = rank, bricks.ranks = ranks;
            bricks.gather = [](const RankPart&, PartReceiver&) { ADD_FAILURE() << "a rank streamed its part to rank 0"; };
            bricks.collectives = board.for_rank(rank);
            RangesOnlySink sink(path, ascii);
            mesh_bricks_to_stream(*source, options, bricks, sink);
        });
    }
    for (std::thread& t : threads) t.join();
}

class BricksRanksTest : public ::testing::Test {
protected:
    void SetUp() override {
        folder_ = std::filesystem::temp_directory_path() / ("vdbmesh_bricks_ranks_" + std::to_string(::getpid()));
        std::filesystem::create_directories(folder_);
    }
    void TearDown() override { std::filesystem::remove_all(folder_); }

    /// One process's file and the ranks' are byte-identical, for each format and rank count.
    void expect_same_bytes(const openvdb::FloatGrid::Ptr& grid, const BrickShape& shape, const std::vector<int>& rank_counts,
                           double iso = 0.5) {
        MeshOptions options;
        options.method = MeshMethod::dc;
        options.iso = iso;
        options.error = 0.25;
        const Mesh whole = mesh_grid(*grid, options).mesh;
        ASSERT_FALSE(whole.triangles.empty());
        for (const auto& [name, ascii] : std::vector<std::pair<std::string, bool>>{{"mesh.obj", false}, {"mesh.ply", false}, {"mesh.ply", true},
                                                                                  {"mesh.stl", false}, {"mesh.stl", true}}) {
            const std::filesystem::path plain = folder_ / ("plain-" + name), ranked = folder_ / ("ranks-" + name);
            write_mesh(whole, plain, MeshWriteOptions{ascii, false});
            for (const int ranks : rank_counts) {
                write_over_ranks(grid, options, shape, ranks, ranked, ascii);
                EXPECT_EQ(bytes_of(ranked), bytes_of(plain)) << name << (ascii ? " (ascii)" : "") << ", " << ranks << " ranks";
                std::filesystem::remove(ranked);
            }
        }
        // No temporary file left beside the target.
        for (const auto& entry : std::filesystem::directory_iterator(folder_))
            EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
    }

    std::filesystem::path folder_;
};

/// A sphere of 168^3 voxels centred where eight nodes meet: every rank border runs through
/// the surface, so some border vertices are used only by the other rank's triangles.
openvdb::FloatGrid::Ptr sphere_on_node_corner() {
    PhantomSpec spec;
    spec.shape = PhantomShape::sphere;
    spec.radius = 36;
    spec.dims = {168, 168, 168};
    spec.centre = std::array<double, 3>{128.3, 127.6, 128.45};
    return test::phantom_scan_grid(spec);
}

TEST_F(BricksRanksTest, RanksWritingTogetherGiveOneProcesssBytesInEveryFormat) {
    // Columns of one node (the ranks' runs cut across columns and layers), 1, 2 and 3 ranks.
    expect_same_bytes(sphere_on_node_corner(), {1, 1}, {1, 2, 3});
}

// A real scan's 397,340 triangles at 0.25 are many runs of the pipeline that formats them
// (65,536 records a run at most), here in one process writing the file's ranges itself.
TEST_F(BricksRanksTest, RealScanCTheadInEveryFormat) {
    openvdb::FloatGrid::Ptr grid;
    const test::SharedScan& scan = test::shared_scan("CThead");
    ASSERT_NO_FATAL_FAILURE(test::convert_shared_scan(scan, grid));
    if (!grid) return;
    expect_same_bytes(grid, {2, 2}, {1}, scan.iso);
}

/// One node's output by hand: a tetrahedron of four crossings, and, with @a unused, a fifth
/// crossing no triangle names (the weld drops it: the numbers after it change).
detail::IfcNodeOutput tetrahedron_node(bool unused) {
    auto vertex = [](int x, int y, int z) {
        return detail::IfcVertex{detail::ifc_edge_key(openvdb::Coord(x, y, z), 0), {float(x) + 0.5f, float(y), float(z)}};
    };
    detail::IfcBlockOutput block;
    block.vertices = {vertex(1, 1, 1), vertex(4, 1, 1), vertex(1, 4, 1)};
    if (unused) block.vertices.push_back(vertex(6, 6, 6));
    block.vertices.push_back(vertex(1, 1, 4));
    auto key = [&](int x, int y, int z) { return detail::ifc_edge_key(openvdb::Coord(x, y, z), 0); };
    const std::uint64_t a = key(1, 1, 1), b = key(4, 1, 1), c = key(1, 4, 1), d = key(1, 1, 4);
    block.triangles = {{a, c, b}, {a, b, d}, {a, d, c}, {b, c, d}};
    detail::IfcNodeOutput node;
    node.origin = openvdb::Coord(0, 0, 0);
    node.blocks.push_back(block);
    return node;
}

// One process writing its file's ranges (the command's sink) takes one pass when every vertex
// is used, and falls back to two when one is not: the weld's bytes either way.
TEST_F(BricksRanksTest, OneProcessGivesTheWeldsBytesWithAndWithoutAnUnusedVertex) {
    for (const bool unused : {false, true}) {
        std::vector<detail::IfcNodeOutput> nodes{tetrahedron_node(unused)};
        const Mesh welded = detail::weld_ifc_nodes(std::vector<detail::IfcNodeOutput>(nodes));
        ASSERT_EQ(welded.vertices.size(), 4u) << "the weld drops the unused vertex";
        for (const auto& [name, ascii] : std::vector<std::pair<std::string, bool>>{{"mesh.ply", false}, {"mesh.obj", false}, {"mesh.stl", true}}) {
            const std::filesystem::path plain = folder_ / ("plain-" + name), spilled = folder_ / ("spilled-" + name);
            write_mesh(welded, plain, MeshWriteOptions{ascii, false});
            detail::IfcSpill spill;
            spill.append(std::move(nodes.front()));
            nodes = {tetrahedron_node(unused)};
            RangesOnlySink sink(spilled, ascii);
            spill.emit(sink, false);
            EXPECT_EQ(bytes_of(spilled), bytes_of(plain)) << name << (unused ? ", a vertex unused" : "");
        }
    }
    for (const auto& entry : std::filesystem::directory_iterator(folder_))
        EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST_F(BricksRanksTest, CylinderThroughFiveNodesSplitByLayers) {
    // One column, so the ranks' runs are node layers, the borders across the tilted wall.
    expect_same_bytes(test::phantom_scan_grid(test::cylinder_through_five_nodes()), {1, 1}, {2, 3});
}

TEST_F(BricksRanksTest, MirroredGridIsWoundAlikeAcrossAColumnBorder) {
    // Columns of one node across x = 128: the two ranks' border runs between columns.
    const auto grid = test::mirrored_sphere_across_a_node_border();
    expect_same_bytes(grid, {1, 1}, {2});
}

TEST_F(BricksRanksTest, RanksWithNoBrickWriteNothingAndTheFileIsWhole) {
    // One column of three layers over 5 ranks: at least two ranks have no brick.
    expect_same_bytes(sphere_on_node_corner(), {4, 4}, {5});
}

}  // namespace
}  // namespace vdbmesh
