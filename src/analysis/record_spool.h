#pragma once
// Private: records kept in the order they come, more than memory holds (the bounded measure's
// per-triangle sums): gathered in a buffer, each full buffer appended to an unlinked temporary
// file, read back in order through a second buffer of the same size. Nothing is written while
// all fit in one.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <vector>

#include "vdbmesh/temp_file.h"

namespace vdbmesh::detail {

template <class Record>
class RecordSpool {
    static_assert(std::is_trivially_copyable_v<Record>, "records are written to a file as bytes");

public:
    /// The buffer's size in bytes: what a spool holds in memory.
    static constexpr std::size_t kBufferBytes = std::size_t(1) << 20;

    void add(const Record& record) {
        if (buffer_.size() == kBufferRecords) flush();
        if (buffer_.capacity() == 0) buffer_.reserve(kBufferRecords);
        buffer_.push_back(record);
    }
    std::uint64_t size() const { return written_ + buffer_.size(); }
    /// The records added, in order, one a call (size() calls in all, after the last add()).
    Record next() {
        if (next_ == chunk_.size()) refill();
        return chunk_[next_++];
    }

private:
    static constexpr std::size_t kBufferRecords = std::max<std::size_t>(kBufferBytes / sizeof(Record), 1);

    void flush() {
        if (!file_) file_.emplace("for the measure's sums");
        file_->append(buffer_.data(), buffer_.size() * sizeof(Record));
        written_ += buffer_.size();
        buffer_.clear();
    }
    /// The next chunk: from the file while it lasts, then the buffer's records.
    void refill() {
        next_ = 0;
        if (read_ < written_) {
            chunk_.resize(std::size_t(std::min<std::uint64_t>(kBufferRecords, written_ - read_)));
            file_->read(read_ * sizeof(Record), chunk_.data(), chunk_.size() * sizeof(Record));
            read_ += chunk_.size();
        } else {
            chunk_.swap(buffer_);
            buffer_.clear();
            buffer_.shrink_to_fit();
        }
    }

    std::vector<Record> buffer_, chunk_;
    std::optional<TempFile> file_;
    std::uint64_t written_ = 0, read_ = 0;
    std::size_t next_ = 0;
};

}  // namespace vdbmesh::detail
