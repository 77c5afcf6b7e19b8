// CANopen byte vectors (CiA 301 / 402 / 406), checked against the values PROTOCOLS.md quotes.
#include "handscan/motor/canopen.hpp"

#include <gtest/gtest.h>

#include "handscan/motor/candump_format.hpp"

namespace handscan::motor {
namespace {

std::string text(const CanFrame& f) { return formatCanFrameText(f); }
CanFrame parse(const char* s) {
    auto r = parseCanFrameText(s);
    EXPECT_TRUE(r) << s;
    return r ? *r : CanFrame{};
}

TEST(CanOpen, EncodesTheTypicalEncoderBringUp) {
    EXPECT_EQ(text(encodeSdoWrite(1, od::kEncoderCyclicTimer, 0, 10, 2)), "601#2B0062000A000000");
    EXPECT_EQ(text(encodeSdoWrite(1, od::kTpdo1Communication, 2, 0xFE, 1)), "601#2F001802FE000000");
    EXPECT_EQ(text(encodeSdoWrite(3, od::kTargetVelocity, 0, 2000, 4)), "603#23FF6000D0070000");
    EXPECT_EQ(text(encodeNmt(NmtCommand::kStart, 1)), "000#0101");
    EXPECT_EQ(text(encodeNmt(NmtCommand::kResetCommunication, 0)), "000#8200");
    EXPECT_EQ(text(encodeHeartbeat(1, NmtState::kBootUp)), "701#00");
    EXPECT_EQ(text(encodeHeartbeat(1, NmtState::kOperational)), "701#05");
    EXPECT_EQ(text(encodeHeartbeat(0x7F, NmtState::kPreOperational)), "77F#7F");
    EXPECT_EQ(text(encodeSdoWriteAck(1, od::kEncoderCyclicTimer, 0)), "581#6000620000000000");
    EXPECT_EQ(text(encodeSdoRead(9, od::kTorqueActual, 0)), "609#4077600000000000");
    EXPECT_EQ(text(encodeSdoReadResponse(9, od::kErrorRegister, 0, 0, 1)), "589#4F01100000000000");
    EXPECT_EQ(text(encodeSdoReadResponse(9, od::kVelocityActual, 0, 0, 4)), "589#436C600000000000");
    EXPECT_EQ(text(encodeSdoReadResponse(9, od::kTorqueActual, 0, 0x10000, 2)),
              "589#4B77600000000000");
    EXPECT_EQ(text(encodeSdoAbort(1, 0x6004, 0, 0x06010002, true)), "581#8004600002000106");
    EXPECT_EQ(text(encodeEncoderPositionTpdo(1, 0x12345678)), "181#78563412");
    EXPECT_EQ(text(encodeSync()), "080#");
    EXPECT_EQ(text(encodeSync(7)), "080#07");
    EXPECT_EQ(text(encodeEmergency({1, 0x8130, 0x11, {1, 2, 3, 4, 5}})), "081#3081110102030405");
    EXPECT_EQ(text(encodeDriveVelocityRpdo(1, 3, controlword::kEnableOperation, -2000)),
              "203#0F0030F8FFFF");
}

TEST(CanOpen, DecodesSdoCommandsBothWays) {
    auto w = decodeSdo(parse("601#2B0062000A000000"));
    ASSERT_TRUE(w);
    EXPECT_EQ(w->kind, SdoKind::kDownloadRequest);
    EXPECT_FALSE(w->from_server);
    EXPECT_EQ(w->node, 1);
    EXPECT_EQ(w->index, 0x6200);
    EXPECT_EQ(w->subindex, 0);
    EXPECT_EQ(w->size, 2);
    EXPECT_EQ(w->value, 10u);

    auto ack = decodeSdo(parse("583#6040600000000000"));
    ASSERT_TRUE(ack);
    EXPECT_EQ(ack->kind, SdoKind::kDownloadResponse);
    EXPECT_TRUE(ack->from_server);
    EXPECT_EQ(ack->index, 0x6040);

    // 0x42: expedited upload response without size: 4 bytes.
    auto up = decodeSdo(parse("583#4200100092010200"));
    ASSERT_TRUE(up);
    EXPECT_EQ(up->kind, SdoKind::kUploadResponse);
    EXPECT_EQ(up->size, 0);
    EXPECT_EQ(up->value, 0x00020192u);

    auto one = decodeSdo(parse("589#4F01100000FFFFFF"));
    ASSERT_TRUE(one);
    EXPECT_EQ(one->size, 1);
    EXPECT_EQ(one->value, 0u) << "bytes beyond the indicated size are not data";

    auto abort = decodeSdo(parse("581#8004600002000106"));
    ASSERT_TRUE(abort);
    EXPECT_EQ(abort->kind, SdoKind::kAbort);
    EXPECT_EQ(abort->value, 0x06010002u);
    EXPECT_STREQ(sdoAbortText(abort->value), "attempt to write a read-only object");

    auto seg = decodeSdo(parse("581#4100100004000000"));
    ASSERT_TRUE(seg);
    EXPECT_EQ(seg->kind, SdoKind::kSegmented);

    EXPECT_FALSE(decodeSdo(parse("581#60006200")));          // short
    EXPECT_FALSE(decodeSdo(parse("181#6000620000000000")));  // not an SDO id
}

TEST(CanOpen, DecodesNmtHeartbeatEmcySync) {
    auto nmt = decodeNmt(parse("000#0103"));
    ASSERT_TRUE(nmt);
    EXPECT_EQ(nmt->command, NmtCommand::kStart);
    EXPECT_EQ(nmt->node, 3);
    EXPECT_FALSE(decodeNmt(parse("000#0903")));
    EXPECT_FALSE(decodeNmt(parse("000#01")));

    auto hb = decodeHeartbeat(parse("705#7F"));
    ASSERT_TRUE(hb);
    EXPECT_EQ(hb->node, 5);
    EXPECT_EQ(hb->state, NmtState::kPreOperational);
    EXPECT_FALSE(decodeHeartbeat(parse("705#33")));
    EXPECT_FALSE(decodeHeartbeat(parse("700#05")));

    auto emcy = decodeEmergency(parse("081#3081110102030405"));
    ASSERT_TRUE(emcy);
    EXPECT_EQ(emcy->node, 1);
    EXPECT_EQ(emcy->error_code, 0x8130);
    EXPECT_EQ(emcy->error_register, 0x11);
    EXPECT_EQ(emcy->vendor[4], 5);

    auto sync = decodeSync(parse("080#"));
    ASSERT_TRUE(sync);
    EXPECT_FALSE(sync->has_value());
}

TEST(CanOpen, ClassifiesCobIds) {
    EXPECT_EQ(classifyCobId(parse("183#3702")).function, CanOpenFunction::kTpdo);
    EXPECT_EQ(classifyCobId(parse("183#3702")).pdo, 1);
    EXPECT_EQ(classifyCobId(parse("381#00")).pdo, 3);
    EXPECT_EQ(classifyCobId(parse("481#00")).pdo, 4);
    EXPECT_EQ(classifyCobId(parse("481#00")).function, CanOpenFunction::kTpdo);
    EXPECT_EQ(classifyCobId(parse("503#00")).function, CanOpenFunction::kRpdo);
    EXPECT_EQ(classifyCobId(parse("503#00")).pdo, 4);
    EXPECT_EQ(classifyCobId(parse("734#00")).node, 0x34);
    EXPECT_EQ(classifyCobId(parse("12345678#00")).function, CanOpenFunction::kUnknown);
}

TEST(CanOpen, DecodesEncoderPosition) {
    auto p = decodeEncoderPositionTpdo(parse("181#FFFFFFFF"));
    ASSERT_TRUE(p);
    EXPECT_EQ(*p, 0xFFFFFFFFu);
    EXPECT_FALSE(decodeEncoderPositionTpdo(parse("181#FFFF")));
    EXPECT_FALSE(decodeEncoderPositionTpdo(parse("281#FFFFFFFF")));
}

TEST(Cia402, DecodesStatewordStates) {
    EXPECT_EQ(cia402StateFromStatusword(0x0237), Cia402State::kOperationEnabled);
    EXPECT_EQ(cia402StateFromStatusword(0x0250), Cia402State::kSwitchOnDisabled);
    EXPECT_EQ(cia402StateFromStatusword(0x0231), Cia402State::kReadyToSwitchOn);
    EXPECT_EQ(cia402StateFromStatusword(0x0233), Cia402State::kSwitchedOn);
    EXPECT_EQ(cia402StateFromStatusword(0x0217), Cia402State::kQuickStopActive);
    EXPECT_EQ(cia402StateFromStatusword(0x0208), Cia402State::kFault);
    EXPECT_EQ(cia402StateFromStatusword(0x020F), Cia402State::kFaultReactionActive);
    EXPECT_EQ(cia402StateFromStatusword(0x0000), Cia402State::kNotReadyToSwitchOn);
    EXPECT_EQ(controlwordTowardsOperationEnabled(Cia402State::kSwitchOnDisabled),
              controlword::kShutdown);
    EXPECT_EQ(controlwordTowardsOperationEnabled(Cia402State::kReadyToSwitchOn),
              controlword::kSwitchOn);
    EXPECT_EQ(controlwordTowardsOperationEnabled(Cia402State::kSwitchedOn),
              controlword::kEnableOperation);
    EXPECT_EQ(controlwordTowardsOperationEnabled(Cia402State::kFault), controlword::kFaultReset);
    EXPECT_FALSE(controlwordTowardsOperationEnabled(Cia402State::kOperationEnabled));
}

}  // namespace
}  // namespace handscan::motor
