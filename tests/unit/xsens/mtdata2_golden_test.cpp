// MTData2 decoding against the golden values that came with the real captures:
//  - MTi-G-710 captures 1, 2, 3, 5 (float32, fp12.20, fp16.32; capture 5 with quaternion, rotation
//    matrix, free acceleration, magnetic field, temperature, ECEF, baro, GNSS) decoded by
//    einride/xsens-go (output.golden): values must be equal to the last bit;
//  - MTi-300 frames with the values Xsens' MT Manager printed (8 significant decimals).
#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <map>
#include <sstream>

#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_parser.hpp"
#include "xsens_test_files.hpp"

namespace handscan::xsens {
namespace {

// One decoded block of output.golden: "Name(...):" then "  Key:Value" lines (or one bare value).
struct GoldenItem {
    std::string name;                                         // before "(" and ":"
    std::vector<std::pair<std::string, std::string>> fields;  // key "" for a bare value
};
using GoldenPacket = std::vector<GoldenItem>;

std::vector<GoldenPacket> readGolden(const std::filesystem::path& p) {
    std::vector<GoldenPacket> packets(1);
    for (const auto& line : test::readLines(p)) {
        if (line.empty()) {
            if (!packets.back().empty()) packets.emplace_back();
        } else if (line.rfind("  ", 0) != 0) {
            GoldenItem item;
            item.name = line.substr(0, line.find_first_of("(:"));
            packets.back().push_back(item);
        } else {
            const std::string body = line.substr(2);
            const auto colon = body.find(':');
            // UTC time strings contain ':' but no key.
            if (colon == std::string::npos || packets.back().back().name == "UTCTime") {
                packets.back().back().fields.emplace_back("", body);
            } else {
                packets.back().back().fields.emplace_back(body.substr(0, colon),
                                                          body.substr(colon + 1));
            }
        }
    }
    if (packets.back().empty()) packets.pop_back();
    return packets;
}

std::string lower(std::string s) {
    for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Golden names -> XDI table names and component names.
std::string tableName(const std::string& golden) {
    static const std::map<std::string, std::string> kMap{{"UTCTime", "UtcTime"},
                                                         {"GNSSPVTData", "GnssPvtData"},
                                                         {"GNSSSatInfo", "GnssSatInfo"},
                                                         {"PositionECEF", "PositionEcef"}};
    auto it = kMap.find(golden);
    return it != kMap.end() ? it->second : golden;
}

std::string componentName(const std::string& item, const std::string& key) {
    if (item == "EulerAngles") {
        static const std::map<std::string, std::string> kEuler{
            {"X", "roll"}, {"Y", "pitch"}, {"Z", "yaw"}};
        return kEuler.at(key);
    }
    return lower(key);
}

std::string utcString(const MtData2Value& v) {
    auto f = [&](std::string_view n) {
        for (const auto& x : v.fields) {
            if (x.name == n) return static_cast<long long>(x.value);
        }
        return -1LL;
    };
    char buf[64];
    std::snprintf(buf, sizeof buf, "%04lld-%02lld-%02lldT%02lld:%02lld:%02lld", f("year"),
                  f("month"), f("day"), f("hour"), f("minute"), f("second"));
    std::string s = buf;
    long long ns = f("ns");
    if (ns != 0) {
        std::snprintf(buf, sizeof buf, ".%09lld", ns);
        std::string frac = buf;
        while (frac.back() == '0') frac.pop_back();
        s += frac;
    }
    return s + "Z";
}

std::string binary(std::uint64_t v, int bits) {
    std::string s;
    for (int i = bits - 1; i >= 0; --i) s.push_back(((v >> i) & 1) != 0 ? '1' : '0');
    return s;
}

std::vector<MtData2Packet> decodeCapture(const std::filesystem::path& dir) {
    XbusParser parser;
    parser.feed(test::readBytes(dir / "output.bin"));
    std::vector<MtData2Packet> packets;
    while (auto f = parser.next()) {
        EXPECT_EQ(f->mid, 0x36);
        auto p = decodeMtData2(f->payload);
        EXPECT_TRUE(p.isOk()) << p.status().message();
        if (p.isOk()) packets.push_back(std::move(*p));
    }
    return packets;
}

class MtData2Golden : public ::testing::TestWithParam<int> {};

TEST_P(MtData2Golden, DecodedValuesEqualTheGoldenValues) {
    const auto dir = test::xsensDataDir() / "mtig710" / std::to_string(GetParam());
    if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " absent";
    const auto packets = decodeCapture(dir);
    const auto golden = readGolden(dir / "output.golden");
    ASSERT_EQ(packets.size(), 100u);
    ASSERT_EQ(golden.size(), 100u);
    std::size_t compared = 0;
    for (std::size_t k = 0; k < golden.size(); ++k) {
        const MtData2Packet& p = packets[k];
        ASSERT_EQ(golden[k].size(), p.values.size()) << "packet " << k;
        for (const GoldenItem& g : golden[k]) {
            const std::string name = tableName(g.name);
            const MtData2Value* v = nullptr;
            for (const auto& x : p.values) {
                if (x.name() == name) v = &x;
            }
            ASSERT_NE(v, nullptr) << "packet " << k << ": " << name << " not decoded";
            ASSERT_TRUE(v->decoded()) << v->problem;
            SCOPED_TRACE("packet " + std::to_string(k) + " " + name);
            if (name == "UtcTime") {
                EXPECT_EQ(utcString(*v), g.fields.at(0).second);
            } else if (name == "StatusWord") {
                EXPECT_EQ(binary(static_cast<std::uint64_t>(v->fields.at(0).value), 32),
                          g.fields.at(0).second);
            } else if (name == "StatusByte") {
                EXPECT_EQ(binary(static_cast<std::uint64_t>(v->fields.at(0).value), 8),
                          g.fields.at(0).second);
            } else if (g.fields.size() == 1 && g.fields[0].first.empty()) {
                ASSERT_EQ(v->fields.size(), 1u);
                EXPECT_EQ(v->fields[0].value, std::stod(g.fields[0].second));
            } else {
                // The golden prints GnssSatInfo's header only; compare what it prints.
                for (const auto& [key, text] : g.fields) {
                    const std::string comp = componentName(name, key);
                    const XdiField* field = nullptr;
                    for (const auto& x : v->fields) {
                        if (x.name == comp && x.element < 0) field = &x;
                    }
                    ASSERT_NE(field, nullptr) << "component " << comp;
                    EXPECT_EQ(field->value, std::stod(text)) << comp;  // bit-exact
                    ++compared;
                }
            }
        }
    }
    EXPECT_GT(compared, 1000u);
}

INSTANTIATE_TEST_SUITE_P(MtiG710, MtData2Golden, ::testing::Values(1, 2, 3, 5));

TEST(MtData2Golden, CaptureFormatsAreWhatTheSourceSays) {
    const auto dir = test::xsensDataDir() / "mtig710";
    if (!std::filesystem::exists(dir)) GTEST_SKIP();
    const Precision expected[] = {Precision::kFloat32, Precision::kFp1220, Precision::kFp1632};
    for (int c = 1; c <= 3; ++c) {
        const auto packets = decodeCapture(dir / std::to_string(c));
        const auto* acc = packets.at(0).find(xdi::kAcceleration);
        ASSERT_NE(acc, nullptr);
        EXPECT_EQ(acc->precision(), expected[c - 1]);
        const auto* euler = packets.at(1).find(xdi::kEulerAngles);
        ASSERT_NE(euler, nullptr);
        EXPECT_EQ(euler->coordSys(), CoordSys::kEnu);
    }
}

// ---- MTi-300 (values printed by Xsens MT Manager) ----

struct Mti300Case {
    std::string name;
    std::vector<std::uint8_t> frame;
    std::vector<std::string> expects;
};

std::vector<Mti300Case> readMti300() {
    std::vector<Mti300Case> cases;
    for (const auto& line :
         test::readLines(test::xsensDataDir() / "mti300" / "xsens_mti300_packets.txt")) {
        if (line.rfind("name: ", 0) == 0) cases.push_back({line.substr(6), {}, {}});
        if (line.rfind("hex: ", 0) == 0) cases.back().frame = test::fromHex(line.substr(5));
        if (line.rfind("expect: ", 0) == 0) cases.back().expects.push_back(line.substr(8));
    }
    return cases;
}

std::vector<double> numbersIn(const std::string& s) {
    std::vector<double> out;
    std::string cleaned = s;
    for (auto& c : cleaned) {
        if (c == '{' || c == '}' || c == ',') c = ' ';
    }
    std::istringstream in(cleaned);
    for (double d; in >> d;) out.push_back(d);
    return out;
}

TEST(MtData2Mti300, EveryFrameChecksAndMatchesMtManager) {
    const auto file = test::xsensDataDir() / "mti300" / "xsens_mti300_packets.txt";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " absent";
    const auto cases = readMti300();
    ASSERT_EQ(cases.size(), 16u);
    int values_checked = 0;
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        auto frame = decodeFrame(c.frame);
        ASSERT_TRUE(frame.isOk()) << frame.status().message();
        if (frame->mid != 0x36) continue;
        auto packet = decodeMtData2(frame->payload);
        ASSERT_TRUE(packet.isOk()) << packet.status().message();
        for (const auto& v : packet->values) EXPECT_TRUE(v.decoded()) << v.problem;
        for (const std::string& e : c.expects) {
            // "float golden_acc[3] = { ... }" or "event[4].u4 = 101669"
            if (e.rfind("event[", 0) == 0) {
                const std::size_t index = std::stoul(e.substr(6));
                const double want = std::stod(e.substr(e.find('=') + 1));
                ASSERT_LT(index, packet->values.size());
                EXPECT_NEAR(packet->values[index].fields.at(0).value, want,
                            5e-8 * std::max(1.0, std::abs(want)))
                    << e;
                ++values_checked;
                continue;
            }
            const std::string var =
                e.substr(e.find("golden_") + 7, e.find('[') - e.find("golden_") - 7);
            const auto want = numbersIn(e.substr(e.find('=') + 1));
            static const std::map<std::string, std::uint16_t> kVar{
                {"quat", xdi::kQuaternion}, {"acc", xdi::kAcceleration},
                {"dv", xdi::kDeltaV},       {"fr_acc", xdi::kFreeAcceleration},
                {"dq", xdi::kDeltaQ},       {"mag", xdi::kMagneticField},
                {"pry", xdi::kEulerAngles}};
            const std::uint16_t type =
                var == "rot" ? (want.size() == 9 ? xdi::kRotationMatrix : xdi::kRateOfTurn)
                             : kVar.at(var);
            const MtData2Value* v = packet->find(type);
            ASSERT_NE(v, nullptr) << e;
            ASSERT_EQ(v->fields.size(), want.size()) << e;
            for (std::size_t i = 0; i < want.size(); ++i) {
                // MT Manager prints 8 decimals (at most 12 for fp16.32 / double).
                EXPECT_NEAR(v->fields[i].value, want[i], 6e-8 * std::max(1.0, std::abs(want[i])))
                    << e << " #" << i;
                ++values_checked;
            }
        }
    }
    EXPECT_GT(values_checked, 60);
}

TEST(MtData2Mti300, Fp1632AndDoubleDecodeToFullPrecision) {
    const auto file = test::xsensDataDir() / "mti300" / "xsens_mti300_packets.txt";
    if (!std::filesystem::exists(file)) GTEST_SKIP();
    for (const auto& c : readMti300()) {
        if (c.name != "test_parse_mdata2_number_formats") continue;
        auto frame = decodeFrame(c.frame);
        ASSERT_TRUE(frame.isOk());
        auto p = decodeMtData2(frame->payload);
        ASSERT_TRUE(p.isOk());
        const auto dq = p->vector4(xdi::kDeltaQ);
        ASSERT_TRUE(dq.has_value());
        EXPECT_EQ(p->find(xdi::kDeltaQ)->precision(), Precision::kFp1632);
        // MT Manager printed 12 decimals for fp16.32.
        EXPECT_NEAR((*dq)[0], 1.000000000233, 1e-12);
        EXPECT_NEAR((*dq)[1], -0.000429107808, 1e-12);
        const auto mag = p->vector3(xdi::kMagneticField);
        ASSERT_TRUE(mag.has_value());
        EXPECT_NEAR((*mag)[0], 0.833747744560242, 1e-15);
        EXPECT_EQ(p->find(xdi::kEulerAngles)->precision(), Precision::kFp1220);
        EXPECT_EQ(p->scalar(xdi::kTemperature), 27.4375);
        return;
    }
    FAIL() << "number-formats frame missing";
}

}  // namespace
}  // namespace handscan::xsens
