// `handscan info REC.mcap`: channels, message counts, rates, durations and gaps of a recording,
// and whether it was cut short and recovered; the raw device channels decoded with the drivers'
// codecs, so each device shows at its own rate (scans, IMU samples, encoder positions, frames per
// second) next to the rate of transport reads. `--json` for scripts and tests. An .e57 file
// (an export) shows its pages, scans, sensor, fields, bounds and colour share (info_e57.hpp).
#include <exception>
#include <iostream>

#include "command_registry.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/log.hpp"
#include "handscan/recording/channels.hpp"
#include "handscan/recording/mcap_reader.hpp"
#include "handscan/recording/recording_summary.hpp"
#include "handscan/replay/device_rates.hpp"
#include "info_e57.hpp"

namespace handscan::cli {
namespace {

const RegisterCommand kInfo{
    "info", "Show a recording's channels, message counts, rates, duration and gaps",
    [](CLI::App& sub) {
        auto file = std::make_shared<std::string>();
        auto json = std::make_shared<bool>(false);
        auto verify = std::make_shared<bool>(false);
        auto device_yaml = std::make_shared<std::string>();
        sub.add_option("REC", *file, "recording (.mcap), or an exported .e57")
            ->required()
            ->check(CLI::ExistingFile);
        sub.add_option("--device", *device_yaml,
                       "device.yaml for the encoder's node id and TPDO period (default: <config "
                       "dir>/device.yaml)");
        sub.add_flag("--json", *json, "print one JSON object instead of a table");
        sub.add_flag("--verify", *verify,
                     "also check every CRC (chunks, data section, summary); exit 3 on a mismatch");
        return std::function<int()>([file, json, verify, device_yaml] {
            if (file->size() > 4 && file->compare(file->size() - 4, 4, ".e57") == 0)
                return printE57Info(*file, std::cout);
            DeviceConfig device;
            const std::string device_path =
                device_yaml->empty() ? defaultConfigDir() + "/device.yaml" : *device_yaml;
            try {
                device = loadDeviceConfig(device_path);
            } catch (const std::exception& e) {
                if (!device_yaml->empty()) {
                    log().error("{}", e.what());
                    return 1;
                }
                log().warn("{}; decoding the encoder with default settings", e.what());
            }
            replay::DeviceRateMeter devices(device);
            auto reader = recording::McapReader::open(*file);
            if (!reader) {
                log().error("{}", reader.status().message());
                return 1;
            }
            // Reading every message of a large recording takes a while: show progress on a
            // terminal.
            std::unique_ptr<Progress> progress;
            if ((*reader)->fileSize() > (64u << 20))
                progress = std::make_unique<Progress>("reading " + *file, 1.0);
            auto summary = recording::summarizeRecording(
                **reader,
                [&](double f) {
                    if (progress) progress->update(f);
                },
                [&](const recording::RecordedMessage& m) {
                    // A device's raw stream by topic and encoding: a --viz file's /camera/track
                    // (foxglove.CompressedImage) is not a camera's frame records.
                    const recording::ChannelSpec* spec = recording::findChannel(m.channel->topic);
                    if (spec != nullptr && spec->message_encoding == m.channel->message_encoding)
                        devices.feed(m.channel->topic, m.log_time, m.data);
                });
            if (progress) progress->finish();
            if (!summary) {
                log().error("{}", summary.status().message());
                return 1;
            }
            summary->devices = devices.summaries();
            if (*verify) {
                if (Status s = recording::checkRecordingCrcs(**reader, *summary); !s) {
                    log().error("{}", s.message());
                    return 1;
                }
            }
            if (*json) {
                recording::printSummaryJson(*summary, std::cout);
            } else {
                recording::printSummaryText(*summary, std::cout);
            }
            return summary->crc_checked && !summary->crc_problems.empty() ? 3 : 0;
        });
    }};

}  // namespace
}  // namespace handscan::cli
