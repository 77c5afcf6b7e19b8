#include "handscan/report/report_html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "module_timeline.hpp"

namespace handscan::report {
namespace {

std::string esc(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '<')
            o += "&lt;";
        else if (c == '>')
            o += "&gt;";
        else if (c == '&')
            o += "&amp;";
        else if (c == '"')
            o += "&quot;";
        else
            o += c;
    }
    return o;
}

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

std::string duration(double s) {
    char b[32];
    std::snprintf(b, sizeof b, "%d min %04.1f s", static_cast<int>(s / 60),
                  s - 60 * std::floor(s / 60));
    return b;
}

// A time series as an inline SVG line chart, with intervals shaded behind it.
std::string chart(const std::string& title, const std::vector<std::pair<double, double>>& series,
                  double t_end, const std::string& unit,
                  const std::vector<std::pair<const std::vector<Interval>*, const char*>>& shades) {
    constexpr double W = 900, H = 150, L = 60, B = 24, T = 22;
    double ymax = 0;
    for (const auto& p : series) ymax = std::max(ymax, p.second);
    ymax = ymax > 0 ? ymax * 1.1 : 1.0;
    const double tmax = std::max(t_end, 1e-3);
    auto x = [&](double t) { return L + (W - L - 10) * t / tmax; };
    auto y = [&](double v) { return T + (H - T - B) * (1.0 - v / ymax); };
    std::ostringstream os;
    os << "<svg class=\"chart\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W
       << ' ' << H << "\" xmlns=\"http://www.w3.org/2000/svg\">\n";
    os << "<text x=\"" << L << "\" y=\"15\" font-size=\"13\" font-weight=\"bold\">" << esc(title)
       << "</text>\n";
    for (const auto& [intervals, colour] : shades) {
        for (const Interval& in : *intervals) {
            os << "<rect x=\"" << x(in.from_s) << "\" y=\"" << T << "\" width=\""
               << std::max(1.0, x(in.to_s) - x(in.from_s)) << "\" height=\"" << H - T - B
               << "\" fill=\"" << colour << "\" opacity=\"0.35\"/>\n";
        }
    }
    os << "<line x1=\"" << L << "\" y1=\"" << H - B << "\" x2=\"" << W - 10 << "\" y2=\"" << H - B
       << "\" stroke=\"#444\"/><line x1=\"" << L << "\" y1=\"" << T << "\" x2=\"" << L << "\" y2=\""
       << H - B << "\" stroke=\"#444\"/>\n";
    os << "<text x=\"" << L - 4 << "\" y=\"" << T + 10 << "\" font-size=\"11\" text-anchor=\"end\">"
       << fmt("%.4g", ymax) << "</text><text x=\"" << L - 4 << "\" y=\"" << H - B
       << "\" font-size=\"11\" text-anchor=\"end\">0</text>\n";
    os << "<text x=\"" << L - 4 << "\" y=\"" << (H - B + T) / 2
       << "\" font-size=\"11\" text-anchor=\"end\">" << esc(unit) << "</text>\n";
    for (int k = 0; k <= 5; ++k) {
        const double t = tmax * k / 5;
        os << "<text x=\"" << x(t) << "\" y=\"" << H - 6
           << "\" font-size=\"11\" text-anchor=\"middle\">" << fmt("%.0f s", t) << "</text>\n";
    }
    os << "<polyline fill=\"none\" stroke=\"#1f5fbf\" stroke-width=\"1.5\" points=\"";
    for (const auto& p : series) os << x(p.first) << ',' << y(p.second) << ' ';
    os << "\"/>\n</svg>\n";
    return os.str();
}

std::string intervalsTable(const std::vector<Interval>& in, bool directions) {
    if (in.empty()) return "<p>none</p>\n";
    const bool reasons =
        std::any_of(in.begin(), in.end(), [](const Interval& i) { return !i.what.empty(); });
    std::ostringstream os;
    os << "<table><tr><th>from</th><th>to</th><th>length</th>"
       << (directions ? "<th>degenerate directions</th>" : "") << (reasons ? "<th>reason</th>" : "")
       << "</tr>\n";
    for (const Interval& i : in) {
        os << "<tr><td>" << fmt("%.1f s", i.from_s) << "</td><td>" << fmt("%.1f s", i.to_s)
           << "</td><td>" << fmt("%.1f s", i.to_s - i.from_s) << "</td>";
        if (directions) os << "<td>" << i.directions << "</td>";
        if (reasons) os << "<td>" << esc(i.what) << "</td>";
        os << "</tr>\n";
    }
    os << "</table>\n";
    return os.str();
}

constexpr const char* kNoSweepStats =
    "timeline unavailable: this scan's journal holds no per-sweep statistics (written before "
    "the journal recorded them) and no replay's stats.json lies beside it";

// Each device's samples per second per sweep (the pipeline's intake), a table of their mean and
// lowest rates, and the windows where one delivered nothing.
std::string devicesSection(const ScanFacts& f) {
    if (f.device_rates.empty()) return {};
    const struct {
        const char* name;
        const char* unit;
        double DeviceRates::*hz;
    } devices[] = {{"laser", "scans/s", &DeviceRates::laser_hz},
                   {"IMU", "samples/s", &DeviceRates::imu_hz},
                   {"encoder", "positions/s", &DeviceRates::encoder_hz},
                   {"colour camera", "frames/s", &DeviceRates::colour_hz},
                   {"tracking camera", "frames/s", &DeviceRates::tracking_hz}};
    std::ostringstream os;
    os << "<h3>Devices: samples per second per sweep</h3>\n<table class=\"devices\"><tr>"
          "<th>device</th><th>mean</th><th>lowest sweep</th><th>dropouts</th></tr>\n";
    std::string charts;
    const std::vector<std::pair<const std::vector<Interval>*, const char*>> shades = {
        {&f.device_dropouts, "#d33"}};
    for (const auto& d : devices) {
        std::vector<std::pair<double, double>> series;
        double sum = 0, lowest = 1e300;
        for (const DeviceRates& r : f.device_rates) {
            series.emplace_back(r.t_s, r.*d.hz);
            sum += r.*d.hz;
            lowest = std::min(lowest, r.*d.hz);
        }
        if (sum <= 0) continue;  // not fitted, or off
        const auto dropouts = std::count_if(f.device_dropouts.begin(), f.device_dropouts.end(),
                                            [&](const Interval& i) { return i.what == d.name; });
        os << "<tr data-device=\"" << d.name << "\"><td>" << d.name << "</td><td>"
           << fmt("%.1f ", sum / double(series.size())) << d.unit << "</td><td>"
           << fmt("%.1f ", lowest) << d.unit << "</td><td>" << dropouts << "</td></tr>\n";
        charts += chart(std::string(d.name) + ": " + d.unit + " per sweep", series, f.duration_s,
                        d.unit, shades);
    }
    os << "</table>\n"
       << charts << "<h3>Device dropouts</h3>\n"
       << intervalsTable(f.device_dropouts, false);
    return os.str();
}

}  // namespace

std::string base64(const std::vector<std::uint8_t>& b) {
    static constexpr char kAlphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string o;
    o.reserve((b.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < b.size(); i += 3) {
        const std::uint32_t v = (std::uint32_t{b[i]} << 16) |
                                (i + 1 < b.size() ? std::uint32_t{b[i + 1]} << 8 : 0) |
                                (i + 2 < b.size() ? std::uint32_t{b[i + 2]} : 0);
        o += kAlphabet[(v >> 18) & 63];
        o += kAlphabet[(v >> 12) & 63];
        o += i + 1 < b.size() ? kAlphabet[(v >> 6) & 63] : '=';
        o += i + 2 < b.size() ? kAlphabet[v & 63] : '=';
    }
    return o;
}

std::string reportHtml(const ReportInputs& in) {
    const ScanFacts& f = in.facts;
    std::ostringstream os;
    os << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>Scan report: "
       << esc(in.scan_name)
       << "</title>\n<style>body{font-family:sans-serif;margin:24px;color:#222}"
          "table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #bbb;padding:3px "
          "10px;"
          "text-align:left}img{max-width:100%;border:1px solid #ccc;margin:6px 0}"
          ".views{display:flex;flex-wrap:wrap;gap:12px}.views figure{margin:0}"
          "figcaption{font-size:13px;color:#555}.warn{color:#a00}"
          // On paper (report.pdf, a browser's print): A4, two map views a row, charts to width.
          "@page{size:A4;margin:12mm}@media print{body{margin:0;font-size:10pt}"
          ".views{display:block}.views figure{display:inline-block;width:49%;"
          "vertical-align:top;break-inside:avoid}svg.chart{width:100%;height:auto;"
          "break-inside:avoid}h2,h3{break-after:avoid}table{break-inside:avoid}}"
          "</style>\n</head><body>\n";
    os << "<h1>Scan report: " << esc(in.scan_name) << "</h1>\n";
    if (!in.journal_damage.empty())
        os << "<p class=\"warn\">The journal was recovered after a crash: "
           << esc(in.journal_damage) << "</p>\n";
    const double share = f.points ? 100.0 * double(f.coloured) / double(f.points) : 0.0;
    os << "<table>\n<tr><th>duration</th><td>" << duration(f.duration_s) << "</td></tr>\n"
       << "<tr><th>distance walked</th><td>" << fmt("%.1f m", f.distance_m) << "</td></tr>\n"
       << "<tr><th>points (journal)</th><td>" << f.points << "</td></tr>\n"
       << "<tr><th>points exported</th><td>" << in.exported_points
       << (in.voxel_m > 0 ? " (voxel " + fmt("%.3f m", in.voxel_m) + ")" : std::string())
       << "</td></tr>\n"
       << "<tr><th>coloured points</th><td>" << fmt("%.1f %%", share) << "</td></tr>\n"
       << "<tr><th>loop-closure gap</th><td>"
       << (f.loop_gap_m ? fmt("%.3f m", *f.loop_gap_m) + ": " : std::string()) << esc(f.loop_note)
       << "</td></tr>\n<tr><th>software</th><td>" << esc(in.software) << "</td></tr>\n</table>\n";
    os << "<h2>Map</h2>\n<div class=\"views\">\n";
    for (const auto& [caption, image] : in.images) {
        os << "<figure><img alt=\"" << esc(caption) << "\" width=\"" << image.width
           << "\" height=\"" << image.height << "\" src=\"data:image/png;base64,"
           << base64(image.png) << "\"><figcaption>" << esc(caption) << "</figcaption></figure>\n";
    }
    os << "</div>\n<h2>Sensor health over time</h2>\n<p>Per " << fmt("%.0f s", f.bin_s)
       << "; shaded red: dropouts (laser points or poses missing for more than 1 s)"
       << (f.have_sweep_stats ? "; orange: degenerate directions" : "") << ".</p>\n";
    std::vector<std::pair<double, double>> rate, colour, poses;
    for (const HealthBin& b : f.bins) {
        rate.emplace_back(b.t_s, double(b.points) / f.bin_s);
        colour.emplace_back(b.t_s, b.points ? 100.0 * double(b.coloured) / double(b.points) : 0.0);
        poses.emplace_back(b.t_s, double(b.poses) / f.bin_s);
    }
    const std::vector<std::pair<const std::vector<Interval>*, const char*>> shades = {
        {&f.laser_dropouts, "#d33"}, {&f.pose_dropouts, "#d33"}, {&f.degenerate, "#f90"}};
    os << chart("laser: registered points per second", rate, f.duration_s, "pts/s", shades);
    os << chart("camera: coloured share of the points", colour, f.duration_s, "%", shades);
    os << chart("trajectory: poses per second", poses, f.duration_s, "Hz", shades);
    if (f.have_sweep_stats) {
        std::vector<std::pair<double, double>> deg;
        for (const auto& [t, d] : f.sweep_degenerate) deg.emplace_back(t, d);
        os << chart("matcher: degenerate directions per sweep", deg, f.duration_s, "dirs", shades);
    }
    os << devicesSection(f);
    os << "<h2>Modules and directions over time</h2>\n";
    for (const std::string& d : in.sweep_damage)
        os << "<p class=\"warn\">Per-sweep statistics left out: " << esc(d) << "</p>\n";
    if (f.have_sweep_stats) {
        os << "<p>From the " << esc(f.sweep_source) << " (" << f.sweep_modules.size()
           << " sweeps).</p>\n";
        os << "<p>Per sweep, each direction (rotation rx ry rz, translation tx ty tz) in the "
              "colour of the module that solved it: <b style=\"color:#3c78eb\">scan "
              "matching</b>, <b style=\"color:#46c85a\">visual-inertial odometry</b>, or <b "
              "style=\"color:#f59628\">the IMU prediction</b> where neither did (degenerate). "
              "VIO: green running, grey bypassed. Tracking: orange a sweep kept out of the map, "
              "red tracking lost. Laser, poses: red dropouts.</p>\n"
           << moduleTimelineSvg(f);
        os << "<h3>Tracking lost</h3>\n" << intervalsTable(f.tracking_lost, false);
        os << "<h3>Visual-inertial odometry bypassed</h3>\n"
           << (f.have_vio ? intervalsTable(f.vio_bypassed, false)
                          : std::string("<p>the VIO did not run (laser + IMU only)</p>\n"));
    } else {
        os << "<p>" << kNoSweepStats << "</p>\n";
    }
    os << "<h3>Laser dropouts</h3>\n" << intervalsTable(f.laser_dropouts, false);
    os << "<h3>Trajectory dropouts</h3>\n" << intervalsTable(f.pose_dropouts, false);
    os << "<h3>Degenerate intervals</h3>\n";
    if (f.have_sweep_stats)
        os << intervalsTable(f.degenerate, true);
    else
        os << "<p>" << kNoSweepStats << "</p>\n";
    os << "<h2>Files</h2>\n<ul>\n";
    for (const std::string& file : in.files) os << "<li>" << esc(file) << "</li>\n";
    os << "</ul>\n</body></html>\n";
    return os.str();
}

}  // namespace handscan::report
