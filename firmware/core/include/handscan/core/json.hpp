// JSON text, written with Debian's nlohmann-json: the one JSON writer of the tree (stats.json,
// scan.json, the decoders' lines, the UI's status dump, journal metadata). Object keys keep their
// insertion order, so files read as their writers list them.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace handscan {

using Json = nlohmann::ordered_json;

// The text of `j` (indent < 0: one line). Strings from devices may hold bytes that are not UTF-8
// (a corrupt reply, a serial number): they are replaced by U+FFFD instead of failing the whole
// document. NaN and infinities are written as null (JSON has neither).
inline std::string jsonText(const Json& j, int indent = -1) {
    return j.dump(indent, ' ', false, Json::error_handler_t::replace);
}

// A JSON string literal (quotes included) for writers that assemble a line field by field.
inline std::string jsonString(std::string_view s) { return jsonText(Json(s)); }

}  // namespace handscan
