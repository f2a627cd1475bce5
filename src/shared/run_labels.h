#pragma once
// Private: plain (voxel by voxel, nothing shared) labelling of the 6-connected inside voxels of a
// box: runs of inside voxels along z, line by line; runs of neighbouring lines that overlap in z
// are one component. The references the shared labelling is compared with.

#include <tbb/parallel_for.h>

#include <cstdint>
#include <vector>

namespace vdbmesh::detail {

/// Inclusive, in box coordinates.
struct ZRun {
    int z0, z1;
};

/// The inside voxels of an nx * ny * nz box as runs along z; line (x, y) at x * ny + y.
struct BoxRuns {
    int nx = 0, ny = 0, nz = 0;
    std::vector<std::vector<ZRun>> lines;
};

/// The runs of the voxels (x, y, z) (box coordinates) for which inside(x, y, z), inside being
/// what make_inside() returns: one per task (an accessor may live in it), tasks in parallel over x.
template <class MakeInside>
BoxRuns collect_runs(int nx, int ny, int nz, const MakeInside& make_inside) {
    BoxRuns out{nx, ny, nz, {}};
    if (nx <= 0 || ny <= 0 || nz <= 0) return out;
    out.lines.resize(std::size_t(nx) * std::size_t(ny));
    tbb::parallel_for(0, nx, [&](int x) {
        auto inside = make_inside();
        for (int y = 0; y < ny; ++y) {
            auto& runs = out.lines[std::size_t(x) * ny + y];
            int start = -1;
            for (int z = 0; z <= nz; ++z) {
                const bool in = z < nz && inside(x, y, z);
                if (in && start < 0) start = z;
                if (!in && start >= 0) {
                    runs.push_back({start, z - 1});
                    start = -1;
                }
            }
        }
    });
    return out;
}

/// The components of a box's runs.
struct RunLabels {
    std::uint32_t count = 0;
    std::vector<std::uint32_t> first;  ///< per line: the index of its first run; one more entry at the end
    std::vector<std::uint32_t> label;  ///< per run: 0..count-1 in order of each component's first run
    /// The label of voxel (x, y, z) of @a runs, or -1 when it is not inside.
    std::int64_t at(const BoxRuns& runs, int x, int y, int z) const;
    /// Inside voxels per component.
    std::vector<std::uint64_t> voxels(const BoxRuns& runs) const;
};

/// @a periodic: each face of the box also touches the opposite one (the box extended periodically).
RunLabels label_runs(const BoxRuns& runs, bool periodic);

}  // namespace vdbmesh::detail
