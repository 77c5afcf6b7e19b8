#include "handscan/journal/journal_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "handscan/journal/journal_format.hpp"

namespace handscan::journal {
namespace {

// RAII fd for reading.
struct ReadFd {
    int fd;
    explicit ReadFd(const std::string& path) : fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {}
    ~ReadFd() {
        if (fd >= 0) ::close(fd);
    }
};

bool readAt(int fd, std::uint64_t offset, std::uint8_t* out, std::size_t n) {
    std::size_t got = 0;
    while (got < n) {
        const ssize_t r = ::pread(fd, out + got, n - got, static_cast<off_t>(offset + got));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;
        got += static_cast<std::size_t>(r);
    }
    return true;
}

}  // namespace

Result<JournalReader> JournalReader::open(const std::string& path) {
    ReadFd f(path);
    if (f.fd < 0)
        return Status(StatusCode::kIoError,
                      "journal " + path + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    ::fstat(f.fd, &st);
    JournalReader reader;
    JournalSummary& s = reader.summary_;
    s.path = path;
    s.file_bytes = static_cast<std::uint64_t>(st.st_size);
    std::uint64_t offset = 0;
    std::vector<std::uint8_t> header(kChunkHeaderBytes);
    std::vector<std::uint8_t> payload;
    while (offset < s.file_bytes) {
        const std::string where =
            "chunk " + std::to_string(s.chunks) + " at byte " + std::to_string(offset);
        if (s.file_bytes - offset < kChunkHeaderBytes ||
            !readAt(f.fd, offset, header.data(), kChunkHeaderBytes)) {
            s.damage = where + ": truncated header";
            break;
        }
        ChunkHeader h;
        if (!decodeHeader(header, h)) {
            s.damage = where + ": bad header (magic, version or CRC)";
            break;
        }
        if (h.sequence != s.chunks) {
            s.damage = where + ": sequence " + std::to_string(h.sequence) + " out of order";
            break;
        }
        if (s.file_bytes - offset - kChunkHeaderBytes < h.payload_bytes) {
            s.damage = where + ": truncated payload (" +
                       std::to_string(s.file_bytes - offset - kChunkHeaderBytes) + " of " +
                       std::to_string(h.payload_bytes) + " bytes)";
            break;
        }
        payload.resize(h.payload_bytes);
        if (!readAt(f.fd, offset + kChunkHeaderBytes, payload.data(), payload.size()) ||
            crc32(payload) != h.payload_crc) {
            if (h.kind != ChunkKind::kSweepStats) {
                s.damage = where + ": payload CRC mismatch";
                break;
            }
            // The header (its own CRC) says how long the chunk is: statistics are not the map,
            // so a damaged one is skipped and named rather than ending the journal there.
            s.sweep_damage.push_back(where + ": per-sweep statistics (" +
                                     std::to_string(h.record_count) +
                                     " sweeps): payload CRC mismatch; left out");
            payload.clear();
        }
        switch (h.kind) {
            case ChunkKind::kMetadata:
                s.metadata_json.assign(payload.begin(), payload.end());
                break;
            case ChunkKind::kPoints:
                if (h.payload_bytes != h.record_count * kPointRecordBytes) {
                    s.damage = where + ": point count does not match the payload size";
                } else {
                    reader.point_chunks_.push_back({offset + kChunkHeaderBytes, h.payload_bytes});
                    s.points += h.record_count;
                }
                break;
            case ChunkKind::kTrajectory:
                decodePoses(payload, s.trajectory);
                break;
            case ChunkKind::kSweepStats:
                if (std::string bad = decodeSweeps(payload, s.sweeps); !bad.empty())
                    s.sweep_damage.push_back(where + ": per-sweep statistics: " + bad +
                                             "; the rest of the chunk left out");
                break;
            case ChunkKind::kEndOfScan:
                s.finished = true;
                break;
            default:
                s.damage =
                    where + ": unknown chunk kind " + std::to_string(static_cast<int>(h.kind));
        }
        if (!s.damage.empty()) break;
        s.t_last_s = std::max(s.t_last_s, h.t_last_s);
        offset += kChunkHeaderBytes + h.payload_bytes;
        ++s.chunks;
        s.good_bytes = offset;
    }
    if (s.chunks == 0) {
        return Status(StatusCode::kTruncated,
                      "journal " + path + ": no intact chunk (" +
                          (s.damage.empty() ? std::string("empty file") : s.damage) + ")");
    }
    return reader;
}

Status JournalReader::forEachPoints(
    const std::function<void(std::span<const MapPoint>)>& sink) const {
    ReadFd f(summary_.path);
    if (f.fd < 0)
        return Status(StatusCode::kIoError,
                      "journal " + summary_.path + ": cannot open: " + std::strerror(errno));
    std::vector<std::uint8_t> payload;
    std::vector<MapPoint> points;
    for (std::size_t i = 0; i < point_chunks_.size(); ++i) {
        const ChunkRef& c = point_chunks_[i];
        if (i + 1 <
            point_chunks_.size()) {  // let the kernel read the next chunk while this one is used
            const ChunkRef& next = point_chunks_[i + 1];
            ::posix_fadvise(f.fd, static_cast<off_t>(next.offset), static_cast<off_t>(next.bytes),
                            POSIX_FADV_WILLNEED);
        }
        payload.resize(c.bytes);
        if (!readAt(f.fd, c.offset, payload.data(), payload.size())) {
            return Status(
                StatusCode::kIoError,
                "journal " + summary_.path + ": read failed at byte " + std::to_string(c.offset));
        }
        // Same size as the last chunk (the usual case): resize() is a no-op, nothing is zeroed.
        points.resize(c.bytes / kPointRecordBytes);
        decodePoints(payload, std::span<MapPoint>(points));
        sink(points);
    }
    return Status::ok();
}

Result<JournalSummary> recoverJournal(const std::string& path) {
    auto reader = JournalReader::open(path);
    if (!reader.isOk()) return reader.status();
    const JournalSummary& s = reader->summary();
    if (s.good_bytes < s.file_bytes) {
        if (::truncate(path.c_str(), static_cast<off_t>(s.good_bytes)) != 0) {
            return Status(
                StatusCode::kIoError,
                "journal " + path + ": cannot cut the damaged tail: " + std::strerror(errno));
        }
    }
    return s;
}

}  // namespace handscan::journal
