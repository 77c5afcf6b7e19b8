// What a recording holds for the viewer beyond the pipeline's samples: the tracking camera's
// frames (/camera/track; the worker does not decode them), the colour camera's when the worker
// does not take them (--no-colour), and the ground truth (/groundtruth/pose, written by the
// simulator). The recorded source reads these topics too and taps each message here
// (sources::RecordedSourceOptions::tap), so the recording is read once.
#pragma once

#include <string>
#include <vector>

#include "handscan/camera/frame_stream_decoder.hpp"
#include "handscan/core/status.hpp"
#include "handscan/recording/mcap_reader.hpp"
#include "handscan/viz/viz_writer.hpp"

namespace handscan::viz {

class RecordedExtras {
public:
    // `colour`: also the /camera/colour frames.
    explicit RecordedExtras(bool colour) : colour_(colour) {}

    // The topics to read for this (`colour`: as the constructor's).
    static std::vector<std::string> topics(bool colour);
    // One recorded message of any topic (others are ignored) into `writer`. A frame or pose that
    // does not decode is logged (once) and skipped; only writing fails.
    [[nodiscard]] Status add(const recording::RecordedMessage& msg, VizWriter& writer);

private:
    [[nodiscard]] Status addFrame(const recording::RecordedMessage& msg, bool track,
                                  VizWriter& writer);

    bool colour_;
    camera::FrameStreamDecoder track_;
    camera::FrameStreamDecoder colour_decoder_;
    std::uint64_t errors_ = 0;
};

}  // namespace handscan::viz
