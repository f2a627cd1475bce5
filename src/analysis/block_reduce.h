#pragma once
// Private: a parallel reduction whose result does not depend on the thread count: the range
// is cut into fixed blocks, each reduced in parallel, and the blocks combined in order.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
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

}  // namespace vdbmesh::detail
