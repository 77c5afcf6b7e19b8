// Exports a scan from its journal into a directory: colourised point cloud (PLY, LAS 1.4, E57),
// trajectory (TUM and CSV), a JSON with device, calibration, software version and statistics, and
// report.html (handscan::report) and, where Debian's weasyprint is installed, report.pdf of it.
// Every file is written safely (see SafeFileWriter); free space is checked first; progress is
// reported. `exportToUsb` picks the removable stick, refuses anything else, and ends with a sync
// so the caller can say "safe to remove". The CLI, the UI and the GPIO export button all call this.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/export/point_formats.hpp"
#include "handscan/export/safe_file.hpp"
#include "handscan/export/usb_target.hpp"

namespace handscan::exporter {

struct ExportOptions {
    std::vector<std::string> formats{"ply", "las", "e57"};  // ply | las | e57
    double voxel_m = 0.0;                                   // 0: full resolution
    std::string scan_name;  // output sub-folder; default from the journal file
    // fraction in [0, 1] and what is being done
    std::function<void(double fraction, const std::string& stage)> progress;
    WriteFaults faults;  // test hook
    bool report = true;  // report.html: map views, health over time, loop-closure gap
    // The HTML-to-PDF program that makes report.pdf of report.html (name on PATH or a path);
    // empty: no PDF. When it is missing or fails the export still succeeds, with a note.
    std::string pdf_tool = "weasyprint";
    // Non-empty: the report's map from above (by height, with the trajectory) also as this PNG,
    // e.g. on the device's storage for the UI's export screen (written after the export files).
    std::string preview_png = {};
    // E57 coordinates: 0 doubles; > 0 scaled integers of this many metres (E57Options).
    double e57_scale_m = 0.0;
};

struct ExportReport {
    std::string directory;
    std::vector<std::string> files;
    std::uint64_t points = 0;  // points written (after voxel filtering)
    std::uint64_t journal_points = 0;
    // Points the colour camera saw (journal::hasColour).
    std::uint64_t coloured_points = 0;
    std::uint64_t bytes = 0;
    Bounds bounds;
    double seconds = 0.0;
    std::string journal_damage;  // non-empty when the journal was recovered after a crash
    // What the export left out and why (e.g. "no report.pdf: 'weasyprint' is not installed").
    std::vector<std::string> notes;
    double pdf_seconds = 0.0;  // rendering report.pdf
    std::string preview_png;   // ExportOptions::preview_png when it was written
};

// `source` is a journal file or a directory holding `journal.hsj`.
Result<ExportReport> exportScan(const std::string& source, const std::string& target_dir,
                                const ExportOptions& options);
// Same onto the USB stick; the report's directory is on the stick. Fails clearly when there is
// no stick, or when `paths` show the target is not removable.
Result<ExportReport> exportToUsb(const std::string& source, const ExportOptions& options,
                                 const SystemPaths& paths = {});

// Resolves a journal file from `source` (file, or directory with journal.hsj).
Result<std::string> findJournal(const std::string& source);

}  // namespace handscan::exporter
