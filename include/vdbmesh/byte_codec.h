#pragma once
/// @file byte_codec.h
/// @brief Values as their bytes in a string and back (memory images of trivially copyable
/// types), shared by the stages whose bytes stay within one build of the program (a rank's
/// messages, the mesher's spill) or whose file format fixes the layout (the splat file).

#include <cstddef>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace vdbmesh::detail {

template <typename T>
void append_value(std::string& out, const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
void append_values(std::string& out, const T* values, std::size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.append(reinterpret_cast<const char*>(values), count * sizeof(T));
}

template <typename T>
void append_values(std::string& out, const std::vector<T>& values) {
    append_values(out, values.data(), values.size());
}

template <typename T>
std::string bytes_of(const std::vector<T>& values) {
    std::string bytes;
    append_values(bytes, values);
    return bytes;
}

/// The value whose bytes start at @a at (the caller has checked that they are there); @a at
/// moves past them.
template <typename T>
T read_value(const std::string& in, std::size_t& at) {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, in.data() + at, sizeof(T));
    at += sizeof(T);
    return value;
}

/// The whole values in @a bytes.
template <typename T>
std::vector<T> values_of(const std::string& bytes) {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<T> values(bytes.size() / sizeof(T));
    if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
    return values;
}

}  // namespace vdbmesh::detail
