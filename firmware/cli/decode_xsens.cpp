// `handscan decode --device xsens FILE`: Xbus byte stream (serial capture, or a recording's
// /xsens/raw channel) as JSON lines, every MTData2 item named as in Xsens' XDI table, SI units.
#include "decoder_registry.hpp"
#include "handscan/xsens/xsens_json.hpp"

namespace handscan::cli {
namespace {

class XsensDecoder : public StreamDecoder {
public:
    void feed(TimeNs t_host, std::span<const std::uint8_t> bytes, std::ostream& jsonl) override {
        decoder_.feed(t_host, bytes, jsonl);
    }
    DecodeSummary finish(std::ostream& /*jsonl*/) override {
        const auto s = decoder_.summary();
        return {s.messages, s.checksum_failures, s.resyncs, s.gaps};
    }

private:
    xsens::XsensJsonDecoder decoder_;
};

const RegisterDecoder kXsens{"xsens", "/xsens/raw",
                             [] { return std::make_unique<XsensDecoder>(); }};

}  // namespace
}  // namespace handscan::cli
