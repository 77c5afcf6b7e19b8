// Writes a small deterministic recording for the interoperability and `handscan info` tests:
// IMU samples at 200 Hz, Hokuyo bytes at 40 Hz, ground truth at 100 Hz, encoder at 100 Hz for
// 3 s, plus pairs of 300 KB random (incompressible, like MJPEG) tracking-camera buffers at 2 Hz, so
// the file holds both zstd chunks and chunks stored uncompressed; ground truth is written 3 ms
// late (out of log-time order), as a late device would be. Writes OUT.expected.json with
// the message count per topic.
//
// usage: recording_sample_writer OUT.mcap
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>

#include "handscan/recording/channels.hpp"
#include "handscan/recording/mcap_writer.hpp"

using namespace handscan;
using namespace handscan::recording;

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.mcap\n", argv[0]);
        return 2;
    }
    const std::string out = argv[1];
    McapWriterOptions opts;
    opts.chunk_size_bytes = 256 * 1024;
    auto w = McapWriter::create(out, opts);
    if (!w) {
        std::fprintf(stderr, "%s\n", w.status().message().c_str());
        return 1;
    }
    McapWriter& writer = **w;
    std::map<std::string, std::uint16_t> id;
    for (const auto* spec :
         {&channels::kImuSamples, &channels::kHokuyoRaw, &channels::kGroundTruthPose,
          &channels::kEncoderAngle, &channels::kCameraTrack}) {
        auto c = addChannel(writer, *spec);
        if (!c) return 1;
        id[std::string(spec->topic)] = *c;
    }
    std::map<std::string, std::uint64_t> counts;
    std::mt19937 rng(7);
    std::vector<std::uint8_t> buf;
    auto put = [&](std::string_view topic, TimeNs t, std::span<const std::uint8_t> data) {
        if (Status s = writer.write(id.at(std::string(topic)), t, data); !s) {
            std::fprintf(stderr, "%s\n", s.message().c_str());
            std::exit(1);
        }
        ++counts[std::string(topic)];
    };
    const TimeNs t0 = 5000 * kNsPerSec;
    // One millisecond tick; each stream fires at its own period.
    for (TimeNs ms = 0; ms < 3000; ++ms) {
        const TimeNs t = t0 + ms * kNsPerMs;
        if (ms % 5 == 0) {
            ImuSample s;
            s.t_host = t;
            s.accel_mps2_imu = {0.1, 0.0, 9.81};
            s.gyro_radps_imu = {0.0, 0.0, std::sin(static_cast<double>(ms) * 1e-3)};
            s.packet_counter = static_cast<std::uint16_t>(ms / 5);
            encodeImuSample(s, buf);
            put(channels::kImuSamples.topic, t, buf);
        }
        if (ms % 25 == 0) {
            // An ME reply's worth of SCIP characters (printable, compressible like the real thing).
            buf.assign(3300, 0);
            for (auto& b : buf) b = static_cast<std::uint8_t>(0x30 + rng() % 64);
            put(channels::kHokuyoRaw.topic, t + 1, buf);
        }
        if (ms % 10 == 0) {
            // Ground truth arrives 3 ms late: the file holds it out of log-time order.
            GroundTruthPose p;
            p.t = t - 3 * kNsPerMs;
            p.p_world_body = {static_cast<double>(ms) * 1e-3, 0.0, 1.5};
            encodeGroundTruthPose(p, buf);
            put(channels::kGroundTruthPose.topic, p.t, buf);
            EncoderSample e;
            e.t_host = t;
            e.angle_rad = static_cast<double>(ms) * 2e-3 * M_PI;
            encodeEncoderSample(e, buf);
            put(channels::kEncoderAngle.topic, t + 2, buf);
        }
        if (ms % 500 == 250) {
            // Two frames back to back: the second fills a chunk of its own, which does not
            // compress.
            for (TimeNs k = 0; k < 2; ++k) {
                buf.resize(300 * 1024);
                for (auto& b : buf) b = static_cast<std::uint8_t>(rng());
                put(channels::kCameraTrack.topic, t + 3 + k, buf);
            }
        }
    }
    if (Status s = writer.close(); !s) {
        std::fprintf(stderr, "%s\n", s.message().c_str());
        return 1;
    }
    std::ofstream js(out + ".expected.json");
    js << "{\"channels\":{";
    bool first = true;
    for (const auto& [topic, n] : counts) {
        js << (first ? "" : ",") << "\"" << topic << "\":" << n;
        first = false;
    }
    js << "},\"messages\":" << writer.messageCount() << ",\"chunks\":" << writer.chunkCount()
       << "}\n";
    std::printf("%s: %llu messages in %u chunks\n", out.c_str(),
                static_cast<unsigned long long>(writer.messageCount()), writer.chunkCount());
    return 0;
}
