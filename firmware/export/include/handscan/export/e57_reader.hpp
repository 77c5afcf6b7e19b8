// Reads ASTM E57 files: ours (the export's verification and `handscan info`) and those of other
// software (libE57Format, CloudCompare). open() checks the file header and, unless told not to,
// the CRC-32C of every page (naming the first corrupt page), then parses the XML section into the
// scans (data3D) with their sensor, pose and compressed vectors. read() decodes a compressed
// vector's data packets (bitpack codec: Float single/double, Integer, ScaledInteger) record
// block by record block, so a large cloud never sits in memory whole.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::exporter {

struct E57Field {
    enum class Kind { kFloat, kInteger, kScaledInteger };
    std::string name;  // as in the prototype: cartesianX, colorRed, handscan:x, ...
    Kind kind = Kind::kFloat;
    bool single = false;                    // Float precision="single"
    std::int64_t minimum = 0, maximum = 0;  // Integer / ScaledInteger raw range
    double scale = 1.0, offset = 0.0;       // ScaledInteger: value = raw * scale + offset
    unsigned bits = 64;                     // per value in its bytestream
};

struct E57CompressedVector {
    std::uint64_t file_offset = 0;  // physical offset of its binary section
    std::uint64_t records = 0;
    std::vector<E57Field> fields;
    int field(const std::string& name) const;  // index, -1 when absent
};

struct E57Scan {
    std::string guid, name, sensor_vendor, sensor_model, sensor_serial, software_version;
    double rotation_wxyz[4] = {1, 0, 0, 0};
    double translation[3] = {0, 0, 0};
    E57CompressedVector points;
    std::optional<E57CompressedVector> trajectory;  // handscan:trajectory extension, when present
};

struct E57File {
    std::uint32_t version_major = 0, version_minor = 0;
    std::uint64_t physical_length = 0, xml_offset = 0, xml_length = 0, pages = 0;
    std::string guid;
    std::vector<E57Scan> scans;
};

class E57Reader {
public:
    static Result<E57Reader> open(const std::string& path, bool check_pages = true);
    const E57File& file() const { return file_; }
    // Calls `sink(columns, n)` per decoded block: columns[f][i] is field f of record i, as a
    // double (scaled integers scaled). Fails on a damaged packet or a short section.
    using Sink =
        std::function<void(const std::vector<std::vector<double>>& columns, std::size_t n)>;
    Status read(const E57CompressedVector& vector, const Sink& sink) const;

private:
    std::string path_;
    E57File file_;
};

}  // namespace handscan::exporter
