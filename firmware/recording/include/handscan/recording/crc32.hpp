// CRC-32 (ISO-HDLC / zlib: reflected polynomial 0xEDB88320, init and final xor 0xFFFFFFFF), the
// checksum MCAP uses for chunks, the data section and the summary. Incremental so the writer can
// checksum the data section as it streams it out. Computed by zlib (crc32_z).
#pragma once

#include <cstdint>
#include <span>

namespace handscan::recording {

class Crc32 {
public:
    void update(std::span<const std::uint8_t> bytes);
    std::uint32_t value() const { return value_; }

private:
    std::uint32_t value_ = 0;  // zlib's running CRC of the bytes so far
};

std::uint32_t crc32(std::span<const std::uint8_t> bytes);

}  // namespace handscan::recording
