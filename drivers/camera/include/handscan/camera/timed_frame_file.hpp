// A file of camera frames to deliver at given host times: what `handscan hil` gives the daemon
// as a `v4l2-replay-host-clock:FILE` camera (the recording's /camera/* records, each due when
// the recording dequeued it, moved onto the host clock by the file's offset). Read as it plays,
// never held whole.
//
//   file:  "HSVT" magic, u32 version (1), i64 clock offset (ns, added to every time in the file:
//          written last, once the player knows when the recording will play), then entries to
//          the end of the file
//   entry: i64 due time (ns, before the offset), u32 record size, the frame record
//          (frame_record.hpp) exactly as recorded (PNG-coded payloads stay coded)
// All integers little-endian; entries in delivery order. The reader applies the offset: due
// times and the records' CLOCK_MONOTONIC times (shiftFrameRecordTimes) come out shifted.
#pragma once

#include <cstdint>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::camera {

class TimedFrameFileWriter {
public:
    // Creates (truncates) `path`; kIoError naming it when it cannot.
    [[nodiscard]] static Result<TimedFrameFileWriter> create(const std::string& path);
    // `record` must be one frame record; kProtocolError when it is not, kIoError on a failed write.
    [[nodiscard]] Status append(TimeNs due, std::span<const std::uint8_t> record);
    [[nodiscard]] Status close();

    // Sets the clock offset of a written file in place.
    [[nodiscard]] static Status setClockOffset(const std::string& path, TimeNs offset);

private:
    std::string path_;
    std::ofstream out_;
};

struct TimedFrameRecord {
    TimeNs due = 0;
    std::vector<std::uint8_t> record;
};

class TimedFrameFileReader {
public:
    // kNotFound / kProtocolError naming `path` when it cannot be read or is not such a file.
    [[nodiscard]] static Result<TimedFrameFileReader> open(const std::string& path);
    // The next entry, its due time and record times shifted by the file's clock offset; nullopt
    // at the end; kProtocolError (naming the entry's byte offset) when truncated or not a record.
    [[nodiscard]] Result<std::optional<TimedFrameRecord>> next();
    const std::string& path() const { return path_; }

private:
    std::string path_;
    std::ifstream in_;
    std::uint64_t offset_ = 0;  // bytes read
    TimeNs clock_offset_ = 0;
};

}  // namespace handscan::camera
