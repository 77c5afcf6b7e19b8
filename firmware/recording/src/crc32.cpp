#include "handscan/recording/crc32.hpp"

#include <zlib.h>

namespace handscan::recording {

// zlib's crc32_z is this CRC (it keeps the pre- and post-inversion inside) and takes size_t
// lengths; an empty span must not reach it with a null pointer (it would restart from 0).
void Crc32::update(std::span<const std::uint8_t> bytes) {
    if (bytes.empty()) return;
    value_ = static_cast<std::uint32_t>(::crc32_z(value_, bytes.data(), bytes.size()));
}

std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
    Crc32 c;
    c.update(bytes);
    return c.value();
}

}  // namespace handscan::recording
