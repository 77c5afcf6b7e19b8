// MCAP's CRC-32 (zlib's): the catalogue check value, incremental updates in any split, and the
// empty input.
#include "handscan/recording/crc32.hpp"

#include <gtest/gtest.h>

#include <string_view>

namespace handscan::recording {
namespace {

std::span<const std::uint8_t> bytes(std::string_view s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

TEST(Crc32, CatalogueCheckValue) {
    // CRC-32/ISO-HDLC of "123456789" (the CRC catalogue's check value).
    EXPECT_EQ(crc32(bytes("123456789")), 0xCBF43926u);
    EXPECT_EQ(crc32(bytes("")), 0u);
}

TEST(Crc32, IncrementalEqualsWhole) {
    const std::string_view text = "The quick brown fox jumps over the lazy dog";
    EXPECT_EQ(crc32(bytes(text)), 0x414FA339u);
    for (std::size_t split = 0; split <= text.size(); ++split) {
        Crc32 c;
        c.update(bytes(text.substr(0, split)));
        c.update({});
        c.update(bytes(text.substr(split)));
        EXPECT_EQ(c.value(), 0x414FA339u) << "split at " << split;
    }
}

}  // namespace
}  // namespace handscan::recording
