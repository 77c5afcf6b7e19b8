// Golden tests on real CANopen traces (../shared/data/can, see SOURCE.txt there): every line
// parses, formats back byte for byte, and the CANopen content decodes to the values the
// trace's authors describe.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"

namespace handscan::motor {
namespace {

std::vector<std::string> readLines(const std::filesystem::path& p) {
    std::vector<std::string> lines;
    std::ifstream in(p);
    for (std::string l; std::getline(in, l);) {
        if (!l.empty()) lines.push_back(l);
    }
    return lines;
}

const std::filesystem::path kCanDir = std::filesystem::path(HANDSCAN_SHARED_DATA_DIR) / "can";

TEST(RealCanTrace, Ros2CanopenCiA402BringUp) {
    const auto path = kCanDir / "ros2_canopen_issue331_candump-L.log";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not present";
    const auto lines = readLines(path);
    ASSERT_EQ(lines.size(), 28u);
    std::vector<CandumpRecord> recs;
    for (const auto& l : lines) {
        auto r = parseCandumpLogLine(l);
        ASSERT_TRUE(r) << l << ": " << r.status().message();
        EXPECT_EQ(formatCandumpLogLine(*r), l);
        recs.push_back(*r);
    }
    EXPECT_EQ(recs.front().timeNs(), 1730301035277560000LL);

    int boot_ups = 0;
    std::vector<std::uint16_t> controlwords;
    std::uint32_t device_type = 0, vendor = 0, target_velocity = 0;
    int mode = -1, mode_display = -1;
    std::uint16_t statusword = 0;
    std::vector<NmtMessage> nmt;
    for (const auto& rec : recs) {
        const CobIdInfo info = classifyCobId(rec.frame);
        switch (info.function) {
            case CanOpenFunction::kHeartbeat: {
                auto hb = decodeHeartbeat(rec.frame);
                ASSERT_TRUE(hb);
                boot_ups += hb->state == NmtState::kBootUp;
                break;
            }
            case CanOpenFunction::kNmt: {
                auto m = decodeNmt(rec.frame);
                ASSERT_TRUE(m);
                nmt.push_back(*m);
                break;
            }
            case CanOpenFunction::kSdoRequest:
            case CanOpenFunction::kSdoResponse: {
                auto sdo = decodeSdo(rec.frame);
                ASSERT_TRUE(sdo) << sdo.status().message();
                if (sdo->kind == SdoKind::kDownloadRequest && sdo->index == od::kControlword)
                    controlwords.push_back(static_cast<std::uint16_t>(sdo->value));
                if (sdo->kind == SdoKind::kDownloadRequest && sdo->index == od::kModesOfOperation)
                    mode = static_cast<int>(sdo->value);
                if (sdo->kind == SdoKind::kDownloadRequest && sdo->index == od::kTargetVelocity)
                    target_velocity = sdo->value;
                if (sdo->kind == SdoKind::kUploadResponse && sdo->index == od::kDeviceType)
                    device_type = sdo->value;
                if (sdo->kind == SdoKind::kUploadResponse && sdo->index == od::kIdentity &&
                    sdo->subindex == 1)
                    vendor = sdo->value;
                if (sdo->kind == SdoKind::kUploadResponse &&
                    sdo->index == od::kModesOfOperationDisplay)
                    mode_display = static_cast<int>(sdo->value);
                break;
            }
            case CanOpenFunction::kTpdo:
                ASSERT_EQ(rec.frame.len, 2);
                statusword =
                    static_cast<std::uint16_t>(rec.frame.data[0] | (rec.frame.data[1] << 8));
                break;
            default:
                ADD_FAILURE() << "unexpected frame " << formatCanFrameText(rec.frame);
        }
    }
    EXPECT_EQ(boot_ups, 6);
    ASSERT_EQ(nmt.size(), 2u);
    EXPECT_EQ(nmt[0].command, NmtCommand::kResetCommunication);
    EXPECT_EQ(nmt[0].node, 0);
    EXPECT_EQ(nmt[1].command, NmtCommand::kStart);
    EXPECT_EQ(nmt[1].node, 3);
    EXPECT_EQ(device_type, 0x00020192u);  // profile 0x0192 = 402
    EXPECT_EQ(device_type & 0xFFFF, 402u);
    EXPECT_EQ(vendor, 0x9Au);
    EXPECT_EQ(controlwords, (std::vector<std::uint16_t>{0x0006, 0x0007, 0x000F, 0x7364}));
    EXPECT_EQ(mode, kModeProfileVelocity);
    EXPECT_EQ(mode_display, kModeProfileVelocity);
    EXPECT_EQ(target_velocity, 2000u);
    EXPECT_EQ(statusword, 0x0237);
    EXPECT_EQ(cia402StateFromStatusword(statusword), Cia402State::kOperationEnabled);
}

TEST(RealCanTrace, RosCanopenSdoPollingDefaultFormat) {
    const auto path = kCanDir / "ros_canopen_issue380_candump.txt";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not present";
    const auto lines = readLines(path);
    ASSERT_EQ(lines.size(), 30u);
    int syncs = 0, reads = 0, responses = 0;
    std::vector<std::uint32_t> torques;
    for (const auto& l : lines) {
        auto r = parseCandumpDefaultLine(l);
        ASSERT_TRUE(r) << l << ": " << r.status().message();
        EXPECT_EQ(formatCandumpDefaultLine(*r), l);
        const CobIdInfo info = classifyCobId(r->frame);
        if (info.function == CanOpenFunction::kSync) {
            ASSERT_TRUE(decodeSync(r->frame));
            ++syncs;
            continue;
        }
        auto sdo = decodeSdo(r->frame);
        ASSERT_TRUE(sdo) << l;
        EXPECT_EQ(sdo->node, 9);
        if (sdo->kind == SdoKind::kUploadRequest) ++reads;
        if (sdo->kind == SdoKind::kUploadResponse) {
            ++responses;
            if (sdo->index == od::kTorqueActual) {
                EXPECT_EQ(sdo->size, 2);
                torques.push_back(sdo->value);
            }
            if (sdo->index == od::kVelocityActual) {
                EXPECT_EQ(sdo->size, 4);
            }
            if (sdo->index == od::kErrorRegister) {
                EXPECT_EQ(sdo->size, 1);
                EXPECT_EQ(sdo->value, 0u);
            }
        }
    }
    EXPECT_EQ(syncs, 6);
    EXPECT_EQ(reads, 12);
    EXPECT_EQ(responses, 12);
    EXPECT_EQ(torques, (std::vector<std::uint32_t>{0, 0, 0, 1, 0, 0}));
}

}  // namespace
}  // namespace handscan::motor
