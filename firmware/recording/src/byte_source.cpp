#include "byte_source.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace handscan::recording::detail {
namespace {

class FileSource final : public ByteSource {
public:
    FileSource(std::FILE* f, std::string path, std::uint64_t size)
        : f_(f), path_(std::move(path)), size_(size) {}
    ~FileSource() override { std::fclose(f_); }
    std::uint64_t size() const override { return size_; }
    Status readAt(std::uint64_t offset, std::size_t n, std::vector<std::uint8_t>& out) override {
        if (offset > size_ || n > size_ - offset) {
            return {StatusCode::kTruncated, path_ + ": read of " + std::to_string(n) +
                                                " bytes at offset " + std::to_string(offset) +
                                                " is past the end of the file (" +
                                                std::to_string(size_) + " bytes)"};
        }
        out.resize(n);
        if (fseeko(f_, static_cast<off_t>(offset), SEEK_SET) != 0 ||
            std::fread(out.data(), 1, n, f_) != n) {
            return {StatusCode::kIoError, path_ + ": reading " + std::to_string(n) +
                                              " bytes at offset " + std::to_string(offset) +
                                              " failed: " + std::strerror(errno)};
        }
        return Status::ok();
    }

private:
    std::FILE* f_;
    std::string path_;
    std::uint64_t size_;
};

class MemorySource final : public ByteSource {
public:
    explicit MemorySource(std::vector<std::uint8_t> bytes) : bytes_(std::move(bytes)) {}
    std::uint64_t size() const override { return bytes_.size(); }
    Status readAt(std::uint64_t offset, std::size_t n, std::vector<std::uint8_t>& out) override {
        if (offset > bytes_.size() || n > bytes_.size() - offset) {
            return {StatusCode::kTruncated, "read of " + std::to_string(n) + " bytes at offset " +
                                                std::to_string(offset) +
                                                " is past the end of the buffer (" +
                                                std::to_string(bytes_.size()) + " bytes)"};
        }
        const auto begin = bytes_.begin() + static_cast<std::ptrdiff_t>(offset);
        out.assign(begin, begin + static_cast<std::ptrdiff_t>(n));
        return Status::ok();
    }

private:
    std::vector<std::uint8_t> bytes_;
};

}  // namespace

Result<std::unique_ptr<ByteSource>> openFileSource(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) {
        return Status{errno == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError,
                      path + ": cannot open the recording: " + std::strerror(errno)};
    }
    if (fseeko(f, 0, SEEK_END) != 0) {
        std::fclose(f);
        return Status{StatusCode::kIoError, path + ": cannot seek (is it a regular file?)"};
    }
    const off_t size = ftello(f);
    return std::unique_ptr<ByteSource>(
        std::make_unique<FileSource>(f, path, static_cast<std::uint64_t>(size)));
}

std::unique_ptr<ByteSource> memorySource(std::vector<std::uint8_t> bytes) {
    return std::make_unique<MemorySource>(std::move(bytes));
}

}  // namespace handscan::recording::detail
