// `handscan calibrate REC.mcap [--calibration START.yaml] --out calibration.yaml`: self-calibration
// of the spinning laser and the clocks from an ordinary walk (handscan::calibrate).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "command_registry.hpp"
#include "handscan/calibrate/self_calibration.hpp"
#include "handscan/core/log.hpp"

namespace handscan::cli {
namespace {

void printCamchain(const calibrate::SelfCalibrationReport& r) {
    for (const auto& c : r.camchain.cameras) std::cout << "camchain: " << c.summary << "\n";
    if (!r.camchain_note.empty()) std::cout << "note: " << r.camchain_note << "\n";
}

bool camchainLooksWrong(const calibrate::SelfCalibrationReport& r) {
    return std::any_of(r.camchain.cameras.begin(), r.camchain.cameras.end(),
                       [](const auto& c) { return c.looks_wrong; });
}

void printReport(const calibrate::SelfCalibrationReport& r, const std::string& out) {
    std::cout << fmt::format("{:<28} {:>12} {:>12} {:>10}\n", "parameter", "start", "found", "std");
    for (const auto& p : r.parameters) {
        if (p.written)
            std::cout << fmt::format("{:<28} {:>9.4f} {:<2} {:>9.4f} {:<2} {:>7.4f} {}\n", p.name,
                                     p.start, p.unit, p.value, p.unit, p.std, p.unit);
        else
            std::cout << fmt::format("{:<28} {:>9.4f} {:<2} {:>12} {:>10}\n", p.name, p.start,
                                     p.unit, "kept", "-");
    }
    for (const auto& n : r.notes) std::cout << "note: " << n << "\n";
    std::cout << fmt::format(
        "half-revolution consistency (robust std of half-to-half distances): {:.2f} mm -> {:.2f} "
        "mm ({} -> {} planes); sweeps trusted by tracking {:.0f} % -> {:.0f} %; {} rounds\n",
        r.consistency_before_m * 1e3, r.consistency_after_m * 1e3, r.residuals_before,
        r.residuals_after, 100.0 * r.sweeps_ok_before, 100.0 * r.sweeps_ok_after, r.rounds);
    printCamchain(r);
    std::cout << "wrote " << out << "\n";
}

const RegisterCommand kCalibrate{
    "calibrate",
    "Self-calibrate the laser on its shaft, the encoder zero and the clocks from a recording",
    [](CLI::App& sub) {
        auto o = std::make_shared<calibrate::SelfCalibrationOptions>();
        sub.add_option("RECORDING", o->recording, "a 30-60 s walk (.mcap), no target needed")
            ->required()
            ->check(CLI::ExistingFile);
        sub.add_option("--out", o->out,
                       "calibration.yaml to write (required unless --check-camchain)");
        sub.add_flag("--check-camchain", o->camchain_only,
                     "only check the camchain against the recording's camera frames (one replay "
                     "with --calibration; writes nothing; exit status 2 when it looks wrong)");
        sub.add_flag("!--no-camchain-check", o->check_camchain,
                     "do not check the camchain after calibrating");
        sub.add_option("--calibration", o->start_calibration,
                       "starting calibration.yaml (default: config dir)")
            ->check(CLI::ExistingFile);
        sub.add_option("--device", o->device_config, "device.yaml (default: config dir)")
            ->check(CLI::ExistingFile);
        sub.add_option("--work-dir", o->work_dir,
                       "keep each round's replay here (default: a temporary folder, removed)");
        sub.add_option("--rounds", o->max_rounds, "at most this many replay-and-solve rounds")
            ->check(CLI::Range(1, 10));
        return std::function<int()>([o] {
            o->log = [](const std::string& line) { log().info("{}", line); };
            if (o->out.empty() && !o->camchain_only) {
                log().error("calibrate: --out is required (the calibration.yaml to write)");
                return 1;
            }
            try {
                auto r = calibrate::selfCalibrate(*o);
                if (!r.isOk()) {
                    log().error("{}", r.status().message());
                    return 1;
                }
                if (o->camchain_only) {
                    printCamchain(*r);
                    return camchainLooksWrong(*r) ? 2 : 0;
                }
                printReport(*r, o->out);
            } catch (const std::exception& e) {  // config loading reports by exception
                log().error("{}", e.what());
                return 1;
            }
            return 0;
        });
    }};

}  // namespace
}  // namespace handscan::cli
