// Each child serves requests over a socket pair: the parent sends a count and that many leaf
// pointers (valid in the child: the tree was there when it was forked), the child copies each
// leaf's buffer (out of core, so the copy shares its place in the file), loads the copy into
// its shared area and frees it, then answers with the length of a failure text (0: done) and
// the text. Each request may use a few seconds of the child's CPU time (RLIMIT_CPU, set anew
// for each: SIGXCPU ends a reader that loops); the parent waits with a much longer wall limit
// instead of the child's alarm: a child that reaches either is killed and the request given
// once more to a fresh one (as run_in_child() does: a child can block, or spin, on a lock
// another thread held at fork()).

#include "leaf_loading_children.h"

#include <poll.h>
#include <signal.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <new>
#include <string>
#include <utility>

#include "vdb_probe.h"
#include "vdbmesh/error.h"
#include "vdbmesh/program_memory.h"

namespace vdbmesh::detail {

namespace {

/// Leaves one request holds: 16 MiB of floats.
constexpr std::size_t kLeavesPerRequest = (std::size_t{16} << 20) / (FloatLeaf::SIZE * sizeof(float));
constexpr std::size_t kRequestBytes = kLeavesPerRequest * FloatLeaf::SIZE * sizeof(float);

bool read_exactly(int fd, void* data, std::size_t bytes) {
    auto* at = static_cast<char*>(data);
    while (bytes > 0) {
        const ssize_t n = ::read(fd, at, bytes);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        at += n;
        bytes -= static_cast<std::size_t>(n);
    }
    return true;
}

/// Writes without SIGPIPE: a child that died is reported by the read that follows.
bool send_exactly(int fd, const void* data, std::size_t bytes) {
    const auto* at = static_cast<const char*>(data);
    while (bytes > 0) {
        const ssize_t n = ::send(fd, at, bytes, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        at += n;
        bytes -= static_cast<std::size_t>(n);
    }
    return true;
}

/// Whether @a fd has something to read (or was closed) within @a seconds.
bool readable_within(int fd, unsigned seconds) {
    pollfd wanted{fd, POLLIN, 0};
    for (;;) {
        const int n = ::poll(&wanted, 1, static_cast<int>(seconds) * 1000);
        if (n < 0 && errno == EINTR) continue;
        return n > 0;
    }
}

/// CPU seconds a request of @a leaves may use.
unsigned request_cpu_seconds(std::size_t leaves) { return reading_cpu_seconds(leaves * FloatLeaf::SIZE * sizeof(float)); }

/// The child's side: serves requests on @a socket until the parent closes it.
[[noreturn]] void serve_requests(int socket, float* values, std::uint64_t address_space) {
    enter_reading_child(address_space);
    std::vector<const FloatLeaf*> leaves;
    for (std::uint64_t count = 0; read_exactly(socket, &count, sizeof(count));) {
        leaves.resize(std::min<std::uint64_t>(count, kLeavesPerRequest));
        if (count > kLeavesPerRequest || !read_exactly(socket, leaves.data(), leaves.size() * sizeof(leaves[0]))) ::_exit(2);
        limit_cpu_from_now(request_cpu_seconds(leaves.size()));
        const std::string failure = failure_of(
            [&] {
                for (std::size_t i = 0; i < leaves.size(); ++i) {
                    FloatLeaf::Buffer buffer(leaves[i]->buffer());  // loaded below, freed at once
                    std::memcpy(values + i * FloatLeaf::SIZE, buffer.data(), FloatLeaf::SIZE * sizeof(float));
                }
            },
            address_space);
        const auto length = static_cast<std::uint32_t>(failure.size());
        if (!send_exactly(socket, &length, sizeof(length)) || !send_exactly(socket, failure.data(), failure.size()) || length != 0)
            ::_exit(1);
    }
    ::_exit(0);
}

}  // namespace

/// One forked child, its socket and its area of shared memory (mapped before the fork).
class LeafLoadingChildren::Child {
public:
    explicit Child(const std::filesystem::path& path) : path_(path) {
        void* memory = ::mmap(nullptr, kRequestBytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
        if (memory == MAP_FAILED) throw std::bad_alloc();
        values_ = static_cast<float*>(memory);
        start();
    }
    ~Child() {
        stop();
        ::munmap(values_, kRequestBytes);
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    const float* values() const { return values_; }

    /// Asks the child for the values of @a count leaves from @a leaves.
    void send(const FloatLeaf* const* leaves, std::size_t count) {
        request_.assign(leaves, leaves + count);
        const std::uint64_t words = count;
        (void)(send_exactly(socket_, &words, sizeof(words)) && send_exactly(socket_, leaves, count * sizeof(leaves[0])));
    }

    /// Waits for the answer to the last request; throws FormatError when it failed.
    void finish() {
        const unsigned cpu_seconds = request_cpu_seconds(request_.size());
        const unsigned seconds = blocked_wall_seconds(cpu_seconds);
        if (answered_within(seconds, cpu_seconds, /*last_try=*/false)) return;
        // Once more from a fresh child (see the file's comment), then give up.
        restart();
        send(request_.data(), request_.size());
        if (answered_within(seconds, cpu_seconds, /*last_try=*/true)) return;
        stop();
        throw FormatError(path_.string(), blocked_failure(seconds));
    }

private:
    void start() {
        int sockets[2];
        if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sockets) != 0)
            throw Error(path_.string() + ": cannot create a socket to read the .vdb file");
        // The child starts with this process's address space (the mapped file, the topology).
        const std::uint64_t address_space = process_memory_now().address_space + std::max<std::uint64_t>(std::uint64_t{2} << 30, 8 * kRequestBytes);
        pid_ = ::fork();
        if (pid_ == 0) {
            ::close(sockets[0]);
            serve_requests(sockets[1], values_, address_space);
        }
        ::close(sockets[1]);
        socket_ = sockets[0];
        if (pid_ < 0) {
            ::close(socket_);
            socket_ = -1;
            throw Error(path_.string() + ": cannot start a process to read the .vdb file");
        }
    }

    void stop() {
        if (socket_ >= 0) ::close(socket_);
        socket_ = -1;
        if (pid_ <= 0) return;
        ::kill(pid_, SIGKILL);
        int status = 0;
        while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
        }
        pid_ = -1;
    }

    void restart() {
        stop();
        start();
    }

    /// True when the child answered done within @a seconds, false when it did not answer in
    /// time, or, unless @a last_try, ran out of its @a cpu_seconds (it may spin on a lock held
    /// at fork(), as it may block on one); throws FormatError when it answered a failure or
    /// ended otherwise.
    bool answered_within(unsigned seconds, unsigned cpu_seconds, bool last_try) {
        if (!readable_within(socket_, seconds)) return false;
        std::uint32_t length = 0;
        if (read_exactly(socket_, &length, sizeof(length))) {
            if (length == 0) return true;
            std::string failure(length, '\0');
            (void)read_exactly(socket_, failure.data(), length);
            stop();
            throw FormatError(path_.string(), failure);
        }
        int status = 0;  // the child ended without answering
        while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
        }
        pid_ = -1;
        stop();
        if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU) {
            if (!last_try) return false;
            throw FormatError(path_.string(), cpu_limit_failure(cpu_seconds));
        }
        if (WIFSIGNALED(status))
            throw FormatError(path_.string(), std::string("corrupt .vdb file: OpenVDB's reader crashed on it (") + ::strsignal(WTERMSIG(status)) + ")");
        throw FormatError(path_.string(), "not a readable .vdb file");
    }

    std::filesystem::path path_;
    float* values_ = nullptr;
    pid_t pid_ = -1;
    int socket_ = -1;
    std::vector<const FloatLeaf*> request_;
};

LeafLoadingChildren::LeafLoadingChildren(std::filesystem::path path, unsigned children)
    : path_(std::move(path)), count_(std::max(children, 1u)) {}

LeafLoadingChildren::~LeafLoadingChildren() = default;

void LeafLoadingChildren::fork_children() {
    for (unsigned i = 0; i < count_; ++i) children_.push_back(std::make_unique<Child>(path_));
}

void LeafLoadingChildren::end_children() { children_.clear(); }

void LeafLoadingChildren::load(const std::vector<const FloatLeaf*>& leaves, const std::function<void(std::size_t, const float*)>& take) {
    if (leaves.empty()) return;
    if (children_.empty()) fork_children();
    const std::size_t requests = (leaves.size() + kLeavesPerRequest - 1) / kLeavesPerRequest;
    auto leaves_of = [&](std::size_t request) { return std::min(kLeavesPerRequest, leaves.size() - request * kLeavesPerRequest); };
    // Request r goes to child r % count_: each child decodes while this process copies out
    // what another has decoded.
    auto send = [&](std::size_t request) {
        children_[request % count_]->send(leaves.data() + request * kLeavesPerRequest, leaves_of(request));
    };
    try {
        for (std::size_t r = 0; r < std::min<std::size_t>(count_, requests); ++r) send(r);
        for (std::size_t r = 0; r < requests; ++r) {
            Child& child = *children_[r % count_];
            child.finish();
            for (std::size_t i = 0; i < leaves_of(r); ++i) take(r * kLeavesPerRequest + i, child.values() + i * FloatLeaf::SIZE);
            if (r + count_ < requests) send(r + count_);
        }
    } catch (...) {
        end_children();  // some may still be decoding
        throw;
    }
}

}  // namespace vdbmesh::detail
