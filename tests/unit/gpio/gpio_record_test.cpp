#include "handscan/gpio/gpio_record.hpp"

#include <gtest/gtest.h>

#include "handscan/gpio/gpio_lines.hpp"

namespace handscan::gpio {
namespace {

TEST(GpioRecord, EncodesTheDocumentedLayoutAndRoundTrips) {
    GpioRecord r{0x0102030405060708LL, 17, GpioRecordKind::kFallingEdge, PanelRole::kScanButton};
    const auto b = encodeGpioRecord(r);
    EXPECT_EQ(b[0], 0x08);
    EXPECT_EQ(b[7], 0x01);
    EXPECT_EQ(b[8], 17);
    EXPECT_EQ(b[12], 2);
    EXPECT_EQ(b[13], 1);
    EXPECT_EQ(b[14], 'G');
    EXPECT_EQ(b[15], 1);
    auto d = decodeGpioRecord(b);
    ASSERT_TRUE(d) << d.status().message();
    EXPECT_EQ(*d, r);
}

TEST(GpioRecord, RejectsBadRecords) {
    auto b = encodeGpioRecord({1, 2, GpioRecordKind::kOutputOn, PanelRole::kLedFault});
    EXPECT_EQ(decodeGpioRecord(std::span<const std::uint8_t>(b).first(15)).status().code(),
              StatusCode::kTruncated);
    auto k = b;
    k[12] = 9;
    EXPECT_FALSE(decodeGpioRecord(k));
    auto m = b;
    m[14] = 'X';
    EXPECT_FALSE(decodeGpioRecord(m));
    auto role = b;
    role[13] = 7;
    EXPECT_FALSE(decodeGpioRecord(role));
}

TEST(EventClock, MapsRealtimeStampsOfOldKernelsToMonotonic) {
    const TimeNs mono = 5000 * kNsPerSec, real = 1'700'000'000 * kNsPerSec;
    EXPECT_EQ(eventTimeToMonotonic(mono - 3 * kNsPerMs, mono, real), mono - 3 * kNsPerMs);
    EXPECT_EQ(eventTimeToMonotonic(real - 3 * kNsPerMs, mono, real), mono - 3 * kNsPerMs);
}

}  // namespace
}  // namespace handscan::gpio
