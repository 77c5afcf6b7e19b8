// MTData2 encode/decode: the builder the simulator uses, in every number format; unknown XDIs
// and malformed items are skipped without losing the rest of the packet.
#include "handscan/xsens/mtdata2.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "handscan/xsens/xbus_frame.hpp"

namespace handscan::xsens {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(MtData2, FixedPointEncodingsMatchXsensDefinitions) {
    Bytes b;
    encodeReal(b, -0.23666316, Precision::kFp1632);
    ASSERT_EQ(b.size(), 6u);
    EXPECT_EQ(b[4], 0xFF);  // integer part -1 comes last
    EXPECT_EQ(b[5], 0xFF);
    EXPECT_NEAR(decodeReal(b.data(), Precision::kFp1632), -0.23666316, 1e-9);
    b.clear();
    encodeReal(b, 1.5, Precision::kFp1220);
    EXPECT_EQ(b, (Bytes{0x00, 0x18, 0x00, 0x00}));
    b.clear();
    encodeReal(b, 1e9, Precision::kFp1220);  // saturates instead of wrapping
    EXPECT_EQ(b, (Bytes{0x7F, 0xFF, 0xFF, 0xFF}));
    b.clear();
    encodeReal(b, 24.375, Precision::kFp1632);  // MTi-300 temperature bytes
    EXPECT_EQ(b, (Bytes{0x60, 0x00, 0x00, 0x00, 0x00, 0x18}));
}

class MtData2Precision : public ::testing::TestWithParam<Precision> {};

TEST_P(MtData2Precision, BuilderRoundTripsTheImuPacket) {
    const Precision p = GetParam();
    const Eigen::Vector3d acc(0.0123, -9.80665, 1.25);
    const Eigen::Vector3d gyro(-0.5, 0.001, 3.75);
    const Eigen::Vector3d dv = acc * 0.005;
    const Eigen::Vector4d dq(0.9999, 0.001, -0.002, 0.0005);
    MtData2Builder b;
    b.packetCounter(65535)
        .sampleTimeFine(4294967000u)
        .acceleration(acc, p)
        .rateOfTurn(gyro, p)
        .statusWord(0x00400003)
        .deltaQ(dq, p)
        .deltaV(dv, p);
    const Bytes frame = b.frame();
    auto f = decodeFrame(frame);
    ASSERT_TRUE(f.isOk()) << f.status().message();
    auto packet = decodeMtData2(f->payload);
    ASSERT_TRUE(packet.isOk()) << packet.status().message();
    ASSERT_EQ(packet->values.size(), 7u);
    // Resolution of each format: float32 ~1e-7 relative, fp12.20 2^-20, fp16.32 2^-32.
    const double tol = p == Precision::kFloat32  ? 1e-6
                       : p == Precision::kFp1220 ? 1.0 / (1 << 20)
                                                 : 1e-9;
    EXPECT_EQ(packet->integer(xdi::kPacketCounter), 65535u);
    EXPECT_EQ(packet->integer(xdi::kSampleTimeFine), 4294967000u);
    EXPECT_EQ(packet->integer(xdi::kStatusWord), 0x00400003u);
    EXPECT_TRUE(packet->vector3(xdi::kAcceleration)->isApprox(acc, tol));
    EXPECT_LT((*packet->vector3(xdi::kRateOfTurn) - gyro).cwiseAbs().maxCoeff(), tol * 10);
    EXPECT_LT((*packet->vector3(xdi::kDeltaV) - dv).cwiseAbs().maxCoeff(), tol);
    EXPECT_LT((*packet->vector4(xdi::kDeltaQ) - dq).cwiseAbs().maxCoeff(), tol);
    EXPECT_EQ(packet->find(xdi::kAcceleration)->precision(), p);
    EXPECT_EQ(packet->find(xdi::kAcceleration)->raw.size(), 3 * realSize(p));
    if (p == Precision::kFloat64) {
        EXPECT_EQ(*packet->vector3(xdi::kAcceleration), acc);  // exact
    }
}

INSTANTIATE_TEST_SUITE_P(AllFormats, MtData2Precision,
                         ::testing::Values(Precision::kFloat32, Precision::kFp1220,
                                           Precision::kFp1632, Precision::kFloat64));

TEST(MtData2, CoordinateSystemBits) {
    for (CoordSys c : {CoordSys::kEnu, CoordSys::kNed, CoordSys::kNwu}) {
        MtData2Builder b;
        b.quaternion(Eigen::Vector4d(1, 0, 0, 0), Precision::kFloat64, c);
        auto packet = decodeMtData2(b.payload());
        ASSERT_TRUE(packet.isOk());
        const auto* q = packet->find(xdi::kQuaternion);
        ASSERT_NE(q, nullptr);
        EXPECT_EQ(q->coordSys(), c);
        EXPECT_EQ(q->precision(), Precision::kFloat64);
        EXPECT_EQ(q->xdi, 0x2013 | static_cast<std::uint16_t>(c));
        EXPECT_EQ(*packet->vector4(xdi::kQuaternion), Eigen::Vector4d(1, 0, 0, 0));
    }
    EXPECT_EQ(coordSysName(CoordSys::kNed), "NED");
    EXPECT_EQ(precisionName(Precision::kFp1632), "FP1632");
}

TEST(MtData2, UnknownAndMalformedItemsAreSkippedNotFatal) {
    MtData2Builder b;
    const Bytes junk{1, 2, 3, 4, 5};
    b.packetCounter(7)
        .raw(0x9990, junk)
        .raw(withFormat(xdi::kAcceleration, Precision::kFloat32), junk)
        .sampleTimeFine(1234);
    auto packet = decodeMtData2(b.payload());
    ASSERT_TRUE(packet.isOk()) << packet.status().message();
    ASSERT_EQ(packet->values.size(), 4u);
    EXPECT_EQ(packet->unknownCount(), 1u);
    EXPECT_EQ(packet->values[1].name(), "Unknown");
    EXPECT_NE(packet->values[1].problem.find("0x9990"), std::string::npos);
    EXPECT_EQ(packet->values[1].raw, junk);
    EXPECT_FALSE(packet->values[2].decoded());
    EXPECT_NE(packet->values[2].problem.find("Acceleration"), std::string::npos);
    EXPECT_FALSE(packet->vector3(xdi::kAcceleration).has_value());
    EXPECT_EQ(packet->integer(xdi::kPacketCounter), 7u);
    EXPECT_EQ(packet->integer(xdi::kSampleTimeFine), 1234u);
}

TEST(MtData2, BrokenItemFramingIsAnErrorNamingTheItem) {
    MtData2Builder b;
    b.packetCounter(1).sampleTimeFine(2);
    Bytes payload = b.payload();
    payload.pop_back();
    auto r = decodeMtData2(payload);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("0x1060"), std::string::npos);
    payload = b.payload();
    payload.push_back(0x10);
    EXPECT_FALSE(decodeMtData2(payload).isOk());
    EXPECT_TRUE(decodeMtData2({}).isOk());
}

TEST(MtData2, EveryTableEntryDecodesItsOwnEncoding) {
    // Sanity of the table: each real XDI round-trips in each format; each struct XDI decodes a
    // zero-filled item of its size.
    for (const XdiInfo& info : xdiTable()) {
        SCOPED_TRACE(std::string(info.name));
        MtData2Builder b;
        if (info.layout == XdiLayout::kReals) {
            const std::size_t n = info.components.empty() ? 2 : info.components.size();
            std::vector<double> values(n);
            for (std::size_t i = 0; i < n; ++i) values[i] = 0.25 * static_cast<double>(i) - 1.0;
            for (Precision p : {Precision::kFloat32, Precision::kFp1220, Precision::kFp1632,
                                Precision::kFloat64}) {
                b.clear();
                b.reals(withFormat(info.type, p), values);
                auto packet = decodeMtData2(b.payload());
                ASSERT_TRUE(packet.isOk());
                ASSERT_TRUE(packet->values[0].decoded()) << packet->values[0].problem;
                ASSERT_EQ(packet->values[0].fields.size(), n);
                for (std::size_t i = 0; i < n; ++i)
                    EXPECT_EQ(packet->values[0].fields[i].value, values[i]);
            }
        } else if (info.layout == XdiLayout::kStruct) {
            std::size_t size = 0;
            for (const auto& f : info.fields) size += intSize(f.type);
            b.raw(info.type, Bytes(size, 0));
            auto packet = decodeMtData2(b.payload());
            ASSERT_TRUE(packet.isOk());
            EXPECT_TRUE(packet->values[0].decoded()) << packet->values[0].problem;
            EXPECT_EQ(packet->values[0].fields.size(), info.fields.size());
        }
        EXPECT_EQ(findXdi(info.type | 0x3), &info);
    }
    EXPECT_EQ(findXdi(0x9990), nullptr);
}

}  // namespace
TEST(PacketCounterTracker, CountsThePacketsMissingBetweenCountersAcrossTheWrap) {
    PacketCounterTracker t;
    EXPECT_EQ(t.missingBefore(65533), 0);  // the first one: nothing to compare with
    EXPECT_EQ(t.missingBefore(65534), 0);
    EXPECT_EQ(t.missingBefore(1), 2);  // 65535 and 0 lost across the wrap
    EXPECT_EQ(t.last(), std::optional<std::uint16_t>(1));
    t.reset();
    EXPECT_FALSE(t.last().has_value());
    EXPECT_EQ(t.missingBefore(500), 0);  // a new sequence starts wherever the device is
}

}  // namespace handscan::xsens
