// Test helpers: an independent walk over an MCAP file's top-level records (to find chunks and
// the summary to corrupt or cut), and reading every message back.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "handscan/recording/mcap_reader.hpp"

namespace handscan::recording::test {

struct TopRecord {
    std::uint8_t op = 0;
    std::size_t offset = 0;  // of the opcode
    std::size_t size = 0;    // whole record
    std::size_t end() const { return offset + size; }
};

inline std::uint64_t le64(const std::vector<std::uint8_t>& b, std::size_t at) {
    std::uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | b[at + static_cast<std::size_t>(i)];
    return v;
}

// Records between the leading magic and the trailing magic (stops at the Footer).
inline std::vector<TopRecord> topLevelRecords(const std::vector<std::uint8_t>& bytes) {
    std::vector<TopRecord> out;
    std::size_t pos = 8;
    while (pos + 9 <= bytes.size()) {
        const TopRecord r{bytes[pos], pos, static_cast<std::size_t>(9 + le64(bytes, pos + 1))};
        out.push_back(r);
        if (r.op == 0x02) break;
        pos = r.end();
    }
    return out;
}

inline std::vector<TopRecord> recordsWithOp(const std::vector<std::uint8_t>& bytes,
                                            std::uint8_t op) {
    std::vector<TopRecord> out;
    for (const auto& r : topLevelRecords(bytes)) {
        if (r.op == op) out.push_back(r);
    }
    return out;
}

struct Msg {
    std::string topic;
    TimeNs t = 0;
    std::vector<std::uint8_t> data;
    bool operator==(const Msg&) const = default;
};

inline std::vector<Msg> readAll(McapReader& reader, const ReadOptions& options = {}) {
    std::vector<Msg> out;
    const Status s = reader.forEachMessage(options, [&](const RecordedMessage& m) {
        out.push_back({m.channel->topic, m.log_time,
                       std::vector<std::uint8_t>(m.data.begin(), m.data.end())});
    });
    EXPECT_TRUE(s) << s.message();
    return out;
}

}  // namespace handscan::recording::test
