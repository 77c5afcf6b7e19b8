// `handscan decode --device D FILE`: decoded samples as JSON lines for support and golden tests.
#include <fstream>
#include <iostream>
#include <iterator>

#include "command_registry.hpp"
#include "decoder_registry.hpp"
#include "handscan/core/log.hpp"

namespace handscan::cli {

std::vector<DecoderEntry>& decoderRegistry() {
    static std::vector<DecoderEntry> decoders;
    return decoders;
}

namespace {

void printSummary(const std::string& device, const DecodeSummary& s) {
    std::cout << "{\"summary\":{\"device\":\"" << device << "\",\"messages\":" << s.messages
              << ",\"checksum_failures\":" << s.checksum_failures << ",\"resyncs\":" << s.resyncs
              << ",\"gaps\":" << s.gaps << "}}\n";
}

const RegisterCommand kDecode{"decode", "Print a device stream's decoded samples as JSON lines", [](CLI::App& sub) {
    auto device = std::make_shared<std::string>();
    auto file = std::make_shared<std::string>();
    std::vector<std::string> names;
    for (const auto& d : decoderRegistry()) names.push_back(d.device);
    sub.add_option("--device", *device, "device whose wire format FILE holds")->required()->check(CLI::IsMember(names));
    sub.add_option("FILE", *file, "raw capture of the device's bytes")->required()->check(CLI::ExistingFile);
    return std::function<int()>([device, file] {
        const DecoderEntry* entry = nullptr;
        for (const auto& d : decoderRegistry()) {
            if (d.device == *device) entry = &d;
        }
        auto decoder = entry->make();
        std::ifstream in(*file, std::ios::binary);
        if (!in) {
            log().error("{}: cannot open for reading", *file);
            return 1;
        }
        const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        decoder->feed(0, bytes, std::cout);
        printSummary(*device, decoder->finish(std::cout));
        return 0;
    });
}};

}  // namespace
}  // namespace handscan::cli
