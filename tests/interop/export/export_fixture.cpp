// Writes a journal of deterministic pseudo-random coloured points, exports it with handscan's
// exporter (E57 with double and with ScaledInteger coordinates), and writes expected.json (count,
// bounds, colour sums) for the independent readers.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "handscan/export/exporter.hpp"
#include "handscan/journal/journal_writer.hpp"

int main(int argc, char** argv) {
    using namespace handscan;
    if (argc != 3) {
        std::fprintf(stderr, "usage: export_fixture OUT_DIR POINTS\n");
        return 2;
    }
    const std::filesystem::path out(argv[1]);
    const std::size_t n = std::stoul(argv[2]);
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out / "internal");
    std::filesystem::create_directories(out / "target");
    const std::string journal_path = (out / "internal" / "journal.hsj").string();
    auto writer = journal::JournalWriter::create(journal_path, R"({"device":"interop fixture"})");
    if (!writer.isOk()) return std::fprintf(stderr, "%s\n", writer.status().message().c_str()), 1;
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> pos(-20.f, 35.f);
    std::uniform_int_distribution<int> col(0, 255);
    double sum_r = 0, sum_g = 0, sum_b = 0;
    exporter::Bounds bounds;
    std::vector<journal::MapPoint> pts;
    for (std::size_t i = 0; i < n; ++i) {
        journal::MapPoint p{1000.0 + i * 1e-4,
                            pos(rng),
                            pos(rng) * 0.5f,
                            pos(rng) * 0.1f,
                            static_cast<std::uint8_t>(col(rng)),
                            static_cast<std::uint8_t>(col(rng)),
                            static_cast<std::uint8_t>(col(rng)),
                            static_cast<std::uint16_t>(i % 4096)};
        sum_r += p.r;
        sum_g += p.g;
        sum_b += p.b;
        bounds.add(p.x, p.y, p.z);
        pts.push_back(p);
    }
    if (!(*writer)->appendPoints(pts).isOk() ||
        !(*writer)->appendPose({1000.0, 0, 0, 0, 0, 0, 0, 1}).isOk() ||
        !(*writer)->finish().isOk()) {
        return 1;
    }
    writer->reset();
    exporter::ExportOptions opt;
    opt.scan_name = "scan";
    auto report = exporter::exportScan(journal_path, (out / "target").string(), opt);
    if (!report.isOk()) return std::fprintf(stderr, "%s\n", report.status().message().c_str()), 1;
    // The same with E57 ScaledInteger coordinates of 0.1 mm (and its PLY to compare with).
    constexpr double kScale = 1e-4;
    opt.scan_name = "scan-scaled";
    opt.formats = {"ply", "e57"};
    opt.e57_scale_m = kScale;
    opt.report = false;
    auto scaled = exporter::exportScan(journal_path, (out / "target").string(), opt);
    if (!scaled.isOk()) return std::fprintf(stderr, "%s\n", scaled.status().message().c_str()), 1;
    std::ofstream js(out / "expected.json");
    js.precision(9);
    js << "{\"count\": " << n << ", \"min\": [" << bounds.min[0] << ", " << bounds.min[1] << ", "
       << bounds.min[2] << "], \"max\": [" << bounds.max[0] << ", " << bounds.max[1] << ", "
       << bounds.max[2] << "], \"sum_rgb\": [" << sum_r << ", " << sum_g << ", " << sum_b
       << "], \"first_rgb\": [" << int(pts[0].r) << ", " << int(pts[0].g) << ", " << int(pts[0].b)
       << "], \"dir\": \"" << report->directory << "\", \"scaled_dir\": \"" << scaled->directory
       << "\", \"scale\": " << kScale << "}\n";
    return 0;
}
