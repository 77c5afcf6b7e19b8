// Serialisation of each MCAP record (spec section "Records") to and from bytes. Writers append a
// whole record (opcode, length, content); parsers take a record's content and fail cleanly on
// short input. Private to the recording library.
#pragma once

#include <optional>
#include <span>

#include "byte_io.hpp"
#include "handscan/recording/mcap_format.hpp"

namespace handscan::recording::detail {

// Appends the opcode and a length placeholder; endRecord patches the length.
std::size_t beginRecord(ByteWriter& w, Opcode op);
void endRecord(ByteWriter& w, std::size_t record_start);

void writeHeader(ByteWriter& w, const Header& h);
void writeFooter(ByteWriter& w, const Footer& f);
void writeSchema(ByteWriter& w, const Schema& s);
void writeChannel(ByteWriter& w, const Channel& c);
void writeMessage(ByteWriter& w, const MessageHeader& m, std::span<const std::uint8_t> data);
void writeMessageIndex(ByteWriter& w, const MessageIndex& mi);
void writeChunkIndex(ByteWriter& w, const ChunkIndex& ci);
void writeStatistics(ByteWriter& w, const Statistics& s);
void writeSummaryOffset(ByteWriter& w, const SummaryOffset& so);
void writeDataEnd(ByteWriter& w, std::uint32_t data_section_crc);

bool parseHeader(std::span<const std::uint8_t> content, Header& h);
bool parseFooter(std::span<const std::uint8_t> content, Footer& f);
bool parseSchema(std::span<const std::uint8_t> content, Schema& s);
bool parseChannel(std::span<const std::uint8_t> content, Channel& c);
bool parseMessage(std::span<const std::uint8_t> content, MessageHeader& m,
                  std::span<const std::uint8_t>& data);
bool parseChunk(std::span<const std::uint8_t> content, ChunkHeader& c,
                std::span<const std::uint8_t>& records);
bool parseMessageIndex(std::span<const std::uint8_t> content, MessageIndex& mi);
bool parseChunkIndex(std::span<const std::uint8_t> content, ChunkIndex& ci);
bool parseStatistics(std::span<const std::uint8_t> content, Statistics& s);
bool parseSummaryOffset(std::span<const std::uint8_t> content, SummaryOffset& so);
bool parseDataEnd(std::span<const std::uint8_t> content, std::uint32_t& data_section_crc);

// One record inside a buffer (a chunk's records, the summary section, a read-in data region).
struct RecordView {
    std::uint8_t opcode = 0;
    std::size_t offset = 0;  // of the opcode, within the scanned buffer
    std::span<const std::uint8_t> content;
    std::size_t size() const { return kRecordPrefixSize + content.size(); }
};

// Walks consecutive records. next() returns the next whole record, std::nullopt at the end;
// truncated() tells whether the end was a record cut short rather than the buffer's end.
class RecordScanner {
public:
    explicit RecordScanner(std::span<const std::uint8_t> buffer) : buffer_(buffer) {}
    std::optional<RecordView> next();
    bool truncated() const { return truncated_; }
    std::size_t position() const { return pos_; }

private:
    std::span<const std::uint8_t> buffer_;
    std::size_t pos_ = 0;
    bool truncated_ = false;
};

}  // namespace handscan::recording::detail
