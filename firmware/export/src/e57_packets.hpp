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
#include <utility>
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

// Index packets (E2807 9.3.5): a 16-byte header (type 0, flags, logical length - 1, entry
// count, index level, 9 reserved bytes) and up to 2048 entries of (first record number, physical
// offset) of the data packets (level 0) or of the index packets one level down. They follow the
// data packets, level by level, the single top-level packet last; the section header points at
// it. A reader seeks a record through them without reading the packets before it.
constexpr std::size_t kIndexHeaderBytes = 16;
constexpr std::size_t kIndexEntryBytes = 16;
constexpr std::size_t kMaxIndexEntries = 2048;
static_assert(kIndexHeaderBytes + kMaxIndexEntries * kIndexEntryBytes <= kMaxPacketBytes);

// Entries per index level for `data_packets` data packets (level 0 first, the last has one
// packet's worth); empty when there are none.
inline std::vector<std::uint64_t> indexLevels(std::uint64_t data_packets) {
    std::vector<std::uint64_t> entries;
    for (std::uint64_t n = data_packets; n > 0;) {
        entries.push_back(n);
        if (n <= kMaxIndexEntries) break;
        n = (n + kMaxIndexEntries - 1) / kMaxIndexEntries;  // packets of this level
    }
    return entries;
}

inline std::uint64_t indexBytes(std::uint64_t data_packets) {
    std::uint64_t n = 0;
    for (std::uint64_t e : indexLevels(data_packets))
        n += ((e + kMaxIndexEntries - 1) / kMaxIndexEntries) * kIndexHeaderBytes +
             e * kIndexEntryBytes;
    return n;
}

// The index packet of `entries` (first record, physical offset) at `level`.
inline void indexPacket(std::vector<std::uint8_t>& out,
                        std::span<const std::pair<std::uint64_t, std::uint64_t>> entries,
                        std::uint8_t level) {
    out.assign(kIndexHeaderBytes + entries.size() * kIndexEntryBytes, 0);
    out[0] = kPacketIndex;
    putLe<std::uint16_t>(out.data() + 2, static_cast<std::uint16_t>(out.size() - 1));
    putLe<std::uint16_t>(out.data() + 4, static_cast<std::uint16_t>(entries.size()));
    out[6] = level;
    std::uint8_t* e = out.data() + kIndexHeaderBytes;
    for (const auto& [record, offset] : entries) {
        putLe<std::uint64_t>(e, record);
        putLe<std::uint64_t>(e + 8, offset);
        e += kIndexEntryBytes;
    }
}

inline std::uint64_t dataPackets(std::uint64_t records, std::size_t per_packet) {
    return (records + per_packet - 1) / per_packet;
}

// Logical bytes of a section's data packets of `per_packet` records each.
inline std::uint64_t dataBytes(std::span<const unsigned> bits, std::uint64_t records,
                               std::size_t per_packet) {
    const std::uint64_t full = records / per_packet;
    const std::size_t rest = static_cast<std::size_t>(records % per_packet);
    return full * packetBytes(bits, per_packet) + (rest ? packetBytes(bits, rest) : 0);
}

// Logical bytes of a whole section: its header, the data packets and their index.
inline std::uint64_t sectionBytes(std::span<const unsigned> bits, std::uint64_t records,
                                  std::size_t per_packet) {
    return kSectionHeaderBytes + dataBytes(bits, records, per_packet) +
           indexBytes(dataPackets(records, per_packet));
}

// The 32-byte section header: id, reserved, logical length, first data packet, top index packet
// (its size is known from the record count, so the header goes first).
inline std::array<std::uint8_t, kSectionHeaderBytes> sectionHeader(std::uint64_t section_logical,
                                                                   std::span<const unsigned> bits,
                                                                   std::uint64_t records,
                                                                   std::size_t per_packet) {
    std::array<std::uint8_t, kSectionHeaderBytes> h{};
    const std::uint64_t length = sectionBytes(bits, records, per_packet);
    const auto levels = indexLevels(dataPackets(records, per_packet));
    h[0] = kSectionCompressedVector;
    putLe<std::uint64_t>(h.data() + 8, length);
    putLe<std::uint64_t>(h.data() + 16, physicalOf(section_logical + kSectionHeaderBytes));
    const std::uint64_t top =
        levels.empty() ? 0 : kIndexHeaderBytes + levels.back() * kIndexEntryBytes;
    putLe<std::uint64_t>(h.data() + 24, top ? physicalOf(section_logical + length - top) : 0);
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
