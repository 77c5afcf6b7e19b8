#include "mcap_records.hpp"

namespace handscan::recording::detail {
namespace {

// Map<K, V> and Array<T> carry a u32 *byte* length (not an element count) before the entries.
std::size_t beginLengthPrefixed(ByteWriter& w) {
    const std::size_t pos = w.size();
    w.u32(0);
    return pos;
}
void endLengthPrefixed(ByteWriter& w, std::size_t pos) {
    w.patchU32(pos, static_cast<std::uint32_t>(w.size() - pos - 4));
}

void writeU16U64Map(ByteWriter& w, const std::map<std::uint16_t, std::uint64_t>& m) {
    const std::size_t pos = beginLengthPrefixed(w);
    for (const auto& [k, v] : m) {
        w.u16(k);
        w.u64(v);
    }
    endLengthPrefixed(w, pos);
}

bool readU16U64Map(ByteReader& r, std::map<std::uint16_t, std::uint64_t>& m) {
    std::uint32_t len = 0;
    std::span<const std::uint8_t> body;
    if (!r.u32(len) || !r.bytes(len, body) || len % 10 != 0) return false;
    ByteReader br(body);
    while (br.remaining() > 0) {
        std::uint16_t k = 0;
        std::uint64_t v = 0;
        if (!br.u16(k) || !br.u64(v)) return false;
        m[k] = v;
    }
    return true;
}

bool readTime(ByteReader& r, TimeNs& t) { return r.i64(t); }

}  // namespace

std::size_t beginRecord(ByteWriter& w, Opcode op) {
    const std::size_t start = w.size();
    w.u8(static_cast<std::uint8_t>(op));
    w.u64(0);
    return start;
}

void endRecord(ByteWriter& w, std::size_t record_start) {
    w.patchU64(record_start + 1, w.size() - record_start - kRecordPrefixSize);
}

void writeHeader(ByteWriter& w, const Header& h) {
    const std::size_t r = beginRecord(w, Opcode::kHeader);
    w.string(h.profile);
    w.string(h.library);
    endRecord(w, r);
}

void writeFooter(ByteWriter& w, const Footer& f) {
    const std::size_t r = beginRecord(w, Opcode::kFooter);
    w.u64(f.summary_start);
    w.u64(f.summary_offset_start);
    w.u32(f.summary_crc);
    endRecord(w, r);
}

void writeSchema(ByteWriter& w, const Schema& s) {
    const std::size_t r = beginRecord(w, Opcode::kSchema);
    w.u16(s.id);
    w.string(s.name);
    w.string(s.encoding);
    w.u32(static_cast<std::uint32_t>(s.data.size()));
    w.bytes(s.data);
    endRecord(w, r);
}

void writeChannel(ByteWriter& w, const Channel& c) {
    const std::size_t r = beginRecord(w, Opcode::kChannel);
    w.u16(c.id);
    w.u16(c.schema_id);
    w.string(c.topic);
    w.string(c.message_encoding);
    const std::size_t pos = beginLengthPrefixed(w);
    for (const auto& [k, v] : c.metadata) {
        w.string(k);
        w.string(v);
    }
    endLengthPrefixed(w, pos);
    endRecord(w, r);
}

void writeMessage(ByteWriter& w, const MessageHeader& m, std::span<const std::uint8_t> data) {
    w.u8(static_cast<std::uint8_t>(Opcode::kMessage));
    w.u64(kMessageHeaderSize + data.size());
    w.u16(m.channel_id);
    w.u32(m.sequence);
    w.u64(static_cast<std::uint64_t>(m.log_time));
    w.u64(static_cast<std::uint64_t>(m.publish_time));
    w.bytes(data);
}

void writeMessageIndex(ByteWriter& w, const MessageIndex& mi) {
    const std::size_t r = beginRecord(w, Opcode::kMessageIndex);
    w.u16(mi.channel_id);
    w.u32(static_cast<std::uint32_t>(mi.records.size() * 16));
    for (const auto& e : mi.records) {
        w.u64(static_cast<std::uint64_t>(e.log_time));
        w.u64(e.offset);
    }
    endRecord(w, r);
}

void writeChunkIndex(ByteWriter& w, const ChunkIndex& ci) {
    const std::size_t r = beginRecord(w, Opcode::kChunkIndex);
    w.u64(static_cast<std::uint64_t>(ci.message_start_time));
    w.u64(static_cast<std::uint64_t>(ci.message_end_time));
    w.u64(ci.chunk_start_offset);
    w.u64(ci.chunk_length);
    writeU16U64Map(w, ci.message_index_offsets);
    w.u64(ci.message_index_length);
    w.string(ci.compression);
    w.u64(ci.compressed_size);
    w.u64(ci.uncompressed_size);
    endRecord(w, r);
}

void writeStatistics(ByteWriter& w, const Statistics& s) {
    const std::size_t r = beginRecord(w, Opcode::kStatistics);
    w.u64(s.message_count);
    w.u16(s.schema_count);
    w.u32(s.channel_count);
    w.u32(s.attachment_count);
    w.u32(s.metadata_count);
    w.u32(s.chunk_count);
    w.u64(static_cast<std::uint64_t>(s.message_start_time));
    w.u64(static_cast<std::uint64_t>(s.message_end_time));
    writeU16U64Map(w, s.channel_message_counts);
    endRecord(w, r);
}

void writeSummaryOffset(ByteWriter& w, const SummaryOffset& so) {
    const std::size_t r = beginRecord(w, Opcode::kSummaryOffset);
    w.u8(static_cast<std::uint8_t>(so.group_opcode));
    w.u64(so.group_start);
    w.u64(so.group_length);
    endRecord(w, r);
}

void writeDataEnd(ByteWriter& w, std::uint32_t data_section_crc) {
    const std::size_t r = beginRecord(w, Opcode::kDataEnd);
    w.u32(data_section_crc);
    endRecord(w, r);
}

// Parsers read the fields they know and ignore any that a newer writer appended (the spec lets
// records grow at the end).
bool parseHeader(std::span<const std::uint8_t> content, Header& h) {
    ByteReader r(content);
    return r.string(h.profile) && r.string(h.library);
}

bool parseFooter(std::span<const std::uint8_t> content, Footer& f) {
    ByteReader r(content);
    return r.u64(f.summary_start) && r.u64(f.summary_offset_start) && r.u32(f.summary_crc);
}

bool parseSchema(std::span<const std::uint8_t> content, Schema& s) {
    ByteReader r(content);
    std::uint32_t n = 0;
    std::span<const std::uint8_t> data;
    if (!r.u16(s.id) || !r.string(s.name) || !r.string(s.encoding) || !r.u32(n) ||
        !r.bytes(n, data))
        return false;
    s.data.assign(data.begin(), data.end());
    return true;
}

bool parseChannel(std::span<const std::uint8_t> content, Channel& c) {
    ByteReader r(content);
    std::uint32_t len = 0;
    std::span<const std::uint8_t> body;
    if (!r.u16(c.id) || !r.u16(c.schema_id) || !r.string(c.topic) ||
        !r.string(c.message_encoding) || !r.u32(len) || !r.bytes(len, body)) {
        return false;
    }
    ByteReader br(body);
    c.metadata.clear();
    while (br.remaining() > 0) {
        std::string k, v;
        if (!br.string(k) || !br.string(v)) return false;
        c.metadata.emplace(std::move(k), std::move(v));
    }
    return true;
}

bool parseMessage(std::span<const std::uint8_t> content, MessageHeader& m,
                  std::span<const std::uint8_t>& data) {
    ByteReader r(content);
    if (!r.u16(m.channel_id) || !r.u32(m.sequence) || !readTime(r, m.log_time) ||
        !readTime(r, m.publish_time)) {
        return false;
    }
    data = content.subspan(kMessageHeaderSize);
    return true;
}

bool parseChunk(std::span<const std::uint8_t> content, ChunkHeader& c,
                std::span<const std::uint8_t>& records) {
    ByteReader r(content);
    if (!readTime(r, c.message_start_time) || !readTime(r, c.message_end_time) ||
        !r.u64(c.uncompressed_size) || !r.u32(c.uncompressed_crc) || !r.string(c.compression) ||
        !r.u64(c.records_size)) {
        return false;
    }
    return r.bytes(c.records_size, records);
}

bool parseMessageIndex(std::span<const std::uint8_t> content, MessageIndex& mi) {
    ByteReader r(content);
    std::uint32_t len = 0;
    if (!r.u16(mi.channel_id) || !r.u32(len) || len % 16 != 0 || r.remaining() < len) return false;
    mi.records.resize(len / 16);
    for (auto& e : mi.records) {
        if (!readTime(r, e.log_time) || !r.u64(e.offset)) return false;
    }
    return true;
}

bool parseChunkIndex(std::span<const std::uint8_t> content, ChunkIndex& ci) {
    ByteReader r(content);
    return readTime(r, ci.message_start_time) && readTime(r, ci.message_end_time) &&
           r.u64(ci.chunk_start_offset) && r.u64(ci.chunk_length) &&
           readU16U64Map(r, ci.message_index_offsets) && r.u64(ci.message_index_length) &&
           r.string(ci.compression) && r.u64(ci.compressed_size) && r.u64(ci.uncompressed_size);
}

bool parseStatistics(std::span<const std::uint8_t> content, Statistics& s) {
    ByteReader r(content);
    return r.u64(s.message_count) && r.u16(s.schema_count) && r.u32(s.channel_count) &&
           r.u32(s.attachment_count) && r.u32(s.metadata_count) && r.u32(s.chunk_count) &&
           readTime(r, s.message_start_time) && readTime(r, s.message_end_time) &&
           readU16U64Map(r, s.channel_message_counts);
}

bool parseSummaryOffset(std::span<const std::uint8_t> content, SummaryOffset& so) {
    ByteReader r(content);
    std::uint8_t op = 0;
    if (!r.u8(op) || !r.u64(so.group_start) || !r.u64(so.group_length)) return false;
    so.group_opcode = static_cast<Opcode>(op);
    return true;
}

bool parseDataEnd(std::span<const std::uint8_t> content, std::uint32_t& data_section_crc) {
    ByteReader r(content);
    return r.u32(data_section_crc);
}

std::optional<RecordView> RecordScanner::next() {
    if (pos_ >= buffer_.size()) return std::nullopt;
    ByteReader r(buffer_.subspan(pos_));
    RecordView v;
    std::uint64_t len = 0;
    if (!r.u8(v.opcode) || !r.u64(len) || r.remaining() < len) {
        truncated_ = true;
        return std::nullopt;
    }
    v.offset = pos_;
    v.content = buffer_.subspan(pos_ + kRecordPrefixSize, static_cast<std::size_t>(len));
    pos_ += kRecordPrefixSize + static_cast<std::size_t>(len);
    return v;
}

}  // namespace handscan::recording::detail
