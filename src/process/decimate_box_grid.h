#pragma once
// Private to the decimator (decimate_*.cpp): the grids that find the boxes meeting a box
// (or what all those near a box have in common), and boxes in columns for the exact tests.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "process/decimate_facing.h"

namespace vdbmesh::detail::decimation {

constexpr std::size_t kCellsPerBox = 8;  ///< a grid has at most about this many cells per box
constexpr double kCellEdges = 1;       ///< triangle grid cell size in mean triangle extents

/// Boxes with payloads (what a query needs of each, and a Summary) in a uniform grid, each in
/// the cell of its low corner (one larger than a cell: in every cell it meets), for finding the
/// boxes that meet a box, or what all those near a box have in common. Built at once and
/// read-only after.
template <class Payload>
class BoxGrid {
public:
    /// The boxes box_of(i) with payloads payload_of(i), i < @a count, but the empty ones
    /// (lo > hi), in cells of kCellEdges mean extents, made at least the largest extent of 99% of
    /// the boxes, and coarser where the boxes are spread thin (at most about eight cells per box).
    /// @a domain: the box the cells cover, when given (a box out of it is kept in the cells at
    /// its rim, and queries clamp the same way); else the boxes' box.
    template <class BoxOf, class PayloadOf>
    void build(std::size_t count, BoxOf&& box_of, PayloadOf&& payload_of, const Box* domain = nullptr) {
        struct Bounds {
            Box box = empty_box();
            std::size_t boxes = 0;  ///< not empty
        };
        const Bounds bounds = domain ? Bounds{*domain, count} : tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, count, 16384), Bounds{},
            [&](const auto& range, Bounds bounds) {
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    const Box b = box_of(i);
                    if (!holds_nothing(b)) grow(bounds.box, b.lo), grow(bounds.box, b.hi), ++bounds.boxes;
                }
                return bounds;
            },
            [](Bounds a, const Bounds& b) { return grow(a.box, b.box.lo), grow(a.box, b.box.hi), a.boxes += b.boxes, a; });
        // (the extents of a regular sample: the cell size sets only the speed of the queries)
        constexpr std::size_t kExtentSamples = 65536;
        std::vector<float> extents;
        for (std::size_t i = 0; i < count; i += std::max<std::size_t>(1, count / kExtentSamples)) {
            const Box& b = box_of(i);
            if (!holds_nothing(b)) extents.push_back(std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]}));
        }
        double cell = extents.empty() ? 0 : kCellEdges * std::accumulate(extents.begin(), extents.end(), 0.0) / double(extents.size());
        if (!extents.empty()) {
            const auto most = extents.begin() + std::ptrdiff_t(std::size_t(0.99 * double(extents.size() - 1)));
            std::nth_element(extents.begin(), most, extents.end());
            cell = std::max(cell, double(*most));
        }
        cell_ = cell > 0 ? cell : 1;
        const bool none = bounds.boxes == 0;
        for (;;) {
            std::uint64_t cells = 1;
            for (int k = 0; k < 3; ++k) {
                origin_[k] = none ? 0 : bounds.box.lo[k];
                dims_[k] = none ? 1 : std::int64_t(std::floor((double(bounds.box.hi[k]) - origin_[k]) / cell_)) + 1;
                cells *= std::uint64_t(dims_[k]);
            }
            if (cells <= kCellsPerBox * bounds.boxes + 64) break;
            cell_ *= 1.25;
        }
        const std::size_t cells = std::size_t(dims_[0] * dims_[1] * dims_[2]);
        // A counting sort by cell: start_[c] counts up to the end of cell c, then down to its
        // start as its boxes are put in (from the last), so a cell keeps them in order.
        start_.assign(cells + 1, 0);
        // The cell of each box of a cell or less (found once, in parallel); kLarge for larger
        // ones, kNone for empty ones.
        constexpr std::uint32_t kLarge = kNone - 1;
        cell_of_.resize(count);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 8192), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                const Box& b = box_of(i);
                cell_of_[i] = holds_nothing(b) ? kNone : small(b) ? std::uint32_t(index(cell_coordinates(b.lo))) : kLarge;
            }
        });
        for (std::size_t i = 0; i < count; ++i) {
            if (cell_of_[i] < kLarge) ++start_[cell_of_[i]];
            else if (cell_of_[i] == kLarge) for_cells(box_of(i), [&](std::size_t c) { ++start_[c]; });
        }
        for (std::size_t c = 1; c <= cells; ++c) start_[c] += start_[c - 1];
        entries_.resize(start_[cells]);
        for (std::size_t i = count; i-- > 0;) {
            if (cell_of_[i] == kNone) continue;
            const Box& b = box_of(i);
            const auto put = [&](std::size_t c) {
                const std::uint32_t at = --start_[c];
                entries_[at] = {b, payload_of(i)};
            };
            if (cell_of_[i] != kLarge) put(cell_of_[i]);
            else for_cells(b, put);
        }
        // Each cell's summary at its first entry.
        summaries_.resize(start_[cells]);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 65536), [&](const auto& range) {
            for (std::size_t c = range.begin(); c != range.end(); ++c) {
                if (start_[c] == start_[c + 1]) continue;
                Summary common;
                for (std::uint32_t i = start_[c]; i < start_[c + 1]; ++i) common.add(entries_[i].payload.summary);
                summaries_[start_[c]] = common;
            }
        });
    }

    bool empty() const { return start_.empty(); }  ///< never built

    /// What the payloads of the boxes that meet @a box have in common (their summaries), with
    /// more (those of the cells visit() passes over).
    Summary summary(const Box& box) const {
        assert(summaries_.size() == entries_.size());
        Summary common;
        for_query_rows(box, [&](std::size_t first, std::size_t last) {
            for (std::size_t c = first; c <= last; ++c) {
                if (start_[c] != start_[c + 1]) common.add(summaries_[start_[c]]);
            }
            return true;
        });
        return common;
    }

    /// Calls visit(payload, box) for each entry whose box meets @a box (one larger than a cell may
    /// come more than once); stops when visit returns false. Returns whether it went through.
    template <class Visit>
    bool visit(const Box& box, Visit&& visit) const {
        return for_query_rows(box, [&](std::size_t first, std::size_t last) {
            for (std::uint32_t i = start_[first]; i < start_[last + 1]; ++i) {
                if (detail::boxes_overlap(entries_[i].box, box) && !visit(entries_[i].payload, entries_[i].box)) return false;
            }
            return true;
        });
    }

private:
    /// Calls rows(first, last) for each row of cells [first, last] that may hold a box meeting
    /// @a box, until it returns false; returns whether it went through. A box of a cell or less
    /// that meets @a box has its low corner in [box.lo - cell, box.hi], so in the cells from the
    /// one before box.lo's; a larger one is in the cells of a point they share.
    template <class Rows>
    bool for_query_rows(const Box& box, Rows&& rows) const {
        std::array<std::int64_t, 3> from = cell_coordinates(box.lo);
        for (std::int64_t& c : from) c = std::max<std::int64_t>(c - 1, 0);
        const std::array<std::int64_t, 3> to = cell_coordinates(box.hi);
        for (std::int64_t z = from[2]; z <= to[2]; ++z) {
            for (std::int64_t y = from[1]; y <= to[1]; ++y) {
                const std::size_t row = index({0, y, z});
                if (!rows(row + std::size_t(from[0]), row + std::size_t(to[0]))) return false;
            }
        }
        return true;
    }

    /// Calls call(cell) for each cell a box larger than a cell meets (a smaller box is kept in
    /// the cell of its low corner alone).
    template <class Call>
    void for_cells(const Box& box, Call&& call) const {
        const std::array<std::int64_t, 3> from = cell_coordinates(box.lo);
        const std::array<std::int64_t, 3> to = cell_coordinates(box.hi);
        for (std::int64_t z = from[2]; z <= to[2]; ++z) {
            for (std::int64_t y = from[1]; y <= to[1]; ++y) {
                for (std::int64_t x = from[0]; x <= to[0]; ++x) call(index({x, y, z}));
            }
        }
    }

    bool small(const Box& box) const {
        bool small = true;
        for (int k = 0; k < 3; ++k) small &= double(box.hi[k]) - box.lo[k] <= cell_;
        return small;
    }

    std::array<std::int64_t, 3> cell_coordinates(const std::array<float, 3>& p) const {
        std::array<std::int64_t, 3> c{};
        for (int k = 0; k < 3; ++k) {
            const double x = std::floor((double(p[k]) - origin_[k]) / cell_);
            c[k] = x < 0 ? 0 : x >= double(dims_[k]) ? dims_[k] - 1 : std::int64_t(x);
        }
        return c;
    }
    std::size_t index(const std::array<std::int64_t, 3>& c) const { return std::size_t(c[0] + dims_[0] * (c[1] + dims_[1] * c[2])); }

    double cell_ = 1;
    std::array<double, 3> origin_{};
    std::array<std::int64_t, 3> dims_{1, 1, 1};
    std::vector<std::uint32_t> start_;  ///< entries of cell c: [start_[c], start_[c + 1])
    struct Entry {
        Box box;
        Payload payload;
    };
    std::vector<Entry> entries_;      ///< by cell (a box beside its payload: one line to write when built)
    std::vector<Summary> summaries_;  ///< each cell's at its first entry
    std::vector<std::uint32_t> cell_of_;  ///< (build()'s, kept for its memory)
};

/// Boxes in columns, to find at once which of them meet a box (without a branch per box).
class BoxColumns {
public:
    void assign(const std::vector<Box>& boxes) {
        for (int k = 0; k < 3; ++k) {
            lo_[k].resize(boxes.size()), hi_[k].resize(boxes.size());
            for (std::size_t i = 0; i < boxes.size(); ++i) lo_[k][i] = boxes[i].lo[k], hi_[k][i] = boxes[i].hi[k];
        }
    }

    /// Calls call(i) for each box i that meets @a box, in order, until it returns false;
    /// returns whether it went through.
    template <class Call>
    bool for_meeting(const Box& box, Call&& call) const {
        const std::size_t size = lo_[0].size();
        for (std::size_t base = 0; base < size; base += 64) {
            const std::size_t count = std::min<std::size_t>(64, size - base);
            std::uint64_t meeting = 0;
            for (std::size_t i = 0; i < count; ++i) {
                const std::size_t j = base + i;
                const bool meets = (lo_[0][j] <= box.hi[0]) & (box.lo[0] <= hi_[0][j]) & (lo_[1][j] <= box.hi[1]) &
                                   (box.lo[1] <= hi_[1][j]) & (lo_[2][j] <= box.hi[2]) & (box.lo[2] <= hi_[2][j]);
                meeting |= std::uint64_t(meets) << i;
            }
            for (; meeting != 0; meeting &= meeting - 1) {
                if (!call(base + std::size_t(__builtin_ctzll(meeting)))) return false;
            }
        }
        return true;
    }

private:
    std::array<std::vector<float>, 3> lo_, hi_;
};


}  // namespace vdbmesh::detail::decimation
