// MTData2 (MID 0x36) payloads: a sequence of items `XDI (u16 BE) | size (u8) | data (BE)`.
// decodeMtData2 turns a payload into one MtData2Value per item, decoded with the XDI table
// (xdi.hpp) in every number format (float32, fp12.20, fp16.32, float64); unknown XDIs and items
// whose size does not match their layout are kept (raw bytes, with a reason) and never stop the
// rest of the packet. MtData2Builder is the encode side used by the fake device and the simulator.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/xsens/xdi.hpp"

namespace handscan::xsens {

// One decoded component. `value` is in the device's unit; value * si_scale is in si_unit.
struct XdiField {
    std::string_view name;
    double value = 0.0;
    double si_scale = 1.0;
    std::string_view si_unit;
    int element = -1;  // index of the repeated element (GnssSatInfo satellites), -1 otherwise
};

struct MtData2Value {
    std::uint16_t xdi = 0;          // as sent, with format bits
    const XdiInfo* info = nullptr;  // nullptr: XDI not in the table
    std::vector<std::uint8_t> raw;  // the item's bytes as sent
    std::vector<XdiField> fields;   // decoded components (empty for opaque / unknown / bad)
    std::string problem;            // why the item could not be decoded ("" when it was)

    std::uint16_t type() const { return xdiTypeOf(xdi); }
    std::string_view name() const {
        return info != nullptr ? info->name : std::string_view("Unknown");
    }
    Precision precision() const { return precisionOf(xdi); }
    CoordSys coordSys() const { return coordSysOf(xdi); }
    bool decoded() const { return problem.empty() && !fields.empty(); }
};

struct MtData2Packet {
    std::vector<MtData2Value> values;  // in wire order

    const MtData2Value* find(std::uint16_t type) const;      // by quantity id (format bits ignored)
    std::optional<double> scalar(std::uint16_t type) const;  // first field
    std::optional<Eigen::Vector3d> vector3(std::uint16_t type) const;  // three components
    std::optional<Eigen::Vector4d> vector4(std::uint16_t type) const;  // q0..q3
    std::optional<std::uint64_t> integer(std::uint16_t type) const;    // single-integer items
    std::size_t unknownCount() const;  // items whose XDI is not in the table
};

// Decodes a payload. Fails only when the item framing itself is broken (an item's size runs
// past the end of the payload), naming the item and offset; bad items inside are kept with
// `problem` set.
Result<MtData2Packet> decodeMtData2(std::span<const std::uint8_t> payload);

// Fixed-point conversions (Xsens: fp12.20 is a signed 32-bit value / 2^20; fp16.32 is sent as
// the 32-bit fraction followed by the signed 16-bit integer part, value = int48 / 2^32).
double decodeReal(const std::uint8_t* p, Precision precision);
void encodeReal(std::vector<std::uint8_t>& out, double v, Precision precision);

// Builds an MTData2 payload item by item, as an MTi would send it (big endian).
class MtData2Builder {
public:
    MtData2Builder& packetCounter(std::uint16_t counter);
    MtData2Builder& sampleTimeFine(std::uint32_t ticks_10khz);
    MtData2Builder& sampleTimeCoarse(std::uint32_t seconds);
    MtData2Builder& statusWord(std::uint32_t status);
    MtData2Builder& statusByte(std::uint8_t status);
    MtData2Builder& acceleration(const Eigen::Vector3d& a_mps2, Precision p = Precision::kFloat32);
    MtData2Builder& freeAcceleration(const Eigen::Vector3d& a_mps2,
                                     Precision p = Precision::kFloat32);
    MtData2Builder& rateOfTurn(const Eigen::Vector3d& w_radps, Precision p = Precision::kFloat32);
    MtData2Builder& deltaV(const Eigen::Vector3d& dv_mps, Precision p = Precision::kFloat32);
    MtData2Builder& deltaQ(const Eigen::Vector4d& q0123, Precision p = Precision::kFloat32);
    MtData2Builder& quaternion(const Eigen::Vector4d& q0123, Precision p = Precision::kFloat32,
                               CoordSys c = CoordSys::kEnu);
    MtData2Builder& magneticField(const Eigen::Vector3d& m_au, Precision p = Precision::kFloat32);
    MtData2Builder& temperature(double deg_c, Precision p = Precision::kFloat32);
    MtData2Builder& baroPressure(std::uint32_t pascal);
    // Any real-valued XDI: the format bits of `xdi` choose the number format.
    MtData2Builder& reals(std::uint16_t xdi, std::span<const double> values);
    MtData2Builder& u8(std::uint16_t xdi, std::uint8_t v);
    MtData2Builder& u16(std::uint16_t xdi, std::uint16_t v);
    MtData2Builder& u32(std::uint16_t xdi, std::uint32_t v);
    // Raw item bytes (unknown XDIs, fault injection). At most 255 bytes per item.
    MtData2Builder& raw(std::uint16_t xdi, std::span<const std::uint8_t> data);

    const std::vector<std::uint8_t>& payload() const { return payload_; }
    // The complete Xbus MTData2 frame (FA FF 36 LEN ... CS).
    std::vector<std::uint8_t> frame() const;
    void clear() { payload_.clear(); }

private:
    std::vector<std::uint8_t> payload_;
};

// The 16-bit PacketCounter across consecutive MTData2 packets: how many went missing between them.
class PacketCounterTracker {
public:
    // Packets lost between the previous counter and `counter` (0 for the first one, and across the
    // 65535 -> 0 wrap); `counter` then becomes the previous one.
    std::uint16_t missingBefore(std::uint16_t counter) {
        const std::uint16_t missing = last_ ? static_cast<std::uint16_t>(counter - *last_ - 1) : 0;
        last_ = counter;
        return missing;
    }
    std::optional<std::uint16_t> last() const { return last_; }
    void reset() { last_.reset(); }

private:
    std::optional<std::uint16_t> last_;
};

}  // namespace handscan::xsens
