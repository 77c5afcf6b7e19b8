// libFuzzer target: arbitrary bytes, cut into arbitrary chunks, through the Xbus parser, the
// MTData2 decoder, the control-message decoders and the JSON writer. Invariants: no crash, no
// hang, the parser's buffer stays bounded, and every frame it hands out re-encodes to a frame
// that decodes to the same message.
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <span>
#include <streambuf>

#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_messages.hpp"
#include "handscan/xsens/xbus_parser.hpp"
#include "handscan/xsens/xsens_json.hpp"

namespace {

struct NullBuffer : std::streambuf {
    int overflow(int c) override { return c; }
};

void check(bool ok) {
    if (!ok) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace handscan::xsens;
    if (size == 0) return 0;
    // The first byte picks the chunk size, so splits land everywhere.
    const std::size_t chunk = 1 + data[0] % 64;
    const std::span<const std::uint8_t> bytes(data + 1, size - 1);
    NullBuffer null_buffer;
    std::ostream null_out(&null_buffer);

    XbusParser parser;
    XsensJsonDecoder json;
    for (std::size_t off = 0; off < bytes.size(); off += chunk) {
        const auto piece = bytes.subspan(off, std::min(chunk, bytes.size() - off));
        json.feed(0, piece, null_out);
        parser.feed(piece);
        while (auto f = parser.next()) {
            const auto frame = encodeFrame(f->mid, f->payload, f->bus_id);
            auto again = decodeFrame(frame);
            check(again.isOk() && again->mid == f->mid &&
                  again->payload.size() == f->payload.size());
            if (f->mid == toByte(MessageId::kMtData2)) {
                auto packet = decodeMtData2(f->payload);
                check(packet.isOk());  // the parser only hands out MTData2 whose items tile
                for (const auto& v : packet->values) writeItemJson(v, null_out);
            }
            (void)decodeError(f->payload);
            (void)decodeOutputConfiguration(f->payload);
            (void)decodeDeviceId(f->payload);
            (void)decodeProductCode(f->payload);
        }
        // At most one incomplete frame plus the chunk is ever held.
        check(parser.pending() <= kMaxPayload + 7 + chunk);
    }
    // MTData2 decoding of the raw bytes as a payload, too.
    (void)decodeMtData2(bytes);
    return 0;
}
