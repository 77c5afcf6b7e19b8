#include "spill_file.hpp"

#include <cerrno>
#include <cstring>

namespace handscan::replay {

Result<std::unique_ptr<SpillFile>> SpillFile::create(const std::string& path, std::string what) {
    std::FILE* f = std::fopen(path.c_str(), "w+bx");
    if (f == nullptr) {
        const int err = errno;
        return Status(StatusCode::kIoError,
                      what + " " + path + ": cannot create: " + std::strerror(err) +
                          "; check that the directory exists and is writable");
    }
    // Unlinked at once: the open stream keeps the data, nothing is left behind however we end.
    if (std::remove(path.c_str()) != 0) {
        const int err = errno;
        std::fclose(f);
        return Status(
            StatusCode::kIoError,
            what + " " + path + ": cannot unlink the scratch file: " + std::strerror(err));
    }
    std::setvbuf(f, nullptr, _IOFBF, std::size_t{1} << 16);
    return std::unique_ptr<SpillFile>(new SpillFile(f, path, std::move(what)));
}

SpillFile::~SpillFile() { std::fclose(f_); }

Status SpillFile::failure(const char* op, std::uint64_t offset, std::size_t bytes, int err) const {
    const bool full = err == ENOSPC || err == EFBIG || err == EDQUOT;
    return Status(
        full ? StatusCode::kNoSpace : StatusCode::kIoError,
        what_ + " " + path_ + ": " + op + " of " + std::to_string(bytes) + " bytes at offset " +
            std::to_string(offset) +
            " failed: " + (err != 0 ? std::strerror(err) : "short transfer") +
            (full ? "; free space on that filesystem or choose another directory for it" : ""));
}

Result<std::uint64_t> SpillFile::append(std::span<const std::uint8_t> bytes) {
    const std::uint64_t offset = size_;
    if (!at_end_) {
        if (std::fseek(f_, static_cast<long>(size_), SEEK_SET) != 0)
            return failure("seek", offset, bytes.size(), errno);
        at_end_ = true;
    }
    errno = 0;
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f_) != bytes.size()) {
        return failure("write", offset, bytes.size(), errno);
    }
    size_ += bytes.size();
    return offset;
}

Status SpillFile::read(std::uint64_t offset, std::span<std::uint8_t> out) {
    // Switching from writing to reading: flush first, so a late write error surfaces here.
    errno = 0;
    if (at_end_ && std::fflush(f_) != 0) return failure("write", size_, 0, errno);
    at_end_ = false;
    if (offset + out.size() > size_) return failure("read past the end", offset, out.size(), 0);
    if (std::fseek(f_, static_cast<long>(offset), SEEK_SET) != 0)
        return failure("seek", offset, out.size(), errno);
    errno = 0;
    if (!out.empty() && std::fread(out.data(), 1, out.size(), f_) != out.size())
        return failure("read", offset, out.size(), errno);
    return Status::ok();
}

}  // namespace handscan::replay
