#pragma once
// Private: sorting more records than memory holds, for the bounded `vdbmesh check` (issue 28).
// Records are gathered into runs of a fixed size; each full run is sorted in memory (TBB's
// parallel sort) and written to an unlinked temporary file; merge() then reads the runs back
// through one buffer each and hands every record out in order (a k-way merge on a heap). When
// all records fit in one run nothing is written. Records must be totally ordered by operator<
// (records that compare equal are identical), so the order handed out is the same for any
// thread count. A sorted run may be shrunk before it is written (CombineRun: records that
// one can stand for, such as the uses of one edge counted together).

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <queue>
#include <type_traits>
#include <vector>

#include "vdbmesh/temp_file.h"

namespace vdbmesh::detail {

/// Writes a sorted run as it is.
struct KeepRun {
    template <class Record>
    void operator()(std::vector<Record>&) const {}
};

template <class Record, class CombineRun = KeepRun>
class ExternalSorter {
    static_assert(std::is_trivially_copyable_v<Record>, "records are written to a file as bytes");

public:
    /// Runs of @a run_records records; merge() reads them back in buffers of that many in all.
    explicit ExternalSorter(std::size_t run_records) : run_records_(std::max<std::size_t>(run_records, 1)) {}

    void add(const Record& record) {
        if (buffer_.size() == run_records_) spill();
        if (buffer_.capacity() == 0) buffer_.reserve(run_records_);
        buffer_.push_back(record);
        ++count_;
    }
    std::uint64_t size() const { return count_; }
    /// Sorted runs written to the file so far (0 while everything fits in one run).
    std::size_t runs() const { return runs_.size(); }

    /// Calls @a visit(record) for every record added, in order; the sorter is empty after.
    template <class Visit>
    void merge(Visit&& visit) {
        if (runs_.empty()) {
            tbb::parallel_sort(buffer_.begin(), buffer_.end());
            for (const Record& record : buffer_) visit(record);
        } else {
            if (!buffer_.empty()) spill();
            std::vector<Record>().swap(buffer_);
            merge_runs(visit);
        }
        std::vector<Record>().swap(buffer_);
        runs_.clear();
        file_.reset();
        count_ = 0;
    }

private:
    struct Run {
        std::uint64_t offset, count;  ///< in records
    };
    /// A run being merged: its next records in a buffer.
    struct Cursor {
        Run run;
        std::vector<Record> buffer;
        std::size_t next = 0;
    };

    void spill() {
        tbb::parallel_sort(buffer_.begin(), buffer_.end());
        CombineRun()(buffer_);
        if (!file_) file_.emplace("for sorting");
        runs_.push_back({file_->size() / sizeof(Record), buffer_.size()});
        file_->append(buffer_.data(), buffer_.size() * sizeof(Record));
        buffer_.clear();
    }

    /// Refills @a cursor's buffer from its run; false when the run is used up.
    bool refill(Cursor& cursor, std::size_t per_run) const {
        if (cursor.run.count == 0) return false;
        const std::size_t n = std::size_t(std::min<std::uint64_t>(per_run, cursor.run.count));
        cursor.buffer.resize(n);
        file_->read(cursor.run.offset * sizeof(Record), cursor.buffer.data(), n * sizeof(Record));
        cursor.run.offset += n, cursor.run.count -= n;
        cursor.next = 0;
        return true;
    }

    template <class Visit>
    void merge_runs(Visit& visit) {
        const std::size_t per_run = std::max<std::size_t>(run_records_ / runs_.size(), 1);
        std::vector<Cursor> cursors(runs_.size());
        using Head = std::pair<Record, std::size_t>;  // a run's smallest record left, and the run
        const auto later = [](const Head& a, const Head& b) { return b.first < a.first; };
        std::priority_queue<Head, std::vector<Head>, decltype(later)> heads(later);
        for (std::size_t r = 0; r < runs_.size(); ++r) {
            cursors[r].run = runs_[r];
            if (refill(cursors[r], per_run)) heads.push({cursors[r].buffer[0], r});
        }
        while (!heads.empty()) {
            const Head head = heads.top();
            heads.pop();
            visit(head.first);
            Cursor& cursor = cursors[head.second];
            if (++cursor.next < cursor.buffer.size() || refill(cursor, per_run)) {
                heads.push({cursor.buffer[cursor.next], head.second});
            }
        }
    }

    std::size_t run_records_;
    std::vector<Record> buffer_;
    std::vector<Run> runs_;
    std::optional<TempFile> file_;
    std::uint64_t count_ = 0;
};

}  // namespace vdbmesh::detail
