// The MTi-20's serial byte stream as the host's tty delivers it, encoded by the Xsens driver's
// codec: the replies to the driver's configuration handshake (GoToConfig ack, DeviceID,
// ProductCode, SetOutputConfiguration ack echoing the configuration, GoToMeasurement ack), then
// one MTData2 frame per sample (PacketCounter, SampleTimeFine, [DeltaV], Acceleration,
// RateOfTurn, [DeltaQ], StatusWord; float32 unless asked otherwise). Samples are taken on the
// IMU's own clock; each frame takes its wire time at the configured baud rate and reaches the
// reader in one or two read() chunks. Fault: a dropped byte (the frame's checksum then fails and
// the parser must resynchronise).
#pragma once

#include <cstdint>
#include <vector>

#include "handscan/sim/device_clock.hpp"
#include "handscan/sim/imu_model.hpp"
#include "handscan/sim/stream_message.hpp"

namespace handscan::sim {

struct XsensStreamConfig {
    ClockModel clock{57.3, -18.0, 0.0008, 0.0003};  // IMU crystal; USB-serial latency
    int rate_hz = 200;
    int baud = 921600;
    bool delta_q_v = false;
    int precision = 0;  // 0 float32, 1 fp12.20, 2 fp16.32, 3 float64
    std::uint32_t device_id = 0x01A01234;
    double split_probability = 0.25;  // a frame arrives in two read() chunks
};

class XsensStream {
public:
    XsensStream(const XsensStreamConfig& config, TimeNs host_start_ns, Rng rng);

    void handshake(double t, std::vector<StreamMessage>& out);
    // Simulation time of sample k (the IMU's clock ticks at rate_hz).
    double sampleTime(std::int64_t k) const;
    // One MTData2 frame for sample k; `drop_byte`: lose one byte on the wire.
    void sample(std::int64_t k, const ImuMeasurement& m, bool drop_byte,
                std::vector<StreamMessage>& out);
    // SampleTimeFine (10 kHz ticks of the IMU clock) of sample k.
    std::uint32_t sampleTimeFine(std::int64_t k) const;

private:
    void deliver(double t_send, std::vector<std::uint8_t> bytes, std::vector<StreamMessage>& out);
    XsensStreamConfig cfg_;
    TimeNs host_start_;
    Rng rng_;
    double first_sample_device_s_ = 0.0;
    double line_free_at_ = 0.0;
};

}  // namespace handscan::sim
