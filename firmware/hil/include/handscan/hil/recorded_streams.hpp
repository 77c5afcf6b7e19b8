// A recording's raw device streams as the fake devices of `handscan hil` play them: the SCIP
// scan frames with the receive time of each frame's last byte, the Xbus bytes the MTi sent after
// acknowledging GoToMeasurement, the candump lines of the CAN bus, each on the recording's clock
// (MCAP log time: the recording host's CLOCK_MONOTONIC). The start-up replies in the recording
// are not played back: the fakes answer the daemon's own handshakes. Camera frames, too large to
// hold, go straight into timed frame files (camera/timed_frame_file.hpp), due at their recorded
// dequeue times; the fakes set those files' clock offset.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/hokuyo_fake/fake_hokuyo_sensor.hpp"
#include "handscan/xsens_fake/recorded_byte_stream.hpp"

namespace handscan::hil {

struct RecordedCanFrame {
    TimeNs t = 0;      // recording clock
    std::string line;  // the candump -l line as recorded (its own time ignored)
};

struct RecordedStreams {
    std::string path;
    TimeNs start = 0;  // first and last log time of the recording
    TimeNs end = 0;
    std::vector<hokuyo::SourceScanFrame> scans;
    std::vector<TimeNs> scan_rx;  // receive time of each scan frame's last byte
    std::vector<xsens::RecordedChunk> xsens_measurement;
    std::uint32_t xsens_device_id = 0;  // from the recorded DeviceID reply (0: none)
    std::string xsens_product_code;
    std::vector<RecordedCanFrame> can;
    // /camera/track and /camera/colour as timed frame files (empty: none recorded or not asked).
    std::string track_frames, colour_frames;
    std::size_t track_frame_count = 0, colour_frame_count = 0;
};

// With `camera_dir` set, the cameras' records are written there (track.frames, colour.frames).
[[nodiscard]] Result<RecordedStreams> loadRecordedStreams(const std::string& path,
                                                          const std::string& camera_dir = {});

// The scan frames of recorded TCP reads, each with the receive time of the read that completed
// it.
void splitTimedScanFrames(const std::vector<xsens::RecordedChunk>& reads,
                          std::vector<hokuyo::SourceScanFrame>& frames, std::vector<TimeNs>& rx);

// The bytes after the MTi's GoToMeasurement acknowledgement (all of them when the recording has
// none: it started while the device was measuring), chunked as recorded.
std::vector<xsens::RecordedChunk> measurementBytes(const std::vector<xsens::RecordedChunk>& reads);

}  // namespace handscan::hil
