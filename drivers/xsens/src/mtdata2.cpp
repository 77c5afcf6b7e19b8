#include "handscan/xsens/mtdata2.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>

#include "handscan/xsens/xbus_frame.hpp"
#include "handscan/xsens/xbus_messages.hpp"

namespace handscan::xsens {
namespace {

std::string hex16(std::uint16_t v) {
    char b[8];
    std::snprintf(b, sizeof b, "0x%04X", v);
    return b;
}

double readInt(const std::uint8_t* p, IntType t) {
    switch (t) {
        case IntType::kU8:
            return p[0];
        case IntType::kI8:
            return static_cast<std::int8_t>(p[0]);
        case IntType::kU16:
            return getU16(p);
        case IntType::kI16:
            return static_cast<std::int16_t>(getU16(p));
        case IntType::kU32:
            return getU32(p);
        case IntType::kI32:
            return static_cast<std::int32_t>(getU32(p));
        case IntType::kU64:
            return static_cast<double>(getU64(p));
    }
    return 0.0;
}

std::size_t structSize(std::span<const IntFieldInfo> fields) {
    std::size_t n = 0;
    for (const auto& f : fields) n += intSize(f.type);
    return n;
}

void decodeStruct(const std::uint8_t* p, std::span<const IntFieldInfo> fields, int element,
                  std::vector<XdiField>& out) {
    for (const auto& f : fields) {
        out.push_back({f.name, readInt(p, f.type), f.si_scale, f.si_unit, element});
        p += intSize(f.type);
    }
}

void decodeValue(MtData2Value& v) {
    const XdiInfo* info = v.info;
    const std::size_t n = v.raw.size();
    if (info == nullptr) {
        v.problem = "XDI " + hex16(v.xdi) + " is not in the XDI table; skipped";
        return;
    }
    switch (info->layout) {
        case XdiLayout::kOpaque:
            v.problem = std::string(info->name) + ": layout not published; kept as raw bytes";
            return;
        case XdiLayout::kReals: {
            const std::size_t each = realSize(v.precision());
            std::size_t count = info->components.size();
            if (count == 0) count = n / each;  // "as many as fit"
            if (count == 0 || count * each != n) {
                v.problem = std::string(info->name) + " (" +
                            std::string(precisionName(v.precision())) + "): " + std::to_string(n) +
                            " bytes, expected " + std::to_string(count * each) +
                            "; the device and the decoder disagree on the format";
                return;
            }
            for (std::size_t i = 0; i < count; ++i) {
                static constexpr std::string_view kIndexNames[] = {
                    "0", "1", "2",  "3",  "4",  "5",  "6",  "7",
                    "8", "9", "10", "11", "12", "13", "14", "15"};
                std::string_view name = i < info->components.size() ? info->components[i]
                                        : i < 16                    ? kIndexNames[i]
                                                                    : std::string_view("n");
                v.fields.push_back({name, decodeReal(&v.raw[i * each], v.precision()),
                                    info->si_scale, info->si_unit});
            }
            return;
        }
        case XdiLayout::kStruct: {
            const std::size_t need = structSize(info->fields);
            if (n != need) {
                v.problem = std::string(info->name) + ": " + std::to_string(n) +
                            " bytes, expected " + std::to_string(need);
                return;
            }
            decodeStruct(v.raw.data(), info->fields, -1, v.fields);
            return;
        }
        case XdiLayout::kStructRepeated: {
            const std::size_t head = structSize(info->fields);
            const std::size_t each = structSize(info->repeated);
            if (n < head || (n - head) % each != 0) {
                v.problem = std::string(info->name) + ": " + std::to_string(n) + " bytes is not " +
                            std::to_string(head) + " + k*" + std::to_string(each);
                return;
            }
            decodeStruct(v.raw.data(), info->fields, -1, v.fields);
            for (std::size_t off = head, k = 0; off < n; off += each, ++k) {
                decodeStruct(v.raw.data() + off, info->repeated, static_cast<int>(k), v.fields);
            }
            return;
        }
    }
}

}  // namespace

double decodeReal(const std::uint8_t* p, Precision precision) {
    switch (precision) {
        case Precision::kFloat32:
            return static_cast<double>(std::bit_cast<float>(getU32(p)));
        case Precision::kFp1220:
            return static_cast<std::int32_t>(getU32(p)) / 1048576.0;
        case Precision::kFp1632: {
            // 32-bit fraction first, then the signed 16-bit integer part.
            const std::uint64_t frac = getU32(p);
            const auto whole = static_cast<std::int16_t>(getU16(p + 4));
            const std::int64_t fixed =
                static_cast<std::int64_t>(whole) * 4294967296LL + static_cast<std::int64_t>(frac);
            return static_cast<double>(fixed) / 4294967296.0;
        }
        case Precision::kFloat64:
            return std::bit_cast<double>(getU64(p));
    }
    return 0.0;
}

void encodeReal(std::vector<std::uint8_t>& out, double v, Precision precision) {
    switch (precision) {
        case Precision::kFloat32:
            putU32(out, std::bit_cast<std::uint32_t>(static_cast<float>(v)));
            return;
        case Precision::kFp1220: {
            // Saturate like a fixed-point converter instead of wrapping (range ±2048).
            const double scaled =
                std::clamp(std::round(v * 1048576.0), -2147483648.0, 2147483647.0);
            putU32(out, static_cast<std::uint32_t>(
                            static_cast<std::int32_t>(std::isnan(scaled) ? 0.0 : scaled)));
            return;
        }
        case Precision::kFp1632: {
            const double scaled =
                std::clamp(std::round(v * 4294967296.0), -140737488355328.0, 140737488355327.0);
            const auto fixed = static_cast<std::int64_t>(std::isnan(scaled) ? 0.0 : scaled);
            putU32(out,
                   static_cast<std::uint32_t>(static_cast<std::uint64_t>(fixed) & 0xFFFFFFFFu));
            putU16(out,
                   static_cast<std::uint16_t>((static_cast<std::uint64_t>(fixed) >> 32) & 0xFFFFu));
            return;
        }
        case Precision::kFloat64:
            putU64(out, std::bit_cast<std::uint64_t>(v));
            return;
    }
}

Result<MtData2Packet> decodeMtData2(std::span<const std::uint8_t> payload) {
    MtData2Packet packet;
    std::size_t off = 0;
    while (off < payload.size()) {
        if (payload.size() - off < 3) {
            return Status{StatusCode::kProtocolError,
                          "MTData2: " + std::to_string(payload.size() - off) +
                              " stray byte(s) at offset " + std::to_string(off) + " of " +
                              std::to_string(payload.size()) +
                              ", too few for an item header (XDI u16 + size u8)"};
        }
        const std::uint16_t id = getU16(&payload[off]);
        const std::size_t size = payload[off + 2];
        if (off + 3 + size > payload.size()) {
            return Status{StatusCode::kProtocolError,
                          "MTData2: item XDI " + hex16(id) + " at offset " + std::to_string(off) +
                              " says " + std::to_string(size) + " bytes but only " +
                              std::to_string(payload.size() - off - 3) + " remain in the " +
                              std::to_string(payload.size()) + "-byte payload"};
        }
        MtData2Value v;
        v.xdi = id;
        v.info = findXdi(id);
        v.raw.assign(payload.begin() + static_cast<std::ptrdiff_t>(off + 3),
                     payload.begin() + static_cast<std::ptrdiff_t>(off + 3 + size));
        decodeValue(v);
        packet.values.push_back(std::move(v));
        off += 3 + size;
    }
    return packet;
}

const MtData2Value* MtData2Packet::find(std::uint16_t type) const {
    for (const auto& v : values) {
        if (v.type() == xdiTypeOf(type)) return &v;
    }
    return nullptr;
}

std::optional<double> MtData2Packet::scalar(std::uint16_t type) const {
    const auto* v = find(type);
    if (v == nullptr || !v->decoded()) return std::nullopt;
    return v->fields[0].value;
}

std::optional<Eigen::Vector3d> MtData2Packet::vector3(std::uint16_t type) const {
    const auto* v = find(type);
    if (v == nullptr || !v->decoded() || v->fields.size() != 3) return std::nullopt;
    return Eigen::Vector3d(v->fields[0].value, v->fields[1].value, v->fields[2].value);
}

std::optional<Eigen::Vector4d> MtData2Packet::vector4(std::uint16_t type) const {
    const auto* v = find(type);
    if (v == nullptr || !v->decoded() || v->fields.size() != 4) return std::nullopt;
    return Eigen::Vector4d(v->fields[0].value, v->fields[1].value, v->fields[2].value,
                           v->fields[3].value);
}

std::optional<std::uint64_t> MtData2Packet::integer(std::uint16_t type) const {
    const auto* v = find(type);
    if (v == nullptr || !v->decoded() || v->fields.size() != 1 ||
        v->info->layout != XdiLayout::kStruct) {
        return std::nullopt;
    }
    return static_cast<std::uint64_t>(v->fields[0].value);
}

std::size_t MtData2Packet::unknownCount() const {
    std::size_t n = 0;
    for (const auto& v : values) n += v.info == nullptr ? 1 : 0;
    return n;
}

// ---- encode ----

MtData2Builder& MtData2Builder::raw(std::uint16_t xdi, std::span<const std::uint8_t> data) {
    const std::size_t n = std::min<std::size_t>(data.size(), 255);
    putU16(payload_, xdi);
    payload_.push_back(static_cast<std::uint8_t>(n));
    payload_.insert(payload_.end(), data.begin(), data.begin() + static_cast<std::ptrdiff_t>(n));
    return *this;
}

MtData2Builder& MtData2Builder::reals(std::uint16_t xdi, std::span<const double> values) {
    std::vector<std::uint8_t> data;
    for (double v : values) encodeReal(data, v, precisionOf(xdi));
    return raw(xdi, data);
}

MtData2Builder& MtData2Builder::u8(std::uint16_t xdi, std::uint8_t v) {
    return raw(xdi, std::span(&v, 1));
}
MtData2Builder& MtData2Builder::u16(std::uint16_t xdi, std::uint16_t v) {
    std::vector<std::uint8_t> d;
    putU16(d, v);
    return raw(xdi, d);
}
MtData2Builder& MtData2Builder::u32(std::uint16_t xdi, std::uint32_t v) {
    std::vector<std::uint8_t> d;
    putU32(d, v);
    return raw(xdi, d);
}

MtData2Builder& MtData2Builder::packetCounter(std::uint16_t c) {
    return u16(xdi::kPacketCounter, c);
}
MtData2Builder& MtData2Builder::sampleTimeFine(std::uint32_t t) {
    return u32(xdi::kSampleTimeFine, t);
}
MtData2Builder& MtData2Builder::sampleTimeCoarse(std::uint32_t s) {
    return u32(xdi::kSampleTimeCoarse, s);
}
MtData2Builder& MtData2Builder::statusWord(std::uint32_t s) { return u32(xdi::kStatusWord, s); }
MtData2Builder& MtData2Builder::statusByte(std::uint8_t s) { return u8(xdi::kStatusByte, s); }
MtData2Builder& MtData2Builder::baroPressure(std::uint32_t pa) {
    return u32(xdi::kBaroPressure, pa);
}

MtData2Builder& MtData2Builder::acceleration(const Eigen::Vector3d& a, Precision p) {
    return reals(withFormat(xdi::kAcceleration, p), std::span<const double>(a.data(), 3));
}
MtData2Builder& MtData2Builder::freeAcceleration(const Eigen::Vector3d& a, Precision p) {
    return reals(withFormat(xdi::kFreeAcceleration, p), std::span<const double>(a.data(), 3));
}
MtData2Builder& MtData2Builder::rateOfTurn(const Eigen::Vector3d& w, Precision p) {
    return reals(withFormat(xdi::kRateOfTurn, p), std::span<const double>(w.data(), 3));
}
MtData2Builder& MtData2Builder::deltaV(const Eigen::Vector3d& dv, Precision p) {
    return reals(withFormat(xdi::kDeltaV, p), std::span<const double>(dv.data(), 3));
}
MtData2Builder& MtData2Builder::deltaQ(const Eigen::Vector4d& q, Precision p) {
    return reals(withFormat(xdi::kDeltaQ, p), std::span<const double>(q.data(), 4));
}
MtData2Builder& MtData2Builder::quaternion(const Eigen::Vector4d& q, Precision p, CoordSys c) {
    return reals(withFormat(xdi::kQuaternion, p, c), std::span<const double>(q.data(), 4));
}
MtData2Builder& MtData2Builder::magneticField(const Eigen::Vector3d& m, Precision p) {
    return reals(withFormat(xdi::kMagneticField, p), std::span<const double>(m.data(), 3));
}
MtData2Builder& MtData2Builder::temperature(double deg_c, Precision p) {
    return reals(withFormat(xdi::kTemperature, p), std::span<const double>(&deg_c, 1));
}

std::vector<std::uint8_t> MtData2Builder::frame() const {
    return encodeFrame(MessageId::kMtData2, payload_);
}

}  // namespace handscan::xsens
