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

/// The most bytes one MPI message carries: counts are ints.
constexpr std::uint64_t kPieceBytes = std::uint64_t{1} << 30;

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

std::vector<std::string> gather_to_rank0(const std::string& bytes) {
    if (!mpi_live) {
        const auto simulated = detail::simulated_rank();
        return simulated ? detail::simulated_gather(*simulated, bytes) : std::vector<std::string>{bytes};
    }
    const int rank = this_rank(), ranks = rank_count();
    std::uint64_t mine = bytes.size();
    std::vector<std::uint64_t> sizes(rank == 0 ? static_cast<std::size_t>(ranks) : 0);
    check(MPI_Gather(&mine, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "MPI_Gather");
    if (rank != 0) {
        for (std::uint64_t at = 0; at < mine; at += kPieceBytes)
            check(MPI_Send(bytes.data() + at, static_cast<int>(std::min(kPieceBytes, mine - at)), MPI_BYTE, 0, 0, MPI_COMM_WORLD), "MPI_Send");
        return {};
    }
    std::vector<std::string> all(static_cast<std::size_t>(ranks));
    all[0] = bytes;
    for (int from = 1; from < ranks; ++from) {
        std::string& theirs = all[static_cast<std::size_t>(from)];
        theirs.resize(sizes[static_cast<std::size_t>(from)]);
        for (std::uint64_t at = 0; at < theirs.size(); at += kPieceBytes)
            check(MPI_Recv(theirs.data() + at, static_cast<int>(std::min<std::uint64_t>(kPieceBytes, theirs.size() - at)), MPI_BYTE, from,
                           0, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
                  "MPI_Recv");
    }
    return all;
}

}  // namespace vdbmesh
