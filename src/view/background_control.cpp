#include "vdbmesh/background_control.h"

#include <string>

#include "vdbmesh/error.h"

namespace vdbmesh {

void BackgroundControl::checkpoint(const char* what) const {
    if (!stopped_ && paused_until_.load(std::memory_order_acquire) == 0) return;  // the usual case: no lock
    std::unique_lock<std::mutex> lock(mutex_);
    bool counted = false;
    for (;;) {
        if (stopped_) throw Error(std::string(what) + " was stopped");
        Clock::rep end = paused_until_.load();
        const Clock::time_point until{Clock::duration(end)};
        if (end == 0) return;
        if (Clock::now() >= until) {
            paused_until_.compare_exchange_strong(end, 0);  // over: the next checkpoints take no lock
            return;
        }
        if (!counted) ++waits_;
        counted = true;
        wake_.wait_until(lock, until);
    }
}

void BackgroundControl::stop() {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
    wake_.notify_all();
}

void BackgroundControl::pause_until(Clock::time_point until) {
    const std::lock_guard<std::mutex> lock(mutex_);
    paused_until_ = until.time_since_epoch().count();
    wake_.notify_all();
}

}  // namespace vdbmesh
