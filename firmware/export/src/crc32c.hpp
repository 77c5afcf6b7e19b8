// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78), the checksum that ends every 1024-byte
// page of an E57 file (ASTM E2807). Uses the CPU's CRC32 instruction when there is one (SSE4.2 on
// x86-64, the CRC extension on ARMv8), a slicing-by-8 table otherwise.
#pragma once

#include <cstdint>
#include <span>

namespace handscan::exporter {

// crc32c(crc32c(a), b) == crc32c(a + b); start with 0.
std::uint32_t crc32c(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

}  // namespace handscan::exporter
