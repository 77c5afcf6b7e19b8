#include "e57_xml.hpp"

#include <cstdio>
#include <random>
#include <sstream>

#include "e57_format.hpp"

namespace handscan::exporter::e57 {
namespace {

std::string escaped(const std::string& s) {
    std::string o;
    for (char c : s) {
        switch (c) {
            case '&':
                o += "&amp;";
                break;
            case '<':
                o += "&lt;";
                break;
            case '>':
                o += "&gt;";
                break;
            case '"':
                o += "&quot;";
                break;
            default:
                o += c;
        }
    }
    return o;
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

class Xml {
public:
    void open(const std::string& name, const std::string& type, const std::string& attrs = "") {
        indent();
        os_ << '<' << name << " type=\"" << type << '"' << attrs << ">\n";
        ++depth_;
    }
    void close(const std::string& name) {
        --depth_;
        indent();
        os_ << "</" << name << ">\n";
    }
    void text(const std::string& name, const std::string& value) {
        leaf(name, "String", escaped(value));
    }
    void integer(const std::string& name, std::int64_t v) {
        leaf(name, "Integer", std::to_string(v));
    }
    void real(const std::string& name, double v) { leaf(name, "Float", number(v)); }
    void raw(const std::string& line) {
        indent();
        os_ << line << '\n';
    }
    std::string str() const { return os_.str(); }

private:
    void leaf(const std::string& name, const std::string& type, const std::string& value) {
        indent();
        os_ << '<' << name << " type=\"" << type << "\">" << value << "</" << name << ">\n";
    }
    void indent() { os_ << std::string(2 * depth_, ' '); }
    std::ostringstream os_;
    int depth_ = 0;
};

void pose(Xml& x) {  // the points are in the file's (world) frame already: identity
    x.open("pose", "Structure");
    x.open("rotation", "Structure");
    x.real("w", 1.0);
    x.real("x", 0.0);
    x.real("y", 0.0);
    x.real("z", 0.0);
    x.close("rotation");
    x.open("translation", "Structure");
    x.real("x", 0.0);
    x.real("y", 0.0);
    x.real("z", 0.0);
    x.close("translation");
    x.close("pose");
}

void limits(Xml& x, const ScanXml& s) {
    const bool any = s.points > 0;
    x.open("cartesianBounds", "Structure");
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        x.real(std::string(axis[i]) + "Minimum", any ? s.bounds.min[i] : 0.0);
        x.real(std::string(axis[i]) + "Maximum", any ? s.bounds.max[i] : 0.0);
    }
    x.close("cartesianBounds");
    x.open("intensityLimits", "Structure");
    x.integer("intensityMinimum", 0);
    x.integer("intensityMaximum", 65535);
    x.close("intensityLimits");
    x.open("colorLimits", "Structure");
    for (const char* c : {"Red", "Green", "Blue"}) {
        x.integer(std::string("color") + c + "Minimum", 0);
        x.integer(std::string("color") + c + "Maximum", 255);
    }
    x.close("colorLimits");
}

void pointsPrototype(Xml& x, const ScanXml& s) {
    x.open("points", "CompressedVector",
           " fileOffset=\"" + std::to_string(s.points_offset) + "\" recordCount=\"" +
               std::to_string(s.points) + '"');
    x.open("prototype", "Structure");
    for (const char* axis : {"cartesianX", "cartesianY", "cartesianZ"}) {
        if (s.coordinate_scale > 0) {
            x.raw(std::string("<") + axis + " type=\"ScaledInteger\" minimum=\"" +
                  std::to_string(s.coordinate_raw_min) + "\" maximum=\"" +
                  std::to_string(s.coordinate_raw_max) + "\" scale=\"" +
                  number(s.coordinate_scale) + "\" offset=\"0\"/>");
        } else {
            x.raw(std::string("<") + axis + " type=\"Float\" precision=\"double\"/>");
        }
    }
    x.raw("<intensity type=\"Integer\" minimum=\"0\" maximum=\"65535\"/>");
    for (const char* c : {"colorRed", "colorGreen", "colorBlue"})
        x.raw(std::string("<") + c + " type=\"Integer\" minimum=\"0\" maximum=\"255\"/>");
    x.raw("<isColorInvalid type=\"Integer\" minimum=\"0\" maximum=\"1\"/>");
    x.raw("<timeStamp type=\"Float\" precision=\"double\"/>");
    x.close("prototype");
    x.raw("<codecs type=\"Vector\" allowHeterogeneousChildren=\"1\"/>");
    x.close("points");
}

void trajectory(Xml& x, const ScanXml& s) {
    x.open("handscan:trajectory", "CompressedVector",
           " fileOffset=\"" + std::to_string(s.trajectory_offset) + "\" recordCount=\"" +
               std::to_string(s.trajectory_poses) + '"');
    x.open("prototype", "Structure");
    for (const char* f : {"handscan:timeStamp", "handscan:x", "handscan:y", "handscan:z",
                          "handscan:qw", "handscan:qx", "handscan:qy", "handscan:qz"})
        x.raw(std::string("<") + f + " type=\"Float\" precision=\"double\"/>");
    x.close("prototype");
    x.raw("<codecs type=\"Vector\" allowHeterogeneousChildren=\"1\"/>");
    x.close("handscan:trajectory");
}

}  // namespace

std::string scanXml(const ScanXml& s) {
    Xml x;
    x.raw("<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    x.open(
        "e57Root", "Structure",
        std::string(" xmlns=\"") + kNamespace + "\" xmlns:handscan=\"" + kHandscanNamespace + '"');
    x.text("formatName", "ASTM E57 3D Imaging Data File");
    x.text("guid", s.file_guid);
    x.integer("versionMajor", 1);
    x.integer("versionMinor", 0);
    x.text("e57LibraryVersion", "handscan " + s.software_version);
    x.text("coordinateMetadata", "");  // a local, gravity-aligned frame: no geodetic reference
    x.open("creationDateTime", "Structure");
    x.real("dateTimeValue", s.creation_gps_s);
    x.integer("isAtomicClockReferenced", 0);
    x.close("creationDateTime");
    x.open("data3D", "Vector", " allowHeterogeneousChildren=\"1\"");
    x.open("vectorChild", "Structure");
    x.text("guid", s.scan_guid);
    x.text("name", s.name);
    x.text("description", s.description);
    x.text("sensorVendor", s.sensor_vendor);
    x.text("sensorModel", s.sensor_model);
    x.text("sensorSerialNumber", s.sensor_serial);
    x.text("sensorSoftwareVersion", s.software_version);
    pose(x);
    limits(x, s);
    pointsPrototype(x, s);
    if (s.trajectory_poses > 0) trajectory(x, s);
    x.close("vectorChild");
    x.close("data3D");
    x.raw("<images2D type=\"Vector\" allowHeterogeneousChildren=\"1\"/>");
    x.close("e57Root");
    return x.str();
}

std::string randomGuid() {
    std::random_device rd;
    std::uint8_t b[16];
    for (int i = 0; i < 16; i += 4) {
        const std::uint32_t v = rd();
        for (int k = 0; k < 4; ++k) b[i + k] = static_cast<std::uint8_t>(v >> (8 * k));
    }
    b[6] = static_cast<std::uint8_t>((b[6] & 0x0F) | 0x40);  // version 4
    b[8] = static_cast<std::uint8_t>((b[8] & 0x3F) | 0x80);  // RFC 4122 variant
    char out[40];
    std::snprintf(out, sizeof out,
                  "{%02x%02x%02x%02x-%02x%02x-%02x%02x-%02x%02x-%02x%02x%02x%02x%02x%02x}", b[0],
                  b[1], b[2], b[3], b[4], b[5], b[6], b[7], b[8], b[9], b[10], b[11], b[12], b[13],
                  b[14], b[15]);
    return out;
}

}  // namespace handscan::exporter::e57
