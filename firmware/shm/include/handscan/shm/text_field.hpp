// Fixed-size, NUL-terminated text fields of the shared-memory structs.
#pragma once

#include <cstddef>
#include <cstring>
#include <string_view>

namespace handscan::shm {

// Copies `text` into `field`, truncating so that a terminating NUL always fits.
template <std::size_t N>
void setText(char (&field)[N], std::string_view text) {
    const std::size_t n = text.size() < N - 1 ? text.size() : N - 1;
    if (n > 0) std::memcpy(field, text.data(), n);  // an empty view's data() may be null
    std::memset(field + n, 0, N - n);
}

// The text of a field, never reading past its end even if a writer left no NUL.
template <std::size_t N>
std::string_view getText(const char (&field)[N]) {
    const void* nul = std::memchr(field, 0, N);
    return {field, nul ? static_cast<std::size_t>(static_cast<const char*>(nul) - field) : N};
}

}  // namespace handscan::shm
