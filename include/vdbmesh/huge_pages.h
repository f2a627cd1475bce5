#pragma once
/// @file huge_pages.h
/// @brief Large arrays first touched with few page faults, for the meshers' outputs (DC's weld,
/// the shared trees' flat meshes). A fresh array of tens of MB costs one page fault per 4 KB
/// page when first written; on virtual machines each fault is dear (the DC weld's arrays,
/// about 100 MB for the bunny CT, spent half its time in them). Backed by transparent huge
/// pages, the same array costs one fault per 2 MB. In vdbmesh::detail: shared between the
/// stages, not a stable API.

#include <cstddef>
#include <vector>

namespace vdbmesh::detail {

/// Asks the kernel to back the whole 2 MB pages within [data, data + bytes) by huge pages
/// when they are first touched: what transparent huge pages in "madvise" mode (the default of
/// many distributions) need. Nothing where the kernel does not support it.
void advise_huge_pages(void* data, std::size_t bytes);

/// Asks the kernel to back the whole 4 KB pages within [data, data + bytes) now, zeroed,
/// without writing them (MADV_POPULATE_WRITE, Linux 5.14): the page faults of a fresh array
/// taken ahead, by the calling thread. Nothing where the kernel does not support it (the
/// pages are then faulted when first written).
void populate_pages(void* data, std::size_t bytes);

/// Reserves room for @a count elements in @a v (empty), advised as above, before any is
/// written.
template <class T>
void reserve_on_huge_pages(std::vector<T>& v, std::size_t count) {
    v.reserve(count);
    advise_huge_pages(v.data(), count * sizeof(T));
}

}  // namespace vdbmesh::detail
