#include <algorithm>
#include <cstring>
#include <vector>

#include "handscan/export/point_formats.hpp"
#include "record_blocks.hpp"

namespace handscan::exporter {
namespace {

constexpr std::size_t kPlyRecordBytes = kPlyPointRecordBytes;

std::string plyHeader(std::uint64_t count, const std::vector<std::string>& comment) {
    std::string h = "ply\nformat binary_little_endian 1.0\n";
    for (const std::string& c : comment) h += "comment " + c + "\n";
    return h + "element vertex " + std::to_string(count) +
           "\nproperty float x\nproperty float y\nproperty float z\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\n"
           "property ushort intensity\nproperty double time\nend_header\n";
}

class PlyWriter final : public PointFileWriter {
public:
    PlyWriter(SafeFileWriter& file, std::vector<std::string> comment)
        : file_(file), comment_(std::move(comment)) {}
    Status begin(std::uint64_t count) override {
        expected_ = count;
        const std::string h = plyHeader(count, comment_);
        return file_.write(std::span(reinterpret_cast<const std::uint8_t*>(h.data()), h.size()));
    }
    Status write(std::span<const journal::MapPoint> points) override {
        written_ += points.size();
        return writeRecords<kPlyRecordBytes>(
            file_, buf_, points,
            [this](const journal::MapPoint& p,
                   std::uint8_t* o) {  // x86 and ARM are little-endian: fields copy as is
                bounds_.add(p.x, p.y, p.z);
                std::memcpy(o, &p.x, 4);
                std::memcpy(o + 4, &p.y, 4);
                std::memcpy(o + 8, &p.z, 4);
                o[12] = p.r;
                o[13] = p.g;
                o[14] = p.b;
                std::memcpy(o + 15, &p.intensity, 2);
                std::memcpy(o + 17, &p.t_s, 8);
                return true;
            },
            [](const journal::MapPoint&) { return Status::ok(); });
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
    std::vector<std::uint8_t> buf_;
    std::uint64_t expected_ = 0;
    std::uint64_t written_ = 0;
};

}  // namespace

std::unique_ptr<PointFileWriter> makePlyWriter(SafeFileWriter& file,
                                               std::vector<std::string> comment) {
    for (std::string& c : comment) std::replace(c.begin(), c.end(), '\n', ' ');  // one line each
    return std::make_unique<PlyWriter>(file, std::move(comment));
}

std::uint64_t plyBytes(std::uint64_t points) {
    return plyHeader(points, kPlyWorldComment).size() + points * kPlyRecordBytes;
}

}  // namespace handscan::exporter
