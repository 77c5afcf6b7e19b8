#include "handscan/xsens_fake/fake_xsens.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "handscan/xsens/mtdata2.hpp"

namespace handscan::xsens {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

bool supported(std::uint16_t xdi) {
    switch (xdiTypeOf(xdi)) {
        case xdi::kPacketCounter:
        case xdi::kSampleTimeFine:
        case xdi::kSampleTimeCoarse:
        case xdi::kAcceleration:
        case xdi::kFreeAcceleration:
        case xdi::kRateOfTurn:
        case xdi::kDeltaQ:
        case xdi::kDeltaV:
        case xdi::kQuaternion:
        case xdi::kMagneticField:
        case xdi::kTemperature:
        case xdi::kStatusWord:
        case xdi::kStatusByte:
            return true;
        default:
            return false;
    }
}

}  // namespace

FakeXsens::FakeXsens(FakeXsensConfig config, FakeXsensFaults faults)
    : cfg_(std::move(config)),
      faults_(std::move(faults)),
      rate_hz_(cfg_.default_rate_hz),
      baud_(cfg_.baudrate),
      measuring_(cfg_.streaming_at_start),
      counter_(cfg_.first_packet_counter),
      sample_time_fine_(cfg_.first_sample_time_fine) {
    outputs_ = {{xdi::kPacketCounter, kEveryPacket},
                {xdi::kSampleTimeFine, kEveryPacket},
                {xdi::kAcceleration, rate_hz_},
                {xdi::kRateOfTurn, rate_hz_},
                {xdi::kStatusWord, kEveryPacket}};
}

Eigen::Vector3d FakeXsens::accelAt(double t) {
    return {0.3 * std::sin(kTwoPi * 0.5 * t), 0.2 * std::cos(kTwoPi * 0.3 * t),
            9.81 + 0.05 * std::sin(kTwoPi * t)};
}

Eigen::Vector3d FakeXsens::gyroAt(double t) {
    return {0.5 * std::sin(kTwoPi * 0.25 * t), -0.2 * std::cos(kTwoPi * 0.4 * t),
            1.5 * std::sin(kTwoPi * 0.1 * t)};
}

void FakeXsens::receive(std::span<const std::uint8_t> bytes) {
    parser_.feed(bytes);
    while (auto f = parser_.next()) {
        const std::vector<std::uint8_t> payload(f->payload.begin(), f->payload.end());
        handle(f->mid, payload);
    }
}

void FakeXsens::reply(MessageId mid, std::span<const std::uint8_t> payload) {
    const auto frame = encodeFrame(mid, payload);
    output_.insert(output_.end(), frame.begin(), frame.end());
}

bool FakeXsens::refuse(std::uint8_t mid) {
    auto it = faults_.error_replies.find(mid);
    if (it == faults_.error_replies.end() || it->second <= 0) return false;
    --it->second;
    const auto frame = encodeErrorFrame(faults_.error_code);
    output_.insert(output_.end(), frame.begin(), frame.end());
    return true;
}

void FakeXsens::handle(std::uint8_t mid, std::span<const std::uint8_t> payload) {
    requests_.push_back(mid);
    if (refuse(mid)) return;
    const auto error = [this](ErrorCode code) {
        const auto frame = encodeErrorFrame(code);
        output_.insert(output_.end(), frame.begin(), frame.end());
    };
    if (awaiting_wakeup_ack_ &&
        (mid == toByte(MessageId::kWakeUpAck) || mid == toByte(MessageId::kGoToConfig))) {
        awaiting_wakeup_ack_ = false;  // the host caught the device: it stays in config mode
        measuring_ = false;
        if (mid == toByte(MessageId::kWakeUpAck)) return;
    }
    switch (static_cast<MessageId>(mid)) {
        case MessageId::kGoToConfig:
            if (goto_configs_ignored_ < cfg_.ignore_first_goto_configs) {
                ++goto_configs_ignored_;
                return;
            }
            measuring_ = false;
            reply(MessageId::kGoToConfigAck);
            return;
        case MessageId::kGoToMeasurement:
            measuring_ = true;
            ++epoch_;
            reply(MessageId::kGoToMeasurementAck);
            return;
        case MessageId::kReqDid:
            reply(MessageId::kDeviceId, encodeDeviceId(cfg_.device_id));
            return;
        case MessageId::kReqProductCode:
            if (measuring_) return error(ErrorCode::kInvalidMessage);
            reply(MessageId::kProductCode, encodeProductCode(cfg_.product_code));
            return;
        case MessageId::kWakeUp:
            reply(MessageId::kWakeUpAck);
            return;
        case MessageId::kWakeUpAck:
            return;  // late (the device was caught by GoToConfig already)
        case MessageId::kReset:
            reply(MessageId::kResetAck);
            switch_after_take_ = true;  // reboot once the ack is on the wire
            return;
        case MessageId::kSetBaudrate: {
            if (measuring_) return error(ErrorCode::kInvalidMessage);
            if (payload.empty()) {  // a request for the current rate
                const std::uint8_t id = *baudrateId(baud_);
                reply(MessageId::kSetBaudrateAck, std::span(&id, 1));
                return;
            }
            auto baud = baudrateFromId(payload[0]);
            if (!baud) return error(ErrorCode::kInvalidBaudrate);
            pending_baud_ = *baud;  // takes effect at the next reset, as on a real MTi
            reply(MessageId::kSetBaudrateAck);
            return;
        }
        case MessageId::kSetOutputConfiguration: {
            if (measuring_) return error(ErrorCode::kInvalidMessage);
            auto entries = decodeOutputConfiguration(payload);
            if (!entries) return error(ErrorCode::kInvalidParameter);
            if (entries->empty()) {  // a request for the current configuration
                reply(MessageId::kSetOutputConfigurationAck, encodeOutputConfiguration(outputs_));
                return;
            }
            std::uint16_t rate = 0;
            for (const auto& e : *entries) {
                if (!supported(e.xdi)) return error(ErrorCode::kInvalidParameter);
                if (e.rate_hz == kEveryPacket || e.rate_hz == 0) continue;
                if (e.rate_hz > 400 || 400 % e.rate_hz != 0)
                    return error(ErrorCode::kInvalidPeriod);
                rate = std::max(rate, e.rate_hz);
            }
            outputs_ = *entries;
            rate_hz_ = rate != 0 ? rate : cfg_.default_rate_hz;
            reply(MessageId::kSetOutputConfigurationAck, encodeOutputConfiguration(outputs_));
            return;
        }
        default:
            error(ErrorCode::kInvalidMessage);
            return;
    }
}

void FakeXsens::powerCycle() {
    parser_.reset();
    measuring_ = false;
    awaiting_wakeup_ack_ = true;
    counter_ = 0;
    sample_time_fine_ = 0;
    reply(MessageId::kWakeUp);
}

bool FakeXsens::emitPacket() {
    if (awaiting_wakeup_ack_) {
        // No WakeUpAck in time: measure with the stored configuration.
        awaiting_wakeup_ack_ = false;
        measuring_ = true;
        ++epoch_;
    }
    if (!measuring_) return false;
    StreamedPacket p;
    p.index = next_index_++;
    p.epoch = epoch_;
    p.packet_counter = counter_++;
    p.sample_time_fine = sample_time_fine_;
    sample_time_fine_ += 10000u / rate_hz_;
    const double t = static_cast<double>(p.index) / rate_hz_;
    const double dt = 1.0 / rate_hz_;
    p.accel_mps2 = cfg_.stationary ? Eigen::Vector3d(0.0, 0.0, 9.81) : accelAt(t);
    p.gyro_radps = cfg_.stationary ? Eigen::Vector3d::Zero() : gyroAt(t);
    p.status_word = 0x00000003;  // self-test ok, filter valid
    MtData2Builder b;
    for (const auto& e : outputs_) {
        const Precision prec = precisionOf(e.xdi);
        switch (xdiTypeOf(e.xdi)) {
            case xdi::kPacketCounter:
                b.packetCounter(p.packet_counter);
                break;
            case xdi::kSampleTimeFine:
                b.sampleTimeFine(p.sample_time_fine);
                break;
            case xdi::kSampleTimeCoarse:
                b.sampleTimeCoarse(p.sample_time_fine / 10000u);
                break;
            case xdi::kAcceleration:
                b.acceleration(p.accel_mps2, prec);
                break;
            case xdi::kFreeAcceleration:
                b.freeAcceleration(p.accel_mps2 - Eigen::Vector3d(0, 0, 9.81), prec);
                break;
            case xdi::kRateOfTurn:
                b.rateOfTurn(p.gyro_radps, prec);
                break;
            case xdi::kDeltaV:
                b.deltaV(p.accel_mps2 * dt, prec);
                break;
            case xdi::kDeltaQ: {
                // The rotation over one sample interval as a unit quaternion.
                const Eigen::Vector3d half = p.gyro_radps * dt / 2.0;
                const double angle = half.norm();
                const Eigen::Vector3d axis =
                    angle > 0 ? Eigen::Vector3d(half / angle) : Eigen::Vector3d::UnitX();
                const Eigen::Vector3d v = std::sin(angle) * axis;
                b.deltaQ(Eigen::Vector4d(std::cos(angle), v.x(), v.y(), v.z()), prec);
                break;
            }
            case xdi::kQuaternion:
                b.quaternion(Eigen::Vector4d(1, 0, 0, 0), prec, coordSysOf(e.xdi));
                break;
            case xdi::kMagneticField:
                b.magneticField(Eigen::Vector3d(0.4, 0.1, -0.9), prec);
                break;
            case xdi::kTemperature:
                b.temperature(31.5, prec);
                break;
            case xdi::kStatusWord:
                b.statusWord(p.status_word);
                break;
            case xdi::kStatusByte:
                b.statusByte(static_cast<std::uint8_t>(p.status_word));
                break;
            default:
                break;
        }
    }
    std::vector<std::uint8_t> frame = b.frame();
    if (faults_.drop_byte_in_packet.count(p.index) != 0) {
        frame.erase(frame.begin() + static_cast<std::ptrdiff_t>(frame.size() / 2));
        p.damaged = true;
    }
    if (faults_.corrupt_checksum_in_packet.count(p.index) != 0) {
        frame.back() ^= 0x01;
        p.damaged = true;
    }
    output_.insert(output_.end(), frame.begin(), frame.end());
    if (faults_.error_after_packet.count(p.index) != 0) {
        const auto err = encodeErrorFrame(faults_.error_code);
        output_.insert(output_.end(), err.begin(), err.end());
    }
    streamed_.push_back(p);
    return true;
}

std::vector<std::uint8_t> FakeXsens::takeOutput() {
    std::vector<std::uint8_t> out;
    out.swap(output_);
    if (switch_after_take_) {
        switch_after_take_ = false;
        if (pending_baud_ != 0) baud_ = pending_baud_;
        pending_baud_ = 0;
        powerCycle();
    }
    return out;
}

void FakeXsens::garble(std::vector<std::uint8_t>& bytes) {
    // A receiver at the wrong rate samples bit soup; keep it deterministic and free of preambles.
    for (auto& b : bytes) {
        const auto g = static_cast<std::uint8_t>(b * 7 + 3);
        b = g == kPreamble ? 0x00 : g;
    }
}

}  // namespace handscan::xsens
