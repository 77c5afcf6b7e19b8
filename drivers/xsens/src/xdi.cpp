// The XDI table. Quantities and ids from Xsens' xsdataidentifier.h; payload layouts from the MT
// low-level protocol documentation as implemented by einride/xsens-go and Scottapotamas/xsens-mti
// and checked against the real captures in ../shared/data/xsens. Layouts we could not confirm are
// kOpaque: reported as raw bytes, never guessed.
#include "handscan/xsens/xdi.hpp"

#include <algorithm>
#include <array>
#include <numbers>

namespace handscan::xsens {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

constexpr std::array<std::string_view, 1> kScalar{"value"};
constexpr std::array<std::string_view, 3> kXyz{"x", "y", "z"};
constexpr std::array<std::string_view, 4> kQuat{"q0", "q1", "q2", "q3"};
constexpr std::array<std::string_view, 9> kMatrix{"a", "b", "c", "d", "e", "f", "g", "h", "i"};
constexpr std::array<std::string_view, 3> kEuler{"roll", "pitch", "yaw"};
constexpr std::array<std::string_view, 2> kLatLon{"lat", "lon"};

constexpr std::array<IntFieldInfo, 1> kU8Value{{{"value", IntType::kU8}}};
constexpr std::array<IntFieldInfo, 1> kI8Value{{{"value", IntType::kI8}}};
constexpr std::array<IntFieldInfo, 1> kU16Value{{{"value", IntType::kU16}}};
constexpr std::array<IntFieldInfo, 1> kU32Value{{{"value", IntType::kU32}}};
constexpr std::array<IntFieldInfo, 1> kSampleTimeFine{{{"value", IntType::kU32, 1e-4, "s"}}};
constexpr std::array<IntFieldInfo, 1> kSampleTimeCoarse{{{"value", IntType::kU32, 1.0, "s"}}};
constexpr std::array<IntFieldInfo, 1> kSampleTime64{{{"value", IntType::kU64, 1e-4, "s"}}};
constexpr std::array<IntFieldInfo, 1> kItow{{{"value", IntType::kU32, 1e-3, "s"}}};
constexpr std::array<IntFieldInfo, 1> kPressure{{{"value", IntType::kU32, 1.0, "Pa"}}};
constexpr std::array<IntFieldInfo, 2> kFrameRange{
    {{"start", IntType::kU16}, {"end", IntType::kU16}}};

constexpr std::array<IntFieldInfo, 8> kUtc{{
    {"ns", IntType::kU32},  // nanoseconds within the second
    {"year", IntType::kU16},
    {"month", IntType::kU8},
    {"day", IntType::kU8},
    {"hour", IntType::kU8},
    {"minute", IntType::kU8},
    {"second", IntType::kU8},
    {"flags", IntType::kU8},
}};

// GNSS PVT data: the u-blox NAV-PVT subset the MTi forwards (94 bytes).
constexpr std::array<IntFieldInfo, 35> kPvtFields{{
    {"itow", IntType::kU32, 1e-3, "s"},
    {"year", IntType::kU16},
    {"month", IntType::kU8},
    {"day", IntType::kU8},
    {"hour", IntType::kU8},
    {"min", IntType::kU8},
    {"sec", IntType::kU8},
    {"valid", IntType::kU8},
    {"tacc", IntType::kU32, 1e-9, "s"},
    {"nano", IntType::kI32, 1e-9, "s"},
    {"fixtype", IntType::kU8},
    {"flags", IntType::kU8},
    {"numsv", IntType::kU8},
    {"reserved1", IntType::kU8},
    {"lon", IntType::kI32, 1e-7 * kDeg, "rad"},
    {"lat", IntType::kI32, 1e-7 * kDeg, "rad"},
    {"height", IntType::kI32, 1e-3, "m"},
    {"hmsl", IntType::kI32, 1e-3, "m"},
    {"hacc", IntType::kU32, 1e-3, "m"},
    {"vacc", IntType::kU32, 1e-3, "m"},
    {"veln", IntType::kI32, 1e-3, "m/s"},
    {"vele", IntType::kI32, 1e-3, "m/s"},
    {"veld", IntType::kI32, 1e-3, "m/s"},
    {"gspeed", IntType::kI32, 1e-3, "m/s"},
    {"headmot", IntType::kI32, 1e-5 * kDeg, "rad"},
    {"sacc", IntType::kU32, 1e-3, "m/s"},
    {"headacc", IntType::kU32, 1e-5 * kDeg, "rad"},
    {"headveh", IntType::kI32, 1e-5 * kDeg, "rad"},
    {"gdop", IntType::kU16, 0.01},
    {"pdop", IntType::kU16, 0.01},
    {"tdop", IntType::kU16, 0.01},
    {"vdop", IntType::kU16, 0.01},
    {"hdop", IntType::kU16, 0.01},
    {"ndop", IntType::kU16, 0.01},
    {"edop", IntType::kU16, 0.01},
}};

constexpr std::array<IntFieldInfo, 5> kSatHeader{{
    {"itow", IntType::kU32, 1e-3, "s"},
    {"numsvs", IntType::kU8},
    {"res1", IntType::kU8},
    {"res2", IntType::kU8},
    {"res3", IntType::kU8},
}};
constexpr std::array<IntFieldInfo, 4> kSat{{
    {"gnssid", IntType::kU8},
    {"svid", IntType::kU8},
    {"cno", IntType::kU8},  // dBHz
    {"flags", IntType::kU8},
}};

// Raw sensor counts (unsigned ADC values, temperature signed).
constexpr std::array<IntFieldInfo, 10> kRawAgmt{{
    {"acc_x", IntType::kU16},
    {"acc_y", IntType::kU16},
    {"acc_z", IntType::kU16},
    {"gyr_x", IntType::kU16},
    {"gyr_y", IntType::kU16},
    {"gyr_z", IntType::kU16},
    {"mag_x", IntType::kU16},
    {"mag_y", IntType::kU16},
    {"mag_z", IntType::kU16},
    {"temp", IntType::kI16},
}};
constexpr std::array<IntFieldInfo, 3> kRawXyz{
    {{"x", IntType::kU16}, {"y", IntType::kU16}, {"z", IntType::kU16}}};
constexpr std::array<IntFieldInfo, 3> kRawGyrTemp{
    {{"x", IntType::kI16}, {"y", IntType::kI16}, {"z", IntType::kI16}}};

constexpr XdiInfo reals(std::uint16_t type, std::string_view name,
                        std::span<const std::string_view> comps, std::string_view unit,
                        double si_scale, std::string_view si_unit, bool coords = false) {
    XdiInfo i;
    i.type = type;
    i.name = name;
    i.layout = XdiLayout::kReals;
    i.components = comps;
    i.device_unit = unit;
    i.si_scale = si_scale;
    i.si_unit = si_unit;
    i.has_precision = true;
    i.has_coord_sys = coords;
    return i;
}
constexpr XdiInfo ints(std::uint16_t type, std::string_view name,
                       std::span<const IntFieldInfo> fields) {
    XdiInfo i;
    i.type = type;
    i.name = name;
    i.layout = XdiLayout::kStruct;
    i.fields = fields;
    return i;
}
constexpr XdiInfo opaque(std::uint16_t type, std::string_view name) {
    XdiInfo i;
    i.type = type;
    i.name = name;
    i.layout = XdiLayout::kOpaque;
    return i;
}
constexpr XdiInfo satInfo() {
    XdiInfo i = ints(0x7020, "GnssSatInfo", kSatHeader);
    i.layout = XdiLayout::kStructRepeated;
    i.repeated = kSat;
    return i;
}

// Sorted by type (findXdi binary-searches).
constexpr std::array kTable{
    reals(0x0810, "Temperature", kScalar, "degC", 1.0, "degC"),
    ints(0x1010, "UtcTime", kUtc),
    ints(0x1020, "PacketCounter", kU16Value),
    ints(0x1030, "Itow", kItow),
    ints(0x1040, "GnssAge", kU8Value),
    ints(0x1050, "PressureAge", kU8Value),
    ints(0x1060, "SampleTimeFine", kSampleTimeFine),
    ints(0x1070, "SampleTimeCoarse", kSampleTimeCoarse),
    ints(0x1080, "FrameRange", kFrameRange),
    ints(0x1090, "PacketCounter8", kU8Value),
    ints(0x10A0, "SampleTime64", kSampleTime64),
    ints(0x10B0, "PacketCounter32", kU32Value),
    reals(0x2010, "Quaternion", kQuat, "", 1.0, "", true),
    reals(0x2020, "RotationMatrix", kMatrix, "", 1.0, "", true),
    reals(0x2030, "EulerAngles", kEuler, "deg", kDeg, "rad", true),
    reals(0x2040, "QuaternionStd", {}, "", 1.0, "", true),
    reals(0x2050, "EulerAnglesStd", kEuler, "deg", kDeg, "rad", true),
    // BaroPressure is a u32 in Pa whatever the format bits say (MTi-300 capture: XDI 0x3013, 4
    // bytes).
    ints(0x3010, "BaroPressure", kPressure),
    reals(0x4010, "DeltaV", kXyz, "m/s", 1.0, "m/s"),
    reals(0x4020, "Acceleration", kXyz, "m/s^2", 1.0, "m/s^2"),
    reals(0x4030, "FreeAcceleration", kXyz, "m/s^2", 1.0, "m/s^2"),
    reals(0x4040, "AccelerationHR", kXyz, "m/s^2", 1.0, "m/s^2"),
    opaque(0x4810, "TriggerIn1"),
    opaque(0x4820, "TriggerIn2"),
    opaque(0x4830, "TriggerIn3"),
    reals(0x5010, "AltitudeMsl", kScalar, "m", 1.0, "m"),
    reals(0x5020, "AltitudeEllipsoid", kScalar, "m", 1.0, "m"),
    reals(0x5030, "PositionEcef", kXyz, "m", 1.0, "m"),
    reals(0x5040, "LatLon", kLatLon, "deg", kDeg, "rad"),
    reals(0x6010, "HeavePosition", {}, "m", 1.0, "m"),
    reals(0x6020, "HeavePeriod", {}, "s", 1.0, "s"),
    ints(0x7010, "GnssPvtData", kPvtFields),
    satInfo(),
    opaque(0x7030, "GnssPvtPulse"),
    reals(0x8020, "RateOfTurn", kXyz, "rad/s", 1.0, "rad/s"),
    reals(0x8030, "DeltaQ", kQuat, "", 1.0, ""),
    reals(0x8040, "RateOfTurnHR", kXyz, "rad/s", 1.0, "rad/s"),
    ints(0xA010, "RawAccGyrMagTemp", kRawAgmt),
    ints(0xA020, "RawGyroTemp", kRawGyrTemp),
    ints(0xA030, "RawAcc", kRawXyz),
    ints(0xA040, "RawGyr", kRawXyz),
    ints(0xA050, "RawMag", kRawXyz),
    opaque(0xA060, "RawDeltaQ"),
    opaque(0xA070, "RawDeltaV"),
    opaque(0xA080, "RawBlob"),
    opaque(0xA090, "RawFloatAccGyrMagTemp"),
    ints(0xB010, "AnalogIn1", kU16Value),
    ints(0xB020, "AnalogIn2", kU16Value),
    reals(0xC020, "MagneticField", kXyz, "a.u.", 1.0, "a.u."),
    reals(0xC030, "MagneticFieldCorrected", kXyz, "a.u.", 1.0, "a.u."),
    opaque(0xC810, "AwindaSnapshot"),
    opaque(0xC820, "FullSnapshot"),
    opaque(0xC830, "GloveSnapshotLeft"),
    opaque(0xC840, "GloveSnapshotRight"),
    opaque(0xCA30, "GloveDataLeft"),
    opaque(0xCA40, "GloveDataRight"),
    reals(0xD010, "VelocityXYZ", kXyz, "m/s", 1.0, "m/s", true),
    ints(0xE010, "StatusByte", kU8Value),
    ints(0xE020, "StatusWord", kU32Value),
    ints(0xE040, "Rssi", kI8Value),
    ints(0xE080, "DeviceId", kU32Value),
    ints(0xE090, "LocationId", kU16Value),
};

}  // namespace

std::string_view precisionName(Precision p) {
    switch (p) {
        case Precision::kFloat32:
            return "Float32";
        case Precision::kFp1220:
            return "FP1220";
        case Precision::kFp1632:
            return "FP1632";
        case Precision::kFloat64:
            return "Float64";
    }
    return "invalid";
}

std::string_view coordSysName(CoordSys c) {
    switch (c) {
        case CoordSys::kEnu:
            return "ENU";
        case CoordSys::kNed:
            return "NED";
        case CoordSys::kNwu:
            return "NWU";
    }
    return "invalid";
}

const XdiInfo* findXdi(std::uint16_t xdi) {
    const std::uint16_t type = xdiTypeOf(xdi);
    const auto it = std::lower_bound(kTable.begin(), kTable.end(), type,
                                     [](const XdiInfo& i, std::uint16_t t) { return i.type < t; });
    return (it != kTable.end() && it->type == type) ? &*it : nullptr;
}

std::span<const XdiInfo> xdiTable() { return kTable; }

}  // namespace handscan::xsens
