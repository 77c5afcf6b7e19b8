// Byte-exact candump text formats (can-utils lib.c conventions).
#include "handscan/motor/candump_format.hpp"

#include <gtest/gtest.h>

namespace handscan::motor {
namespace {

TEST(CandumpLogLine, ParsesTheClassicExample) {
    auto r = parseCandumpLogLine("(1700000000.123456) can0 181#11223344\n");
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_TRUE(r->has_time);
    EXPECT_EQ(r->time_s, 1700000000);
    EXPECT_EQ(r->time_us, 123456);
    EXPECT_EQ(r->timeNs(), 1700000000123456000LL);
    EXPECT_EQ(r->interface, "can0");
    EXPECT_EQ(r->frame.id, 0x181u);
    EXPECT_FALSE(r->frame.extended);
    EXPECT_FALSE(r->frame.remote);
    ASSERT_EQ(r->frame.len, 4);
    EXPECT_EQ(r->frame.data[0], 0x11);
    EXPECT_EQ(r->frame.data[3], 0x44);
}

TEST(CandumpLogLine, RoundTripsByteForByte) {
    for (const char* line :
         {"(1700000000.123456) can0 181#11223344", "(0000000001.000001) vcan1 000#0103",
          "(1700000000.000000) can0 080#", "(1700000000.000000) can0 12345678#DEADBEEF",
          "(1700000000.000000) can0 123#R", "(1700000000.000000) can0 123#R4",
          "(1700000000.000000) can0 123##1112233",
          "(1700000000.000000) can0 20000004#0004000000000000",
          "(1700000000.000000) can0 123#1122334455667788_C", "(1700000000.000000) can0 123#R8_9",
          "(1700000000.000000) can0 181#00 R"}) {
        auto r = parseCandumpLogLine(line);
        ASSERT_TRUE(r) << line << ": " << r.status().message();
        EXPECT_EQ(formatCandumpLogLine(*r), line);
    }
}

TEST(CandumpLogLine, DecodesFlags) {
    auto eff = parseCanFrameText("1ABCDEF0#01");
    ASSERT_TRUE(eff);
    EXPECT_TRUE(eff->extended);
    EXPECT_EQ(eff->id, 0x1ABCDEF0u);
    auto rtr = parseCanFrameText("701#R1");
    ASSERT_TRUE(rtr);
    EXPECT_TRUE(rtr->remote);
    EXPECT_EQ(rtr->len, 1);
    EXPECT_TRUE(rtr->payload().empty());
    auto err = parseCanFrameText("20000080#0000000000000000");
    ASSERT_TRUE(err);
    EXPECT_TRUE(err->error);
    EXPECT_FALSE(err->extended);
    EXPECT_EQ(err->id, 0x80u);
    auto fd = parseCanFrameText(
        "123##3"
        "000102030405060708090A0B");
    ASSERT_TRUE(fd) << fd.status().message();
    EXPECT_TRUE(fd->fd);
    EXPECT_EQ(fd->fd_flags, 3);
    EXPECT_EQ(fd->len, 12);
    EXPECT_EQ(fd->data[11], 0x0B);
    auto dots = parseCanFrameText("181#11.22.33");
    ASSERT_TRUE(dots);
    EXPECT_EQ(dots->len, 3);
    EXPECT_EQ(dots->data[2], 0x33);
}

TEST(CandumpLogLine, RejectsMalformedInputWithAClearMessage) {
    for (const char* bad :
         {"", "can0 181#11", "(1700000000.12345) can0 181#11", "(1700000000.123456) can0 18#11",
          "(1700000000.123456) can0 181#1", "(1700000000.123456) can0 181#112233445566778899",
          "(1700000000.123456) can0 181#GG", "(1700000000.123456) can0 181",
          "(x.123456) can0 181#00", "(1700000000.123456) can0 123##",
          "(1700000000.123456) can0 123##0112233445566778899", "(1700000000.123456) can0 123#R9",
          "(1700000000.123456) can0 C0000000#00", "(1700000000.123456) can0 123#11_9",
          "(1700000000.123456) can0 981#FF0F0000", "(17000000000.000000) can0 181#00"}) {
        auto r = parseCandumpLogLine(bad);
        EXPECT_FALSE(r) << "accepted: '" << bad << "'";
        if (!r) {
            EXPECT_EQ(r.status().code(), StatusCode::kProtocolError);
            EXPECT_NE(r.status().message().find("candump"), std::string::npos);
        }
    }
}

TEST(CandumpDefaultLine, ParsesAndFormatsTheScreenFormat) {
    auto r = parseCandumpDefaultLine("  can0  609   [8]  40 77 60 00 00 00 00 00");
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_FALSE(r->has_time);
    EXPECT_EQ(r->frame.id, 0x609u);
    EXPECT_EQ(r->frame.len, 8);
    EXPECT_EQ(r->frame.data[1], 0x77);
    EXPECT_EQ(formatCandumpDefaultLine(*r), "  can0  609   [8]  40 77 60 00 00 00 00 00");

    auto sync = parseCandumpDefaultLine("  can0  080   [0]");
    ASSERT_TRUE(sync);
    EXPECT_EQ(sync->frame.len, 0);
    EXPECT_EQ(formatCandumpDefaultLine(*sync), "  can0  080   [0]");

    CandumpRecord rec;
    rec.interface = "can0";
    rec.frame = makeCanFrame(0x181, std::array<std::uint8_t, 4>{0x11, 0x22, 0x33, 0x44});
    EXPECT_EQ(formatCandumpDefaultLine(rec), "  can0  181   [4]  11 22 33 44");

    auto rtr = parseCandumpDefaultLine("(1700000000.000001)  can0  12345678   [2]  remote request");
    ASSERT_TRUE(rtr) << rtr.status().message();
    EXPECT_TRUE(rtr->has_time);
    EXPECT_TRUE(rtr->frame.remote);
    EXPECT_TRUE(rtr->frame.extended);
    EXPECT_EQ(rtr->frame.len, 2);

    EXPECT_FALSE(parseCandumpDefaultLine("  can0  609   [8]  40 77"));
    EXPECT_FALSE(parseCandumpDefaultLine(
        "  can0  21184922   [2]  remote request"));  // error frame bit + RTR (fuzzer)
    EXPECT_FALSE(parseCandumpDefaultLine("  can0  609   [9]  00 00 00 00 00 00 00 00 00"));
}

TEST(CandumpAnyLine, DetectsTheFormat) {
    EXPECT_TRUE(parseCandumpAnyLine("(1700000000.123456) can0 181#11223344"));
    EXPECT_TRUE(parseCandumpAnyLine("  can0  181   [4]  11 22 33 44"));
}

TEST(CandumpRecord, SetsTimeFromNanoseconds) {
    CandumpRecord rec;
    rec.setTimeNs(12'345'678'901'234LL);
    EXPECT_EQ(rec.time_s, 12345);
    EXPECT_EQ(rec.time_us, 678901);
    rec.interface = "can0";
    rec.frame = makeCanFrame(0x701, std::array<std::uint8_t, 1>{0x05});
    EXPECT_EQ(formatCandumpLogLine(rec), "(0000012345.678901) can0 701#05");
}

}  // namespace
}  // namespace handscan::motor
