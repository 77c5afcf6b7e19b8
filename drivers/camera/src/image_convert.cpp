#include "handscan/camera/image_convert.hpp"

#include <turbojpeg.h>

#include <memory>
#include <opencv2/imgproc.hpp>
#include <string>

#include "handscan/core/v4l2_types.hpp"

namespace handscan::camera {
namespace {

Status bad(const Image& in, const std::string& what) {
    return {StatusCode::kProtocolError, std::string("camera frame ") + std::to_string(in.sequence) +
                                            " (" + toString(in.format) + " " +
                                            std::to_string(in.width) + "x" +
                                            std::to_string(in.height) + "): " + what};
}

Status checkLayout(const Image& in, int bytes_per_pixel) {
    if (in.width <= 0 || in.height <= 0) return bad(in, "empty image");
    if (in.stride_bytes < in.width * bytes_per_pixel)
        return bad(in, "stride " + std::to_string(in.stride_bytes) + " shorter than a line");
    const auto need =
        static_cast<std::size_t>(in.stride_bytes) * static_cast<std::size_t>(in.height - 1) +
        static_cast<std::size_t>(in.width * bytes_per_pixel);
    if (in.data.size() < need)
        return bad(in, std::to_string(in.data.size()) + " bytes, need " + std::to_string(need));
    return Status::ok();
}

Image like(const Image& in, PixelFormat f, int channels) {
    Image out;
    out.t_host = in.t_host;
    out.sequence = in.sequence;
    out.exposure_ns = in.exposure_ns;
    out.format = f;
    out.width = in.width;
    out.height = in.height;
    out.stride_bytes = in.width * channels;
    out.data.resize(static_cast<std::size_t>(out.stride_bytes) *
                    static_cast<std::size_t>(in.height));
    return out;
}

cv::Mat view(const Image& in, int type) {
    return cv::Mat(in.height, in.width, type, const_cast<std::uint8_t*>(in.data.data()),
                   static_cast<std::size_t>(in.stride_bytes));
}
cv::Mat view(Image& out, int type) {
    return cv::Mat(out.height, out.width, type, out.data.data(),
                   static_cast<std::size_t>(out.stride_bytes));
}

Result<Image> decodeMjpeg(const Image& in, bool grey) {
    struct Closer {
        void operator()(void* h) const { tjDestroy(h); }
    };
    std::unique_ptr<void, Closer> tj(tjInitDecompress());
    if (!tj) return Status(StatusCode::kUnsupported, "libturbojpeg: tjInitDecompress failed");
    int w = 0, h = 0, subsamp = 0, colorspace = 0;
    if (in.data.size() < 4)
        return bad(in, "MJPEG frame of " + std::to_string(in.data.size()) + " bytes");
    if (tjDecompressHeader3(tj.get(), in.data.data(), static_cast<unsigned long>(in.data.size()),
                            &w, &h, &subsamp, &colorspace) != 0) {
        return bad(in, std::string("MJPEG header: ") + tjGetErrorStr2(tj.get()));
    }
    if (w != in.width || h != in.height) {
        return bad(in, "MJPEG is " + std::to_string(w) + "x" + std::to_string(h) +
                           ", the negotiated format says otherwise");
    }
    Image out = like(in, grey ? PixelFormat::kGrey8 : PixelFormat::kBgr8, grey ? 1 : 3);
    if (tjDecompress2(tj.get(), in.data.data(), static_cast<unsigned long>(in.data.size()),
                      out.data.data(), w, out.stride_bytes, h, grey ? TJPF_GRAY : TJPF_BGR,
                      TJFLAG_ACCURATEDCT) != 0) {
        // Warnings (e.g. premature end of data) still give a usable image; errors do not.
        if (tjGetErrorCode(tj.get()) == TJERR_FATAL)
            return bad(in, std::string("MJPEG decode: ") + tjGetErrorStr2(tj.get()));
    }
    return out;
}

}  // namespace

std::optional<PixelFormat> pixelFormatFromFourcc(std::uint32_t fourcc) {
    if (fourcc == kFourccGrey) return PixelFormat::kGrey8;
    if (fourcc == kFourccYuyv) return PixelFormat::kYuyv;
    if (fourcc == kFourccMjpeg) return PixelFormat::kMjpeg;
    return std::nullopt;
}

std::uint32_t fourccFromPixelFormat(PixelFormat f) {
    switch (f) {
        case PixelFormat::kGrey8:
            return kFourccGrey;
        case PixelFormat::kYuyv:
            return kFourccYuyv;
        case PixelFormat::kMjpeg:
            return kFourccMjpeg;
        case PixelFormat::kBgr8:
            return fourcc('B', 'G', 'R', '3');
    }
    return 0;
}

const char* toString(PixelFormat f) {
    switch (f) {
        case PixelFormat::kGrey8:
            return "GREY";
        case PixelFormat::kYuyv:
            return "YUYV";
        case PixelFormat::kMjpeg:
            return "MJPG";
        case PixelFormat::kBgr8:
            return "BGR3";
    }
    return "?";
}

Result<Image> toGrey(const Image& in) {
    switch (in.format) {
        case PixelFormat::kGrey8: {
            if (Status s = checkLayout(in, 1); !s) return s;
            Image out = like(in, PixelFormat::kGrey8, 1);
            view(in, CV_8UC1).copyTo(view(out, CV_8UC1));
            return out;
        }
        case PixelFormat::kYuyv: {
            if (Status s = checkLayout(in, 2); !s) return s;
            if (in.width % 2 != 0) return bad(in, "YUYV width must be even");
            Image out = like(in, PixelFormat::kGrey8, 1);
            cv::cvtColor(view(in, CV_8UC2), view(out, CV_8UC1), cv::COLOR_YUV2GRAY_YUYV);
            return out;
        }
        case PixelFormat::kMjpeg:
            return decodeMjpeg(in, true);
        case PixelFormat::kBgr8: {
            if (Status s = checkLayout(in, 3); !s) return s;
            Image out = like(in, PixelFormat::kGrey8, 1);
            cv::cvtColor(view(in, CV_8UC3), view(out, CV_8UC1), cv::COLOR_BGR2GRAY);
            return out;
        }
    }
    return bad(in, "unknown pixel format");
}

Result<Image> toBgr(const Image& in) {
    switch (in.format) {
        case PixelFormat::kGrey8: {
            if (Status s = checkLayout(in, 1); !s) return s;
            Image out = like(in, PixelFormat::kBgr8, 3);
            cv::cvtColor(view(in, CV_8UC1), view(out, CV_8UC3), cv::COLOR_GRAY2BGR);
            return out;
        }
        case PixelFormat::kYuyv: {
            if (Status s = checkLayout(in, 2); !s) return s;
            if (in.width % 2 != 0) return bad(in, "YUYV width must be even");
            Image out = like(in, PixelFormat::kBgr8, 3);
            cv::cvtColor(view(in, CV_8UC2), view(out, CV_8UC3), cv::COLOR_YUV2BGR_YUYV);
            return out;
        }
        case PixelFormat::kMjpeg:
            return decodeMjpeg(in, false);
        case PixelFormat::kBgr8: {
            if (Status s = checkLayout(in, 3); !s) return s;
            Image out = like(in, PixelFormat::kBgr8, 3);
            view(in, CV_8UC3).copyTo(view(out, CV_8UC3));
            return out;
        }
    }
    return bad(in, "unknown pixel format");
}

}  // namespace handscan::camera
