// Fuzzes the candump parsers (both formats), the CANopen decoders and, through the candump-log
// transport, the motor state machine: no crash, no hang, no unbounded memory on any input; and
// every line that parses formats back to a line that parses to the same frame.
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>

#include "handscan/core/log.hpp"
#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"
#include "handscan/motor/motor_device.hpp"
#include "handscan/motor/virtual_can_buses.hpp"

using namespace handscan;
using namespace handscan::motor;

namespace {

void decodeAll(const CanFrame& f) {
    (void)classifyCobId(f);
    (void)decodeNmt(f);
    (void)decodeHeartbeat(f);
    (void)decodeSync(f);
    (void)decodeEmergency(f);
    if (auto s = decodeSdo(f)) (void)sdoAbortText(s->value);
    (void)decodeEncoderPositionTpdo(f);
}

void checkLine(std::string_view line) {
    auto any = parseCandumpAnyLine(line);
    if (!any) return;
    decodeAll(any->frame);
    // Round trip through the log format.
    CandumpRecord rec = *any;
    if (!rec.has_time) rec.setTimeNs(0);
    const std::string text = formatCandumpLogLine(rec);
    auto again = parseCandumpLogLine(text);
    if (!again || !(again->frame == rec.frame)) std::abort();
    const std::string screen = formatCandumpDefaultLine(rec);
    auto back = parseCandumpDefaultLine(screen);
    if (back && !rec.frame.fd && back->frame.payload().size() != rec.frame.payload().size())
        std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    handscan::log().set_level(spdlog::level::off);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t nl = text.find('\n', start);
        checkLine(
            text.substr(start, nl == std::string_view::npos ? std::string_view::npos : nl - start));
        if (nl == std::string_view::npos) break;
        start = nl + 1;
    }
    // The whole input as a recorded bus, replayed through the driver (bounded: one frame per poll,
    // and at most one poll per input byte).
    CandumpLogBus bus(std::make_unique<std::istringstream>(std::string(text)), nullptr, "fuzz");
    handscan::motor::MotorConfig cfg;
    cfg.boot_timeout = 50 * kNsPerMs;
    cfg.sdo_retries = 0;
    MotorDevice dev(bus, cfg, [&] { return bus.now(); });
    if (dev.start()) {
        for (std::size_t i = 0; i < size; ++i) {
            auto r = dev.poll(kNsPerMs);
            if (!r) break;
        }
    }
    return 0;
}
