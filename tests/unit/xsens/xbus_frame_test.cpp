// Xbus framing: byte-exact frames from PROTOCOLS.md and the MTi-300 capture, extended length,
// checksum failures.
#include "handscan/xsens/xbus_frame.hpp"

#include <gtest/gtest.h>

#include <numeric>

#include "handscan/xsens/xbus_messages.hpp"

namespace handscan::xsens {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(XbusFrame, EncodesTheDocumentedControlFrames) {
    EXPECT_EQ(encodeFrame(MessageId::kGoToConfig), (Bytes{0xFA, 0xFF, 0x30, 0x00, 0xD1}));
    EXPECT_EQ(encodeFrame(MessageId::kGoToMeasurement), (Bytes{0xFA, 0xFF, 0x10, 0x00, 0xF1}));
    EXPECT_EQ(encodeFrame(MessageId::kReqDid), (Bytes{0xFA, 0xFF, 0x00, 0x00, 0x01}));
    // Acks as the MTi-300 sent them.
    EXPECT_EQ(encodeFrame(MessageId::kGoToConfigAck), (Bytes{0xFA, 0xFF, 0x31, 0x00, 0xD0}));
    EXPECT_EQ(encodeFrame(MessageId::kGoToMeasurementAck), (Bytes{0xFA, 0xFF, 0x11, 0x00, 0xF0}));
}

TEST(XbusFrame, EncodesTheDocumentedOutputConfiguration) {
    // Counter, SampleTimeFine, quaternion @100 Hz, acceleration and rate of turn @400 Hz.
    const std::vector<OutputConfigEntry> entries{
        {0x1020, 0xFFFF}, {0x1060, 0xFFFF}, {0x2010, 100}, {0x4020, 400}, {0x8020, 400}};
    const Bytes expected{0xFA, 0xFF, 0xC0, 0x14, 0x10, 0x20, 0xFF, 0xFF, 0x10,
                         0x60, 0xFF, 0xFF, 0x20, 0x10, 0x00, 0x64, 0x40, 0x20,
                         0x01, 0x90, 0x80, 0x20, 0x01, 0x90, 0xDB};
    EXPECT_EQ(encodeFrame(MessageId::kSetOutputConfiguration, encodeOutputConfiguration(entries)),
              expected);
    auto frame = decodeFrame(expected);
    ASSERT_TRUE(frame.isOk()) << frame.status().message();
    auto decoded = decodeOutputConfiguration(frame->payload);
    ASSERT_TRUE(decoded.isOk());
    EXPECT_EQ(*decoded, entries);
}

TEST(XbusFrame, ExtendedLengthRoundTrips) {
    Bytes payload(300);
    std::iota(payload.begin(), payload.end(), std::uint8_t{0});
    const Bytes frame = encodeFrame(MessageId::kMtData2, payload);
    ASSERT_EQ(frame.size(), payload.size() + 7);
    EXPECT_EQ(frame[3], 0xFF);
    EXPECT_EQ(frame[4], 0x01);
    EXPECT_EQ(frame[5], 0x2C);
    unsigned sum = 0;
    for (std::size_t i = 1; i < frame.size(); ++i) sum += frame[i];
    EXPECT_EQ(sum & 0xFF, 0u);
    auto decoded = decodeFrame(frame);
    ASSERT_TRUE(decoded.isOk()) << decoded.status().message();
    EXPECT_EQ(decoded->mid, 0x36);
    EXPECT_TRUE(std::equal(decoded->payload.begin(), decoded->payload.end(), payload.begin(),
                           payload.end()));
    // 254 bytes still use the standard length byte; 255 must use the extended form.
    EXPECT_EQ(encodeFrame(MessageId::kMtData2, Bytes(254)).size(), 254u + 5);
    EXPECT_EQ(encodeFrame(MessageId::kMtData2, Bytes(255)).size(), 255u + 7);
    EXPECT_TRUE(decodeFrame(encodeFrame(MessageId::kMtData2, Bytes(255))).isOk());
}

TEST(XbusFrame, RejectsOversizePayloads) {
    Bytes out;
    const Status s = appendFrame(out, 0x36, Bytes(kMaxPayload + 1));
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(s.message().find("2048"), std::string::npos);
    EXPECT_TRUE(out.empty());
}

TEST(XbusFrame, DecodeReportsDamage) {
    Bytes frame = encodeFrame(MessageId::kGoToConfigAck);
    frame[4] ^= 0x01;
    auto r = decodeFrame(frame);
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().code(), StatusCode::kChecksumError);
    EXPECT_NE(r.status().message().find("GoToConfigAck"), std::string::npos);
    EXPECT_EQ(decodeFrame(Bytes{0xFA, 0xFF, 0x30}).status().code(), StatusCode::kTruncated);
    EXPECT_EQ(decodeFrame(Bytes{0xFB, 0xFF, 0x30, 0x00, 0xD1}).status().code(),
              StatusCode::kProtocolError);
    EXPECT_EQ(decodeFrame(Bytes{0xFA, 0xFF, 0x30, 0x01, 0xD1}).status().code(),
              StatusCode::kTruncated);
}

TEST(XbusMessages, ErrorCodesHaveClearTexts) {
    for (std::uint8_t code : {0x03, 0x04, 0x20, 0x21, 0x28, 0x29, 0x2A}) {
        const std::string text = errorText(code);
        EXPECT_EQ(text.find("unknown"), std::string::npos) << int(code);
        EXPECT_GT(text.size(), 30u);
    }
    EXPECT_NE(errorText(0x03).find("InvalidPeriod"), std::string::npos);
    EXPECT_NE(errorText(0x04).find("GoToConfig"), std::string::npos);  // what to do
    EXPECT_NE(errorText(0x77).find("0x77"), std::string::npos);
    const Bytes frame = encodeErrorFrame(ErrorCode::kInvalidParameter);
    EXPECT_EQ(frame, (Bytes{0xFA, 0xFF, 0x42, 0x01, 0x21,
                            static_cast<std::uint8_t>(-(0xFF + 0x42 + 0x01 + 0x21))}));
    auto f = decodeFrame(frame);
    ASSERT_TRUE(f.isOk());
    auto e = decodeError(f->payload);
    ASSERT_TRUE(e.isOk());
    EXPECT_EQ(e->code, 0x21);
    EXPECT_FALSE(decodeError({}).isOk());
}

TEST(XbusMessages, BaudRatesAndIds) {
    EXPECT_EQ(baudrateId(921600), 0x80);
    EXPECT_EQ(baudrateId(115200), 0x02);
    EXPECT_EQ(baudrateId(1234), std::nullopt);
    for (int baud : {921600, 460800, 230400, 115200, 57600, 38400, 19200, 9600}) {
        EXPECT_EQ(baudrateFromId(*baudrateId(baud)), baud);
    }
    EXPECT_EQ(baudrateFromId(0x0A), 921600);
    auto id = decodeDeviceId(encodeDeviceId(0x037003F8));
    ASSERT_TRUE(id.isOk());
    EXPECT_EQ(*id, 0x037003F8u);
    EXPECT_FALSE(decodeDeviceId(Bytes{1, 2, 3}).isOk());
    EXPECT_EQ(decodeProductCode(encodeProductCode("MTi-20-2A5G4")), "MTi-20-2A5G4");
    EXPECT_EQ(encodeProductCode("MTi-20-2A5G4").size(), 20u);
    EXPECT_FALSE(decodeOutputConfiguration(Bytes{1, 2, 3}).isOk());
}

}  // namespace
}  // namespace handscan::xsens
