#include "handscan/camera/timed_frame_file.hpp"

#include <array>

#include "handscan/camera/frame_record.hpp"

namespace handscan::camera {
namespace {

constexpr std::array<char, 4> kMagic = {'H', 'S', 'V', 'T'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kFileHeader = 16;   // magic, version, clock offset
constexpr std::size_t kOffsetAt = 8;      // of the clock offset
constexpr std::size_t kEntryHeader = 12;  // due time, record size

void putLe(char* out, std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out[i] = static_cast<char>(v >> (8 * i));
}
std::uint64_t getLe(const char* in, int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i)
        v |= static_cast<std::uint64_t>(static_cast<unsigned char>(in[i])) << (8 * i);
    return v;
}

}  // namespace

Result<TimedFrameFileWriter> TimedFrameFileWriter::create(const std::string& path) {
    TimedFrameFileWriter w;
    w.path_ = path;
    w.out_.open(path, std::ios::binary | std::ios::trunc);
    std::array<char, kFileHeader> head{};
    std::copy(kMagic.begin(), kMagic.end(), head.begin());
    putLe(head.data() + 4, kVersion, 4);
    w.out_.write(head.data(), head.size());
    if (!w.out_) return Status(StatusCode::kIoError, path + ": cannot write the camera frames");
    return w;
}

Status TimedFrameFileWriter::append(TimeNs due, std::span<const std::uint8_t> record) {
    auto view = decodeFrameRecord(record, FramePayload::kHeaderOnly);
    if (!view) return view.status();
    std::array<char, kEntryHeader> head{};
    putLe(head.data(), static_cast<std::uint64_t>(due), 8);
    putLe(head.data() + 8, view->record_size, 4);
    out_.write(head.data(), head.size());
    out_.write(reinterpret_cast<const char*>(record.data()),
               static_cast<std::streamsize>(view->record_size));
    if (!out_) return Status(StatusCode::kIoError, path_ + ": writing camera frames failed");
    return Status::ok();
}

Status TimedFrameFileWriter::close() {
    out_.close();
    if (!out_) return Status(StatusCode::kIoError, path_ + ": writing camera frames failed");
    return Status::ok();
}

Status TimedFrameFileWriter::setClockOffset(const std::string& path, TimeNs offset) {
    std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
    std::array<char, 8> v{};
    putLe(v.data(), static_cast<std::uint64_t>(offset), 8);
    f.seekp(static_cast<std::streamoff>(kOffsetAt));
    f.write(v.data(), v.size());
    f.close();
    if (!f) return Status(StatusCode::kIoError, path + ": cannot set the camera frames' clock");
    return Status::ok();
}

Result<TimedFrameFileReader> TimedFrameFileReader::open(const std::string& path) {
    TimedFrameFileReader r;
    r.path_ = path;
    r.in_.open(path, std::ios::binary);
    if (!r.in_) return Status(StatusCode::kNotFound, path + ": cannot open the camera frames");
    std::array<char, kFileHeader> head{};
    r.in_.read(head.data(), head.size());
    if (!r.in_ || !std::equal(kMagic.begin(), kMagic.end(), head.begin()) ||
        getLe(head.data() + 4, 4) != kVersion) {
        return Status(StatusCode::kProtocolError,
                      path + ": not a timed camera frame file (HSVT version 1)");
    }
    r.clock_offset_ = static_cast<TimeNs>(getLe(head.data() + kOffsetAt, 8));
    r.offset_ = head.size();
    return r;
}

Result<std::optional<TimedFrameRecord>> TimedFrameFileReader::next() {
    std::array<char, kEntryHeader> head{};
    in_.read(head.data(), head.size());
    if (in_.gcount() == 0 && in_.eof()) return std::optional<TimedFrameRecord>();
    const auto truncated = [&] {
        return Status(StatusCode::kProtocolError, path_ + ": camera frame entry at byte " +
                                                      std::to_string(offset_) + " is truncated");
    };
    if (!in_) return truncated();
    TimedFrameRecord e;
    e.due = static_cast<TimeNs>(getLe(head.data(), 8)) + clock_offset_;
    const std::uint64_t size = getLe(head.data() + 8, 4);
    if (size > kMaxFramePayload + kFrameRecordCodedHeaderSize) return truncated();
    e.record.resize(size);
    in_.read(reinterpret_cast<char*>(e.record.data()), static_cast<std::streamsize>(size));
    if (!in_) return truncated();
    if (Status s = shiftFrameRecordTimes(e.record, clock_offset_); !s.isOk()) {
        return Status(StatusCode::kProtocolError, path_ + ": camera frame entry at byte " +
                                                      std::to_string(offset_) + ": " + s.message());
    }
    offset_ += kEntryHeader + size;
    return std::optional<TimedFrameRecord>(std::move(e));
}

}  // namespace handscan::camera
