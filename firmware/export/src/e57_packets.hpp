// Data packets of an E57 compressed vector section (ASTM E2807 section 9.3): a 6-byte header
// (type 1, flags, logical length - 1, stream count), the byte length of each bytestream, then the
// bytestreams, one per field of the prototype in prototype order, padded to a multiple of 4.
// Every field here is stored with the bitpack codec at a fixed width per value (64 for doubles,
// 16/8/1 for integers), so a packet's size follows from its record count alone, and a section's
// size from the total: the section header can be written before the points stream through.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "e57_format.hpp"

namespace handscan::exporter::e57 {

constexpr std::size_t streamBytes(unsigned bits, std::size_t records) {
    return (bits * records + 7) / 8;
}

constexpr std::size_t packetBytes(std::span<const unsigned> bits, std::size_t records) {
    std::size_t n = kDataPacketHeaderBytes + 2 * bits.size();
    for (unsigned b : bits) n += streamBytes(b, records);
    return (n + 3) & ~std::size_t{3};
}

// Logical bytes of a whole section: its header and every packet of `per_packet` records.
inline std::uint64_t sectionBytes(std::span<const unsigned> bits, std::uint64_t records,
                                  std::size_t per_packet) {
    const std::uint64_t full = records / per_packet;
    const std::size_t rest = static_cast<std::size_t>(records % per_packet);
    return kSectionHeaderBytes + full * packetBytes(bits, per_packet) +
           (rest ? packetBytes(bits, rest) : 0);
}

// The 32-byte section header: id, reserved, logical length, first data packet, no index packet.
inline std::array<std::uint8_t, kSectionHeaderBytes> sectionHeader(std::uint64_t section_logical,
                                                                   std::uint64_t logical_length) {
    std::array<std::uint8_t, kSectionHeaderBytes> h{};
    h[0] = kSectionCompressedVector;
    putLe<std::uint64_t>(h.data() + 8, logical_length);
    putLe<std::uint64_t>(h.data() + 16, physicalOf(section_logical + kSectionHeaderBytes));
    putLe<std::uint64_t>(h.data() + 24, 0);  // index packets are optional (9.3.5): none
    return h;
}

// Lays out one packet of `records` records in `out` (resized, zeroed padding) and returns where
// each stream's bytes go.
template <std::size_t kStreams>
std::array<std::uint8_t*, kStreams> layOutPacket(std::vector<std::uint8_t>& out,
                                                 const std::array<unsigned, kStreams>& bits,
                                                 std::size_t records) {
    const std::size_t total = packetBytes(bits, records);
    out.resize(total);
    std::uint8_t* p = out.data();
    p[0] = kPacketData;
    p[1] = 0;  // flags: no compressor restart
    putLe<std::uint16_t>(p + 2, static_cast<std::uint16_t>(total - 1));
    putLe<std::uint16_t>(p + 4, static_cast<std::uint16_t>(kStreams));
    std::array<std::uint8_t*, kStreams> streams{};
    std::uint8_t* at = p + kDataPacketHeaderBytes + 2 * kStreams;
    for (std::size_t i = 0; i < kStreams; ++i) {
        const std::size_t n = streamBytes(bits[i], records);
        putLe<std::uint16_t>(p + kDataPacketHeaderBytes + 2 * i, static_cast<std::uint16_t>(n));
        streams[i] = at;
        at += n;
    }
    std::fill(at, p + total, std::uint8_t{0});
    return streams;
}

}  // namespace handscan::exporter::e57
