#pragma once
/// @file background_control.h
/// @brief The word of `vdbmesh view`'s server to its background work (the scan's preparation,
/// the splat tree's fit): stop for good (the server closes), or pause for a while (the page's
/// camera moves: the machine's cores go to the browser's drawing, issue 30's frame time).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace vdbmesh {

class BackgroundControl {
public:
    using Clock = std::chrono::steady_clock;

    /// Called by the work between its pieces (each a fraction of a second): returns at once
    /// unless paused; while paused waits, using no CPU, until the pause ends; once stopped
    /// throws Error(@a what + " was stopped"), a paused work at once.
    void checkpoint(const char* what) const;
    /// For good: every checkpoint throws from now on.
    void stop();
    bool stopped() const { return stopped_; }
    /// Pauses the work at its next checkpoint until @a until (a later end replaces it). A pause
    /// always ends by itself: a page that goes away while its camera moves holds nothing.
    void pause_until(Clock::time_point until);
    /// Ends the pause now.
    void resume() { pause_until(Clock::time_point{}); }
    /// How many checkpoints have waited for a pause to end (figures and tests).
    std::uint64_t waits() const { return waits_; }

private:
    mutable std::mutex mutex_;
    mutable std::condition_variable wake_;
    std::atomic<bool> stopped_{false};
    /// The pause's end (Clock's ticks), 0 when none: read without the lock at each checkpoint.
    mutable std::atomic<Clock::rep> paused_until_{0};
    mutable std::atomic<std::uint64_t> waits_{0};
};

}  // namespace vdbmesh
