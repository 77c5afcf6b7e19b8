#include "handscan/export/safe_file.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace handscan::exporter {
namespace {

constexpr std::size_t kBufferBytes = 4u << 20;  // large sequential writes run at the medium's speed

std::string dirOf(const std::string& path) {
    const std::filesystem::path p(path);
    return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}

}  // namespace

SafeFileWriter::SafeFileWriter(std::string final_path, WriteFaults faults)
    : final_path_(std::move(final_path)), faults_(std::move(faults)) {
    const std::filesystem::path p(final_path_);
    partial_path_ = (std::filesystem::path(dirOf(final_path_)) / ("." + p.filename().string() + ".partial")).string();
}

SafeFileWriter::~SafeFileWriter() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_ && !partial_path_.empty()) ::unlink(partial_path_.c_str());
}

Status SafeFileWriter::fail(const std::string& what, int err) {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    ::unlink(partial_path_.c_str());  // may fail too when the medium is gone; nothing else to do
    std::string hint;
    if (err == ENOSPC) hint = ": the target is full; free space or use a larger stick, then export again";
    else if (err == EROFS || err == EACCES || err == EPERM) hint = ": the target is read-only; check the stick's lock switch";
    else if (err == EIO || err == ENODEV || err == ENOENT || err == ENXIO) hint = ": the target vanished or failed (stick pulled?); reinsert it and export again";
    return Status(err == ENOSPC ? StatusCode::kNoSpace : StatusCode::kIoError,
                  "export " + final_path_ + ": " + what + ": " + std::strerror(err) + hint +
                      " (the scan on internal storage is untouched)");
}

Status SafeFileWriter::open() {
    fd_ = ::open(partial_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) return fail("cannot create " + partial_path_, errno);
    buffer_.reserve(kBufferBytes);
    return Status::ok();
}

Status SafeFileWriter::reserveHeader(std::size_t bytes) {
    if (written_ != 0 || !buffer_.empty()) return Status(StatusCode::kInvalidArgument, "export " + final_path_ + ": header after data");
    header_.assign(bytes, 0);
    buffer_.insert(buffer_.end(), header_.begin(), header_.end());
    return Status::ok();
}

Status SafeFileWriter::patchHeader(std::span<const std::uint8_t> header) {
    if (header.size() != header_.size()) {
        return Status(StatusCode::kInvalidArgument, "export " + final_path_ + ": header is " + std::to_string(header.size()) +
                                                        " bytes, reserved " + std::to_string(header_.size()));
    }
    header_.assign(header.begin(), header.end());
    if (written_ == 0) {  // still in the buffer
        std::copy(header_.begin(), header_.end(), buffer_.begin());
        return Status::ok();
    }
    std::size_t done = 0;
    while (done < header_.size()) {
        const ssize_t n = ::pwrite(fd_, header_.data() + done, header_.size() - done, static_cast<off_t>(done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return fail("header write failed", n == 0 ? EIO : errno);
        done += static_cast<std::size_t>(n);
    }
    return Status::ok();
}

Status SafeFileWriter::write(std::span<const std::uint8_t> bytes) {
    if (fd_ < 0) return Status(StatusCode::kIoError, "export " + final_path_ + ": not open");
    if (bytes.empty()) return Status::ok();  // zlib's crc32 restarts from 0 on a null buffer
    crc_ = static_cast<std::uint32_t>(::crc32_z(crc_, bytes.data(), bytes.size()));
    while (!bytes.empty()) {
        const std::size_t n = std::min(bytes.size(), kBufferBytes - buffer_.size());
        buffer_.insert(buffer_.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
        bytes = bytes.subspan(n);
        if (buffer_.size() == kBufferBytes) {
            if (Status s = flushBuffer(); !s.isOk()) return s;
        }
    }
    return Status::ok();
}

Status SafeFileWriter::flushBuffer() {
    std::size_t done = 0;
    while (done < buffer_.size()) {
        if (faults_.before_write) {
            if (const int err = faults_.before_write(written_); err != 0) return fail("write failed at byte " + std::to_string(written_), err);
        }
        const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return fail("write failed at byte " + std::to_string(written_), n == 0 ? EIO : errno);
        done += static_cast<std::size_t>(n);
        written_ += static_cast<std::uint64_t>(n);
    }
    buffer_.clear();
    return Status::ok();
}

Status SafeFileWriter::commit() {
    if (fd_ < 0) return Status(StatusCode::kIoError, "export " + final_path_ + ": not open");
    if (Status s = flushBuffer(); !s.isOk()) return s;
    if (::fsync(fd_) != 0) return fail("fsync failed", errno);
    // Read back from the medium, not the page cache, and compare.
    ::posix_fadvise(fd_, 0, 0, POSIX_FADV_DONTNEED);
    ::close(fd_);
    fd_ = -1;
    const int rfd = ::open(partial_path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (rfd < 0) return fail("cannot reopen for verification", errno);
    ::posix_fadvise(rfd, 0, 0, POSIX_FADV_DONTNEED);
    std::vector<std::uint8_t> buf(kBufferBytes);
    std::uint32_t crc = 0;
    std::uint64_t total = 0;
    while (true) {
        const ssize_t n = ::read(rfd, buf.data(), buf.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            const int err = errno;
            ::close(rfd);
            return fail("read-back failed", err);
        }
        if (n == 0) break;
        crc = static_cast<std::uint32_t>(::crc32_z(crc, buf.data(), static_cast<std::size_t>(n)));
        total += static_cast<std::uint64_t>(n);
    }
    ::close(rfd);
    const std::uint32_t header_crc = static_cast<std::uint32_t>(::crc32_z(0, header_.data(), header_.size()));
    const std::uint32_t expected = static_cast<std::uint32_t>(
        ::crc32_combine(header_crc, crc_, static_cast<z_off_t>(written_ - header_.size())));
    if (crc != expected || total != written_) {
        return fail("verification failed (read back " + std::to_string(total) + " bytes, CRC mismatch)", EIO);
    }
    if (::rename(partial_path_.c_str(), final_path_.c_str()) != 0) return fail("rename failed", errno);
    committed_ = true;
    const int dfd = ::open(dirOf(final_path_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
    return Status::ok();
}

}  // namespace handscan::exporter
