#include "handscan/viz/viz_sink.hpp"

#include "handscan/core/log.hpp"

namespace handscan::viz {

Result<std::unique_ptr<VizSink>> VizSink::create(const VizSinkOptions& o,
                                                 const Calibration& calibration,
                                                 worker::WorkerSink* next) {
    auto writer = VizWriter::create(o.path, calibration, o.config);
    if (!writer.isOk()) return writer.status();
    return std::unique_ptr<VizSink>(
        new VizSink(std::move(*writer), o.recording_colour, next, o.timer, o.path));
}

VizSink::VizSink(std::unique_ptr<VizWriter> writer, bool recording_colour, worker::WorkerSink* next,
                 CallTimer* timer, std::string path)
    : writer_(std::move(writer)),
      extras_(recording_colour),
      next_(next),
      timer_(timer),
      path_(std::move(path)) {}

void VizSink::keep(const Status& s) {
    if (s.isOk() || !failed_.isOk()) return;
    failed_ = Status(s.code(), "--viz " + path_ + ": " + s.message() +
                                   "; the viz file was given up, the scan went on");
    log().error("{}", failed_.message());
}

Status VizSink::pose(const PoseEstimate& p) {
    return next_ != nullptr ? next_->pose(p) : Status::ok();
}

Status VizSink::trajectoryPose(const PoseEstimate& p) {
    if (failed_.isOk()) timed([&] { keep(writer_->pose(p)); });
    return next_ != nullptr ? next_->trajectoryPose(p) : Status::ok();
}

Status VizSink::sweep(const lio::RegisteredSweep& s, std::span<const journal::MapPoint> points) {
    if (failed_.isOk()) timed([&] { keep(writer_->sweep(s, points, devices_)); });
    return next_ != nullptr ? next_->sweep(s, points) : Status::ok();
}

void VizSink::samples(std::span<const sources::Sample> samples) {
    if (!failed_.isOk()) return;
    timed([&] {
        for (const sources::Sample& sample : samples) {
            if (!failed_.isOk()) return;
            if (const auto* imu = std::get_if<ImuSample>(&sample)) {
                keep(writer_->imu(*imu));
            } else if (const auto* position = std::get_if<EncoderSample>(&sample)) {
                keep(writer_->encoder(*position));
            } else if (const auto* image = std::get_if<Image>(&sample)) {
                keep(writer_->image(Camera::kColour, *image));  // the worker's camera
            }
        }
    });
}

void VizSink::recorded(const recording::RecordedMessage& msg) {
    if (failed_.isOk()) timed([&] { keep(extras_.add(msg, *writer_)); });
}

Status VizSink::close() {
    if (closed_) return failed_;
    closed_ = true;
    if (failed_.isOk()) timed([&] { keep(writer_->close()); });
    return failed_;
}

}  // namespace handscan::viz
