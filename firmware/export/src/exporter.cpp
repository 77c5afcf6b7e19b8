#include "handscan/export/exporter.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>

#include "export_report.hpp"
#include "handscan/core/json.hpp"
#include "handscan/export/e57_reader.hpp"
#include "handscan/export/voxel_filter.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "report_pdf.hpp"

#ifndef HANDSCAN_VERSION
#define HANDSCAN_VERSION "0.0.0"
#endif

namespace handscan::exporter {
namespace {

namespace fs = std::filesystem;

// A small text file's content; empty when it is absent or unreadable.
std::string readText(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    return f ? std::string(std::istreambuf_iterator<char>(f), {}) : std::string();
}

std::string trajectoryTum(const std::vector<journal::TrajectoryPose>& poses) {
    std::ostringstream os;
    os.precision(9);
    os << std::fixed;
    for (const auto& p : poses) {
        os << p.t_s << ' ' << p.x << ' ' << p.y << ' ' << p.z << ' ' << p.qx << ' ' << p.qy << ' '
           << p.qz << ' ' << p.qw << '\n';
    }
    return os.str();
}

std::string trajectoryCsv(const std::vector<journal::TrajectoryPose>& poses) {
    std::ostringstream os;
    os.precision(9);
    os << std::fixed << "time_s,x_m,y_m,z_m,qx,qy,qz,qw\n";
    for (const auto& p : poses) {
        os << p.t_s << ',' << p.x << ',' << p.y << ',' << p.z << ',' << p.qx << ',' << p.qy << ','
           << p.qz << ',' << p.qw << '\n';
    }
    return os.str();
}

std::string metadataJson(const journal::JournalSummary& js, const ExportReport& r,
                         const ExportOptions& o, const std::vector<std::string>& formats) {
    Json j;
    j["software"] = std::string("handscan ") + HANDSCAN_VERSION;
    // The scan's own metadata as the journal holds it; text that is not JSON (an old or damaged
    // journal) is kept as a string rather than dropped.
    Json scan = Json::object();
    if (!js.metadata_json.empty()) {
        scan = Json::parse(js.metadata_json, nullptr, false);
        if (scan.is_discarded()) scan = js.metadata_json;
    }
    j["scan"] = scan;
    j["journal"] = {
        {"path", js.path}, {"points", js.points}, {"finished", js.finished}, {"damage", js.damage}};
    j["export"] = {{"points", r.points},
                   {"coloured_points", r.coloured_points},
                   {"voxel_m", o.voxel_m},
                   {"formats", formats},
                   {"e57_coordinates", o.e57_scale_m > 0 ? "scaled integer" : "double"},
                   {"e57_scale_m", o.e57_scale_m},
                   {"bounds_min", {r.bounds.min[0], r.bounds.min[1], r.bounds.min[2]}},
                   {"bounds_max", {r.bounds.max[0], r.bounds.max[1], r.bounds.max[2]}},
                   {"trajectory_poses", js.trajectory.size()}};
    return jsonText(j, 2) + "\n";
}

// The points to export: straight from the journal (streamed) or voxel-filtered.
class PointSource {
public:
    // `observe` sees every journal point once, whether thinned or not.
    PointSource(const journal::JournalReader& reader, double voxel_m,
                const std::function<void(double)>& progress,
                std::function<void(std::span<const journal::MapPoint>)> observe)
        : reader_(reader), observe_(std::move(observe)) {
        if (voxel_m > 0.0) {
            VoxelFilter filter(voxel_m);
            const double total =
                static_cast<double>(std::max<std::uint64_t>(1, reader.summary().points));
            double done = 0.0;
            status_ = reader.forEachPoints([&](std::span<const journal::MapPoint> pts) {
                observe_(pts);
                filter.add(pts);
                done += static_cast<double>(pts.size());
                progress(done / total);
            });
            filtered_ = std::make_unique<std::vector<journal::MapPoint>>(filter.take());
        }
    }
    const Status& status() const { return status_; }
    std::uint64_t count() const { return filtered_ ? filtered_->size() : reader_.summary().points; }
    Status forEach(const std::function<void(std::span<const journal::MapPoint>)>& sink) const {
        if (!filtered_) {
            return reader_.forEachPoints([&](std::span<const journal::MapPoint> pts) {
                observe_(pts);
                sink(pts);
            });
        }
        constexpr std::size_t kBatch = 1 << 16;
        for (std::size_t i = 0; i < filtered_->size(); i += kBatch) {
            sink(std::span(filtered_->data() + i, std::min(kBatch, filtered_->size() - i)));
        }
        return Status::ok();
    }

private:
    const journal::JournalReader& reader_;
    std::function<void(std::span<const journal::MapPoint>)> observe_;
    std::unique_ptr<std::vector<journal::MapPoint>> filtered_;
    Status status_;
};

std::string formatOf(const std::string& path) {
    const std::string ext = fs::path(path).extension().string();
    return ext.empty() ? ext : ext.substr(1);
}

// The scan's sensor and trajectory for the E57 Data3D. The journal's metadata may name the
// device's serial number ("serial"); the rest is what every handscan is.
E57Options e57Options(const journal::JournalSummary& js, const std::string& scan_name,
                      const ExportOptions& options) {
    E57Options o;
    o.coordinate_scale = options.e57_scale_m;
    o.scan_name = scan_name;
    o.software_version = HANDSCAN_VERSION;
    o.trajectory = js.trajectory;
    const auto meta = Json::parse(js.metadata_json, nullptr, false);
    if (meta.is_object() && meta.contains("serial") && meta["serial"].is_string())
        o.sensor_serial = meta["serial"].get<std::string>();
    return o;
}

// The E57 file as a reader sees it (its pages' CRC-32C were checked on the read-back): the
// header and XML parse, and the Data3D holds every point.
Status checkE57(const std::string& path, std::uint64_t count) {
    auto r = E57Reader::open(path, /*check_pages=*/false);
    if (!r.isOk()) return Status(r.status().code(), "export: verifying " + r.status().message());
    const E57File& f = r->file();
    if (f.scans.size() != 1 || f.scans[0].points.records != count) {
        return Status(StatusCode::kIoError, "export: verifying " + path +
                                                ": the XML does not list one scan of " +
                                                std::to_string(count) + " points");
    }
    return Status::ok();
}

// One point file being written: its safe file and its format's encoder.
struct CloudFile {
    std::string path;
    std::unique_ptr<SafeFileWriter> file;
    std::unique_ptr<PointFileWriter> writer;
};

}  // namespace

Result<std::string> findJournal(const std::string& source) {
    std::error_code ec;
    if (fs::is_regular_file(source, ec)) return source;
    if (fs::is_directory(source, ec)) {
        const fs::path p = fs::path(source) / "journal.hsj";
        if (fs::is_regular_file(p, ec)) return p.string();
        return Status(StatusCode::kNotFound, source + ": no journal.hsj in this directory");
    }
    return Status(StatusCode::kNotFound, source + ": no such journal file or directory");
}

Result<ExportReport> exportScan(const std::string& source, const std::string& target_dir,
                                const ExportOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    auto progress = [&](double f, const std::string& stage) {
        if (options.progress) options.progress(std::clamp(f, 0.0, 1.0), stage);
    };
    std::vector<std::string> formats;  // in the order given, each once
    if (!(options.e57_scale_m >= 0.0 && options.e57_scale_m <= 1.0)) {
        return Status(StatusCode::kInvalidArgument,
                      "export: E57 coordinate scale " + std::to_string(options.e57_scale_m) +
                          " m is not in [0, 1] (0: doubles; e.g. 0.0001 for 0.1 mm steps)");
    }
    for (const std::string& f : options.formats) {
        if (f != "ply" && f != "las" && f != "e57") {
            return Status(StatusCode::kInvalidArgument,
                          "export: unknown format '" + f + "' (expected ply, las, e57)");
        }
        if (std::find(formats.begin(), formats.end(), f) == formats.end()) formats.push_back(f);
    }
    auto journal_path = findJournal(source);
    if (!journal_path.isOk()) return journal_path.status();
    auto reader = journal::JournalReader::open(*journal_path);
    if (!reader.isOk()) return reader.status();
    const journal::JournalSummary& js = reader->summary();

    std::error_code ec;
    if (!fs::is_directory(target_dir, ec)) {
        return Status(StatusCode::kNotFound, "export: target " + target_dir +
                                                 " is not a directory (vanished or not mounted?)");
    }
    std::string name = options.scan_name;
    if (name.empty()) {
        const fs::path jp(*journal_path);
        name = jp.filename() == "journal.hsj" ? jp.parent_path().filename().string()
                                              : jp.stem().string();
        if (name.empty()) name = "scan";
    }
    const fs::path out_dir = fs::path(target_dir) / name;
    fs::create_directories(out_dir, ec);
    if (ec)
        return Status(StatusCode::kIoError,
                      "export: cannot create " + out_dir.string() + ": " + ec.message());

    // Progress: thinning (if any) up to 30 %, writing up to 85 %, then verifying each file.
    const double write_from = options.voxel_m > 0.0 ? 0.3 : 0.0;
    constexpr double kWriteTo = 0.85;
    progress(0.0, options.voxel_m > 0.0 ? "thinning" : "reading journal");
    std::unique_ptr<ExportReportBuilder> scan_report;  // built while the points stream
    if (options.report)
        scan_report = std::make_unique<ExportReportBuilder>(js.points, js.trajectory);
    PointSource points(
        *reader, options.voxel_m, [&](double f) { progress(f * write_from, "thinning"); },
        [&](std::span<const journal::MapPoint> pts) {
            if (scan_report) scan_report->journalPoints(pts);
        });
    if (!points.status().isOk()) return points.status();
    const std::uint64_t count = points.count();

    // Free space first: refuse before writing anything rather than fail half-way.
    std::uint64_t need = 64 * 1024 + js.trajectory.size() * 200;
    for (const std::string& f : formats) {
        need += f == "ply"   ? plyBytes(count)
                : f == "las" ? lasBytes(count)
                             : e57Bytes(count, js.trajectory.size(), options.e57_scale_m > 0);
    }
    const fs::space_info space = fs::space(out_dir, ec);
    if (!ec && space.available < need) {
        return Status(StatusCode::kNoSpace,
                      "export: " + target_dir + " has " + std::to_string(space.available >> 20) +
                          " MiB free but the export needs " + std::to_string((need >> 20) + 1) +
                          " MiB; use a larger stick or --voxel to thin the cloud");
    }

    ExportReport report;
    report.directory = out_dir.string();
    report.points = count;
    report.journal_points = js.points;
    report.journal_damage = js.damage;
    for (const std::string& d : js.sweep_damage)
        report.notes.push_back("journal " + *journal_path + ": " + d);
    // Every format from one pass over the points: the journal is read once, each file's I/O
    // thread writes while the points are encoded for the next block.
    std::vector<CloudFile> clouds;
    std::string writing = "writing";
    for (const std::string& format : formats) {
        CloudFile c;
        c.path = (out_dir / ("cloud." + format)).string();
        c.file = std::make_unique<SafeFileWriter>(c.path, options.faults);
        if (Status s = c.file->open(); !s.isOk()) return s;
        c.writer = format == "ply"   ? makePlyWriter(*c.file)
                   : format == "las" ? makeLasWriter(*c.file)
                                     : makeE57Writer(*c.file, e57Options(js, name, options));
        if (Status s = c.writer->begin(count); !s.isOk()) return s;
        writing += (clouds.empty() ? " " : ", ") + fs::path(c.path).filename().string();
        clouds.push_back(std::move(c));
    }
    const double total = static_cast<double>(std::max<std::uint64_t>(1, count));
    double done = 0.0;
    Status failure;
    if (Status s = points.forEach([&](std::span<const journal::MapPoint> pts) {
            for (CloudFile& c : clouds) {
                if (failure.isOk()) failure = c.writer->write(pts);
            }
            for (const journal::MapPoint& p : pts) {
                if (journal::hasColour(p)) ++report.coloured_points;
            }
            if (scan_report) scan_report->exportedPoints(pts);
            done += static_cast<double>(pts.size());
            progress(write_from + (kWriteTo - write_from) * done / total, writing);
        });
        !s.isOk()) {
        return s;
    }
    if (!failure.isOk()) return failure;
    for (std::size_t i = 0; i < clouds.size(); ++i) {
        CloudFile& c = clouds[i];
        progress(kWriteTo + (0.99 - kWriteTo) * static_cast<double>(i) /
                                static_cast<double>(clouds.size()),
                 "verifying " + fs::path(c.path).filename().string());
        if (Status s = c.writer->end(); !s.isOk()) return s;
        if (formatOf(c.path) == "e57") {
            if (Status s = checkE57(c.path, count); !s.isOk()) return s;
        }
        report.bounds = c.writer->bounds();
        report.files.push_back(c.path);
        report.bytes += c.file->bytesWritten();
    }
    progress(0.99, "writing trajectory and metadata");
    const std::pair<std::string, std::string> small_files[] = {
        {"trajectory.tum", trajectoryTum(js.trajectory)},
        {"trajectory.csv", trajectoryCsv(js.trajectory)},
        {"scan.json", metadataJson(js, report, options, formats)},
    };
    for (const auto& [file_name, text] : small_files) {
        const std::string path = (out_dir / file_name).string();
        if (Status s = writeSmallFile(path, text, options.faults); !s.isOk()) return s;
        report.files.push_back(path);
        report.bytes += text.size();
    }
    if (scan_report) {
        progress(0.995, "writing report.html");
        std::vector<std::string> names;
        for (const std::string& f : report.files) names.push_back(fs::path(f).filename().string());
        const std::string html =
            scan_report->html(js, name, count, options.voxel_m, names,
                              readText(fs::path(*journal_path).parent_path() / "stats.json"));
        if (!options.preview_png.empty()) {
            // The first view (from above, by height): what the UI's export screen shows.
            const auto views = scan_report->images(js);
            if (!views.empty()) {
                const auto& png = views.front().second.png;
                if (writeSmallFile(options.preview_png,
                                   {reinterpret_cast<const char*>(png.data()), png.size()})
                        .isOk())
                    report.preview_png = options.preview_png;
            }
        }
        const std::string path = (out_dir / "report.html").string();
        if (Status s = writeSmallFile(path, html, options.faults); !s.isOk()) return s;
        report.files.push_back(path);
        report.bytes += html.size();
        if (!options.pdf_tool.empty()) progress(0.997, "writing report.pdf");
        const std::string pdf_path = (out_dir / "report.pdf").string();
        auto pdf = writeReportPdf(path, pdf_path, options.pdf_tool, options.faults);
        if (!pdf.isOk()) return pdf.status();
        if (pdf->written) {
            report.files.push_back(pdf_path);
            report.bytes += pdf->bytes;
            report.pdf_seconds = pdf->seconds;
        } else if (!pdf->note.empty()) {
            report.notes.push_back(pdf->note);
        }
    }
    // Flush the whole filesystem (the stick) so that pulling it now loses nothing.
    if (int fd = ::open(out_dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); fd >= 0) {
        ::syncfs(fd);
        ::close(fd);
    }
    progress(1.0, "done");
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return report;
}

Result<ExportReport> exportToUsb(const std::string& source, const ExportOptions& options,
                                 const SystemPaths& paths) {
    auto stick = findUsbStick(paths);
    if (!stick.isOk()) return stick.status();
    return exportScan(source, stick->mount_point, options);
}

}  // namespace handscan::exporter
