// The child only runs the reading it is given (opening the file with io::File and reading all
// grids, their topology, or some leaves' values; no TBB work, which would not be safe after
// fork()), then reports through a pipe: nothing on success, else the text of the exception.
// The parent turns a signal, a failed allocation or that text into a FormatError.

#include "vdb_probe.h"

#include <fcntl.h>
#include <openvdb/openvdb.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <new>
#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/program_memory.h"

namespace vdbmesh::detail {

namespace {

constexpr rlim_t kTwoGiB = rlim_t{2} << 30;

rlim_t memory_limit(std::uintmax_t file_bytes) {
    const auto physical = static_cast<rlim_t>(::sysconf(_SC_PHYS_PAGES)) * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE));
    const rlim_t wanted = std::max<rlim_t>(kTwoGiB, static_cast<rlim_t>(file_bytes) * 64);
    return physical > 0 ? std::min(wanted, physical) : wanted;
}

/// Whether this is an AddressSanitizer build (the fuzz build): its shadow memory reserves
/// terabytes of address space, so an address-space limit would fail every allocation; its
/// own allocator refuses (aborts on) a request beyond its maximum instead.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

/// The child inherits the parent's signal handlers and mask. A handler for SIGALRM (libFuzzer
/// has one, and so may any program that embeds vdbmesh) swallows the alarm below, and a
/// blocked SIGALRM never arrives: either way the parent waits forever. A crash handler would
/// run the host's crash reporting in the child. So the child resets them all to the default:
/// the alarm or the CPU limit (SIGXCPU) ends it, a crash kills it, and the parent reports which.
void restore_default_signals() {
    for (const int signal : {SIGALRM, SIGXCPU, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::signal(signal, SIG_DFL);
    sigset_t limits;
    sigemptyset(&limits);
    sigaddset(&limits, SIGALRM);
    sigaddset(&limits, SIGXCPU);
    ::sigprocmask(SIG_UNBLOCK, &limits, nullptr);
}

[[noreturn]] void read_in_child(const ChildReading& reading, const ChildLimits& limits, int report) {
    enter_reading_child(limits.address_space);
    // A reader that loops ends by SIGXCPU; a child that blocks without using CPU (a lock held
    // by another thread of the parent at fork()) by SIGALRM, instead of hanging the parent.
    limit_cpu_from_now(limits.cpu_seconds);
    ::alarm(limits.wall_seconds);
    const std::string failure = failure_of(reading, limits.address_space);
    if (!failure.empty()) (void)!::write(report, failure.data(), failure.size());
    ::_exit(failure.empty() ? 0 : 1);
}

std::string read_all(int fd) {
    std::string text;
    char buffer[4096];
    for (ssize_t n; (n = ::read(fd, buffer, sizeof(buffer))) != 0;) {
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) break;
        text.append(buffer, static_cast<std::size_t>(n));
    }
    return text;
}

/// What one reading child did: how it ended and what it reported.
struct ChildOutcome {
    int status = 0;
    std::string failure;
};

ChildOutcome read_once_in_child(const std::filesystem::path& path, const ChildReading& reading, const ChildLimits& limits) {
    int report[2];
    if (::pipe2(report, O_CLOEXEC) != 0) throw Error(path.string() + ": cannot create a pipe to check the .vdb file");
    const pid_t child = ::fork();
    if (child == 0) {
        ::close(report[0]);
        read_in_child(reading, limits, report[1]);
    }
    ::close(report[1]);
    ChildOutcome outcome;
    outcome.failure = child > 0 ? read_all(report[0]) : "";
    ::close(report[0]);
    if (child < 0) throw Error(path.string() + ": cannot start a process to check the .vdb file");
    while (::waitpid(child, &outcome.status, 0) < 0 && errno == EINTR) {
    }
    return outcome;
}

bool ended_by(const ChildOutcome& outcome, int signal) { return WIFSIGNALED(outcome.status) && WTERMSIG(outcome.status) == signal; }

std::uintmax_t file_bytes(const std::filesystem::path& path) {
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    return ec ? 0 : bytes;
}

}  // namespace

// A sound file's reading uses about 0.1 s of CPU per 16 MiB (the tiled bunny's topology, 45 MB
// counted, 1.5 s of the child's time at load 9): 4 s and 1 s per 16 MiB leave a margin of 3 or more.
unsigned reading_cpu_seconds(std::uintmax_t bytes) { return 4 + static_cast<unsigned>(bytes >> 24); }

// Ten times the CPU limit and a minute more: a read that gets a tenth of a core (seen beside
// other jobs on a 2-core machine) still finishes, and a blocked child is retried within minutes.
unsigned blocked_wall_seconds(unsigned cpu_seconds) { return 60 + 10 * cpu_seconds; }

std::string cpu_limit_failure(unsigned cpu_seconds) {
    return "reading it used more than " + std::to_string(cpu_seconds) + " s of CPU time (OpenVDB's reader can loop on a corrupt file)";
}

std::string blocked_failure(unsigned wall_seconds) {
    return "reading it did not finish in " + std::to_string(wall_seconds) +
           " s, twice, the reading process blocked (its CPU time has a limit of its own: a read slowed by a busy machine is "
           "not stopped by this one)";
}

void limit_cpu_from_now(unsigned seconds) {
    rusage used{};
    ::getrusage(RUSAGE_SELF, &used);
    const std::uint64_t micros = std::uint64_t(used.ru_utime.tv_sec + used.ru_stime.tv_sec) * 1'000'000 +
                                 std::uint64_t(used.ru_utime.tv_usec + used.ru_stime.tv_usec);
    const auto spent = static_cast<rlim_t>((micros + 999'999) / 1'000'000);  // rounded up
    rlimit limit{};
    ::getrlimit(RLIMIT_CPU, &limit);
    limit.rlim_cur = std::min(limit.rlim_max, spent + seconds);  // RLIM_INFINITY is the largest value
    ::setrlimit(RLIMIT_CPU, &limit);
}

void run_in_child(const std::filesystem::path& path, const ChildReading& reading, const ChildLimits& limits) {
    ChildOutcome outcome = read_once_in_child(path, reading, limits);
    // A child can block, or spin, on a lock another thread of this process held at fork() (a
    // fresh small .vdb a test had just written timed out once in a CI run of the suite; a
    // splat file decoded beside the probe once made a child spin past its CPU limit): a second
    // child, forked at another moment, tells that from a reader that loops on the file.
    if (ended_by(outcome, SIGALRM) || ended_by(outcome, SIGXCPU)) outcome = read_once_in_child(path, reading, limits);
    const int status = outcome.status;
    if (ended_by(outcome, SIGALRM)) throw FormatError(path.string(), blocked_failure(limits.wall_seconds));
    if (ended_by(outcome, SIGXCPU)) throw FormatError(path.string(), cpu_limit_failure(limits.cpu_seconds));
    if (WIFSIGNALED(status))
        throw FormatError(path.string(), std::string("corrupt .vdb file: OpenVDB's reader crashed on it (") +
                                             ::strsignal(WTERMSIG(status)) + ")");
    if (WEXITSTATUS(status) != 0) throw FormatError(path.string(), outcome.failure.empty() ? "not a readable .vdb file" : outcome.failure);
}

void enter_reading_child(std::uint64_t address_space) {
    restore_default_signals();
    const rlimit limit{static_cast<rlim_t>(address_space), static_cast<rlim_t>(address_space)}, no_core{0, 0};
    if (!kAddressSanitizer) ::setrlimit(RLIMIT_AS, &limit);
    ::setrlimit(RLIMIT_CORE, &no_core);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, STDERR_FILENO);
}

std::string failure_of(const ChildReading& reading, std::uint64_t address_space) {
    try {
        reading();
    } catch (const std::bad_alloc&) {
        return "reading it needs more than " + std::to_string(address_space >> 20) +
               " MiB (OpenVDB's reader allocates without bound on a corrupt or truncated file)";
    } catch (const std::exception& e) {
        return std::string("not a readable .vdb file (") + e.what() + ")";
    }
    return {};
}

void probe_vdb_in_child(const std::filesystem::path& path) {
    openvdb::initialize();
    const std::uintmax_t bytes = file_bytes(path);
    const unsigned cpu_seconds = reading_cpu_seconds(bytes);
    run_in_child(
        path,
        [&] {
            openvdb::io::File file(path.string());
            file.open(/*delayLoad=*/false);
            file.getGrids();
            file.close();
        },
        {memory_limit(bytes), cpu_seconds, blocked_wall_seconds(cpu_seconds)});
}

void probe_vdb_topology_in_child(const std::filesystem::path& path, const ChildReading& read_topology) {
    openvdb::initialize();
    const std::uintmax_t bytes = file_bytes(path);
    // The file is mapped whole (delayed loading): its size counts in the address space.
    const rlim_t limit = process_memory_now().address_space + static_cast<rlim_t>(bytes) + memory_limit(bytes / 16);
    const unsigned cpu_seconds = reading_cpu_seconds(bytes / 16);
    run_in_child(path, read_topology, {limit, cpu_seconds, blocked_wall_seconds(cpu_seconds)});
}

}  // namespace vdbmesh::detail
