// The Xsens MTi device state machine over an injected ByteStream (serial tty, USB bulk pipe or a
// test double). configure() brings the device from whatever it is doing (it may be streaming
// since power-up) into config mode with GoToConfig (resent until acknowledged), reads its id and
// product code, sets the 200 Hz output configuration (PacketCounter, SampleTimeFine,
// Acceleration, RateOfTurn, StatusWord, optional DeltaQ/DeltaV) and starts measurement. poll()
// then hands out ImuSamples decoded by the ImuStreamDecoder (the same one replay uses):
// SampleTimeFine mapped to host time, gaps, damage and Error messages counted and described,
// never fatal; a device that restarts mid-stream (WakeUp) is let resume measuring with its stored
// configuration. Every received byte chunk goes to the optional RawTap first.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "handscan/core/clock_mapper.hpp"
#include "handscan/core/raw_tap.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/transport/byte_stream.hpp"
#include "handscan/xsens/imu_stream_decoder.hpp"
#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_messages.hpp"

namespace handscan::xsens {

struct XsensDeviceConfig {
    std::uint16_t output_rate_hz = 200;
    bool delta_q_delta_v = false;                  // also request DeltaQ and DeltaV (SDI outputs)
    Precision precision = Precision::kFloat32;     // number format of the real-valued outputs
    TimeNs reply_timeout = 200 * kNsPerMs;         // wait for an ack before resending
    int attempts = 5;                              // sends per request (GoToConfig while streaming)
    std::function<TimeNs()> clock = monotonicNow;  // host receive time (tests inject a fake)
    // Serial links: the rate to run at, and how to retune the host side (SerialStream::
    // setBaudrate). When set, configure() finds a device that talks at another rate (the MTi
    // ships at 115200) by probing the Xbus rates, then moves it to `baudrate` with SetBaudrate
    // + Reset. Unset (USB, tests): the link rate is taken as given.
    int baudrate = 921600;
    std::function<Status(int baud)> set_link_baudrate;
    // Sample -> first byte at the host (xsens.frame_latency_ms); on serial links each frame's
    // wire time at the current rate comes on top (ImuFrameTiming).
    TimeNs frame_latency = 0;
};

// The decoder's counts (device_errors also counts Error replies to requests) and the bytes read.
struct XsensDeviceStats : ImuStreamStats {
    std::uint64_t bytes = 0;
};

class XsensDevice {
public:
    XsensDevice(transport::ByteStream& stream, XsensDeviceConfig config = {},
                RawTap* tap = nullptr);

    // Opens the stream if needed and runs the handshake. On failure the message says which step
    // failed, what the device answered and what to check.
    Status configure();
    // Reads for at most `timeout`, appends every complete sample to `out`. kDisconnected when the
    // stream went away (call configure() again to recover).
    Status poll(std::vector<ImuSample>& out, TimeNs timeout);

    // In config mode: moves device and link to `baud` (SetBaudrate, Reset, retune, GoToConfig).
    Status switchBaudrate(int baud);
    // The line rate the link runs at now (the configured one until probing finds another).
    int linkBaudrate() const { return link_baud_; }

    std::uint32_t deviceId() const { return device_id_; }
    const std::string& productCode() const { return product_code_; }
    const std::vector<OutputConfigEntry>& outputConfiguration() const { return output_config_; }
    const XsensDeviceStats& stats() const;
    // Human-readable descriptions of the last problems seen (gaps, device errors, damage); the
    // oldest are dropped beyond 32.
    const std::vector<std::string>& problems() const { return problems_; }
    const ClockMapper& clock() const { return decoder_.clock(); }
    bool measuring() const { return measuring_; }

    // The output configuration configure() sends for `config`.
    static std::vector<OutputConfigEntry> outputConfigurationFor(const XsensDeviceConfig& config);

private:
    struct Reply {
        std::uint8_t mid = 0;
        std::vector<std::uint8_t> payload;
    };
    Result<Reply> request(MessageId mid, std::span<const std::uint8_t> payload, const char* step);
    Status readSome(TimeNs timeout, TimeNs& t_rx);
    Status enterConfigMode();
    void note(std::string problem);

    transport::ByteStream& stream_;
    XsensDeviceConfig cfg_;
    RawTap* tap_;
    ImuStreamDecoder decoder_;
    std::vector<std::uint8_t> rx_;
    TimeNs last_rx_ = 0;  // host time of the last read that returned bytes
    std::uint32_t device_id_ = 0;
    std::string product_code_;
    std::vector<OutputConfigEntry> output_config_;
    bool measuring_ = false;
    int link_baud_ = 0;
    std::uint64_t refused_requests_ = 0;  // Error replies to our requests
    mutable XsensDeviceStats stats_;
    std::vector<std::string> problems_;
};

}  // namespace handscan::xsens
