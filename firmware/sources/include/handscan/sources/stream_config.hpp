// The drivers' stream decoders' settings from device.yaml: what the streams themselves do not
// carry (fixed latencies, the encoder's node and cyclic timer). Live devices and recordings are
// decoded with the same settings, so they stamp samples alike.
#pragma once

#include "handscan/core/config.hpp"
#include "handscan/hokuyo/scan_stream_decoder.hpp"
#include "handscan/motor/encoder_stream_decoder.hpp"
#include "handscan/xsens/imu_stream_decoder.hpp"

namespace handscan::sources {

hokuyo::ScanTimingConfig hokuyoTiming(const DeviceConfig& device);
xsens::ImuFrameTiming xsensTiming(const DeviceConfig& device);
motor::EncoderStreamConfig encoderStreamConfig(const DeviceConfig& device);

}  // namespace handscan::sources
