#include "handscan/camera/png_fast_decode.hpp"

#include <libdeflate.h>

#include <array>
#include <cstdlib>
#include <cstring>
#include <memory>

namespace handscan::camera {
namespace {

constexpr std::array<std::uint8_t, 8> kSignature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::uint8_t kColourGrey = 0;
constexpr std::uint8_t kColourGreyAlpha = 4;

std::uint32_t be32(const std::uint8_t* p) {
    return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
           std::uint32_t{p[3]};
}

bool isType(const std::uint8_t* p, const char (&type)[5]) { return std::memcmp(p, type, 4) == 0; }

struct DecompressorDeleter {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// PNG spec 9.4, the Paeth predictor.
std::uint8_t paeth(int a, int b, int c) {
    const int p = a + b - c;
    const int pa = std::abs(p - a);
    const int pb = std::abs(p - b);
    const int pc = std::abs(p - c);
    if (pa <= pb && pa <= pc) return static_cast<std::uint8_t>(a);
    return static_cast<std::uint8_t>(pb <= pc ? b : c);
}

// One row: `src` the filtered bytes (after the filter-type byte), `up` the previous row's
// reconstruction (zeros for the first), `bpp` bytes per pixel (PNG spec 9.2-9.4).
bool unfilterRow(std::uint8_t type, const std::uint8_t* src, const std::uint8_t* up,
                 std::uint8_t* dst, std::size_t n, std::size_t bpp) {
    switch (type) {
        case 0:
            std::memcpy(dst, src, n);
            return true;
        case 1:
            for (std::size_t i = 0; i < n; ++i)
                dst[i] = static_cast<std::uint8_t>(src[i] + (i >= bpp ? dst[i - bpp] : 0));
            return true;
        case 2:
            for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<std::uint8_t>(src[i] + up[i]);
            return true;
        case 3:
            for (std::size_t i = 0; i < bpp && i < n; ++i)
                dst[i] = static_cast<std::uint8_t>(src[i] + (up[i] >> 1));
            if (bpp == 1 && n > 0) {
                // The encoder's filter (png_payload.cpp) on grey: the left pixel kept in a
                // register, not reloaded from the store just made (a serial chain either way).
                unsigned left = dst[0];
                for (std::size_t i = 1; i < n; ++i) {
                    left = (src[i] + ((left + up[i]) >> 1)) & 0xFFu;
                    dst[i] = static_cast<std::uint8_t>(left);
                }
                return true;
            }
            for (std::size_t i = bpp; i < n; ++i)
                dst[i] = static_cast<std::uint8_t>(src[i] + ((dst[i - bpp] + up[i]) >> 1));
            return true;
        case 4:
            for (std::size_t i = 0; i < bpp && i < n; ++i)
                dst[i] = static_cast<std::uint8_t>(src[i] + up[i]);  // paeth(0, b, 0) = b
            for (std::size_t i = bpp; i < n; ++i)
                dst[i] =
                    static_cast<std::uint8_t>(src[i] + paeth(dst[i - bpp], up[i], up[i - bpp]));
            return true;
        default:
            return false;
    }
}

// Four consecutive Average-filtered rows of one byte per pixel (png_payload's grey frames): each
// row's chain (its left pixel, then this one) is serial, so the four run side by side, each one
// pixel behind the row above, whose value it takes from a register (`l[k - 1]` of the previous
// step is the pixel above). `up0` is the row above the first; `up` of the others is the row
// before them in this group.
void unfilterAverageGrey4(const std::uint8_t* const src[4], const std::uint8_t* up0,
                          std::uint8_t* const dst[4], std::size_t n) {
    unsigned l[4] = {0, 0, 0, 0};  // each row's last pixel (0 left of the first, spec 9.3)
    const auto step = [&](std::size_t i) {
        // Bottom row first, so that l[k - 1] still holds the previous step's pixel above.
        for (std::size_t k = 4; k-- > 0;) {
            if (i < k || i - k >= n) continue;
            const std::size_t x = i - k;
            const unsigned above = k == 0 ? up0[x] : l[k - 1];
            l[k] = (src[k][x] + ((l[k] + above) >> 1)) & 0xFFu;
            dst[k][x] = static_cast<std::uint8_t>(l[k]);
        }
    };
    std::size_t i = 0;
    for (; i < 3 && i < n + 3; ++i) step(i);
    for (; i < n; ++i) {  // all four rows inside: no range checks
        l[3] = (src[3][i - 3] + ((l[3] + l[2]) >> 1)) & 0xFFu;
        dst[3][i - 3] = static_cast<std::uint8_t>(l[3]);
        l[2] = (src[2][i - 2] + ((l[2] + l[1]) >> 1)) & 0xFFu;
        dst[2][i - 2] = static_cast<std::uint8_t>(l[2]);
        l[1] = (src[1][i - 1] + ((l[1] + l[0]) >> 1)) & 0xFFu;
        dst[1][i - 1] = static_cast<std::uint8_t>(l[1]);
        l[0] = (src[0][i] + ((l[0] + up0[i]) >> 1)) & 0xFFu;
        dst[0][i] = static_cast<std::uint8_t>(l[0]);
    }
    for (; i < n + 3; ++i) step(i);
}

}  // namespace

bool decodePlainPng(std::span<const std::uint8_t> png, std::uint32_t width, std::uint32_t height,
                    int channels, std::vector<std::uint8_t>& pixels) {
    if (channels != 1 && channels != 2) return false;
    if (png.size() < kSignature.size() ||
        std::memcmp(png.data(), kSignature.data(), kSignature.size()) != 0)
        return false;
    // Chunks: length, type, data, CRC of type + data (PNG spec 5.3).
    std::vector<std::span<const std::uint8_t>> idat;
    std::size_t idat_bytes = 0;
    bool header = false;
    bool end = false;
    for (std::size_t at = kSignature.size(); !end;) {
        if (png.size() - at < 12) return false;
        const std::uint32_t length = be32(png.data() + at);
        if (length > png.size() - at - 12) return false;
        const std::uint8_t* type = png.data() + at + 4;
        const std::uint8_t* data = type + 4;
        if (libdeflate_crc32(0, type, length + 4) != be32(data + length)) return false;
        if (isType(type, "IHDR")) {
            if (header || length != 13 || be32(data) != width || be32(data + 4) != height ||
                data[8] != 8 || data[9] != (channels == 1 ? kColourGrey : kColourGreyAlpha) ||
                data[10] != 0 || data[11] != 0 || data[12] != 0)
                return false;
            header = true;
        } else if (isType(type, "IDAT") && header) {
            idat.emplace_back(data, length);
            idat_bytes += length;
        } else if (isType(type, "IEND") && header && !idat.empty()) {
            end = true;
        } else {
            return false;  // any other chunk (or one out of order): libpng's business
        }
        at += 12 + std::size_t{length};
    }
    // One zlib stream over the IDAT chunks' data: contiguous already when there is one chunk.
    std::vector<std::uint8_t> joined;
    std::span<const std::uint8_t> stream = idat.front();
    if (idat.size() > 1) {
        joined.reserve(idat_bytes);
        for (const auto& part : idat) joined.insert(joined.end(), part.begin(), part.end());
        stream = joined;
    }
    const std::size_t row = std::size_t{width} * static_cast<std::size_t>(channels);
    std::vector<std::uint8_t> filtered((row + 1) * height);
    const std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> inflater(
        libdeflate_alloc_decompressor());
    if (!inflater) return false;
    std::size_t produced = 0;
    if (libdeflate_zlib_decompress(inflater.get(), stream.data(), stream.size(), filtered.data(),
                                   filtered.size(), &produced) != LIBDEFLATE_SUCCESS ||
        produced != filtered.size())
        return false;
    pixels.resize(row * height);
    const std::vector<std::uint8_t> zeros(row, 0);
    const auto bpp = static_cast<std::size_t>(channels);
    for (std::size_t y = 0; y < height;) {
        const std::uint8_t* in = filtered.data() + y * (row + 1);
        std::uint8_t* out = pixels.data() + y * row;
        const std::uint8_t* up = y == 0 ? zeros.data() : out - row;
        if (bpp == 1 && y + 4 <= height && in[0] == 3 && in[row + 1] == 3 &&
            in[2 * (row + 1)] == 3 && in[3 * (row + 1)] == 3) {
            const std::uint8_t* const src[4] = {in + 1, in + row + 2, in + 2 * row + 3,
                                                in + 3 * row + 4};
            std::uint8_t* const dst[4] = {out, out + row, out + 2 * row, out + 3 * row};
            unfilterAverageGrey4(src, up, dst, row);
            y += 4;
            continue;
        }
        if (!unfilterRow(in[0], in + 1, up, out, row, bpp)) return false;
        ++y;
    }
    return true;
}

}  // namespace handscan::camera
