#include "handscan/journal/journal_writer.hpp"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "handscan/core/time.hpp"
#include "handscan/journal/journal_format.hpp"
#include "handscan/journal/journal_reader.hpp"

namespace handscan::journal {
namespace {

std::string mib(std::uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

}  // namespace

JournalWriter::JournalWriter(std::string path, int fd, JournalOptions options)
    : path_(std::move(path)), fd_(fd), options_(options), last_flush_ns_(monotonicNow()) {}

JournalWriter::~JournalWriter() {
    if (fd_ >= 0) {
        (void)flush();
        ::close(fd_);
    }
}

Result<std::unique_ptr<JournalWriter>> JournalWriter::create(const std::string& path,
                                                             const std::string& metadata_json,
                                                             JournalOptions options) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
        return Status(StatusCode::kIoError,
                      "journal " + path + ": cannot create: " + std::strerror(errno));
    }
    std::unique_ptr<JournalWriter> w(new JournalWriter(path, fd, options));
    w->refreshFreeSpace();
    std::vector<std::uint8_t> payload(metadata_json.begin(), metadata_json.end());
    if (Status s = w->writeChunk(static_cast<int>(ChunkKind::kMetadata), 1, 0.0, payload);
        !s.isOk())
        return s;
    // The directory entry must survive a power cut too.
    const std::string dir =
        path.find('/') == std::string::npos ? "." : path.substr(0, path.rfind('/'));
    if (int dfd = ::open(dir.empty() ? "/" : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
    return w;
}

Result<std::unique_ptr<JournalWriter>> JournalWriter::resume(const std::string& path,
                                                             JournalOptions options) {
    auto summary = recoverJournal(path);
    if (!summary.isOk()) return summary.status();
    if (summary->finished) {
        return Status(StatusCode::kInvalidArgument,
                      "journal " + path + ": the scan was finished; start a new one");
    }
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0)
        return Status(StatusCode::kIoError,
                      "journal " + path + ": cannot open: " + std::strerror(errno));
    std::unique_ptr<JournalWriter> w(new JournalWriter(path, fd, options));
    w->end_offset_ = summary->good_bytes;
    w->sequence_ = summary->chunks;
    w->committed_points_ = summary->points;
    w->refreshFreeSpace();
    return w;
}

void JournalWriter::refreshFreeSpace() {
    struct statvfs vfs {};
    if (::fstatvfs(fd_, &vfs) == 0)
        free_bytes_ = static_cast<std::uint64_t>(vfs.f_bavail) * vfs.f_frsize;
}

Status JournalWriter::stop(Status reason) {
    stop_reason_ = reason;
    return reason;
}

Status JournalWriter::appendPoints(std::span<const MapPoint> points) {
    if (stopped()) return stop_reason_;
    pending_points_.insert(pending_points_.end(), points.begin(), points.end());
    if (pending_points_.size() >= options_.max_chunk_points) return flush();
    return Status::ok();
}

Status JournalWriter::appendPose(const TrajectoryPose& pose) {
    if (stopped()) return stop_reason_;
    pending_poses_.push_back(pose);
    return Status::ok();
}

Status JournalWriter::appendSweep(const SweepRecord& sweep) {
    if (stopped()) return stop_reason_;
    pending_sweeps_.push_back(sweep);
    return Status::ok();
}

Status JournalWriter::flushIfDue() {
    if (toSeconds(monotonicNow() - last_flush_ns_) < options_.flush_interval_s) return Status::ok();
    return flush();
}

Status JournalWriter::flush() {
    if (stopped()) return stop_reason_;
    last_flush_ns_ = monotonicNow();
    std::vector<std::uint8_t> payload;
    if (!pending_poses_.empty()) {
        encodePoses(pending_poses_, payload);
        if (Status s = writeChunk(static_cast<int>(ChunkKind::kTrajectory),
                                  static_cast<std::uint32_t>(pending_poses_.size()),
                                  pending_poses_.back().t_s, payload);
            !s.isOk()) {
            return s;
        }
        pending_poses_.clear();
    }
    if (!pending_sweeps_.empty()) {
        payload.clear();
        encodeSweeps(pending_sweeps_, payload);
        if (Status s = writeChunk(static_cast<int>(ChunkKind::kSweepStats),
                                  static_cast<std::uint32_t>(pending_sweeps_.size()),
                                  pending_sweeps_.back().t_start_s, payload);
            !s.isOk()) {
            return s;
        }
        pending_sweeps_.clear();
    }
    // Large backlogs are split so one chunk stays a bounded read for recovery and export.
    std::size_t done = 0;
    while (done < pending_points_.size()) {
        const std::size_t n = std::min(options_.max_chunk_points, pending_points_.size() - done);
        payload.clear();
        const std::span<const MapPoint> part(pending_points_.data() + done, n);
        encodePoints(part, payload);
        double t_last = 0.0;
        for (const MapPoint& p : part) t_last = std::max(t_last, p.t_s);
        if (Status s = writeChunk(static_cast<int>(ChunkKind::kPoints),
                                  static_cast<std::uint32_t>(n), t_last, payload);
            !s.isOk()) {
            pending_points_.erase(pending_points_.begin(),
                                  pending_points_.begin() + static_cast<std::ptrdiff_t>(done));
            return s;
        }
        committed_points_ += n;
        done += n;
    }
    pending_points_.clear();
    return Status::ok();
}

Status JournalWriter::finish() {
    if (Status s = flush(); !s.isOk()) return s;
    return writeChunk(static_cast<int>(ChunkKind::kEndOfScan), 0, 0.0, {});
}

Status JournalWriter::writeChunk(int kind, std::uint32_t records, double t_last,
                                 const std::vector<std::uint8_t>& payload) {
    const std::uint64_t bytes = kChunkHeaderBytes + payload.size();
    refreshFreeSpace();
    if (free_bytes_ < bytes + options_.reserve_bytes) {
        return stop(Status(StatusCode::kNoSpace,
                           "journal " + path_ + ": only " + mib(free_bytes_) + " free, " +
                               mib(options_.reserve_bytes) +
                               " kept in reserve: scan stopped; everything up to chunk " +
                               std::to_string(sequence_) +
                               " is safe; export the scan, then free space"));
    }
    ChunkHeader h;
    h.kind = static_cast<ChunkKind>(kind);
    h.sequence = sequence_;
    h.record_count = records;
    h.payload_bytes = static_cast<std::uint32_t>(payload.size());
    h.t_last_s = t_last;
    h.payload_crc = crc32(payload);
    const std::vector<std::uint8_t> header = encodeHeader(h);
    iovec iov[2] = {{const_cast<std::uint8_t*>(header.data()), header.size()},
                    {const_cast<std::uint8_t*>(payload.data()), payload.size()}};
    std::uint64_t written = 0;
    while (written < bytes) {
        // Advance the iovecs past what was written (pwritev may write partially).
        iovec part[2];
        int count = 0;
        std::uint64_t skip = written;
        for (const iovec& v : iov) {
            if (skip >= v.iov_len) {
                skip -= v.iov_len;
                continue;
            }
            part[count++] = {static_cast<std::uint8_t*>(v.iov_base) + skip, v.iov_len - skip};
            skip = 0;
        }
        const ssize_t n = ::pwritev(fd_, part, count, static_cast<off_t>(end_offset_ + written));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int err = errno;
            // Cut what was partly written so the file ends on a whole chunk.
            (void)!::ftruncate(fd_, static_cast<off_t>(end_offset_));
            return stop(Status(err == ENOSPC ? StatusCode::kNoSpace : StatusCode::kIoError,
                               "journal " + path_ + ": write failed at byte " +
                                   std::to_string(end_offset_) + ": " + std::strerror(err) +
                                   "; scan stopped, everything before is safe"));
        }
        written += static_cast<std::uint64_t>(n);
    }
    if (::fdatasync(fd_) != 0) {
        const int err = errno;
        (void)!::ftruncate(fd_, static_cast<off_t>(end_offset_));
        return stop(Status(StatusCode::kIoError,
                           "journal " + path_ + ": fdatasync failed: " + std::strerror(err)));
    }
    end_offset_ += bytes;
    ++sequence_;
    return Status::ok();
}

}  // namespace handscan::journal
