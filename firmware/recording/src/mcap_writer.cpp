#include "handscan/recording/mcap_writer.hpp"

#include <unistd.h>  // fdatasync: the only way to make a closed chunk survive a power cut

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <set>

#include "byte_io.hpp"
#include "chunk_compression.hpp"
#include "handscan/core/log.hpp"
#include "mcap_records.hpp"

namespace handscan::recording {

using detail::ByteWriter;

class McapWriter::Sink {
public:
    virtual ~Sink() = default;
    [[nodiscard]] virtual Status write(std::span<const std::uint8_t> bytes) = 0;
    [[nodiscard]] virtual Status flush(bool sync) = 0;
    [[nodiscard]] virtual Status close() = 0;
    virtual std::vector<std::uint8_t> take() { return {}; }
};

class McapWriter::FileSink final : public Sink {
public:
    FileSink(std::FILE* f, std::string path) : f_(f), path_(std::move(path)) {}
    ~FileSink() override {
        if (f_ != nullptr) std::fclose(f_);
    }
    Status write(std::span<const std::uint8_t> bytes) override {
        if (std::fwrite(bytes.data(), 1, bytes.size(), f_) != bytes.size()) return error("writing");
        return Status::ok();
    }
    Status flush(bool sync) override {
        if (std::fflush(f_) != 0) return error("flushing");
        if (sync && ::fdatasync(fileno(f_)) != 0) return error("syncing");
        return Status::ok();
    }
    Status close() override {
        const int rc = std::fclose(f_);
        f_ = nullptr;
        if (rc != 0) return error("closing");
        return Status::ok();
    }

private:
    Status error(const char* what) const {
        const int e = errno;
        return {e == ENOSPC ? StatusCode::kNoSpace : StatusCode::kIoError,
                path_ + ": " + what + " the recording failed: " + std::strerror(e) +
                    (e == ENOSPC ? " (free space on the recording disk)" : "")};
    }
    std::FILE* f_;
    std::string path_;
};

class McapWriter::MemorySink final : public Sink {
public:
    Status write(std::span<const std::uint8_t> bytes) override {
        buf_.insert(buf_.end(), bytes.begin(), bytes.end());
        return Status::ok();
    }
    Status flush(bool) override { return Status::ok(); }
    Status close() override { return Status::ok(); }
    std::vector<std::uint8_t> take() override { return std::move(buf_); }

private:
    std::vector<std::uint8_t> buf_;
};

// The chunk being filled: its uncompressed records and the message index per channel.
struct McapWriter::OpenChunk {
    explicit OpenChunk(const McapWriterOptions& o) : compressor(o.compression, o.zstd_level) {}
    std::vector<std::uint8_t> records;
    std::map<std::uint16_t, std::vector<MessageIndexEntry>> index;  // ordered by channel id
    std::set<std::uint16_t> channels_written;  // Channel records already in this chunk
    std::set<std::uint16_t> schemas_written;
    TimeNs start = 0;
    TimeNs end = 0;
    std::uint64_t messages = 0;
    detail::ChunkCompressor compressor;
    std::vector<std::uint8_t> compressed;  // reused between chunks
    std::vector<std::uint8_t> scratch;     // record prefixes and message indexes
};

McapWriter::McapWriter(std::unique_ptr<Sink> sink, McapWriterOptions options)
    : options_(std::move(options)),
      sink_(std::move(sink)),
      chunk_(std::make_unique<OpenChunk>(options_)) {}

McapWriter::~McapWriter() {
    if (!closed_) {
        if (Status s = close(); !s) log().error("recording not closed cleanly: {}", s.message());
    }
}

Result<std::unique_ptr<McapWriter>> McapWriter::create(const std::string& path,
                                                       McapWriterOptions options) {
    if (!detail::isSupportedCompression(options.compression)) {
        return Status{StatusCode::kUnsupported, "McapWriter: compression '" + options.compression +
                                                    "' is not supported (use \"\" or \"zstd\")"};
    }
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        return Status{StatusCode::kIoError,
                      path + ": cannot create the recording: " + std::strerror(errno) +
                          " (check the directory exists and is writable)"};
    }
    std::unique_ptr<McapWriter> w(
        new McapWriter(std::make_unique<FileSink>(f, path), std::move(options)));
    if (Status s = w->start(); !s) return s;
    return w;
}

Result<std::unique_ptr<McapWriter>> McapWriter::inMemory(McapWriterOptions options) {
    if (!detail::isSupportedCompression(options.compression)) {
        return Status{StatusCode::kUnsupported, "McapWriter: compression '" + options.compression +
                                                    "' is not supported (use \"\" or \"zstd\")"};
    }
    std::unique_ptr<McapWriter> w(
        new McapWriter(std::make_unique<MemorySink>(), std::move(options)));
    if (Status s = w->start(); !s) return s;
    return w;
}

Status McapWriter::start() {
    std::vector<std::uint8_t> buf(kMcapMagic.begin(), kMcapMagic.end());
    ByteWriter w(buf);
    detail::writeHeader(w, {options_.profile, options_.library});
    return emit(buf);
}

Status McapWriter::emit(std::span<const std::uint8_t> bytes) {
    if (!failed_) return failed_;
    if (data_crc_active_) data_crc_.update(bytes);
    failed_ = sink_->write(bytes);
    if (failed_) offset_ += bytes.size();
    return failed_;
}

Result<std::uint16_t> McapWriter::addSchema(std::string name, std::string encoding,
                                            std::vector<std::uint8_t> data) {
    if (schemas_.size() >= 0xFFFE)
        return Status{StatusCode::kInvalidArgument, "McapWriter: too many schemas"};
    Schema s;
    s.id = static_cast<std::uint16_t>(schemas_.size() + 1);
    s.name = std::move(name);
    s.encoding = std::move(encoding);
    s.data = std::move(data);
    schemas_.push_back(std::move(s));
    return schemas_.back().id;
}

Result<std::uint16_t> McapWriter::addChannel(std::string topic, std::string message_encoding,
                                             std::uint16_t schema_id,
                                             std::map<std::string, std::string> metadata) {
    if (schema_id > schemas_.size()) {
        return Status{StatusCode::kInvalidArgument,
                      "McapWriter::addChannel(" + topic + "): schema id " +
                          std::to_string(schema_id) + " was never added"};
    }
    for (const auto& c : channels_) {
        if (c.topic == topic) {
            return Status{StatusCode::kInvalidArgument,
                          "McapWriter::addChannel: topic " + topic + " already exists"};
        }
    }
    if (channels_.size() >= 0xFFFF)
        return Status{StatusCode::kInvalidArgument, "McapWriter: too many channels"};
    Channel c;
    c.id = static_cast<std::uint16_t>(channels_.size());
    c.schema_id = schema_id;
    c.topic = std::move(topic);
    c.message_encoding = std::move(message_encoding);
    c.metadata = std::move(metadata);
    channels_.push_back(std::move(c));
    next_sequence_.push_back(0);
    return channels_.back().id;
}

Status McapWriter::write(std::uint16_t channel_id, TimeNs log_time,
                         std::span<const std::uint8_t> data) {
    if (channel_id >= channels_.size()) {
        return {StatusCode::kInvalidArgument,
                "McapWriter::write: unknown channel id " + std::to_string(channel_id)};
    }
    return write(MessageHeader{channel_id, next_sequence_[channel_id], log_time, log_time}, data);
}

Status McapWriter::write(const MessageHeader& header, std::span<const std::uint8_t> data) {
    if (closed_) return {StatusCode::kInvalidArgument, "McapWriter::write after close()"};
    if (!failed_) return failed_;
    if (header.channel_id >= channels_.size()) {
        return {StatusCode::kInvalidArgument,
                "McapWriter::write: unknown channel id " + std::to_string(header.channel_id)};
    }
    if (header.log_time < 0) {
        return {StatusCode::kInvalidArgument, "McapWriter::write: negative log time " +
                                                  std::to_string(header.log_time) + " on " +
                                                  channels_[header.channel_id].topic};
    }
    OpenChunk& c = *chunk_;
    ByteWriter w(c.records);
    // Each chunk is self-contained: the schema and channel precede the channel's first message.
    const Channel& ch = channels_[header.channel_id];
    if (c.channels_written.insert(ch.id).second) {
        if (ch.schema_id != 0 && c.schemas_written.insert(ch.schema_id).second) {
            detail::writeSchema(w, schemas_[ch.schema_id - 1]);
        }
        detail::writeChannel(w, ch);
    }
    c.index[header.channel_id].push_back({header.log_time, c.records.size()});
    detail::writeMessage(w, header, data);
    c.start = c.messages == 0 ? header.log_time : std::min(c.start, header.log_time);
    c.end = c.messages == 0 ? header.log_time : std::max(c.end, header.log_time);
    ++c.messages;
    next_sequence_[header.channel_id] = header.sequence + 1;

    stats_.message_start_time = stats_.message_count == 0
                                    ? header.log_time
                                    : std::min(stats_.message_start_time, header.log_time);
    stats_.message_end_time = stats_.message_count == 0
                                  ? header.log_time
                                  : std::max(stats_.message_end_time, header.log_time);
    ++stats_.message_count;
    ++stats_.channel_message_counts[header.channel_id];

    const bool full = c.records.size() >= options_.chunk_size_bytes;
    const bool long_enough =
        options_.chunk_duration_ns > 0 && c.end - c.start >= options_.chunk_duration_ns;
    if (full || long_enough) return closeChunk();
    return Status::ok();
}

Status McapWriter::closeChunk() {
    OpenChunk& c = *chunk_;
    if (c.messages == 0) return Status::ok();
    if (Status s = c.compressor.compress(c.records, c.compressed); !s) return failed_ = s;

    // Data that does not compress (random noise, already-compressed MJPEG buffers) is stored as
    // is: smaller, and the reader skips a useless decompression.
    std::span<const std::uint8_t> payload = c.compressed;
    std::string compression = c.compressor.compression();
    if (!compression.empty() && c.compressed.size() >= c.records.size()) {
        payload = c.records;
        compression.clear();
    }

    ChunkIndex ci;
    ci.message_start_time = c.start;
    ci.message_end_time = c.end;
    ci.chunk_start_offset = offset_;
    ci.compression = std::move(compression);
    ci.compressed_size = payload.size();
    ci.uncompressed_size = c.records.size();

    // Chunk record: fixed fields, then the (compressed) records written straight from their buffer.
    c.scratch.clear();
    ByteWriter w(c.scratch);
    const std::uint64_t content_size =
        8 + 8 + 8 + 4 + 4 + ci.compression.size() + 8 + payload.size();
    w.u8(static_cast<std::uint8_t>(Opcode::kChunk));
    w.u64(content_size);
    w.u64(static_cast<std::uint64_t>(c.start));
    w.u64(static_cast<std::uint64_t>(c.end));
    w.u64(c.records.size());
    w.u32(crc32(c.records));
    w.string(ci.compression);
    w.u64(payload.size());
    if (Status s = emit(c.scratch); !s) return s;
    if (Status s = emit(payload); !s) return s;
    ci.chunk_length = kRecordPrefixSize + content_size;

    // Message Index records, one per channel present in the chunk.
    c.scratch.clear();
    for (auto& [channel_id, entries] : c.index) {
        // In log-time order, as readers that seek by time expect (arrivals can be out of order).
        std::stable_sort(entries.begin(), entries.end(),
                         [](const MessageIndexEntry& a, const MessageIndexEntry& b) {
                             return a.log_time < b.log_time;
                         });
        ci.message_index_offsets[channel_id] = offset_ + c.scratch.size();
        detail::writeMessageIndex(w, MessageIndex{channel_id, std::move(entries)});
    }
    ci.message_index_length = c.scratch.size();
    if (Status s = emit(c.scratch); !s) return s;
    if (Status s = sink_->flush(options_.sync_each_chunk); !s) return failed_ = s;

    chunk_indexes_.push_back(std::move(ci));
    ++stats_.chunk_count;
    c.records.clear();
    c.index.clear();
    c.channels_written.clear();
    c.schemas_written.clear();
    c.messages = 0;
    return Status::ok();
}

Status McapWriter::flush() {
    if (closed_) return Status::ok();
    if (Status s = closeChunk(); !s) return s;
    return failed_ ? (failed_ = sink_->flush(options_.sync_each_chunk)) : failed_;
}

Status McapWriter::writeSummaryAndFooter() {
    std::vector<std::uint8_t> buf;
    ByteWriter w(buf);
    detail::writeDataEnd(w, data_crc_.value());
    data_crc_active_ = false;

    // Summary section, grouped by opcode; each group gets a Summary Offset record.
    const std::uint64_t summary_start = offset_ + buf.size();
    std::vector<SummaryOffset> groups;
    auto group = [&](Opcode op, auto&& write_all) {
        const std::size_t start = buf.size();
        write_all();
        if (buf.size() > start) groups.push_back({op, offset_ + start, buf.size() - start});
    };
    group(Opcode::kSchema, [&] {
        for (const auto& s : schemas_) detail::writeSchema(w, s);
    });
    group(Opcode::kChannel, [&] {
        for (const auto& c : channels_) detail::writeChannel(w, c);
    });
    group(Opcode::kChunkIndex, [&] {
        for (const auto& ci : chunk_indexes_) detail::writeChunkIndex(w, ci);
    });
    stats_.schema_count = static_cast<std::uint16_t>(schemas_.size());
    stats_.channel_count = static_cast<std::uint32_t>(channels_.size());
    group(Opcode::kStatistics, [&] { detail::writeStatistics(w, stats_); });

    const std::uint64_t summary_offset_start = offset_ + buf.size();
    for (const auto& g : groups) detail::writeSummaryOffset(w, g);

    // The summary CRC covers the summary, the summary offsets and the footer up to summary_crc.
    const std::size_t footer_pos = buf.size();
    detail::writeFooter(w, Footer{summary_start, summary_offset_start, 0});
    const std::size_t summary_pos = static_cast<std::size_t>(summary_start - offset_);
    const std::uint32_t summary_crc = crc32(std::span<const std::uint8_t>(buf).subspan(
        summary_pos, footer_pos + kRecordPrefixSize + 16 - summary_pos));
    w.patchU32(footer_pos + kRecordPrefixSize + 16, summary_crc);
    w.bytes(kMcapMagic);
    return emit(buf);
}

Status McapWriter::close() {
    if (closed_) return failed_;
    Status s = closeChunk();
    if (s) s = writeSummaryAndFooter();
    if (s) s = sink_->flush(options_.sync_each_chunk);
    Status c = sink_->close();
    closed_ = true;
    if (!s) return failed_ = s;
    return failed_ = c;
}

std::vector<std::uint8_t> McapWriter::takeBuffer() { return sink_->take(); }

}  // namespace handscan::recording
