#include "handscan/camera/png_payload.hpp"

#include <png.h>
#include <zlib.h>

#include <csetjmp>
#include <string>

#include "handscan/camera/png_fast_decode.hpp"
#include "handscan/core/v4l2_types.hpp"

namespace handscan::camera {
namespace {

// Average of left and upper neighbour: within 1.5 % of libpng's adaptive filter choice on
// rendered and real camera noise, at 60 % of its time.
constexpr int kPngFilter = PNG_FILTER_AVG;

struct PngLayout {
    int colour_type = 0;       // PNG_COLOR_TYPE_GRAY or _GRAY_ALPHA
    std::uint32_t format = 0;  // simplified-API format of the same pixels
    std::uint32_t width = 0;   // PNG pixels per line
};

PngLayout layoutOf(const FrameRecordHeader& h) {
    if (h.fourcc == kFourccYuyv) return {PNG_COLOR_TYPE_GRAY_ALPHA, PNG_FORMAT_GA, h.stride / 2};
    return {PNG_COLOR_TYPE_GRAY, PNG_FORMAT_GRAY, h.stride};
}

struct WriteContext {
    std::vector<std::uint8_t>* out;
    std::string error;
};

void appendBytes(png_structp png, png_bytep data, png_size_t n) {
    auto* ctx = static_cast<WriteContext*>(png_get_io_ptr(png));
    ctx->out->insert(ctx->out->end(), data, data + n);
}
void noFlush(png_structp) {}
void onError(png_structp png, png_const_charp message) {
    auto* ctx = static_cast<WriteContext*>(png_get_error_ptr(png));
    ctx->error = message;
    png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}

// Only trivially destructible locals between setjmp and the libpng calls that may longjmp.
bool writePng(png_structp png, png_infop info, const PngLayout& l, std::uint32_t height,
              const std::uint8_t* data, std::uint32_t stride) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_IHDR(png, info, l.width, height, 8, l.colour_type, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, kPngFilter);
    png_set_compression_level(png, 1);
    png_set_compression_strategy(png, Z_HUFFMAN_ONLY);
    png_set_compression_buffer_size(png, 1u << 16);
    png_write_info(png, info);
    for (std::uint32_t y = 0; y < height; ++y)
        png_write_row(png, data + static_cast<std::size_t>(y) * stride);
    png_write_end(png, nullptr);
    return true;
}

}  // namespace

bool canStorePng(const FrameRecordHeader& h) {
    const bool grey = h.fourcc == kFourccGrey && h.stride >= h.width;
    const bool yuyv = h.fourcc == kFourccYuyv && h.stride >= 2ull * h.width && h.stride % 2 == 0;
    return (grey || yuyv) && h.height > 0 && h.stride > 0 &&
           static_cast<std::uint64_t>(h.stride) * h.height == h.bytesused;
}

Result<std::vector<std::uint8_t>> encodePngPayload(const FrameRecordHeader& h,
                                                   std::span<const std::uint8_t> buffer) {
    if (!canStorePng(h) || buffer.size() != h.bytesused) {
        return Status(StatusCode::kInvalidArgument,
                      "PNG payload: a " + fourccName(h.fourcc) + " buffer of " +
                          std::to_string(buffer.size()) + " bytes is not " +
                          std::to_string(h.stride) + " x " + std::to_string(h.height) +
                          " whole lines of GREY or YUYV; store it uncoded");
    }
    std::vector<std::uint8_t> out;
    out.reserve(buffer.size() / 2 + 1024);
    WriteContext ctx{&out, {}};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, onError, onWarning);
    png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
    if (info == nullptr) {
        png_destroy_write_struct(&png, nullptr);
        return Status(StatusCode::kIoError, "PNG payload: libpng could not allocate its encoder");
    }
    png_set_write_fn(png, &ctx, appendBytes, noFlush);
    const bool ok = writePng(png, info, layoutOf(h), h.height, buffer.data(), h.stride);
    png_destroy_write_struct(&png, &info);
    if (!ok)
        return Status(StatusCode::kIoError, "PNG payload: libpng failed to encode: " + ctx.error);
    return out;
}

Status decodePngPayload(const FrameRecordHeader& h, std::span<const std::uint8_t> data,
                        std::vector<std::uint8_t>& buffer) {
    if (!canStorePng(h)) {
        return {StatusCode::kProtocolError,
                "PNG payload of a " + fourccName(h.fourcc) + " " + std::to_string(h.width) + "x" +
                    std::to_string(h.height) + " stride " + std::to_string(h.stride) +
                    " buffer of " + std::to_string(h.bytesused) +
                    " bytes: only whole-line GREY and YUYV buffers are stored as PNG"};
    }
    const PngLayout l = layoutOf(h);
    // The files encodePngPayload writes, without libpng (2-3x faster); anything else below.
    if (decodePlainPng(data, l.width, h.height, l.colour_type == PNG_COLOR_TYPE_GRAY ? 1 : 2,
                       buffer))
        return Status::ok();
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (png_image_begin_read_from_memory(&image, data.data(), data.size()) == 0) {
        const std::string why = image.message;
        png_image_free(&image);
        return {StatusCode::kProtocolError, "PNG payload does not decode: " + why};
    }
    // The exact pixel type, not one libpng would convert from (that would change bytes).
    if (image.width != l.width || image.height != h.height || image.format != l.format) {
        const std::string what = std::to_string(image.width) + "x" + std::to_string(image.height) +
                                 " format " + std::to_string(image.format) +
                                 ", the header implies " + std::to_string(l.width) + "x" +
                                 std::to_string(h.height) + " format " + std::to_string(l.format);
        png_image_free(&image);
        return {StatusCode::kProtocolError, "PNG payload is " + what};
    }
    buffer.resize(h.bytesused);
    if (png_image_finish_read(&image, nullptr, buffer.data(), 0, nullptr) == 0) {
        const std::string why = image.message;
        png_image_free(&image);
        return {StatusCode::kProtocolError, "PNG payload does not decode: " + why};
    }
    return Status::ok();
}

}  // namespace handscan::camera
