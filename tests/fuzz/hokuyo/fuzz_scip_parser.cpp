// libFuzzer: any byte stream, split anywhere, through the SCIP stream parser; and the same bytes as
// host commands into the fake sensor. Beyond "no crash, no hang, bounded memory" it checks the
// parser's promises: every emitted scan has exactly the values its echo asked for, re-encodes and
// re-parses to itself, and feeding in two pieces gives the same frames as feeding at once.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "handscan/hokuyo/scip_codec.hpp"
#include "handscan/hokuyo/scip_stream_parser.hpp"
#include "handscan/hokuyo_fake/fake_hokuyo_sensor.hpp"

using namespace handscan::hokuyo;

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

std::vector<ScipEvent> parseSplit(std::string_view bytes, std::size_t cut) {
    ScipStreamParser p;
    std::vector<ScipEvent> out;
    p.feed(bytes.substr(0, cut), out);
    p.feed(bytes.substr(cut), out);
    const ScipParserStats& s = p.stats();
    check(s.bytes == bytes.size());
    check(s.checksum_failures <= s.resyncs);
    return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view all(reinterpret_cast<const char*>(data), size);
    const std::string_view bytes = all.substr(1);
    const std::size_t cut = bytes.empty() ? 0 : data[0] % (bytes.size() + 1);

    const auto split = parseSplit(bytes, cut);
    const auto whole = parseSplit(bytes, bytes.size());
    check(split.size() == whole.size());
    for (std::size_t i = 0; i < whole.size(); ++i) {
        const auto* a = std::get_if<ScipFrame>(&whole[i]);
        const auto* b = std::get_if<ScipFrame>(&split[i]);
        check((a == nullptr) == (b == nullptr));
        if (a == nullptr) continue;
        check(a->echo == b->echo && a->status == b->status && a->items == b->items);
        if (!a->scan) continue;
        check(b->scan && a->scan->ranges == b->scan->ranges);
        const ScanRequest& r = *a->scan_request;
        check(a->scan->ranges.size() == static_cast<std::size_t>(r.valuesPerScan()));
        // Round trip through the encoder the simulator uses.
        ScipStreamParser again;
        std::vector<ScipEvent> events;
        again.feed(encodeScanFrame(r, *a->scan), events);
        check(events.size() == 1);
        const auto* f = std::get_if<ScipFrame>(&events[0]);
        check(f != nullptr && f->scan && f->scan->ranges == a->scan->ranges &&
              f->scan->intensities == a->scan->intensities &&
              f->scan->timestamp_ms == a->scan->timestamp_ms);
    }

    // The same bytes as commands from a host: the fake sensor must answer with well-formed replies.
    FakeHokuyoSensor sensor({});
    sensor.onHostBytes(bytes);
    const std::string replies = sensor.takeReplies();
    ScipStreamParser p;
    std::vector<ScipEvent> events;
    p.feed(replies, events);
    for (const auto& e : events) {
        // Echoes of garbage may not be valid echoes, but what parses must not be a fault of sums.
        if (const auto* fault = std::get_if<ScipFault>(&e))
            check(fault->code != handscan::StatusCode::kChecksumError);
    }
    return 0;
}
