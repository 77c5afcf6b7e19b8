#include "handscan/recording/mcap_reader.hpp"

#include <algorithm>
#include <cstring>
#include <set>

#include "byte_source.hpp"
#include "chunk_compression.hpp"
#include "handscan/recording/crc32.hpp"
#include "mcap_records.hpp"

namespace handscan::recording {
namespace detail {

// Where a chunk is and what it holds. A "virtual" chunk holds the loose (un-chunked) Message
// records of a linearly scanned file, already in memory.
struct ChunkRef {
    std::uint64_t offset = 0;  // of the Chunk record
    std::uint64_t length = 0;  // whole record
    TimeNs start = 0;
    TimeNs end = 0;
    std::vector<std::uint16_t> channels;  // channels with messages here; empty = unknown
    std::shared_ptr<const std::vector<std::uint8_t>> in_memory;
    bool reported = false;  // already in dropped()
};

}  // namespace detail

namespace {

using detail::ByteReader;
using detail::ChunkRef;
using detail::RecordScanner;

// Our chunks are ~1 MiB (one 1600x1200 YUYV frame is 3.7 MiB); other writers use a few MiB. A
// larger declared size means a corrupt header, and must not make us allocate it.
constexpr std::uint64_t kMaxChunkBytes = 256ull << 20;

std::string at(std::uint64_t offset) { return "at byte " + std::to_string(offset); }

const char* recordName(std::uint8_t op) {
    switch (static_cast<Opcode>(op)) {
        case Opcode::kHeader:
            return "Header";
        case Opcode::kFooter:
            return "Footer";
        case Opcode::kSchema:
            return "Schema";
        case Opcode::kChannel:
            return "Channel";
        case Opcode::kMessage:
            return "Message";
        case Opcode::kChunk:
            return "Chunk";
        case Opcode::kMessageIndex:
            return "Message Index";
        case Opcode::kChunkIndex:
            return "Chunk Index";
        case Opcode::kAttachment:
            return "Attachment";
        case Opcode::kAttachmentIndex:
            return "Attachment Index";
        case Opcode::kStatistics:
            return "Statistics";
        case Opcode::kMetadata:
            return "Metadata";
        case Opcode::kMetadataIndex:
            return "Metadata Index";
        case Opcode::kSummaryOffset:
            return "Summary Offset";
        case Opcode::kDataEnd:
            return "Data End";
    }
    return "unknown";
}

// A record's opcode and content length.
struct RecordPrefix {
    std::uint8_t op = 0;
    std::uint64_t len = 0;
};

// Reads the record prefix at `pos`. kTruncated (with the reason) when the file ends inside the
// prefix or before the record's declared end; kIoError when the file cannot be read.
Result<RecordPrefix> readPrefix(detail::ByteSource& src, std::uint64_t pos,
                                std::vector<std::uint8_t>& buf) {
    const std::uint64_t size = src.size();
    if (size - pos < kRecordPrefixSize) {
        return Status{StatusCode::kTruncated,
                      "file ends inside a record prefix " + at(pos) + " (cut short)"};
    }
    if (Status s = src.readAt(pos, kRecordPrefixSize, buf); !s) return s;
    ByteReader pr(buf);
    RecordPrefix p;
    (void)pr.u8(p.op);
    (void)pr.u64(p.len);
    const std::uint64_t avail = size - pos - kRecordPrefixSize;
    if (p.len > avail) {
        return Status{StatusCode::kTruncated, std::string(recordName(p.op)) + " record " + at(pos) +
                                                  " declares " + std::to_string(p.len) +
                                                  " bytes but only " + std::to_string(avail) +
                                                  " remain (file cut short)"};
    }
    return p;
}

// Parses a Chunk record's content, checks its CRC and decompresses its records into `out`.
Status decodeChunk(std::span<const std::uint8_t> content, std::uint64_t offset, ChunkHeader& header,
                   std::vector<std::uint8_t>& out) {
    std::span<const std::uint8_t> records;
    if (!detail::parseChunk(content, header, records)) {
        return {StatusCode::kProtocolError, "chunk " + at(offset) + ": malformed chunk header"};
    }
    if (header.uncompressed_size > kMaxChunkBytes) {
        return {StatusCode::kProtocolError, "chunk " + at(offset) +
                                                ": implausible uncompressed size " +
                                                std::to_string(header.uncompressed_size)};
    }
    if (Status s =
            detail::decompressChunk(header.compression, records, header.uncompressed_size, out);
        !s) {
        return {s.code(), "chunk " + at(offset) + ": " + s.message()};
    }
    if (header.uncompressed_crc != 0) {
        const std::uint32_t crc = crc32(out);
        if (crc != header.uncompressed_crc) {
            char buf[96];
            std::snprintf(buf, sizeof buf, ": CRC32 mismatch (stored 0x%08x, computed 0x%08x)",
                          header.uncompressed_crc, crc);
            return {StatusCode::kChecksumError, "chunk " + at(offset) + buf};
        }
    }
    return Status::ok();
}

// Looks from `from` on for the next whole Chunk record whose CRC verifies: after a damaged
// region (blocks of zeros a power cut left behind, a corrupt length) the scan resumes there
// instead of losing the rest of the file. A candidate must have a consistent chunk header
// before it is decompressed and checked, so the search is cheap and false matches impossible
// in practice (they would also need a matching CRC32).
Result<std::optional<std::uint64_t>> findNextChunk(detail::ByteSource& src, std::uint64_t from) {
    constexpr std::size_t kWindow = 1u << 20;
    constexpr std::size_t kHead = kRecordPrefixSize + 36 + 4 + 8;  // up to records_size with "zstd"
    const std::uint64_t size = src.size();
    std::vector<std::uint8_t> win;
    std::vector<std::uint8_t> content;
    std::vector<std::uint8_t> records;
    for (std::uint64_t base = from; base + kRecordPrefixSize + 40 <= size; base += kWindow) {
        const std::size_t n =
            static_cast<std::size_t>(std::min<std::uint64_t>(kWindow + kHead, size - base));
        if (Status s = src.readAt(base, n, win); !s) return s;
        for (std::size_t i = 0; i < std::min(kWindow, n); ++i) {
            if (win[i] != static_cast<std::uint8_t>(Opcode::kChunk) || i + kHead > n) continue;
            const std::uint64_t q = base + i;
            ByteReader r(std::span<const std::uint8_t>(win).subspan(i + 1));
            std::uint64_t len = 0, start = 0, end = 0, usize = 0, records_size = 0;
            std::uint32_t crc = 0, complen = 0;
            (void)(r.u64(len) && r.u64(start) && r.u64(end) && r.u64(usize) && r.u32(crc) &&
                   r.u32(complen));
            if (len < 40 || len > size - q - kRecordPrefixSize || start > end ||
                usize > kMaxChunkBytes || (complen != 0 && complen != 4)) {
                continue;
            }
            std::span<const std::uint8_t> name;
            (void)(r.bytes(complen, name) && r.u64(records_size));
            if ((complen == 4 && !std::equal(name.begin(), name.end(), "zstd")) ||
                len != 40 + complen + records_size)
                continue;
            if (Status s =
                    src.readAt(q + kRecordPrefixSize, static_cast<std::size_t>(len), content);
                !s)
                return s;
            ChunkHeader ch;
            if (decodeChunk(content, q, ch, records)) return std::optional<std::uint64_t>(q);
        }
    }
    return std::optional<std::uint64_t>();
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Opening: the index when the footer and summary are intact, otherwise a linear scan.

McapReader::McapReader(std::unique_ptr<detail::ByteSource> source, std::string name)
    : source_(std::move(source)), name_(std::move(name)) {}

McapReader::~McapReader() = default;

Result<std::unique_ptr<McapReader>> McapReader::open(const std::string& path) {
    auto src = detail::openFileSource(path);
    if (!src) return src.status();
    std::unique_ptr<McapReader> r(new McapReader(std::move(*src), path));
    if (Status s = r->load(); !s) return s;
    return r;
}

Result<std::unique_ptr<McapReader>> McapReader::fromBuffer(std::vector<std::uint8_t> bytes,
                                                           std::string name) {
    std::unique_ptr<McapReader> r(
        new McapReader(detail::memorySource(std::move(bytes)), std::move(name)));
    if (Status s = r->load(); !s) return s;
    return r;
}

std::uint64_t McapReader::fileSize() const { return source_->size(); }
std::size_t McapReader::chunkCount() const { return chunks_.size(); }

std::pair<TimeNs, TimeNs> McapReader::timeRange() const {
    if (chunks_.empty()) return {0, 0};
    std::pair<TimeNs, TimeNs> r{chunks_.front().start, chunks_.front().end};
    for (const auto& c : chunks_) {
        r.first = std::min(r.first, c.start);
        r.second = std::max(r.second, c.end);
    }
    return r;
}

const Channel* McapReader::channel(std::uint16_t id) const {
    const auto it = channel_by_id_.find(id);
    return it == channel_by_id_.end() ? nullptr : &channels_[it->second];
}

const Channel* McapReader::findTopic(std::string_view topic) const {
    for (const auto& c : channels_) {
        if (c.topic == topic) return &c;
    }
    return nullptr;
}

void McapReader::addChannel(const Channel& c) {
    if (channel_by_id_.count(c.id) != 0) return;
    // Kept sorted by id; only called while loading, before any Channel pointer is handed out.
    const auto pos = std::lower_bound(channels_.begin(), channels_.end(), c.id,
                                      [](const Channel& a, std::uint16_t id) { return a.id < id; });
    channels_.insert(pos, c);
    channel_by_id_.clear();
    for (std::size_t i = 0; i < channels_.size(); ++i) channel_by_id_[channels_[i].id] = i;
}

void McapReader::addSchema(const Schema& s) {
    if (s.id == 0) return;  // invalid per spec: ignore
    for (const auto& have : schemas_) {
        if (have.id == s.id) return;
    }
    schemas_.push_back(s);
}

void McapReader::drop(std::uint64_t offset, std::uint64_t length, std::string reason) {
    dropped_.push_back({offset, length, name_ + ": " + std::move(reason)});
}

Status McapReader::load() {
    const std::uint64_t size = source_->size();
    std::vector<std::uint8_t> buf;
    if (size < kMcapMagic.size()) {
        return {StatusCode::kTruncated,
                name_ + ": " + std::to_string(size) + " bytes is too short for an MCAP file"};
    }
    if (Status s = source_->readAt(0, kMcapMagic.size(), buf); !s) return s;
    if (!std::equal(kMcapMagic.begin(), kMcapMagic.end(), buf.begin())) {
        return {StatusCode::kProtocolError,
                name_ + ": not an MCAP file (the first 8 bytes are not the MCAP0 magic)"};
    }
    // Header: opcode, length, content.
    if (size < kMcapMagic.size() + kRecordPrefixSize) {
        return {StatusCode::kTruncated,
                name_ + ": cut short inside the Header record; it holds no messages"};
    }
    if (Status s = source_->readAt(kMcapMagic.size(), kRecordPrefixSize, buf); !s) return s;
    ByteReader pr(buf);
    std::uint8_t op = 0;
    std::uint64_t len = 0;
    (void)pr.u8(op);
    (void)pr.u64(len);
    if (op != static_cast<std::uint8_t>(Opcode::kHeader)) {
        return {StatusCode::kProtocolError,
                name_ + ": the first record is " + recordName(op) + ", not a Header"};
    }
    const std::uint64_t header_end = kMcapMagic.size() + kRecordPrefixSize + len;
    if (len > size || header_end > size) {
        return {StatusCode::kTruncated,
                name_ + ": cut short inside the Header record; it holds no messages"};
    }
    if (Status s = source_->readAt(kMcapMagic.size() + kRecordPrefixSize,
                                   static_cast<std::size_t>(len), buf);
        !s)
        return s;
    if (!detail::parseHeader(buf, header_)) {
        return {StatusCode::kProtocolError,
                name_ + ": malformed Header record " + at(kMcapMagic.size())};
    }

    // Footer and trailing magic.
    bool footer_ok = false;
    Footer footer;
    std::uint64_t footer_offset = 0;
    if (size >= header_end + kFooterAndMagicSize) {
        footer_offset = size - kFooterAndMagicSize;
        if (Status s = source_->readAt(footer_offset, kFooterAndMagicSize, buf); !s) return s;
        ByteReader fr(buf);
        (void)fr.u8(op);
        (void)fr.u64(len);
        footer_ok =
            op == static_cast<std::uint8_t>(Opcode::kFooter) && len == kFooterContentSize &&
            std::equal(kMcapMagic.begin(), kMcapMagic.end(), buf.end() - kMcapMagic.size()) &&
            detail::parseFooter(std::span<const std::uint8_t>(buf).subspan(kRecordPrefixSize),
                                footer);
    }
    truncated_ = !footer_ok;
    if (footer_ok && footer.summary_start != 0) {
        const Status s = readIndexed(footer, footer_offset);
        if (s) {
            indexed_ = true;
            return Status::ok();
        }
        if (s.code() == StatusCode::kIoError) return s;
        const std::uint64_t summary_at = std::min(footer_offset, footer.summary_start);
        drop(summary_at, footer_offset - summary_at,
             "summary unusable (" + s.message() + "); recovered by scanning the data section");
        channels_.clear();
        channel_by_id_.clear();
        schemas_.clear();
        chunks_.clear();
        statistics_.reset();
    }
    return scanLinear();
}

Status McapReader::readIndexed(const Footer& footer, std::uint64_t footer_offset) {
    if (footer.summary_start >= footer_offset || footer.summary_start < kMcapMagic.size()) {
        return {StatusCode::kProtocolError, "footer's summary_start " +
                                                std::to_string(footer.summary_start) +
                                                " lies outside the file"};
    }
    // The summary plus the footer's fields that the summary CRC covers.
    const std::uint64_t summary_len = footer_offset - footer.summary_start;
    const std::size_t crc_len = static_cast<std::size_t>(summary_len) + kRecordPrefixSize + 16;
    std::vector<std::uint8_t> buf;
    if (Status s = source_->readAt(footer.summary_start, crc_len, buf); !s) return s;
    if (footer.summary_crc != 0 && crc32(buf) != footer.summary_crc) {
        return {StatusCode::kChecksumError, "summary CRC32 mismatch"};
    }
    RecordScanner scan(
        std::span<const std::uint8_t>(buf).first(static_cast<std::size_t>(summary_len)));
    std::vector<ChunkIndex> indexes;
    while (auto rec = scan.next()) {
        const std::uint64_t where = footer.summary_start + rec->offset;
        switch (static_cast<Opcode>(rec->opcode)) {
            case Opcode::kSchema: {
                Schema s;
                if (!detail::parseSchema(rec->content, s))
                    return {StatusCode::kProtocolError, "malformed Schema " + at(where)};
                addSchema(s);
                break;
            }
            case Opcode::kChannel: {
                Channel c;
                if (!detail::parseChannel(rec->content, c))
                    return {StatusCode::kProtocolError, "malformed Channel " + at(where)};
                addChannel(c);
                break;
            }
            case Opcode::kChunkIndex: {
                ChunkIndex ci;
                if (!detail::parseChunkIndex(rec->content, ci)) {
                    return {StatusCode::kProtocolError, "malformed Chunk Index " + at(where)};
                }
                if (ci.chunk_length < kRecordPrefixSize || ci.chunk_length > footer.summary_start ||
                    ci.chunk_start_offset > footer.summary_start - ci.chunk_length) {
                    return {StatusCode::kProtocolError,
                            "Chunk Index " + at(where) + " points outside the data section"};
                }
                indexes.push_back(std::move(ci));
                break;
            }
            case Opcode::kStatistics: {
                Statistics st;
                if (!detail::parseStatistics(rec->content, st)) {
                    return {StatusCode::kProtocolError, "malformed Statistics " + at(where)};
                }
                statistics_ = std::move(st);
                break;
            }
            default:
                break;  // summary offsets, attachment and metadata indexes: not needed here
        }
    }
    if (scan.truncated())
        return {StatusCode::kProtocolError, "summary section ends inside a record"};
    // Messages outside chunks cannot be indexed: only trust an index that accounts for them all.
    if (indexes.empty() && !(statistics_ && statistics_->message_count == 0)) {
        return {StatusCode::kNotFound, "summary has no chunk index"};
    }
    for (auto& ci : indexes) {
        ChunkRef ref;
        ref.offset = ci.chunk_start_offset;
        ref.length = ci.chunk_length;
        ref.start = ci.message_start_time;
        ref.end = ci.message_end_time;
        for (const auto& [channel_id, offset] : ci.message_index_offsets)
            ref.channels.push_back(channel_id);
        chunks_.push_back(std::move(ref));
    }
    return Status::ok();
}

Status McapReader::scanLinear() {
    const std::uint64_t size = source_->size();
    std::vector<std::uint8_t> buf;
    std::vector<std::uint8_t> records;
    std::vector<std::uint8_t> loose;  // un-chunked Message records, kept as a virtual chunk
    ChunkRef loose_ref;
    std::set<std::uint16_t> loose_channels;
    std::uint64_t loose_count = 0;

    if (Status s = source_->readAt(kMcapMagic.size() + 1, 8, buf); !s) return s;
    ByteReader hr(buf);
    std::uint64_t header_len = 0;
    (void)hr.u64(header_len);
    std::uint64_t pos = kMcapMagic.size() + kRecordPrefixSize + header_len;
    bool reached_end = false;

    while (pos < size && !reached_end) {
        auto prefix = readPrefix(*source_, pos, buf);
        // Opcode 0 is no record: zero-filled blocks (a power cut on a delayed-allocation file
        // system) or garbage. Either that or a length past the end: resume at the next chunk.
        if (!prefix || prefix->op == 0) {
            if (!prefix && prefix.status().code() != StatusCode::kTruncated) return prefix.status();
            const std::string why =
                prefix ? "invalid record (opcode 0x00) " + at(pos) + ": zero-filled or corrupt data"
                       : prefix.status().message();
            auto next = findNextChunk(*source_, pos + 1);
            if (!next) return next.status();
            if (!*next) {
                drop(pos, size - pos, why);
                break;
            }
            drop(pos, **next - pos,
                 why + "; resumed at the chunk at byte " + std::to_string(**next));
            pos = **next;
            continue;
        }
        const std::uint8_t op = prefix->op;
        const std::uint64_t len = prefix->len;
        const std::uint64_t record_len = kRecordPrefixSize + len;
        switch (static_cast<Opcode>(op)) {
            case Opcode::kChunk: {
                if (Status s = source_->readAt(pos + kRecordPrefixSize,
                                               static_cast<std::size_t>(len), buf);
                    !s)
                    return s;
                ChunkHeader ch;
                if (Status s = decodeChunk(buf, pos, ch, records); !s) {
                    drop(pos, record_len, s.message());
                    break;
                }
                // Channels and schemas inside the chunk; which channels carry messages.
                ChunkRef ref;
                ref.offset = pos;
                ref.length = record_len;
                ref.start = ch.message_start_time;
                ref.end = ch.message_end_time;
                std::set<std::uint16_t> used;
                RecordScanner inner(records);
                bool bad = false;
                while (auto rec = inner.next()) {
                    if (rec->opcode == static_cast<std::uint8_t>(Opcode::kChannel)) {
                        Channel c;
                        if (!(bad = !detail::parseChannel(rec->content, c))) addChannel(c);
                    } else if (rec->opcode == static_cast<std::uint8_t>(Opcode::kSchema)) {
                        Schema sc;
                        if (!(bad = !detail::parseSchema(rec->content, sc))) addSchema(sc);
                    } else if (rec->opcode == static_cast<std::uint8_t>(Opcode::kMessage)) {
                        if (rec->content.size() < 2)
                            bad = true;
                        else
                            used.insert(
                                static_cast<std::uint16_t>(rec->content[0] | rec->content[1] << 8));
                    }
                    if (bad) break;
                }
                if (bad || inner.truncated()) {
                    drop(pos, record_len,
                         "chunk " + at(pos) + ": CRC matches but its records are malformed");
                    break;
                }
                ref.channels.assign(used.begin(), used.end());
                if (ref.channels.empty()) break;  // nothing to read in it
                chunks_.push_back(std::move(ref));
                break;
            }
            case Opcode::kSchema:
            case Opcode::kChannel:
            case Opcode::kMessage: {
                if (Status s = source_->readAt(pos + kRecordPrefixSize,
                                               static_cast<std::size_t>(len), buf);
                    !s)
                    return s;
                bool ok = true;
                if (op == static_cast<std::uint8_t>(Opcode::kSchema)) {
                    Schema sc;
                    if ((ok = detail::parseSchema(buf, sc))) addSchema(sc);
                } else if (op == static_cast<std::uint8_t>(Opcode::kChannel)) {
                    Channel c;
                    if ((ok = detail::parseChannel(buf, c))) addChannel(c);
                } else {
                    MessageHeader mh;
                    std::span<const std::uint8_t> data;
                    if ((ok = detail::parseMessage(buf, mh, data))) {
                        detail::ByteWriter w(loose);
                        detail::writeMessage(w, mh, data);
                        loose_ref.start =
                            loose_count == 0 ? mh.log_time : std::min(loose_ref.start, mh.log_time);
                        loose_ref.end =
                            loose_count == 0 ? mh.log_time : std::max(loose_ref.end, mh.log_time);
                        loose_channels.insert(mh.channel_id);
                        ++loose_count;
                    }
                }
                if (!ok)
                    drop(pos, record_len,
                         std::string("malformed ") + recordName(op) + " record " + at(pos));
                break;
            }
            case Opcode::kDataEnd:
                data_end_offset_ = pos;
                reached_end = true;
                break;
            case Opcode::kFooter:
                reached_end = true;
                break;
            default:
                break;  // Message Index, Attachment, Metadata, unknown: not needed to read messages
        }
        pos += record_len;
    }
    if (loose_count > 0) {
        loose_ref.offset = kMcapMagic.size();
        loose_ref.channels.assign(loose_channels.begin(), loose_channels.end());
        loose_ref.in_memory = std::make_shared<const std::vector<std::uint8_t>>(std::move(loose));
        chunks_.push_back(std::move(loose_ref));
    }
    return Status::ok();
}

Result<std::shared_ptr<const std::vector<std::uint8_t>>> McapReader::loadChunk(ChunkRef& ref) {
    if (ref.in_memory) return ref.in_memory;
    std::vector<std::uint8_t> raw;
    if (Status s = source_->readAt(ref.offset, static_cast<std::size_t>(ref.length), raw); !s) {
        if (s.code() != StatusCode::kIoError && !ref.reported)
            drop(ref.offset, ref.length, s.message());
        ref.reported = true;
        return s;
    }
    auto out = std::make_shared<std::vector<std::uint8_t>>();
    ChunkHeader ch;
    Status s;
    if (raw[0] != static_cast<std::uint8_t>(Opcode::kChunk)) {
        s = {StatusCode::kProtocolError,
             "chunk index points " + at(ref.offset) + " at a " + recordName(raw[0]) + " record"};
    } else {
        s = decodeChunk(std::span<const std::uint8_t>(raw).subspan(kRecordPrefixSize), ref.offset,
                        ch, *out);
    }
    if (!s) {
        if (!ref.reported) drop(ref.offset, ref.length, s.message());
        ref.reported = true;
        return s;
    }
    return std::shared_ptr<const std::vector<std::uint8_t>>(std::move(out));
}

// ---------------------------------------------------------------------------------------------
// Iteration: a k-way merge of chunks by log time. A chunk is loaded once the earliest pending
// message is not earlier than the chunk's start time, so at most the overlapping chunks are in
// memory at a time.

struct MessageIterator::Impl {
    struct Pending {
        TimeNs log_time;
        std::size_t chunk_rank;  // position of the chunk in load order (file order for ties)
        std::size_t offset;      // of the record within the chunk
        RecordedMessage msg;
    };
    struct Later {
        bool operator()(const Pending& a, const Pending& b) const {
            if (a.log_time != b.log_time) return a.log_time > b.log_time;
            if (a.chunk_rank != b.chunk_rank) return a.chunk_rank > b.chunk_rank;
            return a.offset > b.offset;
        }
    };

    McapReader* reader = nullptr;
    ReadOptions options;
    std::set<std::uint16_t> wanted;  // channel ids
    bool all_channels = true;
    std::vector<std::size_t> order;  // chunk indices sorted by start time
    std::size_t next_chunk = 0;
    std::vector<Pending> heap;
    Status status;
    std::set<std::uint16_t> unknown_reported;

    bool wants(std::uint16_t channel_id) const {
        return all_channels || wanted.count(channel_id) != 0;
    }

    void loadNext() {
        const std::size_t rank = next_chunk;
        ChunkRef& ref = reader->chunks_[order[next_chunk++]];
        auto loaded = reader->loadChunk(ref);
        if (!loaded) {
            if (loaded.status().code() == StatusCode::kIoError) status = loaded.status();
            return;  // corrupt: reported in dropped(), skipped
        }
        std::shared_ptr<const std::vector<std::uint8_t>> buf = std::move(*loaded);
        std::size_t early = 0;
        RecordScanner scan(*buf);
        while (auto rec = scan.next()) {
            if (rec->opcode != static_cast<std::uint8_t>(Opcode::kMessage)) continue;
            MessageHeader mh;
            std::span<const std::uint8_t> data;
            if (!detail::parseMessage(rec->content, mh, data)) {
                reader->drop(ref.offset, ref.length,
                             "chunk " + at(ref.offset) + ": malformed Message record");
                return;
            }
            if (!wants(mh.channel_id) || mh.log_time < options.start_time ||
                mh.log_time > options.end_time)
                continue;
            // The merge has already handed out messages up to this chunk's stated start time, so a
            // message earlier than that (a chunk header or index that lies about its time range)
            // cannot be placed in order: report it rather than break the order promised to callers.
            if (mh.log_time < ref.start) {
                ++early;
                continue;
            }
            const Channel* ch = reader->channel(mh.channel_id);
            if (ch == nullptr) {
                if (unknown_reported.insert(mh.channel_id).second) {
                    reader->drop(ref.offset, ref.length,
                                 "chunk " + at(ref.offset) + ": messages on channel " +
                                     std::to_string(mh.channel_id) +
                                     " which has no Channel record; skipped");
                }
                continue;
            }
            heap.push_back(
                {mh.log_time, rank, rec->offset,
                 RecordedMessage{ch, mh.sequence, mh.log_time, mh.publish_time, data, buf}});
            std::push_heap(heap.begin(), heap.end(), Later{});
        }
        if (scan.truncated()) {
            reader->drop(ref.offset, ref.length,
                         "chunk " + at(ref.offset) + ": records end inside a record");
        }
        if (early != 0) {
            reader->drop(ref.offset, ref.length,
                         "chunk " + at(ref.offset) + ": " + std::to_string(early) +
                             " message(s) logged before the chunk's stated start time " +
                             std::to_string(ref.start) +
                             " ns; skipped (the chunk header or index is inconsistent)");
        }
    }
};

MessageIterator::MessageIterator(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MessageIterator::~MessageIterator() = default;
MessageIterator::MessageIterator(MessageIterator&&) noexcept = default;
MessageIterator& MessageIterator::operator=(MessageIterator&&) noexcept = default;

const Status& MessageIterator::status() const { return impl_->status; }

bool MessageIterator::next(RecordedMessage& out) {
    Impl& d = *impl_;
    while (d.status) {
        while (d.next_chunk < d.order.size() &&
               (d.heap.empty() ||
                d.reader->chunks_[d.order[d.next_chunk]].start <= d.heap.front().log_time)) {
            d.loadNext();
            if (!d.status) return false;
        }
        if (d.heap.empty()) return false;
        std::pop_heap(d.heap.begin(), d.heap.end(), Impl::Later{});
        out = std::move(d.heap.back().msg);
        d.heap.pop_back();
        return true;
    }
    return false;
}

MessageIterator McapReader::messages(ReadOptions options) {
    auto impl = std::make_unique<MessageIterator::Impl>();
    impl->reader = this;
    impl->all_channels = options.topics.empty();
    for (const auto& topic : options.topics) {
        if (const Channel* c = findTopic(topic)) impl->wanted.insert(c->id);
    }
    for (std::size_t i = 0; i < chunks_.size(); ++i) {
        const ChunkRef& c = chunks_[i];
        if (c.end < options.start_time || c.start > options.end_time) continue;
        if (!impl->all_channels && !c.channels.empty() &&
            std::none_of(c.channels.begin(), c.channels.end(),
                         [&](std::uint16_t id) { return impl->wanted.count(id) != 0; })) {
            continue;
        }
        impl->order.push_back(i);
    }
    std::stable_sort(impl->order.begin(), impl->order.end(), [&](std::size_t a, std::size_t b) {
        return chunks_[a].start != chunks_[b].start ? chunks_[a].start < chunks_[b].start
                                                    : chunks_[a].offset < chunks_[b].offset;
    });
    impl->options = std::move(options);
    return MessageIterator(std::move(impl));
}

Status McapReader::forEachMessage(const ReadOptions& options,
                                  const std::function<void(const RecordedMessage&)>& fn) {
    MessageIterator it = messages(options);
    RecordedMessage m;
    while (it.next(m)) fn(m);
    return it.status();
}

// ---------------------------------------------------------------------------------------------

Status McapReader::verify() {
    const std::uint64_t size = source_->size();
    std::vector<std::string> problems;
    std::vector<std::uint8_t> buf;
    std::vector<std::uint8_t> records;
    Crc32 data_crc;
    // Magic and Header are part of the data-section CRC, as in the reference writers.
    std::uint64_t pos = 0;
    if (Status s = source_->readAt(0, kMcapMagic.size(), buf); !s) return s;
    data_crc.update(buf);
    pos = kMcapMagic.size();
    bool data_end_seen = false;
    while (pos < size) {
        auto rp = readPrefix(*source_, pos, buf);
        if (!rp) {
            if (rp.status().code() != StatusCode::kTruncated) return rp.status();
            problems.push_back(rp.status().message());
            break;
        }
        const std::uint8_t op = rp->op;
        const std::uint64_t len = rp->len;
        std::vector<std::uint8_t> prefix = buf;
        if (Status s = source_->readAt(pos + kRecordPrefixSize, static_cast<std::size_t>(len), buf);
            !s)
            return s;
        if (op == static_cast<std::uint8_t>(Opcode::kDataEnd)) {
            std::uint32_t stored = 0;
            if (!detail::parseDataEnd(buf, stored)) {
                problems.push_back("malformed Data End " + at(pos));
            } else if (stored != 0 && stored != data_crc.value()) {
                char msg[96];
                std::snprintf(msg, sizeof msg,
                              "data section CRC32 mismatch (stored 0x%08x, computed 0x%08x)",
                              stored, data_crc.value());
                problems.push_back(msg);
            }
            data_end_seen = true;
            break;
        }
        data_crc.update(prefix);
        data_crc.update(buf);
        if (op == static_cast<std::uint8_t>(Opcode::kChunk)) {
            ChunkHeader ch;
            if (Status s = decodeChunk(buf, pos, ch, records); !s) problems.push_back(s.message());
        }
        pos += kRecordPrefixSize + len;
    }
    if (!data_end_seen) problems.push_back("no Data End record (file cut short)");
    if (truncated_) problems.push_back("no valid footer (file cut short)");
    for (const auto& d : dropped_) {
        if (d.reason.find("summary") != std::string::npos) problems.push_back(d.reason);
    }
    if (problems.empty()) return Status::ok();
    std::string msg = name_ + ": " + std::to_string(problems.size()) + " problem(s): ";
    for (std::size_t i = 0; i < problems.size(); ++i) msg += (i ? "; " : "") + problems[i];
    return {StatusCode::kChecksumError, msg};
}

}  // namespace handscan::recording
