// HokuyoDevice: the UTM-30LX-EW state machine over an injected transport::ByteStream.
//
//   disconnected --open--> handshake: SCIP2.0, VV, PP (DMIN..SCAN read, never assumed), II, BM,
//   ME AMIN..AMAX (range + intensity, unlimited) --> streaming --(drop, silence, stream error)-->
//   back-off (100 ms, doubling up to the configured maximum) --> reconnect --> streaming ...
//   stop(): QT, close.
//
// poll() does one step and never blocks longer than one handshake (a few reply timeouts) or one
// read slice, so a driver thread can call it in a loop and check a stop flag in between. Every raw
// chunk goes to the optional RawTap with its host receive time before it is decoded by the
// ScanStreamDecoder (the same one replay uses). Faults are reported (returned, logged, counted)
// and recovered from; only damaged scans are lost.
#pragma once

#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/raw_tap.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/hokuyo/scan_stream_decoder.hpp"
#include "handscan/hokuyo/sensor_parameters.hpp"
#include "handscan/transport/byte_stream.hpp"

namespace handscan::hokuyo {

struct HokuyoDeviceConfig {
    TimeNs reply_timeout_ns = 1 * kNsPerSec;   // per handshake command
    TimeNs read_slice_ns = 50 * kNsPerMs;      // longest single wait in poll()
    TimeNs stream_timeout_ns = 1 * kNsPerSec;  // no verified scan for this long: reconnect
    TimeNs backoff_initial_ns = 100 * kNsPerMs;
    TimeNs backoff_max_ns = 5 * kNsPerSec;  // device.yaml hokuyo.reconnect_max_backoff_s
    int start_step = -1;                    // -1: AMIN from PP
    int end_step = -1;                      // -1: AMAX from PP
    int cluster = 1;
    ScanTimingConfig timing;
};

// The device settings of config/device.yaml's `hokuyo:` section (host/port go to the TcpStream).
HokuyoDeviceConfig hokuyoDeviceConfig(const HokuyoConfig& config);

struct HokuyoDeviceStats {
    std::uint64_t scans = 0;             // LaserScans handed out
    std::uint64_t connects = 0;          // successful handshakes
    std::uint64_t connect_failures = 0;  // open or handshake failed
    std::uint64_t disconnects = 0;       // stream lost (drop, silence, sensor error)
    std::uint64_t faults = 0;            // every fault reported
    std::uint64_t missed_scans = 0;      // scans missing between consecutive timestamps
    ScipParserStats parser;              // checksum failures, resyncs, discarded bytes
};

class HokuyoDevice {
public:
    enum class State { kDisconnected, kStreaming, kStopped };
    using Clock = std::function<TimeNs()>;
    using Sleep = std::function<void(TimeNs)>;

    explicit HokuyoDevice(transport::ByteStream& link, HokuyoDeviceConfig config = {},
                          RawTap* tap = nullptr, Clock now = monotonicNow, Sleep sleep = {});

    // One step: (re)connects and handshakes when due, otherwise reads one slice and appends the
    // scans it completed to `out`. Returns ok, or the fault it met and handled.
    Status poll(std::vector<LaserScan>& out);
    // Stops the stream (QT), closes the link. poll() after stop() reconnects.
    Status stop();

    State state() const { return state_; }
    const std::optional<SensorParameters>& parameters() const { return params_; }
    const SensorIdentity& identity() const { return identity_; }
    HokuyoDeviceStats stats() const;
    const ClockMapper& clock() const { return decoder_.clock(); }
    const std::string& lastFault() const { return last_fault_; }
    const ScanRequest& request() const { return request_; }

private:
    Status connect();
    Status handshake();
    Result<ScipFrame> transact(const std::string& command);
    Result<std::size_t> readChunk(TimeNs timeout);
    Status handleEvents(std::vector<LaserScan>& out);
    Status fault(Status status);
    void dropLink(const Status& why);

    transport::ByteStream& link_;
    HokuyoDeviceConfig cfg_;
    RawTap* tap_;
    Clock now_;
    Sleep sleep_;

    State state_ = State::kDisconnected;
    ScanStreamDecoder decoder_;
    std::vector<LaserScan> ready_;  // decoded, not handed out yet
    std::deque<ScipEvent> pending_;
    std::vector<ScipEvent> scratch_;
    std::vector<std::uint8_t> rx_;
    TimeNs last_rx_ = 0;  // host time of the latest chunk
    std::uint64_t frame_start_offset_ = 0;

    std::optional<SensorParameters> params_;
    SensorIdentity identity_;
    ScanRequest request_;

    TimeNs next_attempt_ = 0;
    TimeNs backoff_;
    TimeNs last_scan_rx_ = 0;
    bool scanned_since_connect_ = false;
    HokuyoDeviceStats stats_;
    std::string last_fault_;
};

}  // namespace handscan::hokuyo
