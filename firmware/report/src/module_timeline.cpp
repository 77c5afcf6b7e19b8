#include "module_timeline.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <vector>

namespace handscan::report {
namespace {

constexpr double kWidth = 900, kLabel = 80, kLane = 16, kGap = 4, kTop = 8, kAxis = 22;
constexpr const char* kScan = "#3c78eb";  // figure 14: scan matching
constexpr const char* kVio = "#46c85a";   // visual-inertial odometry
constexpr const char* kImu = "#f59628";   // IMU prediction
constexpr const char* kOff = "#bbbbbb";
constexpr const char* kLost = "#d33333";
constexpr const char* kDirections[6] = {"rx", "ry", "rz", "tx", "ty", "tz"};

struct Span {
    double from_s, to_s;
    const char* colour;
};

class Lanes {
public:
    explicit Lanes(double t_end) : t_end_(std::max(t_end, 1e-3)) {}
    double x(double t) const {
        return kLabel + (kWidth - kLabel - 10) * std::clamp(t / t_end_, 0.0, 1.0);
    }
    double y(int lane) const { return kTop + lane * (kLane + kGap); }
    void lane(int row, const std::string& label, const std::vector<Span>& spans,
              const std::string& note = {}) {
        os_ << "<text x=\"" << kLabel - 6 << "\" y=\"" << y(row) + kLane - 4
            << "\" font-size=\"11\" text-anchor=\"end\">" << label << "</text>\n";
        os_ << "<rect x=\"" << kLabel << "\" y=\"" << y(row) << "\" width=\"" << x(t_end_) - kLabel
            << "\" height=\"" << kLane << "\" fill=\"#f4f4f4\"/>\n";
        // The span's times as data too, so that a reader (or a test) needs no pixel arithmetic.
        for (const Span& s : spans) {
            char times[80];
            std::snprintf(times, sizeof times, "data-from=\"%.3f\" data-to=\"%.3f\"", s.from_s,
                          s.to_s);
            os_ << "<rect x=\"" << x(s.from_s) << "\" y=\"" << y(row) << "\" width=\""
                << std::max(1.0, x(s.to_s) - x(s.from_s)) << "\" height=\"" << kLane << "\" fill=\""
                << s.colour << "\" data-lane=\"" << label << "\" " << times << "/>\n";
        }
        if (!note.empty()) {
            os_ << "<text x=\"" << kLabel + 6 << "\" y=\"" << y(row) + kLane - 4
                << "\" font-size=\"11\" fill=\"#555\">" << note << "</text>\n";
        }
    }
    std::string finish(int lanes) {
        const double axis_y = y(lanes);
        std::ostringstream out;
        out << "<svg class=\"chart\" width=\"" << kWidth << "\" height=\"" << axis_y + kAxis
            << "\" viewBox=\"0 0 " << kWidth << ' ' << axis_y + kAxis
            << "\" xmlns=\"http://www.w3.org/2000/svg\">\n"
            << os_.str();
        for (int k = 0; k <= 5; ++k) {
            char t[32];
            std::snprintf(t, sizeof t, "%.0f s", t_end_ * k / 5);
            out << "<text x=\"" << x(t_end_ * k / 5) << "\" y=\"" << axis_y + 12
                << "\" font-size=\"11\" text-anchor=\"middle\">" << t << "</text>\n";
        }
        out << "</svg>\n";
        return out.str();
    }
    double end() const { return t_end_; }

private:
    double t_end_;
    std::ostringstream os_;
};

// Per-sweep colours as spans, each sweep lasting until the next starts; equal neighbours merge.
template <typename ColourOf>
std::vector<Span> sweepSpans(const std::vector<SweepModules>& sweeps, double t_end,
                             ColourOf colour_of) {
    std::vector<Span> spans;
    for (std::size_t k = 0; k < sweeps.size(); ++k) {
        const double to = k + 1 < sweeps.size() ? sweeps[k + 1].t_s : t_end;
        const char* c = colour_of(sweeps[k]);
        if (c == nullptr) continue;
        if (!spans.empty() && spans.back().colour == c && spans.back().to_s >= sweeps[k].t_s)
            spans.back().to_s = to;
        else
            spans.push_back({sweeps[k].t_s, to, c});
    }
    return spans;
}

std::vector<Span> intervalSpans(const std::vector<Interval>& in, const char* colour) {
    std::vector<Span> spans;
    for (const Interval& i : in) spans.push_back({i.from_s, i.to_s, colour});
    return spans;
}

}  // namespace

std::string moduleTimelineSvg(const ScanFacts& f) {
    Lanes lanes(f.duration_s);
    int row = 0;
    for (int d = 0; d < 6; ++d) {
        const unsigned bit = 1u << d;
        lanes.lane(row++, kDirections[d],
                   sweepSpans(f.sweep_modules, lanes.end(), [bit](const SweepModules& m) {
                       return (m.scan_mask & bit) ? kScan : (m.vio_mask & bit) ? kVio : kImu;
                   }));
    }
    if (f.have_vio) {
        std::vector<Span> vio{{f.vio_from_s, lanes.end(), kVio}};
        for (const Interval& b : f.vio_bypassed) vio.push_back({b.from_s, b.to_s, kOff});
        lanes.lane(row++, "VIO", vio);
    } else {
        lanes.lane(row++, "VIO", {}, "off (laser + IMU only)");
    }
    auto tracking = sweepSpans(f.sweep_modules, lanes.end(), [](const SweepModules& m) {
        return m.tracking == 'l'   ? kLost
               : m.tracking == 'r' ? kImu
                                   : static_cast<const char*>(nullptr);
    });
    for (const Span& s : intervalSpans(f.tracking_lost, kLost)) tracking.push_back(s);
    lanes.lane(row++, "tracking", tracking);
    lanes.lane(row++, "laser", intervalSpans(f.laser_dropouts, kLost));
    lanes.lane(row++, "poses", intervalSpans(f.pose_dropouts, kLost));
    return lanes.finish(row);
}

}  // namespace handscan::report
