// `handscan decode --device NAME` dispatches to per-device stream decoders that register
// themselves from firmware/cli/decode_<device>.cpp. A decoder is fed raw byte chunks exactly as
// the device sent them (a whole capture file as one chunk, or one recorded message per chunk with
// its host receive time), prints one JSON line per decoded message and ends with a summary.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/time.hpp"

namespace handscan::cli {

struct DecodeSummary {
    std::uint64_t messages = 0;
    std::uint64_t checksum_failures = 0;
    std::uint64_t resyncs = 0;
    std::uint64_t gaps = 0;  // counter / sequence gaps (lost messages)
};

class StreamDecoder {
public:
    virtual ~StreamDecoder() = default;
    // `t_host`: host receive time of the chunk (0 when decoding a plain file).
    virtual void feed(TimeNs t_host, std::span<const std::uint8_t> bytes, std::ostream& jsonl) = 0;
    // Flushes what is pending and returns the counts for the summary line.
    virtual DecodeSummary finish(std::ostream& jsonl) = 0;
};

struct DecoderEntry {
    std::string device;   // hokuyo | xsens | can | camera
    std::string channel;  // the recording channel holding this device's raw stream
    std::function<std::unique_ptr<StreamDecoder>()> make;
};

std::vector<DecoderEntry>& decoderRegistry();

struct RegisterDecoder {
    RegisterDecoder(std::string device, std::string channel,
                    std::function<std::unique_ptr<StreamDecoder>()> make) {
        decoderRegistry().push_back({std::move(device), std::move(channel), std::move(make)});
    }
};

}  // namespace handscan::cli
