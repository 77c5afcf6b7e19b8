// McapWriter: writes an indexed, chunked MCAP file (https://mcap.dev/spec) as a recorder thread
// produces messages. Messages are batched into Chunks (optionally zstd-compressed, each with a
// CRC32 of its uncompressed records and followed by Message Index records); a chunk closes when
// its records reach `chunk_size_bytes` or span `chunk_duration_ns` of log time, and is then
// written and flushed, so a power cut loses at most the open chunk. close() appends Data End
// (with the data-section CRC), the summary (Schemas, Channels, Chunk Indexes, Statistics),
// Summary Offsets and the Footer.
//
// Every chunk repeats the Schema and Channel records of the channels it uses, so each chunk can
// be decoded on its own when a truncated file is recovered.
//
// Not thread-safe: one thread owns a writer (the Recorder's writer thread).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/recording/crc32.hpp"
#include "handscan/recording/mcap_format.hpp"

namespace handscan::recording {

struct McapWriterOptions {
    std::string profile;  // "" : handscan recordings follow no well-known profile
    std::string library = "handscan-recording";  // written to the Header
    std::string compression = "zstd";            // "" (none) or "zstd"
    int zstd_level = 1;                          // fast: the writer must keep up with camera images
    std::size_t chunk_size_bytes = 1u << 20;     // close a chunk at this many uncompressed bytes
    TimeNs chunk_duration_ns = kNsPerSec;  // ... or when it spans this much log time (0: never)
    bool sync_each_chunk = false;          // fdatasync() after every chunk (power-cut safety)
};

class McapWriter {
public:
    // Creates (truncates) `path` and writes the magic and Header.
    [[nodiscard]] static Result<std::unique_ptr<McapWriter>> create(const std::string& path,
                                                                    McapWriterOptions options = {});
    // A writer into memory (tests, simulators that post-process); see takeBuffer().
    [[nodiscard]] static Result<std::unique_ptr<McapWriter>> inMemory(
        McapWriterOptions options = {});

    ~McapWriter();  // closes the file if close() was not called (errors are logged)
    McapWriter(const McapWriter&) = delete;
    McapWriter& operator=(const McapWriter&) = delete;

    // Registers a schema; returns its id (>= 1).
    [[nodiscard]] Result<std::uint16_t> addSchema(std::string name, std::string encoding,
                                                  std::vector<std::uint8_t> data = {});
    // Registers a channel (topics must be unique); returns its id.
    [[nodiscard]] Result<std::uint16_t> addChannel(
        std::string topic, std::string message_encoding, std::uint16_t schema_id = 0,
        std::map<std::string, std::string> metadata = {});

    // Appends one message. `log_time` is the host receive time; sequence numbers count per channel
    // and publish_time equals log_time.
    [[nodiscard]] Status write(std::uint16_t channel_id, TimeNs log_time,
                               std::span<const std::uint8_t> data);
    // Appends one message with an explicit header (sequence, publish_time).
    [[nodiscard]] Status write(const MessageHeader& header, std::span<const std::uint8_t> data);

    // Closes the open chunk and hands everything to the OS.
    [[nodiscard]] Status flush();
    // Writes the open chunk, Data End, summary and footer. Further writes fail.
    [[nodiscard]] Status close();

    // The file's bytes (in-memory writers only; after close() for a complete file).
    std::vector<std::uint8_t> takeBuffer();

    std::uint64_t bytesWritten() const { return offset_; }
    std::uint64_t messageCount() const { return stats_.message_count; }
    std::uint32_t chunkCount() const { return stats_.chunk_count; }
    const std::vector<Channel>& channels() const { return channels_; }

private:
    class Sink;
    class FileSink;
    class MemorySink;
    struct OpenChunk;

    McapWriter(std::unique_ptr<Sink> sink, McapWriterOptions options);
    [[nodiscard]] Status start();
    [[nodiscard]] Status emit(std::span<const std::uint8_t> bytes);
    [[nodiscard]] Status closeChunk();
    [[nodiscard]] Status writeSummaryAndFooter();

    McapWriterOptions options_;
    std::unique_ptr<Sink> sink_;
    std::unique_ptr<OpenChunk> chunk_;
    std::vector<Schema> schemas_;
    std::vector<Channel> channels_;
    std::vector<std::uint32_t> next_sequence_;  // per channel id
    std::vector<ChunkIndex> chunk_indexes_;
    Statistics stats_;
    std::uint64_t offset_ = 0;  // bytes written so far
    Crc32 data_crc_;
    bool data_crc_active_ = true;  // the data-section CRC covers everything before Data End
    bool closed_ = false;
    Status failed_;  // first write error: the writer stops and keeps reporting it
};

}  // namespace handscan::recording
