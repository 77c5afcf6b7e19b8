#include "handscan/export/safe_file.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "buffer_pipeline.hpp"

namespace handscan::exporter {
namespace {

// Large sequential requests run at the medium's speed; three of them keep the encoder, the
// checksum and the device busy at the same time (12 MiB per file being written).
constexpr std::size_t kBufferBytes = 4u << 20;
constexpr std::size_t kBuffers = 3;

std::string dirOf(const std::string& path) {
    const std::filesystem::path p(path);
    return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}

// zlib's crc32 restarts from 0 on a null buffer: empty spans must not reach it.
std::uint32_t crcUpdate(std::uint32_t crc, std::span<const std::uint8_t> bytes) {
    if (bytes.empty()) return crc;
    return static_cast<std::uint32_t>(::crc32_z(crc, bytes.data(), bytes.size()));
}

// The part of `bytes` (at file `offset`) after the header region, which is checksummed apart.
std::span<const std::uint8_t> afterHeader(std::span<const std::uint8_t> bytes, std::uint64_t offset,
                                          std::size_t header_bytes) {
    const std::uint64_t skip = offset < header_bytes ? header_bytes - offset : 0;
    return skip >= bytes.size() ? std::span<const std::uint8_t>{}
                                : bytes.subspan(static_cast<std::size_t>(skip));
}

bool clearDirect(int fd) {
    const int flags = ::fcntl(fd, F_GETFL);
    return flags >= 0 && ::fcntl(fd, F_SETFL, flags & ~O_DIRECT) == 0;
}

}  // namespace

SafeFileWriter::SafeFileWriter(std::string final_path, WriteFaults faults)
    : final_path_(std::move(final_path)), faults_(std::move(faults)) {
    const std::filesystem::path p(final_path_);
    partial_path_ =
        (std::filesystem::path(dirOf(final_path_)) / ("." + p.filename().string() + ".partial"))
            .string();
}

SafeFileWriter::~SafeFileWriter() {
    pipe_.reset();  // the I/O thread stops before its file descriptor goes
    if (fd_ >= 0) ::close(fd_);
    if (!committed_ && !partial_path_.empty()) ::unlink(partial_path_.c_str());
}

Status SafeFileWriter::fail(const std::string& what, int err) {
    pipe_.reset();
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    ::unlink(partial_path_.c_str());  // may fail too when the medium is gone; nothing else to do
    std::string hint;
    if (err == ENOSPC)
        hint = ": the target is full; free space or use a larger stick, then export again";
    else if (err == EROFS || err == EACCES || err == EPERM)
        hint = ": the target is read-only; check the stick's lock switch";
    else if (err == EIO || err == ENODEV || err == ENOENT || err == ENXIO)
        hint = ": the target vanished or failed (stick pulled?); reinsert it and export again";
    return Status(err == ENOSPC ? StatusCode::kNoSpace : StatusCode::kIoError,
                  "export " + final_path_ + ": " + what + ": " + std::strerror(err) + hint +
                      " (the scan on internal storage is untouched)");
}

Status SafeFileWriter::open() {
    constexpr int kFlags = O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC;
    if (!faults_.buffered_only) {
        fd_ = ::open(partial_path_.c_str(), kFlags | O_DIRECT, 0644);
        if (fd_ < 0 && errno != EINVAL) return fail("cannot create " + partial_path_, errno);
        direct_ = fd_ >= 0;
    }
    if (fd_ < 0) fd_ = ::open(partial_path_.c_str(), kFlags, 0644);  // no O_DIRECT here (EINVAL)
    if (fd_ < 0) return fail("cannot create " + partial_path_, errno);
    // The I/O thread checksums each buffer, then writes it; it alone touches crc_ until finish().
    pipe_ = std::make_unique<BufferPipeline>(
        kBufferBytes, kBuffers, [this](std::span<const std::uint8_t> bytes, std::uint64_t offset) {
            crc_ = crcUpdate(crc_, afterHeader(bytes, offset, header_bytes_));
            return writeAt(bytes, offset);
        });
    return Status::ok();
}

Status SafeFileWriter::reserveHeader(std::size_t bytes) {
    if (fd_ < 0) return Status(StatusCode::kIoError, "export " + final_path_ + ": not open");
    if (flushed_ != 0 || fill_ != 0 || bytes > kBufferBytes) {
        return Status(StatusCode::kInvalidArgument,
                      "export " + final_path_ + ": header after data");
    }
    header_bytes_ = bytes;
    header_.assign(bytes, 0);
    std::memset(pipe_->current().data(), 0, bytes);
    fill_ = bytes;
    return Status::ok();
}

Status SafeFileWriter::patchHeader(std::span<const std::uint8_t> header) {
    if (header.size() != header_.size()) {
        return Status(StatusCode::kInvalidArgument,
                      "export " + final_path_ + ": header is " + std::to_string(header.size()) +
                          " bytes, reserved " + std::to_string(header_.size()));
    }
    header_.assign(header.begin(), header.end());
    // Still in the first buffer: patch it there. Otherwise commit() writes it once the data is out.
    if (flushed_ == 0 && pipe_)
        std::memcpy(pipe_->current().data(), header_.data(), header_.size());
    return Status::ok();
}

Status SafeFileWriter::write(std::span<const std::uint8_t> bytes) {
    if (fd_ < 0) return Status(StatusCode::kIoError, "export " + final_path_ + ": not open");
    while (!bytes.empty()) {
        const std::span<std::uint8_t> buf = pipe_->current();
        const std::size_t n = std::min(bytes.size(), buf.size() - fill_);
        std::memcpy(buf.data() + fill_, bytes.data(), n);
        fill_ += n;
        bytes = bytes.subspan(n);
        if (fill_ == buf.size()) {
            if (Status s = handOff(); !s.isOk()) return s;
        }
    }
    return Status::ok();
}

Status SafeFileWriter::handOff() {
    const int err = pipe_->submit(fill_, flushed_);
    flushed_ += fill_;
    fill_ = 0;
    return err == 0 ? Status::ok() : ioFailure(err);
}

Status SafeFileWriter::ioFailure(int err) {
    return fail("write failed at byte " + std::to_string(error_offset_), err);
}

int SafeFileWriter::writeAt(std::span<const std::uint8_t> bytes, std::uint64_t offset) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        if (faults_.before_write) {
            if (const int err = faults_.before_write(offset + done); err != 0) {
                error_offset_ = offset + done;
                return err;
            }
        }
        const ssize_t n = ::pwrite(fd_, bytes.data() + done, bytes.size() - done,
                                   static_cast<off_t>(offset + done));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && errno == EINVAL && direct_ && clearDirect(fd_)) {
            direct_ = false;  // the filesystem opened with O_DIRECT but refuses such writes
            continue;
        }
        if (n <= 0) {
            error_offset_ = offset + done;
            return n == 0 ? EIO : errno;
        }
        done += static_cast<std::size_t>(n);
    }
    return 0;
}

Status SafeFileWriter::commit() {
    if (fd_ < 0) return Status(StatusCode::kIoError, "export " + final_path_ + ": not open");
    // Whole blocks go through the I/O thread; with O_DIRECT, the unaligned tail is then written
    // through the page cache (fsync below covers it).
    const std::size_t aligned = direct_ ? fill_ & ~(BufferPipeline::kAlignment - 1) : fill_;
    const std::span<const std::uint8_t> tail(pipe_->current().data() + aligned, fill_ - aligned);
    const std::uint64_t tail_offset = flushed_ + aligned;
    int err = aligned > 0 ? pipe_->submit(aligned, flushed_) : 0;
    if (err == 0)
        err = pipe_->finish();  // the tail's buffer is not reused after this: nothing fills it
    if (err != 0) return ioFailure(err);
    flushed_ += fill_;
    fill_ = 0;
    if ((!tail.empty() || !header_.empty()) && direct_ && !clearDirect(fd_))
        return fail("fcntl(O_DIRECT) failed", errno);
    if (!tail.empty()) {
        crc_ = crcUpdate(crc_, afterHeader(tail, tail_offset, header_bytes_));
        if (const int e = writeAt(tail, tail_offset); e != 0) return ioFailure(e);
    }
    // The header region went out as placeholder bytes; now that the data is out, the real header.
    for (std::size_t done = 0; done < header_.size();) {
        const ssize_t n =
            ::pwrite(fd_, header_.data() + done, header_.size() - done, static_cast<off_t>(done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return fail("header write failed", n == 0 ? EIO : errno);
        done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd_) != 0) return fail("fsync failed", errno);
    pipe_.reset();
    ::posix_fadvise(fd_, 0, 0, POSIX_FADV_DONTNEED);  // the read-back must come from the medium
    ::close(fd_);
    fd_ = -1;
    if (faults_.before_verify) faults_.before_verify(partial_path_);
    if (Status s = verify(); !s.isOk()) return s;
    if (::rename(partial_path_.c_str(), final_path_.c_str()) != 0)
        return fail("rename failed", errno);
    committed_ = true;
    const int dfd = ::open(dirOf(final_path_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
    return Status::ok();
}

// Reads the file back from the medium (O_DIRECT, or buffered after dropping the cached pages)
// while the I/O thread checksums the previous block, and compares with what was written.
Status SafeFileWriter::verify() {
    bool direct_read = false;
    int rfd = -1;
    if (direct_) {
        rfd = ::open(partial_path_.c_str(), O_RDONLY | O_CLOEXEC | O_DIRECT);
        direct_read = rfd >= 0;
    }
    auto openBuffered = [&](std::uint64_t at) {
        rfd = ::open(partial_path_.c_str(), O_RDONLY | O_CLOEXEC);
        if (rfd < 0) return false;
        ::posix_fadvise(rfd, 0, 0, POSIX_FADV_DONTNEED);
        return ::lseek(rfd, static_cast<off_t>(at), SEEK_SET) == static_cast<off_t>(at);
    };
    if (rfd < 0 && !openBuffered(0)) return fail("cannot reopen for verification", errno);
    std::uint32_t crc = 0;     // the reader thread's until finish()
    std::string format_error;  // the same
    std::uint64_t total = 0;
    int read_err = 0;
    {
        BufferPipeline checksum(kBufferBytes, kBuffers,
                                [&](std::span<const std::uint8_t> bytes, std::uint64_t) {
                                    crc = crcUpdate(crc, bytes);
                                    if (read_back_check_ && format_error.empty())
                                        format_error = read_back_check_(bytes);
                                    return 0;
                                });
        while (true) {
            const std::span<std::uint8_t> buf = checksum.current();
            const ssize_t n = ::read(rfd, buf.data(), buf.size());
            if (n < 0 && errno == EINTR) continue;
            if (n < 0 && errno == EINVAL && direct_read) {  // e.g. a short read left us unaligned
                ::close(rfd);
                direct_read = false;
                if (!openBuffered(total)) {
                    read_err = errno;
                    break;
                }
                continue;
            }
            if (n < 0) {
                read_err = errno;
                break;
            }
            if (n == 0) break;
            (void)checksum.submit(static_cast<std::size_t>(n), total);  // the checksum never fails
            total += static_cast<std::uint64_t>(n);
        }
        (void)checksum.finish();
    }
    if (rfd >= 0) ::close(rfd);
    if (read_err != 0) return fail("read-back failed", read_err);
    if (!format_error.empty()) return fail("verification failed: " + format_error, EIO);
    const std::uint32_t header_crc = crcUpdate(0, header_);
    const std::uint32_t expected = static_cast<std::uint32_t>(
        ::crc32_combine(header_crc, crc_, static_cast<z_off_t>(flushed_ - header_bytes_)));
    if (crc != expected || total != flushed_) {
        return fail("verification failed (read back " + std::to_string(total) + " of " +
                        std::to_string(flushed_) + " bytes, CRC mismatch)",
                    EIO);
    }
    return Status::ok();
}

Status writeSmallFile(const std::string& path, std::string_view text, WriteFaults faults) {
    SafeFileWriter f(path, std::move(faults));
    if (Status s = f.open(); !s.isOk()) return s;
    if (Status s = f.write({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
        !s.isOk())
        return s;
    return f.commit();
}

}  // namespace handscan::exporter
