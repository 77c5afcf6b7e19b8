#include "info_e57.hpp"

#include <algorithm>
#include <limits>

#include "handscan/core/log.hpp"
#include "handscan/export/e57_reader.hpp"

namespace handscan::cli {
namespace {

using exporter::E57CompressedVector;
using exporter::E57Field;

const char* kindName(const E57Field& f) {
    switch (f.kind) {
        case E57Field::Kind::kFloat:
            return f.single ? "Float single" : "Float double";
        case E57Field::Kind::kInteger:
            return "Integer";
        case E57Field::Kind::kScaledInteger:
            return "ScaledInteger";
    }
    return "?";
}

// Bounds of cartesianX/Y/Z and the share of points with a valid colour, from every record.
Status printPointStats(const exporter::E57Reader& r, const E57CompressedVector& v,
                       std::ostream& out) {
    const int axis[3] = {v.field("cartesianX"), v.field("cartesianY"), v.field("cartesianZ")};
    const int red = v.field("colorRed"), invalid = v.field("isColorInvalid");
    double lo[3], hi[3];
    std::fill(lo, lo + 3, std::numeric_limits<double>::max());
    std::fill(hi, hi + 3, std::numeric_limits<double>::lowest());
    std::uint64_t coloured = 0, total = 0;
    Status s = r.read(v, [&](const std::vector<std::vector<double>>& c, std::size_t n) {
        for (int a = 0; a < 3; ++a) {
            if (axis[a] < 0) continue;
            for (std::size_t i = 0; i < n; ++i) {
                lo[a] = std::min(lo[a], c[axis[a]][i]);
                hi[a] = std::max(hi[a], c[axis[a]][i]);
            }
        }
        for (std::size_t i = 0; i < n && red >= 0; ++i)
            coloured += invalid < 0 || c[invalid][i] == 0.0;
        total += n;
    });
    if (!s.isOk()) return s;
    if (axis[0] >= 0 && total > 0) {
        out << "    bounds      [" << lo[0] << ", " << lo[1] << ", " << lo[2] << "] .. [" << hi[0]
            << ", " << hi[1] << ", " << hi[2] << "] m\n";
    }
    if (red >= 0 && total > 0) {
        out << "    coloured    " << coloured << " of " << total << " ("
            << 100.0 * static_cast<double>(coloured) / static_cast<double>(total) << " %)\n";
    }
    return Status::ok();
}

}  // namespace

int printE57Info(const std::string& path, std::ostream& out) {
    auto r = exporter::E57Reader::open(path);
    if (!r.isOk()) {
        log().error("{}", r.status().message());
        return r.status().code() == StatusCode::kChecksumError ? 3 : 1;
    }
    const exporter::E57File& f = r->file();
    out << path << ": ASTM E57 " << f.version_major << '.' << f.version_minor << ", " << f.pages
        << " pages (CRC-32C all good), XML " << f.xml_length << " bytes, guid " << f.guid << '\n';
    for (const exporter::E57Scan& s : f.scans) {
        out << "  scan '" << s.name << "' " << s.guid << '\n';
        out << "    sensor      " << s.sensor_vendor << " / " << s.sensor_model << " / serial "
            << s.sensor_serial << " / software " << s.software_version << '\n';
        out << "    pose        q(w x y z) = " << s.rotation_wxyz[0] << ' ' << s.rotation_wxyz[1]
            << ' ' << s.rotation_wxyz[2] << ' ' << s.rotation_wxyz[3]
            << ", t = " << s.translation[0] << ' ' << s.translation[1] << ' ' << s.translation[2]
            << '\n';
        out << "    points      " << s.points.records << " records:";
        for (const E57Field& fd : s.points.fields)
            out << ' ' << fd.name << " (" << kindName(fd) << ", " << fd.bits << " bits)";
        out << '\n';
        if (Status st = printPointStats(*r, s.points, out); !st.isOk()) {
            log().error("{}", st.message());
            return 1;
        }
        if (s.trajectory) out << "    trajectory  " << s.trajectory->records << " poses\n";
    }
    return 0;
}

}  // namespace handscan::cli
