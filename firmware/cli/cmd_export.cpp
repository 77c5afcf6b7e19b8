// `handscan export JOURNAL|DIR --to PATH|usb`: the scan onto a stick or into a directory
// (PLY, LAS 1.4, E57, trajectory, scan.json, report.html, report.pdf where weasyprint is
// installed).
#include <cstdio>
#include <iostream>
#include <sstream>

#include "command_registry.hpp"
#include "handscan/core/log.hpp"
#include "handscan/export/exporter.hpp"

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
        };
        auto a = std::make_shared<Args>();
        sub.add_option("SOURCE", a->source, "journal file, or a directory holding journal.hsj")
            ->required();
        sub.add_option("--to", a->to, "target directory, or 'usb' for the removable stick")
            ->required();
        sub.add_option("--format", a->formats, "comma-separated: ply,las,e57")
            ->capture_default_str();
        sub.add_option("--voxel", a->voxel,
                       "voxel size in metres for thinning (0 = full resolution)")
            ->check(CLI::Range(0.0, 10.0));
        sub.add_option("--name", a->name, "output folder name (default: the scan's name)");
        return std::function<int()>([a] {
            exporter::ExportOptions opt;
            opt.formats = splitComma(a->formats);
            opt.voxel_m = a->voxel;
            opt.scan_name = a->name;
            Progress bar("export", 1.0);
            std::string last_stage;
            opt.progress = [&](double f, const std::string& stage) {
                if (stage != last_stage) log().debug("export: {}", stage);
                last_stage = stage;
                bar.update(f);
            };
            const auto report = a->to == "usb" ? exporter::exportToUsb(a->source, opt)
                                               : exporter::exportScan(a->source, a->to, opt);
            bar.finish();
            if (!report.isOk()) {
                log().error("{}", report.status().message());
                return 1;
            }
            if (!report->journal_damage.empty()) {
                log().warn("the journal was recovered after a crash: {}", report->journal_damage);
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
