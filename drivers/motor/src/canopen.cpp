#include "handscan/motor/canopen.hpp"

#include <cstdio>

namespace handscan::motor {
namespace {

Status wrongFrame(const char* what, const CanFrame& f, const char* expected) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "CANopen %s: frame id 0x%03X len %u is not a valid %s (%s)",
                  what, static_cast<unsigned>(f.id), static_cast<unsigned>(f.len), what, expected);
    return {StatusCode::kProtocolError, buf};
}

bool isClassicData(const CanFrame& f) { return !f.extended && !f.remote && !f.error && !f.fd; }

void putLe(CanFrame& f, std::size_t at, std::uint32_t v, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) f.data[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint32_t getLe(const CanFrame& f, std::size_t at, std::size_t n) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < n; ++i) v |= static_cast<std::uint32_t>(f.data[at + i]) << (8 * i);
    return v;
}

CanFrame frame(std::uint32_t id, std::uint8_t len) {
    CanFrame f;
    f.id = id;
    f.len = len;
    return f;
}

CanFrame sdoFrame(std::uint32_t id, std::uint8_t command, std::uint16_t index, std::uint8_t sub,
                  std::uint32_t data) {
    CanFrame f = frame(id, 8);
    f.data[0] = command;
    putLe(f, 1, index, 2);
    f.data[3] = sub;
    putLe(f, 4, data, 4);
    return f;
}

}  // namespace

const char* toString(CanOpenFunction f) {
    switch (f) {
        case CanOpenFunction::kNmt:
            return "nmt";
        case CanOpenFunction::kSync:
            return "sync";
        case CanOpenFunction::kEmcy:
            return "emcy";
        case CanOpenFunction::kTime:
            return "time";
        case CanOpenFunction::kTpdo:
            return "tpdo";
        case CanOpenFunction::kRpdo:
            return "rpdo";
        case CanOpenFunction::kSdoResponse:
            return "sdo_response";
        case CanOpenFunction::kSdoRequest:
            return "sdo_request";
        case CanOpenFunction::kHeartbeat:
            return "heartbeat";
        case CanOpenFunction::kLss:
            return "lss";
        case CanOpenFunction::kUnknown:
            break;
    }
    return "unknown";
}

CobIdInfo classifyCobId(const CanFrame& f) {
    CobIdInfo info;
    if (f.extended || f.error) return info;
    const std::uint32_t id = f.id & kCanSffMask;
    const std::uint32_t fn = id >> 7;
    const auto node = static_cast<std::uint8_t>(id & 0x7F);
    if (id == 0x000) return {CanOpenFunction::kNmt, 0, 0};
    if (id == 0x080) return {CanOpenFunction::kSync, 0, 0};
    if (id == 0x100) return {CanOpenFunction::kTime, 0, 0};
    if (id == 0x7E4 || id == 0x7E5) return {CanOpenFunction::kLss, 0, 0};
    if (node == 0) return info;
    switch (fn) {
        case 0x1:
            return {CanOpenFunction::kEmcy, node, 0};
        case 0x3:
        case 0x5:
        case 0x7:
        case 0x9:
            return {CanOpenFunction::kTpdo, node, static_cast<int>((fn - 1) / 2)};
        case 0x4:
        case 0x6:
        case 0x8:
        case 0xA:
            return {CanOpenFunction::kRpdo, node, static_cast<int>((fn - 2) / 2)};
        case 0xB:
            return {CanOpenFunction::kSdoResponse, node, 0};
        case 0xC:
            return {CanOpenFunction::kSdoRequest, node, 0};
        case 0xE:
            return {CanOpenFunction::kHeartbeat, node, 0};
        default:
            return info;
    }
}

const char* toString(NmtCommand c) {
    switch (c) {
        case NmtCommand::kStart:
            return "start";
        case NmtCommand::kStop:
            return "stop";
        case NmtCommand::kEnterPreOperational:
            return "enter_pre_operational";
        case NmtCommand::kResetNode:
            return "reset_node";
        case NmtCommand::kResetCommunication:
            return "reset_communication";
    }
    return "?";
}

CanFrame encodeNmt(NmtCommand command, std::uint8_t node) {
    CanFrame f = frame(kCobNmt, 2);
    f.data[0] = static_cast<std::uint8_t>(command);
    f.data[1] = node;
    return f;
}

Result<NmtMessage> decodeNmt(const CanFrame& f) {
    if (!isClassicData(f) || f.id != kCobNmt || f.len != 2)
        return wrongFrame("NMT", f, "id 000, 2 bytes");
    switch (f.data[0]) {
        case 0x01:
        case 0x02:
        case 0x80:
        case 0x81:
        case 0x82:
            return NmtMessage{static_cast<NmtCommand>(f.data[0]), f.data[1]};
        default:
            return wrongFrame("NMT", f, "command 01, 02, 80, 81 or 82");
    }
}

const char* toString(NmtState s) {
    switch (s) {
        case NmtState::kBootUp:
            return "boot_up";
        case NmtState::kStopped:
            return "stopped";
        case NmtState::kOperational:
            return "operational";
        case NmtState::kPreOperational:
            return "pre_operational";
    }
    return "?";
}

CanFrame encodeHeartbeat(std::uint8_t node, NmtState state) {
    CanFrame f = frame(cobHeartbeat(node), 1);
    f.data[0] = static_cast<std::uint8_t>(state);
    return f;
}

Result<Heartbeat> decodeHeartbeat(const CanFrame& f) {
    const CobIdInfo info = classifyCobId(f);
    if (!isClassicData(f) || info.function != CanOpenFunction::kHeartbeat || f.len != 1) {
        return wrongFrame("heartbeat", f, "id 701..77F, 1 byte");
    }
    const std::uint8_t s = f.data[0] & 0x7F;
    if (s != 0x00 && s != 0x04 && s != 0x05 && s != 0x7F)
        return wrongFrame("heartbeat", f, "state 00, 04, 05 or 7F");
    return Heartbeat{info.node, static_cast<NmtState>(s), (f.data[0] & 0x80) != 0};
}

CanFrame encodeSync(std::optional<std::uint8_t> counter) {
    CanFrame f = frame(kCobSync, counter ? 1 : 0);
    if (counter) f.data[0] = *counter;
    return f;
}

Result<std::optional<std::uint8_t>> decodeSync(const CanFrame& f) {
    if (!isClassicData(f) || f.id != kCobSync || f.len > 1)
        return wrongFrame("SYNC", f, "id 080, 0 or 1 byte");
    return f.len == 1 ? std::optional<std::uint8_t>(f.data[0]) : std::optional<std::uint8_t>();
}

CanFrame encodeEmergency(const Emergency& e) {
    CanFrame f = frame(cobEmcy(e.node), 8);
    putLe(f, 0, e.error_code, 2);
    f.data[2] = e.error_register;
    for (std::size_t i = 0; i < 5; ++i) f.data[3 + i] = e.vendor[i];
    return f;
}

Result<Emergency> decodeEmergency(const CanFrame& f) {
    const CobIdInfo info = classifyCobId(f);
    if (!isClassicData(f) || info.function != CanOpenFunction::kEmcy || f.len != 8) {
        return wrongFrame("EMCY", f, "id 081..0FF, 8 bytes");
    }
    Emergency e;
    e.node = info.node;
    e.error_code = static_cast<std::uint16_t>(getLe(f, 0, 2));
    e.error_register = f.data[2];
    for (std::size_t i = 0; i < 5; ++i) e.vendor[i] = f.data[3 + i];
    return e;
}

const char* toString(SdoKind k) {
    switch (k) {
        case SdoKind::kDownloadRequest:
            return "write";
        case SdoKind::kDownloadResponse:
            return "write_ack";
        case SdoKind::kUploadRequest:
            return "read";
        case SdoKind::kUploadResponse:
            return "read_response";
        case SdoKind::kAbort:
            return "abort";
        case SdoKind::kSegmented:
            return "segmented";
    }
    return "?";
}

// Expedited command byte: ccs/scs in bits 7..5, n (unused bytes) in bits 3..2, e bit 1, s bit 0.
CanFrame encodeSdoWrite(std::uint8_t node, std::uint16_t index, std::uint8_t sub,
                        std::uint32_t value, std::uint8_t size) {
    const std::uint8_t n = static_cast<std::uint8_t>(4 - (size >= 1 && size <= 4 ? size : 4));
    const std::uint32_t masked = n == 0 ? value : (value & ((1u << (8 * (4 - n))) - 1u));
    return sdoFrame(cobSdoClientToServer(node), static_cast<std::uint8_t>(0x23 | (n << 2)), index,
                    sub, masked);
}

CanFrame encodeSdoRead(std::uint8_t node, std::uint16_t index, std::uint8_t sub) {
    return sdoFrame(cobSdoClientToServer(node), 0x40, index, sub, 0);
}

CanFrame encodeSdoWriteAck(std::uint8_t node, std::uint16_t index, std::uint8_t sub) {
    return sdoFrame(cobSdoServerToClient(node), 0x60, index, sub, 0);
}

CanFrame encodeSdoReadResponse(std::uint8_t node, std::uint16_t index, std::uint8_t sub,
                               std::uint32_t value, std::uint8_t size) {
    const std::uint8_t n = static_cast<std::uint8_t>(4 - (size >= 1 && size <= 4 ? size : 4));
    const std::uint32_t masked = n == 0 ? value : (value & ((1u << (8 * (4 - n))) - 1u));
    return sdoFrame(cobSdoServerToClient(node), static_cast<std::uint8_t>(0x43 | (n << 2)), index,
                    sub, masked);
}

CanFrame encodeSdoAbort(std::uint8_t node, std::uint16_t index, std::uint8_t sub,
                        std::uint32_t code, bool from_server) {
    return sdoFrame(from_server ? cobSdoServerToClient(node) : cobSdoClientToServer(node), 0x80,
                    index, sub, code);
}

Result<SdoMessage> decodeSdo(const CanFrame& f) {
    const CobIdInfo info = classifyCobId(f);
    const bool server = info.function == CanOpenFunction::kSdoResponse;
    if (!isClassicData(f) || (!server && info.function != CanOpenFunction::kSdoRequest)) {
        return wrongFrame("SDO", f, "id 581..5FF or 601..67F");
    }
    if (f.len != 8) return wrongFrame("SDO", f, "8 bytes");
    SdoMessage m;
    m.node = info.node;
    m.from_server = server;
    m.command = f.data[0];
    m.index = static_cast<std::uint16_t>(getLe(f, 1, 2));
    m.subindex = f.data[3];
    m.value = getLe(f, 4, 4);
    const std::uint8_t cs = f.data[0] >> 5;
    const bool expedited = (f.data[0] & 0x02) != 0;
    const bool size_indicated = (f.data[0] & 0x01) != 0;
    const auto size = static_cast<std::uint8_t>(size_indicated ? 4 - ((f.data[0] >> 2) & 0x3) : 0);
    if (cs == 4) {
        m.kind = SdoKind::kAbort;
        return m;
    }
    if (!server) {
        if (cs == 1 && expedited) {
            m.kind = SdoKind::kDownloadRequest;
            m.size = size;
        } else if (cs == 2) {
            m.kind = SdoKind::kUploadRequest;
            m.value = 0;
        } else {
            m.kind = SdoKind::kSegmented;  // segment, block, or non-expedited initiate
        }
    } else {
        if (cs == 3) {
            m.kind = SdoKind::kDownloadResponse;
            m.value = 0;
        } else if (cs == 2 && expedited) {
            m.kind = SdoKind::kUploadResponse;
            m.size = size;
        } else {
            m.kind = SdoKind::kSegmented;
        }
    }
    if (m.size > 0 && m.size < 4) m.value &= (1u << (8 * m.size)) - 1u;
    return m;
}

const char* sdoAbortText(std::uint32_t code) {
    switch (code) {
        case 0x05030000:
            return "toggle bit not alternated";
        case 0x05040000:
            return "SDO protocol timed out";
        case 0x05040001:
            return "client/server command specifier not valid or unknown";
        case 0x06010000:
            return "unsupported access to an object";
        case 0x06010001:
            return "attempt to read a write-only object";
        case 0x06010002:
            return "attempt to write a read-only object";
        case 0x06020000:
            return "object does not exist in the object dictionary";
        case 0x06040041:
            return "object cannot be mapped to the PDO";
        case 0x06040042:
            return "number and length of mapped objects would exceed PDO length";
        case 0x06040043:
            return "general parameter incompatibility";
        case 0x06060000:
            return "access failed due to a hardware error";
        case 0x06070010:
            return "data type does not match, length of service parameter does not match";
        case 0x06090011:
            return "sub-index does not exist";
        case 0x06090030:
            return "invalid value for parameter";
        case 0x06090031:
            return "value of parameter written too high";
        case 0x06090032:
            return "value of parameter written too low";
        case 0x08000000:
            return "general error";
        case 0x08000020:
            return "data cannot be transferred or stored to the application";
        case 0x08000021:
            return "data cannot be transferred because of local control";
        case 0x08000022:
            return "data cannot be transferred in the present device state";
        default:
            return "unknown abort code";
    }
}

CanFrame encodeEncoderPositionTpdo(std::uint8_t node, std::uint32_t position) {
    CanFrame f = frame(cobTpdo(1, node), 4);
    putLe(f, 0, position, 4);
    return f;
}

Result<std::uint32_t> decodeEncoderPositionTpdo(const CanFrame& f) {
    const CobIdInfo info = classifyCobId(f);
    if (!isClassicData(f) || info.function != CanOpenFunction::kTpdo || info.pdo != 1 ||
        f.len < 4) {
        return wrongFrame("encoder TPDO1", f, "id 181..1FF with at least 4 bytes (6004h u32 LE)");
    }
    return getLe(f, 0, 4);
}

const char* toString(Cia402State s) {
    switch (s) {
        case Cia402State::kNotReadyToSwitchOn:
            return "not_ready_to_switch_on";
        case Cia402State::kSwitchOnDisabled:
            return "switch_on_disabled";
        case Cia402State::kReadyToSwitchOn:
            return "ready_to_switch_on";
        case Cia402State::kSwitchedOn:
            return "switched_on";
        case Cia402State::kOperationEnabled:
            return "operation_enabled";
        case Cia402State::kQuickStopActive:
            return "quick_stop_active";
        case Cia402State::kFaultReactionActive:
            return "fault_reaction_active";
        case Cia402State::kFault:
            return "fault";
    }
    return "?";
}

Cia402State cia402StateFromStatusword(std::uint16_t sw) {
    if ((sw & 0x4F) == 0x00) return Cia402State::kNotReadyToSwitchOn;
    if ((sw & 0x4F) == 0x40) return Cia402State::kSwitchOnDisabled;
    if ((sw & 0x6F) == 0x21) return Cia402State::kReadyToSwitchOn;
    if ((sw & 0x6F) == 0x23) return Cia402State::kSwitchedOn;
    if ((sw & 0x6F) == 0x27) return Cia402State::kOperationEnabled;
    if ((sw & 0x6F) == 0x07) return Cia402State::kQuickStopActive;
    if ((sw & 0x4F) == 0x0F) return Cia402State::kFaultReactionActive;
    if ((sw & 0x4F) == 0x08) return Cia402State::kFault;
    return Cia402State::kNotReadyToSwitchOn;  // undefined bit patterns: treat as not ready
}

std::optional<std::uint16_t> controlwordTowardsOperationEnabled(Cia402State s) {
    switch (s) {
        case Cia402State::kFault:
            return controlword::kFaultReset;
        case Cia402State::kSwitchOnDisabled:
            return controlword::kShutdown;
        case Cia402State::kReadyToSwitchOn:
            return controlword::kSwitchOn;
        case Cia402State::kSwitchedOn:
            return controlword::kEnableOperation;
        case Cia402State::kQuickStopActive:
            return controlword::kDisableVoltage;
        case Cia402State::kOperationEnabled:  // already there; in the two below
        case Cia402State::kNotReadyToSwitchOn:
        case Cia402State::kFaultReactionActive:
            return std::nullopt;  // the drive moves on by itself
    }
    return std::nullopt;
}

CanFrame encodeDriveVelocityRpdo(int pdo, std::uint8_t node, std::uint16_t cw,
                                 std::int32_t target_velocity) {
    CanFrame f = frame(cobRpdo(pdo, node), 6);
    putLe(f, 0, cw, 2);
    putLe(f, 2, static_cast<std::uint32_t>(target_velocity), 4);
    return f;
}

}  // namespace handscan::motor
