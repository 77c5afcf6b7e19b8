#include "handscan/sim/hokuyo_stream.hpp"

#include <algorithm>
#include <cmath>

#include "handscan/hokuyo/scip_codec.hpp"

namespace handscan::sim {

using hokuyo::ScanEncoding;
using hokuyo::ScanPayload;
using hokuyo::ScanRequest;

namespace {

ScanRequest meRequest(const LaserConfig& laser) {
    ScanRequest r;
    r.mode = 'M';
    r.encoding = ScanEncoding::kThreeCharWithIntensity;
    r.start_step = 0;
    r.end_step = laser.steps - 1;
    r.cluster = 1;
    r.interval = 0;
    r.count = 0;
    return r;
}

}  // namespace

HokuyoStream::HokuyoStream(const HokuyoStreamConfig& config, const LaserConfig& laser,
                           TimeNs host_start_ns, Rng rng)
    : cfg_(config), laser_(laser), host_start_(host_start_ns), rng_(rng) {}

std::uint32_t HokuyoStream::timestampMs(double t) const {
    const double ms = std::floor(cfg_.clock.deviceSeconds(t) * 1000.0);
    return static_cast<std::uint32_t>(static_cast<std::uint64_t>(ms) & 0xFFFFFFu);
}

void HokuyoStream::deliver(double t_send, const std::string& bytes,
                           std::vector<StreamMessage>& out) {
    // Segments serialise on the link one after another, then wait for the reader to wake up.
    double t = std::max(t_send, link_free_at_);
    std::vector<std::pair<double, std::size_t>> segments;  // arrival time, end offset
    for (std::size_t off = 0; off < bytes.size();) {
        const std::size_t n = std::min(cfg_.mss_bytes, bytes.size() - off);
        t += static_cast<double>(n + 66) * 8.0 / cfg_.link_bps;  // + Ethernet/IP/TCP headers
        off += n;
        segments.emplace_back(t + cfg_.clock.latency_s, off);
    }
    link_free_at_ = t;
    std::size_t begin = 0, k = 0;
    while (k < segments.size()) {
        const double wake = segments[k].first + cfg_.clock.delay(rng_) - cfg_.clock.latency_s;
        const double read_at = wake - cfg_.reader_wakeup_s * std::log(1.0 - rng_.uniform());
        while (k + 1 < segments.size() && segments[k + 1].first <= read_at) ++k;
        const std::size_t end = segments[k].second;
        StreamMessage m;
        m.t_host_rx = hostNs(host_start_, read_at);
        m.channel = SimChannel::kHokuyo;
        m.bytes.assign(bytes.begin() + static_cast<long>(begin),
                       bytes.begin() + static_cast<long>(end));
        out.push_back(std::move(m));
        begin = end;
        ++k;
    }
}

void HokuyoStream::handshake(double t, std::vector<StreamMessage>& out) {
    const std::string time4 = hokuyo::encodeScipChars(timestampMs(t), 4);
    const std::vector<std::string> replies = {
        hokuyo::encodeReply("SCIP2.0", "0E"),  // the UTM-30LX boots in SCIP 2.0 already
        hokuyo::encodeKeyValueReply("VV", "00",
                                    {{"VEND", "Hokuyo Automatic Co.,Ltd."},
                                     {"PROD", "SOKUIKI Sensor TOP-URG UTM-30LX-EW"},
                                     {"FIRM", "1.1.0(2012-12-06)"},
                                     {"PROT", "SCIP 2.0"},
                                     {"SERI", cfg_.serial}}),
        hokuyo::encodeKeyValueReply(
            "PP", "00",
            {{"MODL", "UTM-30LX-EW"},
             {"DMIN", std::to_string(laser_.dmin_mm)},
             {"DMAX", std::to_string(laser_.dmax_mm)},
             {"ARES", std::to_string(laser_.steps_per_rev)},
             {"AMIN", "0"},
             {"AMAX", std::to_string(laser_.steps - 1)},
             {"AFRT", std::to_string(laser_.front_step)},
             {"SCAN", std::to_string(static_cast<int>(std::lround(60.0 / laser_.scan_period_s)))}}),
        hokuyo::encodeKeyValueReply("II", "00",
                                    {{"MODL", "UTM-30LX-EW"},
                                     {"LASR", "OFF"},
                                     {"SCSP", "2400"},
                                     {"MESM", "Measuring by Normal Mode"},
                                     {"SBPS", "Ethernet 100 [Mbps]"},
                                     {"TIME", time4},
                                     {"STAT", "Stable 000 no error."}}),
        hokuyo::encodeReply("BM", "00"),
        hokuyo::encodeScanAck(meRequest(laser_), "00"),
    };
    // Request/reply: each reply follows the host's next command by a round trip.
    double at = t;
    for (const std::string& r : replies) {
        deliver(at, r, out);
        at += 0.0012;
    }
}

void HokuyoStream::scan(const LaserScanTruth& scan, bool corrupt, std::vector<StreamMessage>& out) {
    ScanPayload payload;
    payload.timestamp_ms = timestampMs(scan.t_first_step);
    payload.ranges = scan.ranges_mm;
    payload.intensities = scan.intensities;
    std::string frame = hokuyo::encodeScanFrame(meRequest(laser_), payload);
    if (corrupt) {
        // Change one character inside a data block (after the echo, status and timestamp lines).
        std::size_t lines = 0, pos = 0;
        while (lines < 3 && pos < frame.size()) lines += frame[pos++] == '\n';
        const std::size_t at = pos + 5 + static_cast<std::size_t>(rng_.below(50));
        if (at < frame.size() && frame[at] != '\n')
            frame[at] = static_cast<char>(frame[at] == '0' ? '1' : '0');
    }
    const double t_last =
        scan.t_first_step + laser_.scan_period_s * (laser_.steps - 1) / laser_.steps_per_rev;
    deliver(t_last + cfg_.processing_s, frame, out);
}

}  // namespace handscan::sim
