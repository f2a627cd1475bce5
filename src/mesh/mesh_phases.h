#pragma once
// Private: timing the phases of a mesher into its MeshReport.

#include <chrono>
#include <string>

#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

/// Adds @a seconds to the phase @a name of @a report, appending the phase at its first use
/// (a phase run in every round of a loop is reported once, with its total).
inline void add_phase_seconds(MeshReport& report, const std::string& name, double seconds) {
    for (MeshPhase& phase : report.phases) {
        if (phase.name == name) {
            phase.seconds += seconds;
            return;
        }
    }
    report.phases.push_back({name, seconds});
}

/// Wall time since construction or the last lap().
class PhaseClock {
public:
    /// Seconds since the last lap (or construction), restarting the count.
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double seconds = std::chrono::duration<double>(now - start_).count();
        start_ = now;
        return seconds;
    }
    /// Adds the lap to the phase @a name of @a report.
    void lap(MeshReport& report, const std::string& name) { add_phase_seconds(report, name, lap()); }

private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace vdbmesh::detail
