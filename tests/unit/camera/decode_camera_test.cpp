// `handscan decode --device camera` on a file of frame records with damage between records.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "handscan/camera/frame_record.hpp"
#include "handscan/transport/v4l2_device.hpp"

namespace handscan::camera {
namespace {

std::vector<std::string> run(const std::string& args) {
    const std::string cmd =
        std::string(HANDSCAN_BINARY_DIR) + "/firmware/cli/handscan decode " + args + " 2>/dev/null";
    std::vector<std::string> lines;
    FILE* p = popen(cmd.c_str(), "r");
    if (p == nullptr) return lines;
    std::array<char, 8192> buf{};
    while (fgets(buf.data(), buf.size(), p) != nullptr) {
        std::string l = buf.data();
        if (!l.empty() && l.back() == '\n') l.pop_back();
        lines.push_back(l);
    }
    pclose(p);
    return lines;
}

TEST(DecodeCamera, PrintsEachFrameAndResyncsAfterDamage) {
    FrameRecordHeader h;
    h.flags = transport::kV4l2BufFlagTimestampMonotonic | transport::kV4l2BufFlagTstampSrcSoe;
    h.fourcc = transport::kFourccGrey;
    h.width = 4;
    h.height = 2;
    h.stride = 4;
    h.exposure_us = 1000;
    std::vector<std::uint8_t> file;
    for (std::uint32_t seq : {0u, 1u, 3u}) {
        h.sequence = seq;
        h.timestamp_ns = 1000 * (seq + 1);
        h.t_host_ns = h.timestamp_ns + 500'000;
        const auto rec =
            encodeFrameRecord(h, std::vector<std::uint8_t>(8, static_cast<std::uint8_t>(50 * seq)));
        file.insert(file.end(), rec.begin(), rec.end());
        if (seq == 1) file.insert(file.end(), {'j', 'u', 'n', 'k'});
    }
    const auto path = std::filesystem::temp_directory_path() /
                      ("decode_camera_test_" + std::to_string(::getpid()) + ".bin");
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(file.data()),
               static_cast<std::streamsize>(file.size()));
    const auto out = run("--device camera " + path.string());
    std::filesystem::remove(path);
    ASSERT_EQ(out.size(), 5u);
    EXPECT_EQ(out[0],
              "{\"t_host_ns\":null,\"sequence\":0,\"timestamp_ns\":1000,\"timestamp_clock\":"
              "\"monotonic\",\"timestamp_source\":"
              "\"start_of_exposure\",\"error_flag\":false,\"flags\":73728,\"format\":\"GREY\","
              "\"width\":4,\"height\":2,\"stride\":4,"
              "\"bytesused\":8,\"coding\":\"raw\",\"stored_bytes\":8,\"exposure_us\":1000,\"t_mid_"
              "exposure_ns\":501000,\"mean_grey\":0}");
    EXPECT_NE(out[2].find("\"error\":\"camera frame record: magic is not 'HSVF'\""),
              std::string::npos)
        << out[2];
    EXPECT_NE(out[3].find("\"sequence\":3"), std::string::npos);
    EXPECT_NE(out[3].find("\"mean_grey\":150"), std::string::npos) << out[3];
    EXPECT_EQ(out[4],
              "{\"summary\":{\"device\":\"camera\",\"messages\":3,\"checksum_failures\":0,"
              "\"resyncs\":1,\"gaps\":1}}");
}

}  // namespace
}  // namespace handscan::camera
