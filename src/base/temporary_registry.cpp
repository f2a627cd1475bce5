// A fixed table of paths that a signal handler can walk without allocating or locking: each
// slot is claimed with a compare-and-swap, filled, then published; the handler only reads
// published slots and calls async-signal-safe system calls (unlink, open, getdents64,
// unlinkat, rmdir, sigaction, raise).

#include "base/temporary_registry.h"

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

namespace vdbmesh::detail {

namespace {

enum SlotState : int { kFree, kFilling, kPublished };

struct Slot {
    std::atomic<int> state{kFree};
    char path[PATH_MAX];
};

std::array<Slot, 64> slots;

constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};

/// Deletes the files directly inside @a folder, then the folder itself.
void remove_flat_folder(const char* folder) {
    const int fd = ::open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    alignas(8) char buffer[4096];
    for (;;) {
        const long bytes = ::syscall(SYS_getdents64, fd, buffer, sizeof(buffer));
        if (bytes <= 0) break;
        for (long offset = 0; offset < bytes;) {
            // struct linux_dirent64: ino (8), off (8), reclen (2), type (1), name.
            unsigned short record_length;
            std::memcpy(&record_length, buffer + offset + 16, sizeof(record_length));
            const char* name = buffer + offset + 19;
            if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(fd, name, 0);
            offset += record_length;
        }
    }
    ::close(fd);
    ::rmdir(folder);
}

void remove_temporaries_and_die(int signal_number) {
    const int saved_errno = errno;
    for (Slot& slot : slots) {
        if (slot.state.load(std::memory_order_acquire) != kPublished) continue;
        if (::unlink(slot.path) != 0 && (errno == EISDIR || errno == EPERM)) remove_flat_folder(slot.path);
    }
    errno = saved_errno;
    ::raise(signal_number);  // the handler was installed with SA_RESETHAND: the default action ends the process
}

void install_handlers() {
    for (const int signal_number : kSignals) {
        struct sigaction current {};
        if (::sigaction(signal_number, nullptr, &current) != 0 || current.sa_handler != SIG_DFL) continue;
        struct sigaction action {};
        action.sa_handler = remove_temporaries_and_die;
        sigemptyset(&action.sa_mask);
        action.sa_flags = SA_RESETHAND | SA_NODEFER;
        ::sigaction(signal_number, &action, nullptr);
    }
}

}  // namespace

int remember_temporary(const std::filesystem::path& path) {
    static std::once_flag installed;
    std::call_once(installed, install_handlers);
    std::error_code ec;
    const std::string absolute = std::filesystem::absolute(path, ec).string();
    if (ec || absolute.size() >= PATH_MAX) return -1;
    for (int index = 0; index < static_cast<int>(slots.size()); ++index) {
        int expected = kFree;
        if (!slots[index].state.compare_exchange_strong(expected, kFilling)) continue;
        std::memcpy(slots[index].path, absolute.c_str(), absolute.size() + 1);
        slots[index].state.store(kPublished, std::memory_order_release);
        return index;
    }
    return -1;
}

void forget_temporary(int slot) {
    if (slot >= 0) slots[slot].state.store(kFree, std::memory_order_release);
}

}  // namespace vdbmesh::detail
