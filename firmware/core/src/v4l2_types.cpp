#include "handscan/core/v4l2_types.hpp"

namespace handscan {

std::string fourccName(std::uint32_t code) {
    std::string s(4, '?');
    for (int i = 0; i < 4; ++i) {
        const char c = static_cast<char>((code >> (8 * i)) & 0xFF);
        if (c >= 0x20 && c < 0x7F) s[static_cast<std::size_t>(i)] = c;
    }
    return s;
}

}  // namespace handscan
