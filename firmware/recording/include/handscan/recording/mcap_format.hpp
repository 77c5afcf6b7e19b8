// The MCAP container format (https://mcap.dev/spec, major version 0), implemented from the public
// specification: magic bytes, record opcodes and the records a handscan recording contains.
// All integers are little-endian; timestamps are uint64 nanoseconds. We store host
// CLOCK_MONOTONIC nanoseconds (TimeNs, never negative on Linux) as MCAP timestamps.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "handscan/core/time.hpp"

namespace handscan::recording {

// 0x89 'M' 'C' 'A' 'P' '0' '\r' '\n': begins and ends every MCAP file.
inline constexpr std::array<std::uint8_t, 8> kMcapMagic = {0x89, 'M',  'C',  'A',
                                                           'P',  0x30, '\r', '\n'};

enum class Opcode : std::uint8_t {
    kHeader = 0x01,
    kFooter = 0x02,
    kSchema = 0x03,
    kChannel = 0x04,
    kMessage = 0x05,
    kChunk = 0x06,
    kMessageIndex = 0x07,
    kChunkIndex = 0x08,
    kAttachment = 0x09,
    kAttachmentIndex = 0x0A,
    kStatistics = 0x0B,
    kMetadata = 0x0C,
    kMetadataIndex = 0x0D,
    kSummaryOffset = 0x0E,
    kDataEnd = 0x0F,
};

// Every record: <opcode u8><content length u64><content>.
inline constexpr std::size_t kRecordPrefixSize = 1 + 8;
// Footer content: summary_start u64, summary_offset_start u64, summary_crc u32.
inline constexpr std::size_t kFooterContentSize = 8 + 8 + 4;
// Footer record + trailing magic: what an indexed reader reads first from the end of the file.
inline constexpr std::size_t kFooterAndMagicSize =
    kRecordPrefixSize + kFooterContentSize + kMcapMagic.size();

struct Header {
    std::string profile;  // "" or a custom profile ("x-" prefix)
    std::string library;  // free-form writer name and version
};

struct Footer {
    std::uint64_t summary_start = 0;         // 0: no summary section
    std::uint64_t summary_offset_start = 0;  // 0: no summary offset section
    std::uint32_t summary_crc = 0;  // CRC32 of summary start .. footer's summary_offset_start
};

struct Schema {
    std::uint16_t id = 0;  // never 0 (0 means "no schema" in a Channel)
    std::string name;
    std::string encoding;  // "" when no schema is available
    std::vector<std::uint8_t> data;
};

struct Channel {
    std::uint16_t id = 0;
    std::uint16_t schema_id = 0;  // 0: no schema
    std::string topic;
    std::string message_encoding;
    std::map<std::string, std::string> metadata;
};

// A Message record's fixed part; the payload follows it.
struct MessageHeader {
    std::uint16_t channel_id = 0;
    std::uint32_t sequence = 0;
    TimeNs log_time = 0;      // host receive time
    TimeNs publish_time = 0;  // = log_time unless the publisher knows better
};
inline constexpr std::size_t kMessageHeaderSize = 2 + 4 + 8 + 8;

// A Chunk record's fixed part; `records` (compressed) follows.
struct ChunkHeader {
    TimeNs message_start_time = 0;
    TimeNs message_end_time = 0;
    std::uint64_t uncompressed_size = 0;
    std::uint32_t uncompressed_crc = 0;  // 0: not available
    std::string compression;             // "" or "zstd"
    std::uint64_t records_size = 0;      // compressed size of `records`
};

struct MessageIndexEntry {
    TimeNs log_time = 0;
    std::uint64_t offset = 0;  // into the chunk's uncompressed records
};

struct MessageIndex {
    std::uint16_t channel_id = 0;
    std::vector<MessageIndexEntry> records;
};

struct ChunkIndex {
    TimeNs message_start_time = 0;
    TimeNs message_end_time = 0;
    std::uint64_t chunk_start_offset = 0;                          // of the Chunk record's opcode
    std::uint64_t chunk_length = 0;                                // whole record, prefix included
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;  // channel -> file offset
    std::uint64_t message_index_length = 0;
    std::string compression;
    std::uint64_t compressed_size = 0;
    std::uint64_t uncompressed_size = 0;
};

struct Statistics {
    std::uint64_t message_count = 0;
    std::uint16_t schema_count = 0;
    std::uint32_t channel_count = 0;
    std::uint32_t attachment_count = 0;
    std::uint32_t metadata_count = 0;
    std::uint32_t chunk_count = 0;
    TimeNs message_start_time = 0;
    TimeNs message_end_time = 0;
    std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

struct SummaryOffset {
    Opcode group_opcode = Opcode::kSchema;
    std::uint64_t group_start = 0;
    std::uint64_t group_length = 0;
};

}  // namespace handscan::recording
