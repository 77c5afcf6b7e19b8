#include <algorithm>
#include <cstring>
#include <vector>

#include "handscan/export/point_formats.hpp"
#include "record_blocks.hpp"

namespace handscan::exporter {
namespace {

constexpr std::size_t kPlyRecordBytes = kPlyPointRecordBytes;

std::string plyHeader(std::uint64_t count, const std::vector<std::string>& comment,
                      bool with_session) {
    std::string h = "ply\nformat binary_little_endian 1.0\n";
    for (const std::string& c : comment) h += "comment " + c + "\n";
    return h + "element vertex " + std::to_string(count) +
           "\nproperty float x\nproperty float y\nproperty float z\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\n"
           "property ushort intensity\nproperty double time\n" +
           (with_session ? "property ushort session\n" : "") + "end_header\n";
}

// One record: x86 and ARM are little-endian, fields copy as is.
template <bool kWithSession>
void encodeRecord(const journal::MapPoint& p, std::uint8_t* o) {
    std::memcpy(o, &p.x, 4);
    std::memcpy(o + 4, &p.y, 4);
    std::memcpy(o + 8, &p.z, 4);
    o[12] = p.r;
    o[13] = p.g;
    o[14] = p.b;
    std::memcpy(o + 15, &p.intensity, 2);
    std::memcpy(o + 17, &p.t_s, 8);
    if constexpr (kWithSession) std::memcpy(o + 25, &p.session, 2);
}

class PlyWriter final : public PointFileWriter {
public:
    PlyWriter(SafeFileWriter& file, std::vector<std::string> comment, bool with_session)
        : file_(file), comment_(std::move(comment)), with_session_(with_session) {}
    Status begin(std::uint64_t count) override {
        expected_ = count;
        const std::string h = plyHeader(count, comment_, with_session_);
        return file_.write(std::span(reinterpret_cast<const std::uint8_t*>(h.data()), h.size()));
    }
    Status write(std::span<const journal::MapPoint> points) override {
        written_ += points.size();
        const auto ok = [](const journal::MapPoint&) { return Status::ok(); };
        if (with_session_) {
            return writeRecords<kPlyRecordBytes + 2>(
                file_, buf_, points,
                [this](const journal::MapPoint& p, std::uint8_t* o) {
                    bounds_.add(p.x, p.y, p.z);
                    encodeRecord<true>(p, o);
                    return true;
                },
                ok);
        }
        return writeRecords<kPlyRecordBytes>(
            file_, buf_, points,
            [this](const journal::MapPoint& p, std::uint8_t* o) {
                bounds_.add(p.x, p.y, p.z);
                encodeRecord<false>(p, o);
                return true;
            },
            ok);
    }
    Status end() override {
        if (written_ != expected_) {
            return Status(StatusCode::kInvalidArgument,
                          "export " + file_.finalPath() + ": wrote " + std::to_string(written_) +
                              " points but the header says " + std::to_string(expected_));
        }
        return file_.commit();
    }

private:
    SafeFileWriter& file_;
    std::vector<std::string> comment_;
    bool with_session_ = false;
    std::vector<std::uint8_t> buf_;
    std::uint64_t expected_ = 0;
    std::uint64_t written_ = 0;
};

}  // namespace

std::unique_ptr<PointFileWriter> makePlyWriter(SafeFileWriter& file,
                                               std::vector<std::string> comment,
                                               bool with_session) {
    for (std::string& c : comment) std::replace(c.begin(), c.end(), '\n', ' ');  // one line each
    return std::make_unique<PlyWriter>(file, std::move(comment), with_session);
}

std::uint64_t plyBytes(std::uint64_t points) {
    return plyHeader(points, kPlyWorldComment, false).size() + points * kPlyRecordBytes;
}

}  // namespace handscan::exporter
