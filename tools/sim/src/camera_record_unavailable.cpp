// Built when drivers/camera (the V4L2 buffer record codec) is absent: the simulator then runs
// without camera streams rather than invent a second encoding of the record.
#include <stdexcept>

#include "handscan/sim/camera_stream.hpp"

namespace handscan::sim {

bool cameraRecordsAvailable() { return false; }

std::vector<std::uint8_t> encodeCameraRecord(const V4l2FrameInfo&, const CameraStreamConfig&,
                                             const std::vector<std::uint8_t>&) {
    throw std::logic_error(
        "handscan sim was built without drivers/camera: no V4L2 buffer record encoder");
}

}  // namespace handscan::sim
