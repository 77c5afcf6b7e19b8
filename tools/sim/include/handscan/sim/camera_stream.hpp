// The V4L2 side of a camera: frames on the camera's own frame clock (its oscillator drifts
// against the host), exposure, V4L2 buffer metadata (sequence, CLOCK_MONOTONIC timestamp, flags
// with the timestamp source), the buffer's bytes in the pixel format the device delivers (GREY,
// YUYV or MJPEG), and the dequeue time at which the driver receives the buffer. Lost frames show
// up as sequence gaps, as on a real V4L2 device. The recording payload is the camera codec's
// V4L2 buffer record.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "handscan/sim/device_clock.hpp"
#include "handscan/sim/stream_message.hpp"

namespace handscan::sim {

struct CameraStreamConfig {
    ClockModel clock{0.0, 25.0, 0.004, 0.0005};  // frame oscillator; readout + USB + DQBUF delay
    double fps = 50.0;
    double exposure_s = 0.005;
    std::string format = "GREY";  // GREY | YUYV | MJPEG
    int width = 640;
    int height = 512;
    int mjpeg_quality = 85;
    bool start_of_exposure = true;  // timestamp source: SOE (tracking camera) or EOF (UVC)
    // End of exposure to the last line transferred (device.yaml readout_ms): an EOF stamp is
    // this much after the exposure's end.
    double readout_s = 0.014;
    SimChannel channel = SimChannel::kTrackingCamera;
};

// One frame's V4L2 metadata as DQBUF reports it.
struct V4l2FrameInfo {
    std::uint32_t sequence = 0;
    TimeNs timestamp_ns = 0;  // CLOCK_MONOTONIC, start of exposure or end of frame
    std::uint32_t flags = 0;  // V4L2_BUF_FLAG_* (timestamp type/source)
    std::uint32_t bytesused = 0;
    double t_exposure_start = 0.0;  // simulation time
    TimeNs exposure_ns = 0;
    TimeNs readout_ns = 0;    // end of exposure to the last line transferred
    TimeNs t_dequeue_ns = 0;  // host time the driver dequeues the buffer
};

class CameraStream {
public:
    CameraStream(const CameraStreamConfig& config, TimeNs host_start_ns, Rng rng);

    // Simulation time at which exposure of frame k starts.
    double exposureStart(std::int64_t k) const;
    // Packs a rendered frame (grey: w*h bytes; colour: w*h*3 RGB) into the delivered format and
    // emits its buffer record. `lost`: the frame is dropped (its sequence number is used up).
    void frame(std::int64_t k, const std::vector<std::uint8_t>& pixels, bool lost,
               std::vector<StreamMessage>& out);
    const V4l2FrameInfo& lastInfo() const { return last_; }

private:
    CameraStreamConfig cfg_;
    TimeNs host_start_;
    Rng rng_;
    std::uint32_t sequence_ = 0;
    V4l2FrameInfo last_;
    std::vector<std::uint8_t> packed_;
};

// Pixel packing as a UVC/V4L2 camera delivers it (BT.601 limited range for YUYV; JPEG 4:2:2).
void rgbToYuyv(const std::vector<std::uint8_t>& rgb, int width, int height,
               std::vector<std::uint8_t>& out);
void rgbToMjpeg(const std::vector<std::uint8_t>& rgb, int width, int height, int quality,
                std::vector<std::uint8_t>& out);

// The recording payload of one buffer (the camera codec's V4L2 buffer record), and whether this
// build has that codec (drivers/camera).
bool cameraRecordsAvailable();
std::vector<std::uint8_t> encodeCameraRecord(const V4l2FrameInfo& info,
                                             const CameraStreamConfig& config,
                                             const std::vector<std::uint8_t>& data);

}  // namespace handscan::sim
