// The Hokuyo's side of a SCIP 2.0 TCP session as the host's socket receives it: the replies to
// the driver's handshake (SCIP2.0, VV, PP, II, BM, ME) and then one ME frame per scan, all
// encoded by the driver's own ScipCodec. Frames leave the sensor after the scan's last step and
// cross a 100 Mbit/s link in MSS-sized TCP segments; each read() returns whatever segments had
// arrived when the reading thread woke up, so chunks split frames anywhere, as a socket does.
// Faults: a corrupted data block (one character changed: the line's sum no longer matches) and a
// TCP reconnect (the connection drops; a new session repeats the handshake).
#pragma once

#include <cstdint>
#include <vector>

#include "handscan/sim/device_clock.hpp"
#include "handscan/sim/laser_model.hpp"
#include "handscan/sim/stream_message.hpp"

namespace handscan::sim {

struct HokuyoStreamConfig {
    ClockModel clock{1234.567, 35.0, 0.0004, 0.00015};
    std::size_t mss_bytes = 1448;  // TCP payload per segment (1500 MTU, timestamps option)
    double link_bps = 100e6;
    double processing_s = 0.0008;     // scan end -> first byte on the wire
    double reader_wakeup_s = 0.0002;  // mean of the exponential delay before read() runs
    std::string serial = "H1234567";
};

class HokuyoStream {
public:
    HokuyoStream(const HokuyoStreamConfig& config, const LaserConfig& laser, TimeNs host_start_ns,
                 Rng rng);

    // The handshake replies, the first arriving at simulation time t.
    void handshake(double t, std::vector<StreamMessage>& out);
    // One scan as an ME frame. `corrupt`: damage one data character.
    void scan(const LaserScanTruth& scan, bool corrupt, std::vector<StreamMessage>& out);
    // The 24-bit millisecond timestamp the sensor puts on a scan whose step 0 is at time t.
    std::uint32_t timestampMs(double t) const;

private:
    void deliver(double t_send, const std::string& bytes, std::vector<StreamMessage>& out);
    HokuyoStreamConfig cfg_;
    LaserConfig laser_;
    TimeNs host_start_;
    Rng rng_;
    double link_free_at_ = 0.0;  // the link is busy until then (segments queue)
};

}  // namespace handscan::sim
