#pragma once
/// @file error.h
/// @brief The exceptions vdbmesh throws. The library never prints; callers decide.

#include <stdexcept>
#include <string>

namespace vdbmesh {

/// @brief A runtime failure (I/O, bad data). The command-line tool exits with status 1.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// @brief Input that does not match its format. The message names the file, the
/// field, the expected and the actual value: "scan.nii: dim[1]: expected > 0, got -3".
class FormatError : public Error {
public:
    FormatError(const std::string& file, const std::string& field, const std::string& expected,
                const std::string& actual)
        : Error(file + ": " + field + ": expected " + expected + ", got " + actual) {}
    /// A free-form message (still prefixed with the file).
    FormatError(const std::string& file, const std::string& message) : Error(file + ": " + message) {}
};

/// @brief A bad command line or option value. The command-line tool exits with status 2.
class UsageError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

}  // namespace vdbmesh
