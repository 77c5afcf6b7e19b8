// FakeHokuyoSensor: the SCIP 2.0 behaviour of a UTM-30LX-EW without any I/O. It answers commands
// (SCIP2.0, VV, PP, II, BM, QT, RS, TM0/1/2, MD/MS/ME with parameter checks and status codes,
// GD/GS/GE) with bytes built by the driver's own codec, and streams scans from a source: the scan
// frames found in a raw byte stream (a recording's /hokuyo/raw, or the simulator's output). A scan
// frame whose request equals the client's is sent verbatim (byte for byte as recorded); otherwise
// it is re-encoded for the client's request (step range, cluster, encoding, remaining count).
// FakeHokuyoServer puts it behind a real loopback TCP socket.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "handscan/hokuyo/scip_codec.hpp"

namespace handscan::hokuyo {

// One scan frame of a source stream.
struct SourceScanFrame {
    std::string bytes;    // the frame as it was on the wire
    ScanRequest request;  // its echo
    ScanPayload scan;     // its decoded data
};

// The scan frames (M*/G* frames with data, sums verified) of a raw SCIP byte stream, in order.
std::vector<SourceScanFrame> splitScanFrames(std::string_view stream);

using KeyValues = std::vector<std::pair<std::string, std::string>>;

struct FakeHokuyoIdentity {
    KeyValues vv = {{"VEND", "Hokuyo Automatic Co.,Ltd."},
                    {"PROD", "SOKUIKI Sensor TOP-URG UTM-30LX-EW"},
                    {"FIRM", "1.1.0(2012-12-06)"},
                    {"PROT", "SCIP 2.0"},
                    {"SERI", "H0000000"}};
    // The real UTM-30LX-EW PP reply (../shared/data/hokuyo).
    KeyValues pp = {{"MODL", "UTM-30LX-EW"}, {"DMIN", "23"},   {"DMAX", "60000"}, {"ARES", "1440"},
                    {"AMIN", "0"},           {"AMAX", "1080"}, {"AFRT", "540"},   {"SCAN", "2400"}};
    std::string stat = "Sensor works well.";
};

class FakeHokuyoSensor {
public:
    explicit FakeHokuyoSensor(std::vector<SourceScanFrame> source,
                              FakeHokuyoIdentity identity = {});

    // Bytes from the host, split anywhere; commands end in LF, CR or CRLF.
    void onHostBytes(std::string_view bytes);
    // Replies produced so far (moved out).
    std::string takeReplies();
    // The next scan frame to stream, when a stream is running and the source has one; advances the
    // source. `timestamp_ms` receives the frame's sensor timestamp.
    std::optional<std::string> nextStreamFrame(std::uint32_t* timestamp_ms = nullptr);
    bool streaming() const { return streaming_; }
    bool sourceExhausted() const { return next_ >= source_.size(); }
    // Index (into the source) of the frame nextStreamFrame() returned last.
    std::size_t lastFrameIndex() const { return last_index_; }
    // The client went away: the sensor stops streaming (as the UTM-30LX-EW does on a TCP close).
    void onDisconnect();

    const std::vector<SourceScanFrame>& source() const { return source_; }

private:
    void onCommand(const std::string& command);
    void onScanCommand(const std::string& command);
    std::string encodeForRequest(const SourceScanFrame& frame, const ScanRequest& request) const;
    int ppInt(const char* key, int fallback) const;

    std::vector<SourceScanFrame> source_;
    FakeHokuyoIdentity identity_;
    std::string line_;
    std::string out_;
    bool laser_on_ = false;
    bool streaming_ = false;
    ScanRequest stream_request_;
    int remaining_ = 0;  // scans still to send when the request had a count (0 = unlimited)
    std::size_t next_ = 0;
    std::size_t last_index_ = 0;
    std::uint32_t time_ms_ = 0;  // TM1 answer when the source is empty
};

}  // namespace handscan::hokuyo
