// JSON string literals for the decoders' output lines (quotes, backslashes, control bytes).
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace handscan::cli {

inline std::string jsonString(std::string_view s) {
    std::string o = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') {
            o += '\\';
            o += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char b[8];
            std::snprintf(b, sizeof b, "\\u%04x",
                          static_cast<unsigned>(static_cast<unsigned char>(c)));
            o += b;
        } else {
            o += c;
        }
    }
    return o + "\"";
}

}  // namespace handscan::cli
