// A CAN frame as a plain value type mirroring Linux `struct can_frame` / `struct canfd_frame`
// without including <linux/can.h>: the CANopen codec (drivers/motor), the candump text format and
// the transports all use it, and only the SocketCAN transport converts to and from the kernel
// structs. Filters keep the kernel's semantics so that transports without kernel filters agree.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "handscan/core/time.hpp"

namespace handscan {

// Identifier masks and flag values as in include/uapi/linux/can.h.
constexpr std::uint32_t kCanSffMask = 0x000007FFu;
constexpr std::uint32_t kCanEffMask = 0x1FFFFFFFu;
constexpr std::uint32_t kCanErrMask = 0x1FFFFFFFu;
constexpr std::size_t kCanMaxDataLength = 8;
constexpr std::size_t kCanFdMaxDataLength = 64;

struct CanFrame {
    std::uint32_t id = 0;   // 11-bit (SFF) or 29-bit (EFF) identifier, or error class bits (ERR)
    bool extended = false;  // CAN_EFF_FLAG: 29-bit identifier
    bool remote = false;    // CAN_RTR_FLAG: remote transmission request (no data bytes)
    bool error = false;     // CAN_ERR_FLAG: error frame reported by the controller
    bool fd = false;        // CAN FD frame (up to 64 data bytes)
    std::uint8_t fd_flags = 0;  // CAN FD flags (CANFD_BRS 0x01, CANFD_ESI 0x02)
    std::uint8_t len = 0;  // payload length in bytes (the DLC for classic frames, also for RTR)
    std::uint8_t len8_dlc = 0;  // classic CAN raw DLC 9..15 when len == 8 (0 = not used)
    std::array<std::uint8_t, kCanFdMaxDataLength> data{};

    std::span<const std::uint8_t> payload() const { return {data.data(), remote ? 0u : len}; }
    friend bool operator==(const CanFrame&, const CanFrame&) = default;
};

// Builds a classic data frame with an 11-bit identifier.
inline CanFrame makeCanFrame(std::uint32_t id, std::span<const std::uint8_t> bytes) {
    CanFrame f;
    f.id = id & kCanSffMask;
    f.len = static_cast<std::uint8_t>(bytes.size() < kCanMaxDataLength ? bytes.size()
                                                                       : kCanMaxDataLength);
    for (std::size_t i = 0; i < f.len; ++i) f.data[i] = bytes[i];
    return f;
}

// A receive filter with the kernel's semantics: a frame passes when
// (frame_id & mask) == (id & mask), or when it does not match if `inverted` (CAN_INV_FILTER).
// `id` and `mask` are in the kernel's encoding (flags included), see canFilterMatches().
struct CanFilter {
    std::uint32_t id = 0;
    std::uint32_t mask = 0;
    bool inverted = false;
};

// Kernel flag bits, used only to compose filter ids/masks (e.g. mask SFF + EFF flag + RTR flag).
constexpr std::uint32_t kCanEffFlag = 0x80000000u;
constexpr std::uint32_t kCanRtrFlag = 0x40000000u;
constexpr std::uint32_t kCanErrFlag = 0x20000000u;
constexpr std::size_t kCanMaxFilters = 512;  // CAN_RAW_FILTER_MAX

// The kernel-encoded can_id of a frame (identifier | EFF | RTR | ERR flags).
inline std::uint32_t canIdWithFlags(const CanFrame& f) {
    return f.id | (f.extended ? kCanEffFlag : 0u) | (f.remote ? kCanRtrFlag : 0u) |
           (f.error ? kCanErrFlag : 0u);
}

// Filter that passes exactly the 11-bit data frames with identifier `id`.
inline CanFilter exactSffFilter(std::uint32_t id) {
    return {id & kCanSffMask, kCanSffMask | kCanEffFlag | kCanRtrFlag, false};
}

// Software filter check with the kernel's semantics (used by transports without kernel filters).
// Error frames are never delivered through the id filters (the kernel uses CAN_RAW_ERR_FILTER).
inline bool canFilterMatches(std::span<const CanFilter> filters, const CanFrame& f) {
    if (f.error) return false;
    if (filters.empty()) return true;  // no filter installed: everything passes
    const std::uint32_t can_id = canIdWithFlags(f);
    for (const CanFilter& flt : filters) {
        const bool match = (can_id & flt.mask) == (flt.id & flt.mask);
        if (match != flt.inverted) return true;
    }
    return false;
}

// A received frame with its host receive time.
struct TimedCanFrame {
    TimeNs t_host = 0;
    CanFrame frame;
};

}  // namespace handscan
