#pragma once
// Private: a parallel reduction whose result does not depend on the thread count: the range
// is cut into fixed blocks, each reduced in parallel, and the blocks combined in order.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace vdbmesh::detail {

/// reduce_block(begin, end) -> T for each block of @a block_size; combine(T&, const T&) in order.
template <class T, class ReduceBlock, class Combine>
T block_reduce(std::size_t count, std::size_t block_size, T initial, ReduceBlock reduce_block, Combine combine) {
    const std::size_t blocks = (count + block_size - 1) / block_size;
    std::vector<T> partial(blocks, initial);
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
        partial[b] = reduce_block(b * block_size, std::min(count, (b + 1) * block_size));
    });
    for (const T& value : partial) combine(initial, value);
    return initial;
}

/// Count, minimum, maximum, sum and sum of squares of a set of values, and how many of them
/// were flagged: the one accumulator of the figures analysis reduces (angles, distances).
struct ValueStats {
    std::size_t count = 0, flagged = 0;
    double min = std::numeric_limits<double>::infinity();
    double max = -std::numeric_limits<double>::infinity();
    double sum = 0, sum_squares = 0;

    void add(double value, bool flag = false) {
        ++count;
        flagged += flag;
        min = std::min(min, value);
        max = std::max(max, value);
        sum += value;
        sum_squares += value * value;
    }
    void merge(const ValueStats& other) {
        count += other.count;
        flagged += other.flagged;
        min = std::min(min, other.min);
        max = std::max(max, other.max);
        sum += other.sum;
        sum_squares += other.sum_squares;
    }
};

/// block_reduce() of a ValueStats: add_values(i, stats) adds the values of item i.
template <class AddValues>
ValueStats block_stats(std::size_t count, std::size_t block_size, AddValues add_values) {
    return block_reduce(
        count, block_size, ValueStats{},
        [&](std::size_t begin, std::size_t end) {
            ValueStats local;
            for (std::size_t i = begin; i < end; ++i) add_values(i, local);
            return local;
        },
        [](ValueStats& total, const ValueStats& block) { total.merge(block); });
}

}  // namespace vdbmesh::detail
