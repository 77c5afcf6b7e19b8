// The physical layout of an E57 file (ASTM E2807 section 8), shared by the writer and the reader:
// the 48-byte file header at offset 0, then 1024-byte pages each holding 1020 "logical" bytes and
// a CRC-32C of them, stored big-endian (checked against files written by libE57Format and
// CloudCompare in ../shared/data/e57). Offsets inside the XML and in section headers are physical;
// binary sections and packets are laid out in logical bytes that skip the checksums.
#pragma once

#include <cstdint>
#include <cstring>

namespace handscan::exporter::e57 {

constexpr std::uint64_t kPageBytes = 1024;
constexpr std::uint64_t kPagePayload = 1020;  // the rest is the page's CRC-32C
constexpr std::size_t kFileHeaderBytes = 48;  // signature, version, lengths, page size
constexpr char kSignature[8] = {'A', 'S', 'T', 'M', '-', 'E', '5', '7'};
constexpr std::size_t kSectionHeaderBytes = 32;       // compressed vector section header
constexpr std::size_t kDataPacketHeaderBytes = 6;     // type, flags, length - 1, stream count
constexpr std::size_t kMaxPacketBytes = 64 * 1024;    // the length field is 16 bits (length - 1)
constexpr std::uint8_t kSectionCompressedVector = 1;  // sectionId
constexpr std::uint8_t kPacketIndex = 0, kPacketData = 1, kPacketEmpty = 2;
constexpr const char* kNamespace = "http://www.astm.org/COMMIT/E57/2010-e57-v1.0";
// Our extension (E57 section 7.3: extensions are elements in their own XML namespace): the
// walk's trajectory as a compressed vector under each Data3D.
constexpr const char* kHandscanNamespace = "https://github.com/handscan/e57/trajectory/1.0";

constexpr std::uint64_t physicalOf(std::uint64_t logical) {
    return logical / kPagePayload * kPageBytes + logical % kPagePayload;
}
constexpr std::uint64_t logicalOf(std::uint64_t physical) {
    return physical / kPageBytes * kPagePayload + physical % kPageBytes;
}

template <typename T>
void putLe(std::uint8_t* out, T v) {  // x86-64 and ARM are little-endian, as E57 is
    std::memcpy(out, &v, sizeof v);
}
template <typename T>
T getLe(const std::uint8_t* in) {
    T v;
    std::memcpy(&v, in, sizeof v);
    return v;
}
inline void putCrcBigEndian(std::uint8_t* out, std::uint32_t crc) {
    out[0] = static_cast<std::uint8_t>(crc >> 24);
    out[1] = static_cast<std::uint8_t>(crc >> 16);
    out[2] = static_cast<std::uint8_t>(crc >> 8);
    out[3] = static_cast<std::uint8_t>(crc);
}
inline std::uint32_t getCrcBigEndian(const std::uint8_t* in) {
    return (std::uint32_t{in[0]} << 24) | (std::uint32_t{in[1]} << 16) |
           (std::uint32_t{in[2]} << 8) | std::uint32_t{in[3]};
}

}  // namespace handscan::exporter::e57
