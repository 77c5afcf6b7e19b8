// McapReader: reads MCAP files written by McapWriter or any other conforming writer.
//
// A complete file is read through its summary (Chunk Indexes, Channels, Statistics; the summary
// CRC is checked). A file without a usable footer or summary - a power cut while recording, a
// copy cut short - is scanned linearly from the start: every complete chunk whose CRC verifies is
// kept, and everything else (a chunk cut short, a chunk with a bad CRC, a partial record) is
// reported in dropped() with its byte offset and the reason. Chunks found corrupt while iterating
// an indexed file are skipped and reported the same way; the other chunks still read.
//
// Messages come out in log-time order (ties in file order), optionally limited to some topics
// and a time range. Chunks are loaded lazily, so memory stays at a few chunks for any file size.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/recording/mcap_format.hpp"

namespace handscan::recording {

// A part of the file the reader could not use.
struct DroppedRegion {
    std::uint64_t offset = 0;  // byte offset in the file
    std::uint64_t length = 0;  // bytes affected (to the end of the file for truncation)
    std::string reason;
};

// One message. `data` stays valid as long as this object (it shares its chunk's buffer).
struct RecordedMessage {
    const Channel* channel = nullptr;  // owned by the reader
    std::uint32_t sequence = 0;
    TimeNs log_time = 0;  // host receive time
    TimeNs publish_time = 0;
    std::span<const std::uint8_t> data;
    std::shared_ptr<const std::vector<std::uint8_t>> storage;
};

struct ReadOptions {
    std::vector<std::string> topics;                         // empty: every topic
    TimeNs start_time = std::numeric_limits<TimeNs>::min();  // inclusive
    TimeNs end_time = std::numeric_limits<TimeNs>::max();    // inclusive
};

namespace detail {
class ByteSource;
struct ChunkRef;
}  // namespace detail

class McapReader;

// Pulls messages one by one: `while (it.next(msg)) {...}` then check status().
class MessageIterator {
public:
    ~MessageIterator();
    MessageIterator(MessageIterator&&) noexcept;
    MessageIterator& operator=(MessageIterator&&) noexcept;

    // The next message in log-time order; false at the end or on an I/O error (see status()).
    [[nodiscard]] bool next(RecordedMessage& out);
    // Ok unless reading the file failed; corrupt chunks are not errors (see McapReader::dropped()).
    const Status& status() const;

private:
    friend class McapReader;
    struct Impl;
    explicit MessageIterator(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

class McapReader {
public:
    [[nodiscard]] static Result<std::unique_ptr<McapReader>> open(const std::string& path);
    [[nodiscard]] static Result<std::unique_ptr<McapReader>> fromBuffer(
        std::vector<std::uint8_t> bytes, std::string name = "<memory>");
    ~McapReader();
    McapReader(const McapReader&) = delete;
    McapReader& operator=(const McapReader&) = delete;

    const std::string& name() const { return name_; }
    std::uint64_t fileSize() const;
    const Header& header() const { return header_; }
    // Channels by ascending id.
    const std::vector<Channel>& channels() const { return channels_; }
    const Channel* channel(std::uint16_t id) const;
    const Channel* findTopic(std::string_view topic) const;
    const std::vector<Schema>& schemas() const { return schemas_; }
    // From the summary of an indexed file; absent after a linear scan.
    const std::optional<Statistics>& statistics() const { return statistics_; }
    std::size_t chunkCount() const;
    // Earliest and latest log time over the readable chunks ({0, 0} when there are none).
    std::pair<TimeNs, TimeNs> timeRange() const;

    // True when the summary index was used; false after a linear (recovery) scan.
    bool indexed() const { return indexed_; }
    // True when the file had no valid footer: it was cut short and recovered by a linear scan.
    bool truncated() const { return truncated_; }
    // What could not be read (grows while iterating when corrupt chunks are met).
    const std::vector<DroppedRegion>& dropped() const { return dropped_; }

    [[nodiscard]] MessageIterator messages(ReadOptions options = {});
    // Calls `fn` for every message in order; returns the first I/O error.
    [[nodiscard]] Status forEachMessage(const ReadOptions& options,
                                        const std::function<void(const RecordedMessage&)>& fn);

    // Reads the whole file and checks every CRC (chunks, data section, summary). Ok only if all
    // present CRCs match; the message names every mismatch.
    [[nodiscard]] Status verify();

private:
    friend class MessageIterator;
    friend struct MessageIterator::Impl;
    McapReader(std::unique_ptr<detail::ByteSource> source, std::string name);
    [[nodiscard]] Status load();
    [[nodiscard]] Status readIndexed(const Footer& footer, std::uint64_t footer_offset);
    [[nodiscard]] Status scanLinear();
    void addChannel(const Channel& c);
    void addSchema(const Schema& s);
    // Reads, CRC-checks and decompresses a chunk; parses its schemas/channels.
    // Chunk corruption is reported in dropped() and returned with its code; kIoError means the
    // file itself could not be read.
    [[nodiscard]] Result<std::shared_ptr<const std::vector<std::uint8_t>>> loadChunk(
        detail::ChunkRef& ref);
    void drop(std::uint64_t offset, std::uint64_t length, std::string reason);

    std::unique_ptr<detail::ByteSource> source_;
    std::string name_;
    Header header_;
    std::vector<Channel> channels_;
    std::vector<Schema> schemas_;
    std::optional<Statistics> statistics_;
    std::vector<detail::ChunkRef> chunks_;
    std::map<std::uint16_t, std::size_t> channel_by_id_;  // into channels_
    std::vector<DroppedRegion> dropped_;
    std::uint64_t data_end_offset_ = 0;  // where Data End starts (0: not seen)
    bool indexed_ = false;
    bool truncated_ = false;
};

}  // namespace handscan::recording
