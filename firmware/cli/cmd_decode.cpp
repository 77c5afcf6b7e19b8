// `handscan decode --device D FILE`: decoded samples as JSON lines for support and golden tests.
// FILE is a raw capture of the device's bytes, or a recording (.mcap): then the messages of the
// device's channel are fed one by one with their host receive times.
#include <algorithm>
#include <array>
#include <fstream>
#include <iostream>
#include <iterator>

#include "command_registry.hpp"
#include "decoder_registry.hpp"
#include "handscan/core/json.hpp"
#include "handscan/core/log.hpp"
#include "handscan/recording/mcap_format.hpp"
#include "handscan/recording/mcap_reader.hpp"

namespace handscan::cli {

std::vector<DecoderEntry>& decoderRegistry() {
    static std::vector<DecoderEntry> decoders;
    return decoders;
}

namespace {

void printSummary(const std::string& device, const DecodeSummary& s) {
    const Json summary = {{"device", device},
                          {"messages", s.messages},
                          {"checksum_failures", s.checksum_failures},
                          {"resyncs", s.resyncs},
                          {"gaps", s.gaps}};
    std::cout << jsonText({{"summary", summary}}) << "\n";
}

// An MCAP recording starts with the MCAP magic; anything else is a raw capture.
bool isRecording(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    std::array<char, recording::kMcapMagic.size()> head{};
    if (!in.read(head.data(), head.size())) return false;
    return std::equal(head.begin(), head.end(), recording::kMcapMagic.begin(),
                      [](char a, std::uint8_t b) { return static_cast<std::uint8_t>(a) == b; });
}

// Feeds the decoder every message of the device's channel, in log-time order, with its host time.
int feedRecording(const std::string& file, const DecoderEntry& entry, StreamDecoder& decoder) {
    auto reader = recording::McapReader::open(file);
    if (!reader) {
        log().error("{}", reader.status().message());
        return 1;
    }
    if ((*reader)->findTopic(entry.channel) == nullptr) {
        std::string topics;
        for (const auto& c : (*reader)->channels()) topics += " " + c.topic;
        log().error("{}: no channel {} for device {} (channels:{})", file, entry.channel,
                    entry.device, topics.empty() ? " none" : topics);
        return 1;
    }
    const Status s = (*reader)->forEachMessage(
        {{entry.channel}},
        [&](const recording::RecordedMessage& m) { decoder.feed(m.log_time, m.data, std::cout); });
    for (const auto& d : (*reader)->dropped()) log().warn("{}", d.reason);
    if (!s) {
        log().error("{}", s.message());
        return 1;
    }
    return 0;
}

const RegisterCommand kDecode{
    "decode", "Print a device stream's decoded samples as JSON lines", [](CLI::App& sub) {
        auto device = std::make_shared<std::string>();
        auto file = std::make_shared<std::string>();
        std::vector<std::string> names;
        for (const auto& d : decoderRegistry()) names.push_back(d.device);
        sub.add_option("--device", *device, "device whose wire format FILE holds")
            ->required()
            ->check(CLI::IsMember(names));
        sub.add_option("FILE", *file, "raw capture of the device's bytes, or a recording (.mcap)")
            ->required()
            ->check(CLI::ExistingFile);
        return std::function<int()>([device, file] {
            const DecoderEntry* entry = nullptr;
            for (const auto& d : decoderRegistry()) {
                if (d.device == *device) entry = &d;
            }
            auto decoder = entry->make();
            if (isRecording(*file)) {
                if (int rc = feedRecording(*file, *entry, *decoder); rc != 0) return rc;
                printSummary(*device, decoder->finish(std::cout));
                return 0;
            }
            std::ifstream in(*file, std::ios::binary);
            if (!in) {
                log().error("{}: cannot open for reading", *file);
                return 1;
            }
            const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                                  std::istreambuf_iterator<char>());
            decoder->feed(0, bytes, std::cout);
            printSummary(*device, decoder->finish(std::cout));
            return 0;
        });
    }};

}  // namespace
}  // namespace handscan::cli
