// Xsens data identifiers (XDIs) as in Xsens' xsdataidentifier.h (../shared/data/xsens/id-tables):
// a 16-bit id whose bits 0xFFF0 name the quantity, 0x0003 the number format (float32, fp12.20,
// fp16.32, float64) and 0x000C the coordinate system (ENU, NED, NWU). The table below says how
// each quantity is laid out in an MTData2 packet, its components, the unit the device sends and
// the factor to SI. Pure data; no I/O.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace handscan::xsens {

constexpr std::uint16_t kXdiTypeMask = 0xFFF0;       // XDI_FullTypeMask
constexpr std::uint16_t kXdiPrecisionMask = 0x0003;  // XDI_SubFormatMask
constexpr std::uint16_t kXdiCoordSysMask = 0x000C;   // XDI_CoordSysMask

enum class Precision : std::uint8_t { kFloat32 = 0, kFp1220 = 1, kFp1632 = 2, kFloat64 = 3 };
enum class CoordSys : std::uint8_t { kEnu = 0x0, kNed = 0x4, kNwu = 0x8 };

constexpr Precision precisionOf(std::uint16_t xdi) {
    return static_cast<Precision>(xdi & kXdiPrecisionMask);
}
// Bits 0x000C = 0x000C is not defined by Xsens; it is reported as ENU-less "unknown" by name only.
constexpr CoordSys coordSysOf(std::uint16_t xdi) {
    return static_cast<CoordSys>(xdi & kXdiCoordSysMask);
}
constexpr std::uint16_t xdiTypeOf(std::uint16_t xdi) { return xdi & kXdiTypeMask; }
constexpr std::uint16_t withFormat(std::uint16_t type, Precision p, CoordSys c = CoordSys::kEnu) {
    return static_cast<std::uint16_t>(type | static_cast<std::uint16_t>(p) |
                                      static_cast<std::uint16_t>(c));
}
// Bytes per real value in the given number format.
constexpr std::size_t realSize(Precision p) {
    switch (p) {
        case Precision::kFloat32:
        case Precision::kFp1220:
            return 4;
        case Precision::kFp1632:
            return 6;
        case Precision::kFloat64:
            return 8;
    }
    return 4;
}
std::string_view precisionName(Precision p);  // "Float32", "FP1220", "FP1632", "Float64"
std::string_view coordSysName(CoordSys c);    // "ENU", "NED", "NWU", "invalid"

// Quantity ids (the XDI without format bits) the driver uses by name.
namespace xdi {
constexpr std::uint16_t kTemperature = 0x0810;
constexpr std::uint16_t kUtcTime = 0x1010;
constexpr std::uint16_t kPacketCounter = 0x1020;
constexpr std::uint16_t kSampleTimeFine = 0x1060;
constexpr std::uint16_t kSampleTimeCoarse = 0x1070;
constexpr std::uint16_t kQuaternion = 0x2010;
constexpr std::uint16_t kRotationMatrix = 0x2020;
constexpr std::uint16_t kEulerAngles = 0x2030;
constexpr std::uint16_t kBaroPressure = 0x3010;
constexpr std::uint16_t kDeltaV = 0x4010;
constexpr std::uint16_t kAcceleration = 0x4020;
constexpr std::uint16_t kFreeAcceleration = 0x4030;
constexpr std::uint16_t kAltitudeEllipsoid = 0x5020;
constexpr std::uint16_t kPositionEcef = 0x5030;
constexpr std::uint16_t kLatLon = 0x5040;
constexpr std::uint16_t kGnssPvtData = 0x7010;
constexpr std::uint16_t kGnssSatInfo = 0x7020;
constexpr std::uint16_t kRateOfTurn = 0x8020;
constexpr std::uint16_t kDeltaQ = 0x8030;
constexpr std::uint16_t kMagneticField = 0xC020;
constexpr std::uint16_t kVelocityXyz = 0xD010;
constexpr std::uint16_t kStatusByte = 0xE010;
constexpr std::uint16_t kStatusWord = 0xE020;
}  // namespace xdi

enum class XdiLayout : std::uint8_t {
    kReals,   // `components.size()` reals in the XDI's number format (0 components: as many as fit)
    kStruct,  // fixed big-endian integer fields (`fields`)
    kStructRepeated,  // `fields` once, then `repeated` per element until the end (GnssSatInfo)
    kOpaque,          // layout not published / not confirmed: reported as raw bytes
};

enum class IntType : std::uint8_t { kU8, kI8, kU16, kI16, kU32, kI32, kU64 };
constexpr std::size_t intSize(IntType t) {
    switch (t) {
        case IntType::kU8:
        case IntType::kI8:
            return 1;
        case IntType::kU16:
        case IntType::kI16:
            return 2;
        case IntType::kU32:
        case IntType::kI32:
            return 4;
        case IntType::kU64:
            return 8;
    }
    return 1;
}

struct IntFieldInfo {
    std::string_view name;
    IntType type;
    double si_scale = 1.0;          // value * si_scale is in si_unit
    std::string_view si_unit = "";  // empty: dimensionless / count / flags
};

struct XdiInfo {
    std::uint16_t type = 0;  // quantity id (format bits clear)
    std::string_view name;   // as in the XDI table without "XDI_": "Acceleration"
    XdiLayout layout = XdiLayout::kOpaque;
    std::span<const std::string_view> components;  // kReals: component names
    std::string_view device_unit;                  // kReals: unit the device sends ("deg", "m/s^2")
    double si_scale = 1.0;                         // kReals: device value * si_scale is in si_unit
    std::string_view si_unit;
    bool has_precision = false;              // the format bits choose the number format
    bool has_coord_sys = false;              // the coordinate-system bits apply
    std::span<const IntFieldInfo> fields;    // kStruct / kStructRepeated
    std::span<const IntFieldInfo> repeated;  // kStructRepeated
};

// The table entry for an XDI (format bits ignored), or nullptr when the quantity is unknown.
const XdiInfo* findXdi(std::uint16_t xdi);
// Every quantity the decoder knows (for tests and documentation).
std::span<const XdiInfo> xdiTable();

}  // namespace handscan::xsens
