// The receive side of an MTi in measurement: Xbus bytes as the host got them (with host receive
// times) in, ImuSamples on the host clock out. No transport and no commands, so the live
// XsensDevice, replay of a recording's /xsens/raw and tests share this one copy.
//
// MTData2 packets carrying SampleTimeFine, Acceleration and RateOfTurn become samples; their
// SampleTimeFine (10 kHz, 32 bit) is mapped onto host time by a ClockMapper from the
// (SampleTimeFine, receive time) pairs. Packet-counter gaps, damaged frames (checksum, resync),
// packets without the needed outputs and Error (0x42) messages are counted and described, never
// fatal. A WakeUp means the device restarted: its clocks start from 0, so the time mapping starts
// afresh. Other frames (late acks, replies) are skipped.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/clock_mapper.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/stream_counters.hpp"
#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_parser.hpp"

namespace handscan::xsens {

// When a sample's frame reaches the host, after the sample's own time (SampleTimeFine): the
// clock fit places the lower envelope of the receive times, so a delay every frame has is
// taken out before it, or every sample (and the whole IMU motion) comes out that much late.
struct ImuFrameTiming {
    TimeNs frame_latency_ns =
        0;         // sample -> first byte at the host (processing, USB-serial bridge)
    int baud = 0;  // serial line rate: each frame's own wire time (8N1) is added; 0: USB

    // Receive time of the frame's last byte minus this = the sample's time on the host clock,
    // for the fastest delivery.
    TimeNs delayOf(std::size_t frame_bytes) const;
};

struct ImuStreamStats {
    std::uint64_t packets = 0;        // MTData2 frames received
    std::uint64_t samples = 0;        // ImuSamples handed out
    std::uint64_t gaps = 0;           // packet-counter discontinuities
    std::uint64_t lost_packets = 0;   // packets missing across those gaps
    std::uint64_t incomplete = 0;     // MTData2 without SampleTimeFine / Acceleration / RateOfTurn
    std::uint64_t malformed = 0;      // MTData2 whose items could not be decoded
    std::uint64_t device_errors = 0;  // Error (0x42) messages received
    std::uint64_t restarts = 0;       // WakeUp seen (power glitch, reset)
    std::uint64_t checksum_failures = 0;
    std::uint64_t resyncs = 0;
};

class ImuStreamDecoder {
public:
    // `source` names the stream in problem descriptions ("Xsens serial /dev/ttyUSB0 921600").
    explicit ImuStreamDecoder(std::string source = "Xsens", ImuFrameTiming timing = {});

    // Bytes received at host time `t_rx`: every frame they complete is decoded at once into `out`.
    void feed(TimeNs t_rx, std::span<const std::uint8_t> bytes, std::vector<ImuSample>& out);

    // For a state machine that waits for replies in config mode: bytes in without decoding, and
    // the complete frames one by one (valid until the next feed). decodePending() decodes what
    // is left after the awaited reply, stamped with the time those bytes arrived.
    void feedRaw(std::span<const std::uint8_t> bytes) { parser_.feed(bytes); }
    std::optional<XbusFrameView> nextFrame() { return parser_.next(); }
    void decodePending(TimeNs t_rx, std::vector<ImuSample>& out);
    // A new connection or line rate: buffered bytes are dropped and the counter sequence starts
    // afresh (statistics and the time mapping are kept).
    void resetLink();
    // Entering measurement: the packet counter continues from wherever the device is.
    void forgetCounter() { counter_.reset(); }

    void setSource(std::string source) { source_ = std::move(source); }
    // A new line rate (the device switched baud): later frames take their wire time at it.
    void setTiming(ImuFrameTiming timing) { timing_ = timing; }
    // Called with each problem description as it happens (the device logs and keeps them).
    void onProblem(std::function<void(const std::string&)> f) { on_problem_ = std::move(f); }

    ImuStreamStats stats() const;
    // The same as the counters every stream decoder reports.
    StreamCounters counters() const;
    const ClockMapper& clock() const { return clock_; }
    const std::string& lastProblem() const { return last_problem_; }

private:
    void decode(const XbusFrameView& frame, TimeNs t_rx, std::vector<ImuSample>& out);
    void problem(std::string text);

    std::string source_;
    ImuFrameTiming timing_;
    XbusParser parser_;
    ClockMapper clock_;
    PacketCounterTracker counter_;
    ImuStreamStats stats_;
    std::string last_problem_;
    std::function<void(const std::string&)> on_problem_;
};

}  // namespace handscan::xsens
