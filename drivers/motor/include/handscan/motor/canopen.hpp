// CANopen (CiA 301) messages as CAN frames, pure encode + decode: NMT, SYNC, EMCY, SDO expedited
// transfers, heartbeat / boot-up, PDOs; plus the CiA 406 encoder TPDO1 (position value 6004h,
// u32 little-endian in bytes 0..3, the default mapping 1A00:01 = 0x60040020) and the CiA 402 drive
// objects (controlword 6040h, statusword 6041h, modes of operation 6060h, target velocity 60FFh).
// COB-IDs follow the predefined connection set (CANopenNode, python-canopen). The simulator
// generates the encoder's traffic with these same functions.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "handscan/core/can_frame.hpp"
#include "handscan/core/status.hpp"

namespace handscan::motor {

// ---- COB-IDs of the predefined connection set -------------------------------------------------
constexpr std::uint32_t kCobNmt = 0x000;
constexpr std::uint32_t kCobSync = 0x080;
constexpr std::uint32_t cobEmcy(std::uint8_t node) { return 0x080u + node; }
// PDO number 1..4: TPDOn = 0x180 + 0x100*(n-1) + node, RPDOn = 0x200 + 0x100*(n-1) + node.
constexpr std::uint32_t cobTpdo(int pdo, std::uint8_t node) {
    return 0x180u + 0x100u * static_cast<std::uint32_t>(pdo - 1) + node;
}
constexpr std::uint32_t cobRpdo(int pdo, std::uint8_t node) {
    return 0x200u + 0x100u * static_cast<std::uint32_t>(pdo - 1) + node;
}
constexpr std::uint32_t cobSdoServerToClient(std::uint8_t node) { return 0x580u + node; }
constexpr std::uint32_t cobSdoClientToServer(std::uint8_t node) { return 0x600u + node; }
constexpr std::uint32_t cobHeartbeat(std::uint8_t node) { return 0x700u + node; }

enum class CanOpenFunction : std::uint8_t {
    kNmt,
    kSync,
    kEmcy,
    kTime,
    kTpdo,
    kRpdo,
    kSdoResponse,
    kSdoRequest,
    kHeartbeat,
    kLss,
    kUnknown
};
const char* toString(CanOpenFunction f);

struct CobIdInfo {
    CanOpenFunction function = CanOpenFunction::kUnknown;
    std::uint8_t node = 0;  // 1..127; 0 for NMT, SYNC, TIME
    int pdo = 0;            // 1..4 for PDOs
};
// Classifies an 11-bit identifier by the predefined connection set.
CobIdInfo classifyCobId(const CanFrame& frame);

// ---- NMT
// -------------------------------------------------------------------------------------------
enum class NmtCommand : std::uint8_t {
    kStart = 0x01,
    kStop = 0x02,
    kEnterPreOperational = 0x80,
    kResetNode = 0x81,
    kResetCommunication = 0x82
};
const char* toString(NmtCommand c);
struct NmtMessage {
    NmtCommand command = NmtCommand::kStart;
    std::uint8_t node = 0;  // 0 = all nodes
};
CanFrame encodeNmt(NmtCommand command, std::uint8_t node);
Result<NmtMessage> decodeNmt(const CanFrame& frame);

// ---- Heartbeat / boot-up (0x700 + node, one byte of state) -------------------------------------
enum class NmtState : std::uint8_t {
    kBootUp = 0x00,
    kStopped = 0x04,
    kOperational = 0x05,
    kPreOperational = 0x7F
};
const char* toString(NmtState s);
struct Heartbeat {
    std::uint8_t node = 0;
    NmtState state = NmtState::kBootUp;
    bool toggle = false;  // bit 7 (node guarding toggle bit), 0 in heartbeats
};
CanFrame encodeHeartbeat(std::uint8_t node, NmtState state);
Result<Heartbeat> decodeHeartbeat(const CanFrame& frame);

// ---- SYNC (0x080, optional 1-byte counter)
// --------------------------------------------------------
CanFrame encodeSync(std::optional<std::uint8_t> counter = std::nullopt);
Result<std::optional<std::uint8_t>> decodeSync(const CanFrame& frame);

// ---- EMCY (0x080 + node, 8 bytes) ---------------------------------------------------------------
struct Emergency {
    std::uint8_t node = 0;
    std::uint16_t error_code = 0;     // 0x0000 = error reset / no error
    std::uint8_t error_register = 0;  // object 1001h
    std::array<std::uint8_t, 5> vendor{};
};
CanFrame encodeEmergency(const Emergency& emcy);
Result<Emergency> decodeEmergency(const CanFrame& frame);

// ---- SDO (expedited transfers; segmented/block transfers are recognised, not carried) ----------
enum class SdoKind : std::uint8_t {
    kDownloadRequest,   // client writes: 0x23/0x27/0x2B/0x2F (0x22 size not indicated)
    kDownloadResponse,  // server acknowledges a write: 0x60
    kUploadRequest,     // client reads: 0x40
    kUploadResponse,    // server answers a read: 0x43/0x47/0x4B/0x4F (0x42 size not indicated)
    kAbort,             // either side: 0x80 + abort code
    kSegmented,         // segmented or block transfer frame (not carried by this driver)
};
const char* toString(SdoKind k);
struct SdoMessage {
    SdoKind kind = SdoKind::kUploadRequest;
    std::uint8_t node = 0;
    bool from_server = false;  // 0x580+n (server to client) vs 0x600+n
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint32_t value = 0;   // expedited data, little-endian, or the abort code
    std::uint8_t size = 0;     // 1..4 data bytes; 0 = size not indicated (treat as 4)
    std::uint8_t command = 0;  // the raw command byte
};
// Writes `size` (1, 2 or 4) bytes of `value` to node's object `index:subindex`.
CanFrame encodeSdoWrite(std::uint8_t node, std::uint16_t index, std::uint8_t subindex,
                        std::uint32_t value, std::uint8_t size);
CanFrame encodeSdoRead(std::uint8_t node, std::uint16_t index, std::uint8_t subindex);
CanFrame encodeSdoWriteAck(std::uint8_t node, std::uint16_t index, std::uint8_t subindex);
CanFrame encodeSdoReadResponse(std::uint8_t node, std::uint16_t index, std::uint8_t subindex,
                               std::uint32_t value, std::uint8_t size);
CanFrame encodeSdoAbort(std::uint8_t node, std::uint16_t index, std::uint8_t subindex,
                        std::uint32_t abort_code, bool from_server);
Result<SdoMessage> decodeSdo(const CanFrame& frame);
// Plain-language meaning of a CiA 301 SDO abort code ("object does not exist in the object
// dictionary").
const char* sdoAbortText(std::uint32_t abort_code);

// ---- PDO payloads
// -------------------------------------------------------------------------------- CiA 406 encoder
// TPDO1 with the default mapping: position value 6004h, u32 LE.
CanFrame encodeEncoderPositionTpdo(std::uint8_t node, std::uint32_t position);
Result<std::uint32_t> decodeEncoderPositionTpdo(const CanFrame& frame);

// ---- Object dictionary indices used here
// ---------------------------------------------------------
namespace od {
constexpr std::uint16_t kDeviceType = 0x1000;
constexpr std::uint16_t kErrorRegister = 0x1001;
constexpr std::uint16_t kProducerHeartbeatTime = 0x1017;  // u16, ms
constexpr std::uint16_t kIdentity = 0x1018;
constexpr std::uint16_t kRpdo1Communication = 0x1400;
constexpr std::uint16_t kRpdo1Mapping = 0x1600;
constexpr std::uint16_t kTpdo1Communication =
    0x1800;  // sub 1 COB-ID, sub 2 transmission type, sub 5 event timer
constexpr std::uint16_t kTpdo1Mapping = 0x1A00;
// CiA 406 encoder
constexpr std::uint16_t kEncoderOperatingParameters = 0x6000;  // bit 0: code sequence (direction)
constexpr std::uint16_t kEncoderUnitsPerRevolution = 0x6001;  // measuring units per revolution, u32
constexpr std::uint16_t kEncoderTotalRange = 0x6002;          // total measuring range, u32
constexpr std::uint16_t kEncoderPreset = 0x6003;
constexpr std::uint16_t kEncoderPosition = 0x6004;     // position value, u32, read-only
constexpr std::uint16_t kEncoderCyclicTimer = 0x6200;  // ms, u16
// CiA 402 drive
constexpr std::uint16_t kControlword = 0x6040;
constexpr std::uint16_t kStatusword = 0x6041;
constexpr std::uint16_t kModesOfOperation = 0x6060;  // i8; 3 = profile velocity
constexpr std::uint16_t kModesOfOperationDisplay = 0x6061;
constexpr std::uint16_t kVelocityActual = 0x606C;  // i32
constexpr std::uint16_t kTorqueActual = 0x6077;    // i16
constexpr std::uint16_t kTargetVelocity = 0x60FF;  // i32
}  // namespace od

// Transmission types of a PDO (1800h sub 2): 1..240 = every n-th SYNC, 0xFE/0xFF = event-driven
// (manufacturer / device profile; with the event timer or the CiA 406 cyclic timer 6200h).
constexpr std::uint8_t kTransmissionEventManufacturer = 0xFE;
constexpr std::uint8_t kTransmissionEventProfile = 0xFF;

// ---- CiA 402 drive state machine ----------------------------------------------------------------
namespace controlword {
constexpr std::uint16_t kDisableVoltage = 0x0000;
constexpr std::uint16_t kQuickStop = 0x0002;
constexpr std::uint16_t kShutdown = 0x0006;         // -> ready to switch on
constexpr std::uint16_t kSwitchOn = 0x0007;         // -> switched on
constexpr std::uint16_t kEnableOperation = 0x000F;  // -> operation enabled
constexpr std::uint16_t kFaultReset = 0x0080;       // rising edge of bit 7
constexpr std::uint16_t kHalt = 0x0100;
}  // namespace controlword
constexpr std::int8_t kModeProfileVelocity = 3;

enum class Cia402State : std::uint8_t {
    kNotReadyToSwitchOn,
    kSwitchOnDisabled,
    kReadyToSwitchOn,
    kSwitchedOn,
    kOperationEnabled,
    kQuickStopActive,
    kFaultReactionActive,
    kFault
};
const char* toString(Cia402State s);
// Decodes the state from statusword bits 0,1,2,3,5,6 (CiA 402 table of state masks).
Cia402State cia402StateFromStatusword(std::uint16_t statusword);
// The controlword that moves the drive one step towards `operation enabled` from `state`
// (fault -> fault reset, switch on disabled -> shutdown, ...); nullopt when already there.
std::optional<std::uint16_t> controlwordTowardsOperationEnabled(Cia402State state);
// The RPDO payload "controlword u16 + target velocity i32" (6 bytes, LE) for an RPDO whose
// mapping is 6040h:00/16 bit then 60FFh:00/32 bit.
CanFrame encodeDriveVelocityRpdo(int pdo, std::uint8_t node, std::uint16_t controlword,
                                 std::int32_t target_velocity);

}  // namespace handscan::motor
