// The child only opens the file with io::File and reads all grids (no TBB work, which would
// not be safe after fork()), then reports through a pipe: nothing on success, else the text of
// the exception. The parent turns a signal, a failed allocation or that text into a FormatError.

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

namespace vdbmesh::detail {

namespace {

rlim_t memory_limit(std::uintmax_t file_bytes) {
    const auto physical = static_cast<rlim_t>(::sysconf(_SC_PHYS_PAGES)) * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE));
    const rlim_t wanted = std::max<rlim_t>(rlim_t{2} << 30, static_cast<rlim_t>(file_bytes) * 64);
    return physical > 0 ? std::min(wanted, physical) : wanted;
}

/// Seconds the child may take: generous for a sound file of any size.
unsigned time_limit(std::uintmax_t file_bytes) { return 30 + static_cast<unsigned>(file_bytes >> 24); }

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
/// the alarm ends it, a crash kills it, and the parent reports which.
void restore_default_signals() {
    for (const int signal : {SIGALRM, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::signal(signal, SIG_DFL);
    sigset_t alarm_only;
    sigemptyset(&alarm_only);
    sigaddset(&alarm_only, SIGALRM);
    ::sigprocmask(SIG_UNBLOCK, &alarm_only, nullptr);
}

[[noreturn]] void read_in_child(const std::filesystem::path& path, rlim_t limit, unsigned seconds, int report) {
    restore_default_signals();
    const rlimit address_space{limit, limit}, no_core{0, 0};
    if (!kAddressSanitizer) ::setrlimit(RLIMIT_AS, &address_space);
    ::setrlimit(RLIMIT_CORE, &no_core);
    // A reader that loops, or a child that blocks (a lock held by another thread of the parent
    // at fork()), ends by SIGALRM instead of hanging the parent.
    ::alarm(seconds);
    const int null = ::open("/dev/null", O_WRONLY);  // glibc's and OpenVDB's own complaints
    if (null >= 0) ::dup2(null, STDERR_FILENO);
    std::string failure;
    try {
        openvdb::io::File file(path.string());
        file.open(/*delayLoad=*/false);
        file.getGrids();
        file.close();
    } catch (const std::bad_alloc&) {
        failure = "reading it needs more than " + std::to_string(limit >> 20) +
                  " MiB (OpenVDB's reader allocates without bound on a corrupt or truncated file)";
    } catch (const std::exception& e) {
        failure = std::string("not a readable .vdb file (") + e.what() + ")";
    }
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

ChildOutcome read_once_in_child(const std::filesystem::path& path, rlim_t limit, unsigned seconds) {
    int report[2];
    if (::pipe2(report, O_CLOEXEC) != 0) throw Error(path.string() + ": cannot create a pipe to check the .vdb file");
    const pid_t child = ::fork();
    if (child == 0) {
        ::close(report[0]);
        read_in_child(path, limit, seconds, report[1]);
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

bool ended_by_alarm(const ChildOutcome& outcome) { return WIFSIGNALED(outcome.status) && WTERMSIG(outcome.status) == SIGALRM; }

}  // namespace

void probe_vdb_in_child(const std::filesystem::path& path) {
    openvdb::initialize();
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    const rlim_t limit = memory_limit(bytes);
    const unsigned seconds = time_limit(bytes);
    ChildOutcome outcome = read_once_in_child(path, limit, seconds);
    // A child can also block on a lock another thread of this process held at fork() (a fresh
    // small .vdb a test had just written timed out once in a CI run of the suite): a second
    // child, forked at another moment, tells that from a reader that loops on the file.
    if (ended_by_alarm(outcome)) outcome = read_once_in_child(path, limit, seconds);
    const int status = outcome.status;
    if (ended_by_alarm(outcome))
        throw FormatError(path.string(), "reading it did not finish in " + std::to_string(seconds) +
                                             " s, twice (OpenVDB's reader can loop on a corrupt file)");
    if (WIFSIGNALED(status))
        throw FormatError(path.string(), std::string("corrupt .vdb file: OpenVDB's reader crashed on it (") +
                                             ::strsignal(WTERMSIG(status)) + ")");
    if (WEXITSTATUS(status) != 0) throw FormatError(path.string(), outcome.failure.empty() ? "not a readable .vdb file" : outcome.failure);
}

}  // namespace vdbmesh::detail
