// A scratch file for what does not fit a memory budget: blocks appended, read back by offset.
// It is unlinked right after it is created, so it never outlives the process that made it: gone
// on success, on error and on a crash alike (its space is returned when it is closed). Every
// failure names the file, says what failed and what to do.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <string>

#include "handscan/core/status.hpp"

namespace handscan::replay {

class SpillFile {
public:
    // `what` says in errors what the file is for ("map spill file").
    [[nodiscard]] static Result<std::unique_ptr<SpillFile>> create(const std::string& path,
                                                                   std::string what);
    ~SpillFile();
    SpillFile(const SpillFile&) = delete;
    SpillFile& operator=(const SpillFile&) = delete;

    // Appends `bytes` at the end; returns the offset they start at.
    [[nodiscard]] Result<std::uint64_t> append(std::span<const std::uint8_t> bytes);
    // Reads exactly out.size() bytes at `offset`.
    [[nodiscard]] Status read(std::uint64_t offset, std::span<std::uint8_t> out);

    std::uint64_t size() const { return size_; }
    const std::string& path() const { return path_; }

private:
    SpillFile(std::FILE* f, std::string path, std::string what)
        : f_(f), path_(std::move(path)), what_(std::move(what)) {}
    Status failure(const char* op, std::uint64_t offset, std::size_t bytes, int err) const;

    std::FILE* f_;
    std::string path_;
    std::string what_;
    std::uint64_t size_ = 0;
    bool at_end_ = true;  // the stream is positioned for appending
};

}  // namespace handscan::replay
