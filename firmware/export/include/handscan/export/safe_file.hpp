// Writes one file onto a target that may fail at any moment (a USB stick pulled mid-write, a full
// or read-only filesystem) without ever leaving a partial file that looks complete: data goes to
// ".<name>.partial", is fsync'ed, read back from the medium and compared by CRC32, and only then
// renamed to its final name (and the directory fsync'ed). Any failure removes the partial file.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::exporter {

struct WriteFaults {
    // Test hook: called before each write with the bytes written so far; returning an errno value
    // (e.g. EIO) makes that write fail as the kernel would report it.
    std::function<int(std::uint64_t written)> before_write;
};

class SafeFileWriter {
public:
    SafeFileWriter(std::string final_path, WriteFaults faults = {});
    ~SafeFileWriter();  // removes the partial file unless commit() succeeded
    SafeFileWriter(const SafeFileWriter&) = delete;
    SafeFileWriter& operator=(const SafeFileWriter&) = delete;

    Status open();
    // Reserves the first `bytes` of the file for a header only known at the end (counts, bounds),
    // so the points stream through once. Call right after open(); fill with patchHeader().
    Status reserveHeader(std::size_t bytes);
    Status patchHeader(std::span<const std::uint8_t> header);
    Status write(std::span<const std::uint8_t> bytes);  // buffered
    // fsync, read back and verify, rename, fsync the directory.
    Status commit();
    std::uint64_t bytesWritten() const { return written_ + buffer_.size(); }
    const std::string& finalPath() const { return final_path_; }

private:
    Status flushBuffer();
    Status fail(const std::string& what, int err);

    std::string final_path_;
    std::string partial_path_;
    WriteFaults faults_;
    int fd_ = -1;
    std::vector<std::uint8_t> buffer_;
    std::uint64_t written_ = 0;
    std::uint32_t crc_ = 0;                  // over everything after the header region
    std::vector<std::uint8_t> header_;       // the reserved / patched header region
    bool committed_ = false;
};

}  // namespace handscan::exporter
