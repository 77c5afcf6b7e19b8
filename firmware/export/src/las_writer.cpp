// LAS 1.4 (ASPRS R15) with point data record format 7.
#include <cmath>
#include <cstring>
#include <vector>

#include "handscan/export/point_formats.hpp"

namespace handscan::exporter {
namespace {

class ByteWriter {
public:
    template <typename T>
    void put(T v) {
        std::uint8_t raw[sizeof(T)];
        std::memcpy(raw, &v, sizeof(T));
        bytes.insert(bytes.end(), raw, raw + sizeof(T));
    }
    void text(const std::string& s, std::size_t width) {  // fixed-width, NUL padded
        for (std::size_t i = 0; i < width; ++i) bytes.push_back(i < s.size() ? static_cast<std::uint8_t>(s[i]) : 0);
    }
    std::vector<std::uint8_t> bytes;
};

class LasWriter final : public PointFileWriter {
public:
    LasWriter(SafeFileWriter& file, LasOptions options) : file_(file), opt_(std::move(options)) {}

    Status begin(const CloudInfo& info) override {
        expected_ = info.count;
        for (int i = 0; i < 3; ++i) {
            // Offsets on a round grid near the minimum keep the integers small and readable.
            offset_[i] = info.count ? std::floor(info.bounds.min[i]) : 0.0;
            const double span = info.count ? (info.bounds.max[i] - offset_[i]) / opt_.scale : 0.0;
            if (span > 2147483647.0) {
                return Status(StatusCode::kInvalidArgument, "export " + file_.finalPath() + ": extent " +
                                                                std::to_string(info.bounds.max[i] - info.bounds.min[i]) +
                                                                " m does not fit LAS integers at scale " + std::to_string(opt_.scale));
            }
        }
        ByteWriter h;
        h.text("LASF", 4);
        h.put<std::uint16_t>(0);       // file source id
        h.put<std::uint16_t>(0x0010);  // global encoding: bit 4 = WKT (required for formats 6-10)
        for (int i = 0; i < 16; ++i) h.bytes.push_back(0);  // project GUID
        h.put<std::uint8_t>(1);
        h.put<std::uint8_t>(4);
        h.text(opt_.system_identifier, 32);
        h.text(opt_.generating_software, 32);
        h.put<std::uint16_t>(static_cast<std::uint16_t>(opt_.creation_day_of_year));
        h.put<std::uint16_t>(static_cast<std::uint16_t>(opt_.creation_year));
        h.put<std::uint16_t>(kLasHeaderBytes);
        h.put<std::uint32_t>(kLasHeaderBytes);  // offset to point data (no VLRs)
        h.put<std::uint32_t>(0);                // number of VLRs
        h.put<std::uint8_t>(7);                 // point data record format
        h.put<std::uint16_t>(kLasPointRecordBytes);
        h.put<std::uint32_t>(0);  // legacy point count: 0 for formats > 5
        for (int i = 0; i < 5; ++i) h.put<std::uint32_t>(0);
        for (int i = 0; i < 3; ++i) h.put<double>(opt_.scale);
        for (int i = 0; i < 3; ++i) h.put<double>(offset_[i]);
        // Bounds of the stored (quantised) coordinates: quantisation is monotonic, so the
        // quantised extremes are the extremes of the quantised points.
        for (int i = 0; i < 3; ++i) {
            h.put<double>(info.count ? dequantise(quantise(info.bounds.max[i], i), i) : 0.0);
            h.put<double>(info.count ? dequantise(quantise(info.bounds.min[i], i), i) : 0.0);
        }
        h.put<std::uint64_t>(0);  // start of waveform data
        h.put<std::uint64_t>(0);  // start of first EVLR
        h.put<std::uint32_t>(0);  // number of EVLRs
        h.put<std::uint64_t>(info.count);
        h.put<std::uint64_t>(info.count);  // every point is return 1 of 1
        for (int i = 1; i < 15; ++i) h.put<std::uint64_t>(0);
        if (h.bytes.size() != kLasHeaderBytes) {
            return Status(StatusCode::kInvalidArgument, "internal: LAS header is " + std::to_string(h.bytes.size()) + " bytes");
        }
        return file_.write(h.bytes);
    }

    Status write(std::span<const journal::MapPoint> points) override {
        ByteWriter w;
        w.bytes.reserve(points.size() * kLasPointRecordBytes);
        for (const journal::MapPoint& p : points) {
            w.put<std::int32_t>(quantise(p.x, 0));
            w.put<std::int32_t>(quantise(p.y, 1));
            w.put<std::int32_t>(quantise(p.z, 2));
            w.put<std::uint16_t>(p.intensity);
            w.put<std::uint8_t>(0x11);  // return 1 of 1
            w.put<std::uint8_t>(0);     // classification flags, channel, scan direction, edge
            w.put<std::uint8_t>(0);     // classification: never classified
            w.put<std::uint8_t>(0);     // user data
            w.put<std::int16_t>(0);     // scan angle
            w.put<std::uint16_t>(0);    // point source id
            w.put<double>(p.t_s);       // seconds of the scan clock
            w.put<std::uint16_t>(static_cast<std::uint16_t>(p.r * 257));  // 8 -> 16 bit colour
            w.put<std::uint16_t>(static_cast<std::uint16_t>(p.g * 257));
            w.put<std::uint16_t>(static_cast<std::uint16_t>(p.b * 257));
        }
        written_ += points.size();
        return file_.write(w.bytes);
    }

    Status end() override {
        if (written_ != expected_) {
            return Status(StatusCode::kInvalidArgument, "export " + file_.finalPath() + ": wrote " + std::to_string(written_) +
                                                            " points but the header says " + std::to_string(expected_));
        }
        return file_.commit();
    }

private:
    std::int32_t quantise(double v, int axis) const {
        return static_cast<std::int32_t>(std::llround((v - offset_[axis]) / opt_.scale));
    }
    double dequantise(std::int32_t q, int axis) const { return q * opt_.scale + offset_[axis]; }

    SafeFileWriter& file_;
    LasOptions opt_;
    double offset_[3] = {0, 0, 0};
    std::uint64_t expected_ = 0;
    std::uint64_t written_ = 0;
};

}  // namespace

std::unique_ptr<PointFileWriter> makeLasWriter(SafeFileWriter& file, LasOptions options) {
    return std::make_unique<LasWriter>(file, std::move(options));
}

std::uint64_t lasBytes(std::uint64_t points) { return kLasHeaderBytes + points * kLasPointRecordBytes; }

}  // namespace handscan::exporter
