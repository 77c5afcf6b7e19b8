// report.pdf beside report.html, rendered by an external HTML-to-PDF program (Debian's
// `weasyprint`, no browser engine) from the report.html the export has just written. The PDF is a
// convenience: when the program is missing or fails, the export goes on without it and says so
// (`note`); only the medium failing while the PDF is written fails the export. The program's
// output streams into the same verified write as every other file (SafeFileWriter), and both the
// program's output and the copy read back from the medium must be a whole PDF (the "%PDF-"
// header and the "%%EOF" trailer).
#pragma once

#include <cstdint>
#include <string>

#include "handscan/core/status.hpp"
#include "handscan/export/safe_file.hpp"

namespace handscan::exporter {

struct ReportPdf {
    bool written = false;
    std::string note;  // why there is no report.pdf (empty when written or not asked for)
    std::uint64_t bytes = 0;
    double seconds = 0.0;  // the program's run, from start to its last byte
};

// `tool`: the program's name on PATH or its path; empty: no PDF, no note.
Result<ReportPdf> writeReportPdf(const std::string& html_path, const std::string& pdf_path,
                                 const std::string& tool, const WriteFaults& faults = {});

// Whether `head` (the file's first bytes) and `tail` (its last up to 1024) frame a PDF file.
bool looksLikePdf(const std::string& head, const std::string& tail);

}  // namespace handscan::exporter
