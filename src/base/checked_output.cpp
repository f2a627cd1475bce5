#include "vdbmesh/checked_output.h"

#include <cerrno>
#include <cstring>
#include <string>

#include "vdbmesh/error.h"

namespace vdbmesh {

namespace {

[[noreturn]] void fail(const std::filesystem::path& target, const std::string& what) {
    throw Error(target.string() + ": " + what + " (" + std::strerror(errno) + ")");
}

}  // namespace

CheckedOutput::CheckedOutput(std::filesystem::path target)
    : target_(std::move(target)), file_(target_), out_(file_.temp_path(), std::ios::binary) {
    if (!out_) fail(target_, "cannot create the file");
}

void CheckedOutput::commit() {
    out_.flush();
    if (!out_) fail(target_, "cannot write the file");
    out_.close();
    if (!out_) fail(target_, "cannot finish writing the file");
    file_.commit();
}

}  // namespace vdbmesh
