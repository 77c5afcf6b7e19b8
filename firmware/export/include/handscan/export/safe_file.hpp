// Writes one file onto a target that may fail at any moment (a USB stick pulled mid-write, a full
// or read-only filesystem) without ever leaving a partial file that looks complete: data goes to
// ".<name>.partial", is fsync'ed, read back from the medium and compared by CRC32, and only then
// renamed to its final name (and the directory fsync'ed). Any failure removes the partial file.
//
// At the medium's speed: bytes are gathered into 4 MiB page-aligned buffers that a second thread
// checksums and writes with O_DIRECT while the caller encodes the next ones (triple buffering), so
// the page cache neither costs a copy nor fills with dirty pages that fsync then waits for (and a
// progress bar then tracks the stick, not RAM). The read-back also bypasses the page cache and
// overlaps reading with checksumming. Filesystems without O_DIRECT get the same pipeline with
// buffered writes, and the read-back drops the cached pages first (POSIX_FADV_DONTNEED).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::exporter {

struct WriteFaults {
    // Test hook: called before each write with the bytes written so far; returning an errno value
    // (e.g. EIO) makes that write fail as the kernel would report it.
    // Called on the writer's I/O thread for all but the last (partial) block.
    std::function<int(std::uint64_t written)> before_write;
    bool buffered_only = false;  // test hook: behave as on a filesystem without O_DIRECT
    // Test hook: called with the temporary file's path after fsync, before the read-back (e.g. to
    // damage it the way a fake-capacity stick would).
    std::function<void(const std::string& partial_path)> before_verify;
};

class BufferPipeline;

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
    Status write(std::span<const std::uint8_t> bytes);  // buffered; the I/O overlaps the caller
    // fsync, read back and verify, rename, fsync the directory.
    Status commit();
    // A format's own check of the bytes read back from the medium (e.g. E57's per-page CRC-32C):
    // fed the whole file in order, in pieces of any size, on the read-back thread; returns an
    // empty string when fine, else what is wrong (the export then fails with it).
    using ReadBackCheck = std::function<std::string(std::span<const std::uint8_t> bytes)>;
    void setReadBackCheck(ReadBackCheck check) { read_back_check_ = std::move(check); }
    std::uint64_t bytesWritten() const { return flushed_ + fill_; }
    const std::string& finalPath() const { return final_path_; }
    // Whether the data went to the medium with O_DIRECT (false: buffered, e.g. on tmpfs).
    bool directIo() const { return direct_.load(); }

private:
    Status handOff();           // the full current buffer to the I/O thread
    Status ioFailure(int err);  // the I/O thread's error as a Status
    int writeAt(std::span<const std::uint8_t> bytes, std::uint64_t offset);  // errno or 0
    Status verify();
    Status fail(const std::string& what, int err);

    std::string final_path_;
    std::string partial_path_;
    WriteFaults faults_;
    int fd_ = -1;
    std::atomic<bool> direct_{false};
    std::unique_ptr<BufferPipeline> pipe_;
    std::size_t fill_ = 0;          // bytes in the current buffer
    std::uint64_t flushed_ = 0;     // bytes handed to the I/O thread (offset of the current buffer)
    std::size_t header_bytes_ = 0;  // the reserved header region at offset 0
    std::vector<std::uint8_t> header_;  // its final content (patchHeader)
    // Owned by the I/O thread while it runs; read after BufferPipeline::finish().
    std::uint32_t crc_ = 0;           // over everything after the header region
    std::uint64_t error_offset_ = 0;  // where the I/O thread's write failed
    bool committed_ = false;
    ReadBackCheck read_back_check_;
};

// A whole small file (a JSON, a TUM, a report) through a SafeFileWriter: written, verified,
// renamed into place, or not there at all.
[[nodiscard]] Status writeSmallFile(const std::string& path, std::string_view text,
                                    WriteFaults faults = {});

}  // namespace handscan::exporter
