// libFuzzer target: arbitrary bytes as a recording. The reader must refuse or recover them
// without crashing, hanging or allocating without bound; what it hands out must be consistent:
// messages in log-time order, each payload inside the buffer that owns it, each on a known channel.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "handscan/recording/mcap_reader.hpp"

namespace {

void check(bool ok) {
    if (!ok) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace handscan;
    using namespace handscan::recording;
    auto r = McapReader::fromBuffer(std::vector<std::uint8_t>(data, data + size), "fuzz.mcap");
    if (!r) return 0;
    McapReader& reader = **r;
    TimeNs last = std::numeric_limits<TimeNs>::min();
    MessageIterator it = reader.messages();
    RecordedMessage m;
    while (it.next(m)) {
        check(m.log_time >= last);
        last = m.log_time;
        check(m.channel != nullptr && reader.channel(m.channel->id) == m.channel);
        check(m.storage != nullptr);
        const std::uint8_t* begin = m.storage->data();
        check(m.data.data() >= begin && m.data.data() + m.data.size() <= begin + m.storage->size());
    }
    check(it.status().isOk());  // in memory: no I/O errors, only reported drops
    for (const auto& d : reader.dropped()) check(d.offset <= size && d.length <= size - d.offset);
    // With a topic filter the messages are a subset, still ordered.
    if (!reader.channels().empty()) {
        ReadOptions o;
        o.topics = {reader.channels().front().topic};
        last = std::numeric_limits<TimeNs>::min();
        const Status s = reader.forEachMessage(o, [&](const RecordedMessage& msg) {
            check(msg.channel->topic == o.topics[0] && msg.log_time >= last);
            last = msg.log_time;
        });
        check(s.isOk());
    }
    (void)reader.verify();
    return 0;
}
