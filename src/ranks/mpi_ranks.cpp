// ranks.h with MPI (VDBMESH_MPI=ON): MPI_COMM_WORLD while a RanksSession lives under a launcher;
// without one, a single process or a rank of a simulated run (simulated_ranks.h).

#include <mpi.h>

#include <algorithm>
#include <cstdint>

#include "ranks/simulated_ranks.h"
#include "vdbmesh/error.h"
#include "vdbmesh/ranks.h"

namespace vdbmesh {

namespace {

/// Whether this process initialised MPI (a RanksSession under a launcher).
bool mpi_live = false;

void check(int code, const char* call) {
    if (code != MPI_SUCCESS) throw Error(std::string("MPI: ") + call + " failed (code " + std::to_string(code) + ")");
}

}  // namespace

RanksSession::RanksSession() {
    if (!started_by_mpi_launcher()) return;
    int provided = 0;
    // TBB threads never call MPI: only the main thread does.
    check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    mpi_live = true;
}

RanksSession::~RanksSession() {
    if (!mpi_live) return;
    mpi_live = false;
    MPI_Finalize();
}

int this_rank() {
    int rank = 0;
    if (mpi_live) {
        check(MPI_Comm_rank(MPI_COMM_WORLD, &rank), "MPI_Comm_rank");
    } else if (const auto simulated = detail::simulated_rank()) {
        rank = simulated->rank;
    }
    return rank;
}

int rank_count() {
    int size = 1;
    if (mpi_live) {
        check(MPI_Comm_size(MPI_COMM_WORLD, &size), "MPI_Comm_size");
    } else if (const auto simulated = detail::simulated_rank()) {
        size = simulated->ranks;
    }
    return size;
}

void stream_to_rank0(const RankPart& mine, PartReceiver& receiver) {
    if (!mpi_live) {
        if (const auto simulated = detail::simulated_rank()) detail::simulated_stream(*simulated, mine, receiver);
        return;
    }
    const int rank = this_rank(), ranks = rank_count();
    std::uint64_t size = mine.size;
    std::vector<std::uint64_t> sizes(rank == 0 ? static_cast<std::size_t>(ranks) : 0);
    check(MPI_Gather(&size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "MPI_Gather");
    std::vector<char> piece(std::min<std::uint64_t>(kPartPieceBytes, rank == 0 ? *std::max_element(sizes.begin(), sizes.end()) : size));
    if (rank != 0) {
        // Sent in order: MPI keeps the order of messages between two ranks on one tag.
        for (std::uint64_t at = 0; at < size; at += piece.size()) {
            const std::size_t count = std::size_t(std::min<std::uint64_t>(piece.size(), size - at));
            mine.read(at, count, piece.data());
            check(MPI_Send(piece.data(), static_cast<int>(count), MPI_BYTE, 0, 0, MPI_COMM_WORLD), "MPI_Send");
        }
        return;
    }
    for (int from = 1; from < ranks; ++from) {
        const std::uint64_t theirs = sizes[static_cast<std::size_t>(from)];
        receiver.begin(from, theirs);
        for (std::uint64_t at = 0; at < theirs; at += piece.size()) {
            const std::size_t count = std::size_t(std::min<std::uint64_t>(piece.size(), theirs - at));
            check(MPI_Recv(piece.data(), static_cast<int>(count), MPI_BYTE, from, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
            receiver.piece(piece.data(), count);
        }
    }
}

}  // namespace vdbmesh
