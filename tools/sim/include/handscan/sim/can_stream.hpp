// The CAN bus of the spinning shaft as the host's SocketCAN socket (and candump) sees it, one
// `candump -l` line per frame, encoded by the motor driver's CANopen and candump codecs:
// boot-up of the CiA 406 encoder and the CiA 402 drive, the host's SDO configuration of the
// encoder (heartbeat time, cyclic timer, transmission type) with the encoder's acknowledgements,
// NMT start, then the encoder's TPDO1 (position u32 LE) every cyclic-timer period of its own
// clock, and both nodes' heartbeats.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "handscan/sim/device_clock.hpp"
#include "handscan/sim/shaft_model.hpp"
#include "handscan/sim/stream_message.hpp"
#include "handscan/transport/can_bus.hpp"

namespace handscan::sim {

struct CanStreamConfig {
    ClockModel clock{0.0, -42.0, 0.00012, 0.00004};  // encoder crystal; CAN frame + softirq delay
    std::string interface = "can0";
    std::uint8_t encoder_node = 1;
    std::uint8_t drive_node = 2;
    std::uint32_t counts_per_rev = 16384;  // single-turn: the position wraps every revolution
    double tpdo_period_s = 0.005;          // CiA 406 cyclic timer 6200h (1..10 ms)
    double heartbeat_period_s = 0.1;
    double encoder_zero_offset_rad = 0.0;
};

struct EncoderReading {
    double t = 0.0;              // simulation time the position was latched
    std::uint32_t position = 0;  // counts as sent
};

class CanStream {
public:
    CanStream(const CanStreamConfig& config, const ShaftModel& shaft, TimeNs host_start_ns,
              Rng rng);

    // All frames whose transmission starts in [t0, t1).
    void generate(double t0, double t1, std::vector<StreamMessage>& out);
    // Every TPDO position sent so far (for tests).
    const std::vector<EncoderReading>& readings() const { return readings_; }
    std::uint32_t positionAt(double t) const;

private:
    void emit(double t_send, const CanFrame& frame, std::vector<StreamMessage>& out);
    CanStreamConfig cfg_;
    const ShaftModel& shaft_;
    TimeNs host_start_;
    Rng rng_;
    double operational_at_ = 0.0;  // after the NMT start
    std::int64_t next_tpdo_ = 0;   // index of the next TPDO on the encoder's clock
    std::int64_t next_hb_ = 0;
    bool started_ = false;
    std::vector<EncoderReading> readings_;
};

}  // namespace handscan::sim
