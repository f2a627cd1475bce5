// N ranks simulated one process at a time (simulated_ranks.h).

#include "ranks/simulated_ranks.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "vdbmesh/atomic_file.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

std::filesystem::path part_path(const SimulatedRank& simulated, int rank) {
    return simulated.folder / ("part-" + std::to_string(rank));
}

}  // namespace

std::optional<SimulatedRank> simulated_rank() {
    const char* text = std::getenv("VDBMESH_SIMULATE_RANKS");
    if (!text || !*text) return std::nullopt;
    std::istringstream in(text);
    SimulatedRank simulated;
    char slash = 0, colon = 0;
    std::string folder;
    if (!(in >> simulated.rank >> slash >> simulated.ranks >> colon) || slash != '/' || colon != ':' || !std::getline(in, folder) ||
        folder.empty() || simulated.ranks < 1 || simulated.rank < 0 || simulated.rank >= simulated.ranks) {
        throw UsageError(std::string("VDBMESH_SIMULATE_RANKS: expected RANK/RANKS:FOLDER with 0 <= RANK < RANKS, got \"") + text + "\"");
    }
    simulated.folder = folder;
    return simulated;
}

void simulated_stream(const SimulatedRank& simulated, const RankPart& mine, PartReceiver& receiver) {
    std::vector<char> piece(kPartPieceBytes);
    if (simulated.rank != 0) {
        AtomicFile part(part_path(simulated, simulated.rank));
        std::ofstream out(part.temp_path(), std::ios::binary);
        for (std::uint64_t at = 0; at < mine.size; at += piece.size()) {
            const std::size_t count = std::size_t(std::min<std::uint64_t>(piece.size(), mine.size - at));
            mine.read(at, count, piece.data());
            out.write(piece.data(), std::streamsize(count));
        }
        if (!out.flush()) throw Error(part.temp_path().string() + ": cannot write simulated rank " + std::to_string(simulated.rank) + "'s part");
        out.close();
        part.commit();
        return;
    }
    for (int rank = 1; rank < simulated.ranks; ++rank) {
        std::ifstream in(part_path(simulated, rank), std::ios::binary);
        if (!in) throw Error(part_path(simulated, rank).string() + ": no part of simulated rank " + std::to_string(rank) + " (run ranks " +
                             std::to_string(simulated.ranks - 1) + " .. 1 before rank 0)");
        receiver.begin(rank, std::filesystem::file_size(part_path(simulated, rank)));
        while (in.read(piece.data(), std::streamsize(piece.size())) || in.gcount() > 0) receiver.piece(piece.data(), std::size_t(in.gcount()));
    }
}

}  // namespace vdbmesh::detail
