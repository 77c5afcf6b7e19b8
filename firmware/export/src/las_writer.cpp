// LAS 1.4 (ASPRS R15) with point data record format 7.
#include <cmath>
#include <cstring>
#include <vector>

#include "handscan/export/point_formats.hpp"
#include "record_blocks.hpp"

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
        for (std::size_t i = 0; i < width; ++i)
            bytes.push_back(i < s.size() ? static_cast<std::uint8_t>(s[i]) : 0);
    }
    std::vector<std::uint8_t> bytes;
};

class LasWriter final : public PointFileWriter {
public:
    LasWriter(SafeFileWriter& file, LasOptions options) : file_(file), opt_(std::move(options)) {}

    Status begin(std::uint64_t count) override {
        expected_ = count;
        return file_.reserveHeader(kLasHeaderBytes);
    }

    std::vector<std::uint8_t> header() const {
        const bool any = written_ > 0;
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
            h.put<double>(any ? dequantise(quantise(bounds_.max[i], i), i) : 0.0);
            h.put<double>(any ? dequantise(quantise(bounds_.min[i], i), i) : 0.0);
        }
        h.put<std::uint64_t>(0);  // start of waveform data
        h.put<std::uint64_t>(0);  // start of first EVLR
        h.put<std::uint32_t>(0);  // number of EVLRs
        h.put<std::uint64_t>(written_);
        h.put<std::uint64_t>(written_);  // every point is return 1 of 1
        for (int i = 1; i < 15; ++i) h.put<std::uint64_t>(0);
        return h.bytes;
    }

    Status write(std::span<const journal::MapPoint> points) override {
        if (written_ == 0 && !points.empty()) {
            // Offsets on a round grid at the first point keep the integers small; the i32 range
            // at 0.1 mm reaches +-214 km from there.
            offset_[0] = std::floor(points[0].x);
            offset_[1] = std::floor(points[0].y);
            offset_[2] = std::floor(points[0].z);
        }
        written_ += points.size();
        // Fixed-layout records (little-endian CPUs: fields copy as is).
        return writeRecords<kLasPointRecordBytes>(
            file_, buf_, points,
            [this](const journal::MapPoint& p, std::uint8_t* o) {
                const double xyz[3] = {p.x, p.y, p.z};
                std::int32_t q[3];
                for (int i = 0; i < 3; ++i) {
                    const double v = (xyz[i] - offset_[i]) * inv_scale_;
                    if (!(std::abs(v) <= 2147483647.0)) return false;  // also NaN
                    q[i] = roundAway(v);
                }
                bounds_.add(p.x, p.y, p.z);
                std::memcpy(o, q, 12);
                std::memcpy(o + 12, &p.intensity, 2);
                o[14] = 0x11;  // return 1 of 1
                o[15] = 0;  // classification flags, scanner channel, scan direction, edge of flight
                            // line
                o[16] = 0;  // classification: never classified
                o[17] = 0;  // user data
                std::memset(o + 18, 0, 2);           // scan angle
                std::memcpy(o + 20, &p.session, 2);  // point source ID: the session
                std::memcpy(o + 22, &p.t_s, 8);      // GPS time: seconds of the scan clock
                const std::uint16_t rgb[3] = {
                    static_cast<std::uint16_t>(p.r * 257), static_cast<std::uint16_t>(p.g * 257),
                    static_cast<std::uint16_t>(p.b * 257)};  // 8 -> 16 bit colour
                std::memcpy(o + 30, rgb, 6);
                return true;
            },
            [this](const journal::MapPoint& p) {
                return Status(
                    StatusCode::kInvalidArgument,
                    "export " + file_.finalPath() + ": point (" + std::to_string(p.x) + ", " +
                        std::to_string(p.y) + ", " + std::to_string(p.z) +
                        ") m is not finite or too far from the scan origin for LAS integers");
            });
    }

    Status end() override {
        if (written_ != expected_) {
            return Status(StatusCode::kInvalidArgument,
                          "export " + file_.finalPath() + ": wrote " + std::to_string(written_) +
                              " points, expected " + std::to_string(expected_));
        }
        const std::vector<std::uint8_t> h = header();
        if (h.size() != kLasHeaderBytes) {
            return Status(StatusCode::kInvalidArgument,
                          "internal: LAS header is " + std::to_string(h.size()) + " bytes");
        }
        if (Status s = file_.patchHeader(h); !s.isOk()) return s;
        return file_.commit();
    }

private:
    // Rounds half away from zero, like llround, without the libm call per coordinate.
    static std::int32_t roundAway(double v) {
        return static_cast<std::int32_t>(v + std::copysign(0.5, v));
    }
    std::int32_t quantise(double v, int axis) const {
        return roundAway((v - offset_[axis]) * inv_scale_);
    }
    double dequantise(std::int32_t q, int axis) const { return q * opt_.scale + offset_[axis]; }

    SafeFileWriter& file_;
    LasOptions opt_;
    double offset_[3] = {0, 0, 0};
    double inv_scale_ = 1.0 / opt_.scale;  // 1e4 exactly for 0.1 mm
    std::vector<std::uint8_t> buf_;
    std::uint64_t expected_ = 0;
    std::uint64_t written_ = 0;
};

}  // namespace

std::unique_ptr<PointFileWriter> makeLasWriter(SafeFileWriter& file, LasOptions options) {
    return std::make_unique<LasWriter>(file, std::move(options));
}

std::uint64_t lasBytes(std::uint64_t points) {
    return kLasHeaderBytes + points * kLasPointRecordBytes;
}

}  // namespace handscan::exporter
