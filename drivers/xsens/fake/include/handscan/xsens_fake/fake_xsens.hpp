// A fake Xsens MTi-20 for tests: the device side of the Xbus protocol as a pure engine. It answers
// the config handshake like an MTi-20 (GoToConfig, ReqDID, ReqProductCode, SetOutputConfiguration
// with an echo, SetBaudrate, GoToMeasurement, WakeUp, Reset), streams MTData2 with the configured
// outputs (deterministic synthetic motion) and injects faults: a dropped byte or a corrupted
// checksum in chosen packets, Error replies to chosen requests, Error messages mid-stream.
// Transport adapters (in-memory stream, pty, fake USB) move its bytes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "handscan/xsens/xbus_messages.hpp"
#include "handscan/xsens/xbus_parser.hpp"

namespace handscan::xsens {

struct FakeXsensConfig {
    std::uint32_t device_id = 0x01A00E3Fu;  // MTi-20 ids start with 0x01A
    std::string product_code = "MTi-20-2A5G4";
    bool streaming_at_start = true;              // a powered MTi streams until told otherwise
    std::uint16_t first_packet_counter = 65530;  // near the wrap on purpose
    std::uint32_t first_sample_time_fine = 0xFFFFF000u;  // wraps 2^32 after ~410 ms at 10 kHz
    std::uint16_t default_rate_hz = 100;                 // before any SetOutputConfiguration
    int ignore_first_goto_configs = 0;  // "busy" device: drops this many GoToConfig
    // Line rate at power-up. A real MTi-20 ships at 115200; tests start at the driver's 921600
    // unless they exercise baud-rate probing and switching.
    int baudrate = 921600;
    // At rest: specific force = gravity along +z, no rotation (the static start the pipeline
    // aligns with gravity on); otherwise the synthetic motion of accelAt() / gyroAt().
    bool stationary = false;
};

struct FakeXsensFaults {
    std::set<std::uint64_t> drop_byte_in_packet;         // packet index -> lose one byte mid-frame
    std::set<std::uint64_t> corrupt_checksum_in_packet;  // packet index -> flip the checksum
    std::set<std::uint64_t> error_after_packet;  // packet index -> Error(error_code) after it
    std::map<std::uint8_t, int> error_replies;   // request MID -> how many times to refuse
    ErrorCode error_code = ErrorCode::kInvalidMessage;
};

// What the fake streamed, packet by packet (the ground truth of a test).
struct StreamedPacket {
    std::uint64_t index = 0;
    std::uint32_t epoch =
        0;  // measurement period: counts GoToMeasurement acks (0 = since power-up)
    std::uint16_t packet_counter = 0;
    std::uint32_t sample_time_fine = 0;
    Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();
    Eigen::Vector3d gyro_radps = Eigen::Vector3d::Zero();
    std::uint32_t status_word = 0;
    bool damaged = false;  // a fault was injected into this packet
};

class FakeXsens {
public:
    explicit FakeXsens(FakeXsensConfig config = {}, FakeXsensFaults faults = {});

    // Bytes from the host. Replies are queued for takeOutput().
    void receive(std::span<const std::uint8_t> bytes);
    // Queues the next MTData2 packet when measuring; false in config mode.
    bool emitPacket();
    // Bytes for the host, oldest first; the queue is emptied.
    std::vector<std::uint8_t> takeOutput();
    bool hasOutput() const { return !output_.empty(); }

    // Power cycle / reset: the MTi announces itself with WakeUp and, unless the host answers
    // WakeUpAck (or GoToConfig) before the next packet is due, starts measuring with the stored
    // configuration; the packet counter and SampleTimeFine restart from 0.
    void powerCycle();
    // Measuring, or about to start (waiting for a WakeUpAck that may never come).
    bool measuring() const { return measuring_ || awaiting_wakeup_ack_; }
    std::uint16_t rateHz() const { return rate_hz_; }
    // The line rate the device talks at now. SetBaudrate takes effect at the next Reset, after
    // the ResetAck has gone out at the old rate (takeOutput() applies it).
    int baudrate() const { return baud_; }
    // Transport adapters call this with the host's line rate: bytes crossing a mismatched link
    // arrive as garbage (device -> host) or not at all (host -> device), as on a real UART.
    static void garble(std::vector<std::uint8_t>& bytes);
    const std::vector<OutputConfigEntry>& outputConfiguration() const { return outputs_; }
    const std::vector<StreamedPacket>& streamed() const { return streamed_; }
    std::uint32_t epoch() const { return epoch_; }
    const std::vector<std::uint8_t>& requestsSeen() const { return requests_; }  // MIDs, in order

    // The synthetic motion at packet index k (also used by tests to predict samples).
    static Eigen::Vector3d accelAt(double t_s);
    static Eigen::Vector3d gyroAt(double t_s);

private:
    void handle(std::uint8_t mid, std::span<const std::uint8_t> payload);
    void reply(MessageId mid, std::span<const std::uint8_t> payload = {});
    bool refuse(std::uint8_t mid);

    FakeXsensConfig cfg_;
    FakeXsensFaults faults_;
    XbusParser parser_;
    std::vector<std::uint8_t> output_;
    std::vector<OutputConfigEntry> outputs_;
    std::uint16_t rate_hz_;
    int baud_ = 921600;
    int pending_baud_ = 0;  // set by SetBaudrate, applied at Reset
    bool switch_after_take_ = false;
    bool measuring_;
    int goto_configs_ignored_ = 0;
    std::uint32_t epoch_ = 0;
    bool awaiting_wakeup_ack_ = false;
    std::uint64_t next_index_ = 0;
    std::uint16_t counter_;
    std::uint32_t sample_time_fine_;
    std::vector<StreamedPacket> streamed_;
    std::vector<std::uint8_t> requests_;
};

}  // namespace handscan::xsens
