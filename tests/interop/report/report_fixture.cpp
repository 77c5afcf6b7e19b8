// A synthetic walk for the report: a 12 x 8 m room (floor, four walls 2.5 m high, a table and a
// shelf) walked once around a loop for 60 s, coloured by the "camera" except for the first 10 s,
// with the laser silent from 20 to 22 s, and a replay-style stats.json saying the matcher was
// degenerate in tx from 30 to 35 s (the VIO solving it from 32 s), the VIO bypassed from 40 to
// 45 s and tracking lost from 50 to 52 s.
// Exports it (E57 + report.html + report.pdf) into OUT_DIR/target/walk.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "handscan/export/exporter.hpp"
#include "handscan/journal/journal_writer.hpp"

int main(int argc, char** argv) {
    using namespace handscan;
    if (argc != 2) {
        std::fprintf(stderr, "usage: report_fixture OUT_DIR\n");
        return 2;
    }
    const std::filesystem::path out(argv[1]);
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out / "walk");
    std::filesystem::create_directories(out / "target");
    const std::string journal_path = (out / "walk" / "journal.hsj").string();
    auto w = journal::JournalWriter::create(journal_path, R"({"source": "report fixture"})");
    if (!w.isOk()) return std::fprintf(stderr, "%s\n", w.status().message().c_str()), 1;
    constexpr double kT0 = 500.0;  // scan clock at the start (s)
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> ux(-6.f, 6.f), uy(-4.f, 4.f), uz(0.f, 2.5f);
    std::uniform_int_distribution<int> face(0, 7);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    std::vector<journal::MapPoint> batch;
    for (int s = 0; s < 600; ++s) {  // 0.1 s sweeps of 500 points
        const double t = kT0 + s * 0.1;
        if (t >= kT0 + 20.0 && t < kT0 + 22.0) continue;  // laser dropout
        batch.clear();
        for (int k = 0; k < 500; ++k) {
            journal::MapPoint p;
            p.t_s = t + k * 2e-4;
            switch (face(rng)) {
                case 0:
                case 1:
                case 2:
                    p.x = ux(rng);
                    p.y = uy(rng);
                    p.z = 0.f;
                    break;  // floor
                case 3:
                    p.x = ux(rng);
                    p.y = k % 2 ? -4.f : 4.f;
                    p.z = uz(rng);
                    break;
                case 4:  // a table
                    p.x = -2.f + 2.f * u01(rng);
                    p.y = -1.f + 2.f * u01(rng);
                    p.z = 0.75f;
                    break;
                case 5:  // a shelf
                    p.x = 2.f + u01(rng);
                    p.y = -3.f + 6.f * u01(rng);
                    p.z = 1.8f;
                    break;
                default:
                    p.x = k % 2 ? -6.f : 6.f;
                    p.y = uy(rng);
                    p.z = uz(rng);
                    break;
            }
            // Unseen by the camera, a point keeps its laser grey, as the worker journals it.
            const bool coloured = t >= kT0 + 10.0;
            p.intensity = 1000;
            const std::uint8_t grey = journal::laserGrey(p.intensity);
            p.r = coloured ? static_cast<std::uint8_t>(120 + 40 * (p.z > 0)) : grey;
            p.g = coloured ? static_cast<std::uint8_t>(80 + 100 * (p.x > 0)) : grey;
            p.b = coloured ? 60 : grey;
            batch.push_back(p);
        }
        if (!(*w)->appendPoints(batch).isOk()) return 1;
    }
    for (int k = 0; k <= 1200; ++k) {  // 20 Hz around an ellipse, back to the start
        const double a = 2 * M_PI * k / 1200.0;
        if (!(*w)->appendPose({kT0 + k * 0.05, 4.0 * std::cos(a), 2.5 * std::sin(a), 1.4, 0, 0,
                               std::sin(a / 2), std::cos(a / 2)})
                 .isOk())
            return 1;
    }
    if (!(*w)->finish().isOk()) return 1;
    w->reset();
    std::ofstream stats(out / "walk" / "stats.json");
    // tx degenerate from 30 to 35 s (the VIO solves it from 32 s), the VIO bypassed from 40 to
    // 45 s, tracking lost from 50 to 52 s.
    stats << "{\"vio\": {\"first_frame_s\": " << kT0 + 0.5
          << ", \"bypassed\": [{\"begin_s\": " << kT0 + 40.0 << ", \"end_s\": " << kT0 + 45.0
          << ", \"frames\": 50}]}, "
          << "\"tracking\": {\"lost_intervals\": [{\"begin_s\": " << kT0 + 50.0
          << ", \"end_s\": " << kT0 + 52.0 << ", \"reason\": \"too_few_correspondences\"}]}, "
          << "\"per_sweep\": [";
    for (int s = 0; s < 600; ++s) {
        const double t = kT0 + s * 0.1;
        const bool degenerate = t >= kT0 + 30.0 && t < kT0 + 35.0;
        const bool lost = t >= kT0 + 50.0 && t < kT0 + 52.0;
        stats << (s ? ", " : "") << "{\"t_start_s\": " << t
              << ", \"degenerate_directions\": " << (degenerate ? 1 : 0)
              << ", \"solved_dof_mask\": " << (degenerate ? 0x37 : 0x3F)
              << ", \"vio_solved_dof_mask\": " << (t >= kT0 + 32.0 && t < kT0 + 40.0 ? 0x3F : 0)
              << ", \"tracking\": \"" << (lost ? "lost" : "ok") << "\"}";
    }
    stats << "]}\n";
    stats.close();
    exporter::ExportOptions opt;
    opt.formats = {"e57"};
    auto r = exporter::exportScan((out / "walk").string(), (out / "target").string(), opt);
    if (!r.isOk()) return std::fprintf(stderr, "%s\n", r.status().message().c_str()), 1;
    std::printf("%s/report.html\n", r->directory.c_str());
    return 0;
}
