#pragma once
/// @file union_find.h
/// @brief Union-find over 0..n-1 whose roots are the smallest elements, so that the roots and
/// the labels it hands out follow element order (and so never depend on the order of the
/// unions). In vdbmesh::detail: shared between the stages, not a stable API.

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace vdbmesh::detail {

class UnionFind {
public:
    UnionFind() = default;
    explicit UnionFind(std::size_t n) { reset(n); }
    /// Back to @a n singletons, keeping the memory (for one set per item of a loop).
    void reset(std::size_t n) {
        parent_.resize(n);
        std::iota(parent_.begin(), parent_.end(), std::uint32_t(0));
    }
    std::uint32_t find(std::uint32_t x) {
        while (parent_[x] != x) {
            parent_[x] = parent_[parent_[x]];
            x = parent_[x];
        }
        return x;
    }
    /// Joins the sets of @a a and @a b; returns whether they were apart.
    bool unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return false;
        if (a < b) std::swap(a, b);
        parent_[a] = b;  // the smaller index is the root: labels follow element order
        return true;
    }
    /// Labels 0..count-1 in order of each component's first element.
    std::vector<std::uint32_t> labels(std::uint32_t& count) {
        std::vector<std::uint32_t> out(parent_.size());
        std::vector<std::uint32_t> of_root(parent_.size(), ~0u);
        count = 0;
        for (std::uint32_t i = 0; i < parent_.size(); ++i) {
            const std::uint32_t r = find(i);
            if (of_root[r] == ~0u) of_root[r] = count++;
            out[i] = of_root[r];
        }
        return out;
    }

private:
    std::vector<std::uint32_t> parent_;
};

}  // namespace vdbmesh::detail
