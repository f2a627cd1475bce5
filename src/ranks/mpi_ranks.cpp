// ranks.h with MPI (VDBMESH_MPI=ON): MPI_COMM_WORLD while a RanksSession lives under a launcher;
// without one, a single process or a rank of a simulated run (simulated_ranks.h).

#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <list>
#include <string>

#include "ranks/simulated_ranks.h"
#include "vdbmesh/error.h"
#include "vdbmesh/ranks.h"

namespace vdbmesh {

namespace {

/// Whether this process initialised MPI (a RanksSession under a launcher).
bool mpi_live = false;

/// Messages post() sent that may not have been received yet: their bytes must live until then.
struct PostedMessage {
    std::string bytes;
    MPI_Request request = MPI_REQUEST_NULL;
};
std::list<PostedMessage> posted;

void wait_for_posted() {
    for (PostedMessage& message : posted) MPI_Wait(&message.request, MPI_STATUS_IGNORE);
    posted.clear();
}

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
    wait_for_posted();
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

namespace {

/// MPI's counts are ints: a part beyond 2 GiB is refused rather than truncated.
int count_of(std::size_t bytes) {
    if (bytes > std::size_t(std::numeric_limits<int>::max())) throw Error("MPI: a message of " + std::to_string(bytes) + " bytes (at most 2 GiB)");
    return static_cast<int>(bytes);
}

/// Displacements of @a counts laid end to end, and their total.
std::vector<int> displacements(const std::vector<int>& counts, std::size_t& total) {
    std::vector<int> at(counts.size());
    total = 0;
    for (std::size_t q = 0; q < counts.size(); ++q) {
        at[q] = count_of(total);
        total += std::size_t(counts[q]);
    }
    count_of(total);
    return at;
}

std::vector<std::string> mpi_allgather(const std::string& mine) {
    const int ranks = rank_count();
    const int count = count_of(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(ranks), 0);
    check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
    std::size_t total = 0;
    const std::vector<int> at = displacements(counts, total);
    std::string all(total, '\0');
    check(MPI_Allgatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), at.data(), MPI_BYTE, MPI_COMM_WORLD), "MPI_Allgatherv");
    std::vector<std::string> each(static_cast<std::size_t>(ranks));
    for (std::size_t q = 0; q < each.size(); ++q) each[q] = all.substr(std::size_t(at[q]), std::size_t(counts[q]));
    return each;
}

std::vector<std::string> mpi_exchange(const std::vector<std::string>& to_each) {
    const int ranks = rank_count();
    if (to_each.size() != std::size_t(ranks)) throw Error("MPI: an exchange needs one message per rank");
    std::vector<int> send_counts(static_cast<std::size_t>(ranks)), receive_counts(static_cast<std::size_t>(ranks));
    std::string sent;
    for (std::size_t q = 0; q < to_each.size(); ++q) send_counts[q] = count_of(to_each[q].size()), sent += to_each[q];
    check(MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Alltoall");
    std::size_t sent_total = 0, received_total = 0;
    const std::vector<int> send_at = displacements(send_counts, sent_total), receive_at = displacements(receive_counts, received_total);
    std::string received(received_total, '\0');
    check(MPI_Alltoallv(sent.data(), send_counts.data(), send_at.data(), MPI_BYTE, received.data(), receive_counts.data(), receive_at.data(),
                        MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Alltoallv");
    std::vector<std::string> from_each(static_cast<std::size_t>(ranks));
    for (std::size_t q = 0; q < from_each.size(); ++q) from_each[q] = received.substr(std::size_t(receive_at[q]), std::size_t(receive_counts[q]));
    return from_each;
}

void mpi_or_words(std::vector<std::uint64_t>& words) {
    // In pieces, so that each count is an int whatever the length.
    constexpr std::size_t kPiece = std::size_t{1} << 24;
    for (std::size_t at = 0; at < words.size(); at += kPiece) {
        const int count = static_cast<int>(std::min(kPiece, words.size() - at));
        check(MPI_Allreduce(MPI_IN_PLACE, words.data() + at, count, MPI_UINT64_T, MPI_BOR, MPI_COMM_WORLD), "MPI_Allreduce");
    }
}

std::string mpi_from_rank0(const std::string& text) {
    std::uint64_t size = text.size();
    check(MPI_Bcast(&size, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "MPI_Bcast");
    std::string received = this_rank() == 0 ? text : std::string(std::size_t(size), '\0');
    check(MPI_Bcast(received.data(), count_of(received.size()), MPI_BYTE, 0, MPI_COMM_WORLD), "MPI_Bcast");
    return received;
}

bool mpi_all(bool mine) {
    int value = mine ? 1 : 0;
    check(MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD), "MPI_Allreduce");
    return value != 0;
}

void mpi_post(int to, int tag, std::string bytes) {
    PostedMessage& message = posted.emplace_back();
    message.bytes = std::move(bytes);
    check(MPI_Isend(message.bytes.data(), count_of(message.bytes.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD, &message.request), "MPI_Isend");
}

std::string mpi_take(int from, int tag) {
    MPI_Status status;
    check(MPI_Probe(from, tag, MPI_COMM_WORLD, &status), "MPI_Probe");
    int count = 0;
    check(MPI_Get_count(&status, MPI_BYTE, &count), "MPI_Get_count");
    std::string bytes(std::size_t(count), '\0');
    check(MPI_Recv(bytes.data(), count, MPI_BYTE, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
    return bytes;
}

}  // namespace

std::optional<RankCollectives> ranks_collectives() {
    if (!mpi_live || rank_count() < 2) return std::nullopt;
    return RankCollectives{this_rank(), rank_count(), mpi_allgather, mpi_exchange, mpi_or_words, mpi_from_rank0, mpi_all, mpi_post, mpi_take};
}

}  // namespace vdbmesh
