#include "chunk_compression.hpp"

#include <zstd.h>

namespace handscan::recording::detail {

struct ChunkCompressor::Zstd {
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    ~Zstd() { ZSTD_freeCCtx(cctx); }
};

ChunkCompressor::ChunkCompressor(std::string compression, int zstd_level)
    : compression_(std::move(compression)), level_(zstd_level) {
    if (compression_ == "zstd") zstd_ = std::make_unique<Zstd>();
}

ChunkCompressor::~ChunkCompressor() = default;

bool isSupportedCompression(std::string_view compression) {
    return compression.empty() || compression == "zstd";
}

Status ChunkCompressor::compress(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out) {
    if (compression_.empty()) {
        out.assign(in.begin(), in.end());
        return Status::ok();
    }
    if (!zstd_) {
        return {StatusCode::kUnsupported,
                "chunk compression '" + compression_ + "' is not supported (use \"\" or zstd)"};
    }
    out.resize(ZSTD_compressBound(in.size()));
    const std::size_t n =
        ZSTD_compressCCtx(zstd_->cctx, out.data(), out.size(), in.data(), in.size(), level_);
    if (ZSTD_isError(n)) {
        return {StatusCode::kIoError,
                std::string("zstd compression of a chunk failed: ") + ZSTD_getErrorName(n)};
    }
    out.resize(n);
    return Status::ok();
}

Status decompressChunk(std::string_view compression, std::span<const std::uint8_t> in,
                       std::uint64_t uncompressed_size, std::vector<std::uint8_t>& out) {
    if (compression.empty()) {
        if (in.size() != uncompressed_size) {
            return {StatusCode::kProtocolError,
                    "uncompressed chunk holds " + std::to_string(in.size()) +
                        " bytes but declares " + std::to_string(uncompressed_size)};
        }
        out.assign(in.begin(), in.end());
        return Status::ok();
    }
    if (compression != "zstd") {
        return {StatusCode::kUnsupported, "chunk compression '" + std::string(compression) +
                                              "' is not supported (handscan reads \"\" and zstd)"};
    }
    // A corrupt size field must not make us allocate terabytes: zstd frames record their content
    // size, and both must agree.
    const unsigned long long frame_size = ZSTD_getFrameContentSize(in.data(), in.size());
    if (frame_size == ZSTD_CONTENTSIZE_ERROR)
        return {StatusCode::kProtocolError, "chunk is not a valid zstd frame"};
    if (frame_size != ZSTD_CONTENTSIZE_UNKNOWN && frame_size != uncompressed_size) {
        return {StatusCode::kProtocolError, "zstd frame holds " + std::to_string(frame_size) +
                                                " bytes but the chunk declares " +
                                                std::to_string(uncompressed_size)};
    }
    out.resize(static_cast<std::size_t>(uncompressed_size));
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), in.data(), in.size());
    if (ZSTD_isError(n)) {
        return {StatusCode::kProtocolError,
                std::string("zstd decompression failed: ") + ZSTD_getErrorName(n)};
    }
    if (n != uncompressed_size) {
        return {StatusCode::kProtocolError, "zstd chunk decompressed to " + std::to_string(n) +
                                                " bytes, declared " +
                                                std::to_string(uncompressed_size)};
    }
    return Status::ok();
}

}  // namespace handscan::recording::detail
