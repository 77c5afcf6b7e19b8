// `handscan export JOURNAL|DIR --to PATH|usb`: the scan onto a stick or into a directory
// (PLY, LAS 1.4, E57, trajectory, scan.json, report.html, report.pdf where weasyprint is
// installed).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string_view>

#include "command_registry.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/log.hpp"
#include "handscan/export/exporter.hpp"
#include "handscan/viz/journal_viz.hpp"

namespace handscan::cli {
namespace {

// The share of exported points that carry a camera colour, to one decimal.
std::string colouredPercent(const exporter::ExportReport& r) {
    if (r.points == 0) return "0";
    const double pct =
        100.0 * static_cast<double>(r.coloured_points) / static_cast<double>(r.points);
    char text[16];
    std::snprintf(text, sizeof text, "%.1f", pct);
    return text;
}

// --e57-coordinates: "double" (0) or "scaled:S" (S metres per step, e.g. scaled:0.0001).
std::optional<double> e57Scale(const std::string& s) {
    if (s == "double") return 0.0;
    constexpr std::string_view kScaled = "scaled:";
    if (s.rfind(kScaled, 0) != 0) return std::nullopt;
    char* end = nullptr;
    const std::string number = s.substr(kScaled.size());
    const double v = std::strtod(number.c_str(), &end);
    if (number.empty() || *end != '\0' || !(v > 0.0 && v <= 1.0)) return std::nullopt;
    return v;
}

// scan.viz.mcap beside the export's files (and in its list): the journal as Foxglove channels.
Status writeViz(const std::string& source, exporter::ExportReport& report,
                const std::string& calibration_path) {
    auto journal = exporter::findJournal(source);
    if (!journal.isOk()) return journal.status();
    Calibration calibration;
    try {
        calibration = loadCalibration(
            calibration_path.empty() ? defaultConfigDir() + "/calibration.yaml" : calibration_path);
    } catch (const std::exception& e) {
        return Status(StatusCode::kInvalidArgument, std::string("export mcap: ") + e.what());
    }
    viz::JournalVizOptions o;
    o.journal = *journal;
    o.out = (std::filesystem::path(report.directory) / "scan.viz.mcap").string();
    auto written = viz::writeJournalViz(o, calibration);
    if (!written.isOk())
        return Status(written.status().code(), "export mcap: " + written.status().message());
    report.files.push_back(o.out);
    report.bytes += written->bytes;
    return Status::ok();
}

std::vector<std::string> splitComma(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, ',');) {
        if (!item.empty()) out.push_back(item);
    }
    return out;
}

const RegisterCommand kExport{
    "export",
    "Export a scan (journal) as PLY / LAS 1.4 / E57 + trajectory + report.html (+ report.pdf with "
    "weasyprint) to a directory or the USB stick",
    [](CLI::App& sub) {
        struct Args {
            std::string source;
            std::string to;
            std::string formats = "ply,las,e57";
            double voxel = 0.0;
            std::string name;
            std::string e57_coordinates = "double";
            std::string calibration;
        };
        auto a = std::make_shared<Args>();
        sub.add_option("SOURCE", a->source, "journal file, or a directory holding journal.hsj")
            ->required();
        sub.add_option("--to", a->to, "target directory, or 'usb' for the removable stick")
            ->required();
        sub.add_option("--format", a->formats,
                       "comma-separated: ply,las,e57,mcap (mcap: scan.viz.mcap, the trajectory "
                       "and map for Foxglove)")
            ->capture_default_str();
        sub.add_option("--voxel", a->voxel,
                       "voxel size in metres for thinning (0 = full resolution)")
            ->check(CLI::Range(0.0, 10.0));
        sub.add_option("--name", a->name, "output folder name (default: the scan's name)");
        sub.add_option("--calibration", a->calibration,
                       "calibration.yaml for mcap's camera frames (default: config dir)");
        sub.add_option("--e57-coordinates", a->e57_coordinates,
                       "E57 cartesianX/Y/Z: 'double', or 'scaled:S' for 32-bit integers of S "
                       "metres (scaled:0.0001 = 0.1 mm steps, 12 bytes less per point)")
            ->capture_default_str();
        return std::function<int()>([a] {
            exporter::ExportOptions opt;
            opt.formats = splitComma(a->formats);
            // mcap: the scan for Foxglove (viz::writeJournalViz), beside the exporter's files.
            const auto mcap = std::find(opt.formats.begin(), opt.formats.end(), "mcap");
            const bool viz = mcap != opt.formats.end();
            if (viz) opt.formats.erase(mcap);
            opt.voxel_m = a->voxel;
            opt.scan_name = a->name;
            const auto scale = e57Scale(a->e57_coordinates);
            if (!scale) {
                log().error(
                    "--e57-coordinates {}: expected 'double' or 'scaled:S' with S in (0, 1] "
                    "metres, e.g. scaled:0.0001",
                    a->e57_coordinates);
                return 2;
            }
            opt.e57_scale_m = *scale;
            Progress bar("export", 1.0);
            std::string last_stage;
            opt.progress = [&](double f, const std::string& stage) {
                if (stage != last_stage) log().debug("export: {}", stage);
                last_stage = stage;
                bar.update(f);
            };
            auto report = a->to == "usb" ? exporter::exportToUsb(a->source, opt)
                                         : exporter::exportScan(a->source, a->to, opt);
            bar.finish();
            if (!report.isOk()) {
                log().error("{}", report.status().message());
                return 1;
            }
            if (!report->journal_damage.empty()) {
                log().warn("the journal was recovered after a crash: {}", report->journal_damage);
            }
            if (viz) {
                if (Status s = writeViz(a->source, report.value(), a->calibration); !s.isOk()) {
                    log().error("{}", s.message());
                    return 1;
                }
            }
            for (const auto& note : report->notes) log().warn("{}", note);
            if (report->pdf_seconds > 0) log().debug("report.pdf: {:.2f} s", report->pdf_seconds);
            for (const auto& f : report->files) std::cout << f << '\n';
            std::cout << "exported " << report->points << " points (" << report->journal_points
                      << " in the journal; " << report->coloured_points << " coloured, "
                      << colouredPercent(*report) << " %), " << (report->bytes >> 20) << " MiB in "
                      << report->seconds << " s to " << report->directory << '\n';
            if (a->to == "usb") std::cout << "safe to remove the USB stick\n";
            return 0;
        });
    }};

}  // namespace
}  // namespace handscan::cli
