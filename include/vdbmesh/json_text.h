#pragma once
/// @file json_text.h
/// @brief JSON as text for every `--json` report and the viewer's API. A file name on Linux is
/// any bytes; JSON text must be UTF-8, and nlohmann's plain dump() throws on a name that is not,
/// after the command's work is done. Bytes that are not UTF-8 become U+FFFD instead. Header
/// only, for code that already uses nlohmann::json; in vdbmesh::detail, not a stable API.

#include <string>

namespace vdbmesh::detail {

/// @a value (nlohmann::json or ordered_json) as JSON text, @a indent as dump() takes it.
template <class Json>
std::string json_text(const Json& value, int indent = -1) {
    return value.dump(indent, ' ', false, Json::error_handler_t::replace);
}

}  // namespace vdbmesh::detail
