// SocketCAN needs a kernel with CAN (and a vcan0 for the loopback test): skipped otherwise.
#include "handscan/transport/socketcan.hpp"

#include <gtest/gtest.h>

namespace handscan::transport {
namespace {

TEST(SocketCan, LoopsBackFramesThroughVcanWithFilters) {
    SocketCanBus rx("vcan0"), tx("vcan0");
    Status s = rx.open();
    if (s.code() == StatusCode::kUnsupported || s.code() == StatusCode::kNotFound)
        GTEST_SKIP() << s.message();
    ASSERT_TRUE(s) << s.message();
    ASSERT_TRUE(tx.open());
    const CanFilter only181 = exactSffFilter(0x181);
    ASSERT_TRUE(rx.setFilters({&only181, 1}));
    ASSERT_TRUE(tx.send(makeCanFrame(0x701, std::array<std::uint8_t, 1>{0x05})));
    const CanFrame pos = makeCanFrame(0x181, std::array<std::uint8_t, 4>{1, 2, 3, 4});
    ASSERT_TRUE(tx.send(pos));
    auto got = rx.receive(100 * kNsPerMs);
    ASSERT_TRUE(got) << got.status().message();
    EXPECT_EQ(got->frame, pos) << "the 701 frame must have been filtered out";
}

TEST(SocketCan, OpenFailsCleanlyOnAMissingInterface) {
    SocketCanBus bus("nosuchcan9");
    Status s = bus.open();
    ASSERT_FALSE(s);
    if (s.code() == StatusCode::kUnsupported) GTEST_SKIP() << s.message();
    EXPECT_EQ(s.code(), StatusCode::kNotFound);
    EXPECT_NE(s.message().find("nosuchcan9"), std::string::npos);
    EXPECT_FALSE(bus.isOpen());
}

}  // namespace
}  // namespace handscan::transport
