#pragma once
// Shared by the stream tests (check, measure, section --memory; issue 28): a limit too small
// is refused with a message naming the smallest limit that works.

#include <gtest/gtest.h>

#include <cstdint>
#include <regex>
#include <string>

#include "vdbmesh/error.h"

namespace vdbmesh::test {

/// A --memory limit (256 MiB) that the stream tests' meshes never reach.
inline constexpr std::uint64_t kPlenty = std::uint64_t(256) << 20;

/// Runs @a run at a limit of 1 MiB, which must throw UsageError naming "the smallest limit
/// that works is N M", and at N - 1 MiB, which must throw too; returns N MiB in bytes, or 0
/// after a test failure. @a message receives the first refusal's text when given.
template <class Run>
std::uint64_t smallest_limit_named(const Run& run, std::string* message = nullptr) {
    constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
    std::string text;
    try {
        run(kMiB);
        ADD_FAILURE() << "1M accepted";
        return 0;
    } catch (const UsageError& e) {
        text = e.what();
    }
    if (message) *message = text;
    std::smatch match;
    if (!std::regex_search(text, match, std::regex("smallest limit that works is ([0-9]+)M"))) {
        ADD_FAILURE() << text;
        return 0;
    }
    const std::uint64_t smallest = std::stoull(match[1]) * kMiB;
    EXPECT_THROW(run(smallest - kMiB), UsageError);
    return smallest;
}

}  // namespace vdbmesh::test
