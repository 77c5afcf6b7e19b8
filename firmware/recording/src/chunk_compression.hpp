// Chunk compression for MCAP: "" (none) and "zstd" (Debian libzstd). The compressor keeps its zstd
// context between chunks so the recorder thread does not allocate one per chunk.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::recording::detail {

class ChunkCompressor {
public:
    ChunkCompressor(std::string compression, int zstd_level);
    ~ChunkCompressor();
    ChunkCompressor(const ChunkCompressor&) = delete;
    ChunkCompressor& operator=(const ChunkCompressor&) = delete;

    const std::string& compression() const { return compression_; }
    // Replaces `out` with the compressed form of `in` (or a copy when compression is "").
    [[nodiscard]] Status compress(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out);

private:
    std::string compression_;
    int level_;
    struct Zstd;
    std::unique_ptr<Zstd> zstd_;
};

bool isSupportedCompression(std::string_view compression);

// Decompresses a chunk's records into `out` (exactly `uncompressed_size` bytes or an error).
[[nodiscard]] Status decompressChunk(std::string_view compression, std::span<const std::uint8_t> in,
                                     std::uint64_t uncompressed_size,
                                     std::vector<std::uint8_t>& out);

}  // namespace handscan::recording::detail
