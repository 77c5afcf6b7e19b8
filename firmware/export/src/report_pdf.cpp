#include "report_pdf.hpp"

#include <algorithm>
#include <memory>

#include "tool_process.hpp"

namespace handscan::exporter {
namespace {

constexpr double kTimeoutS = 300.0;  // a board renders a long walk's report in well under this
constexpr std::size_t kTail = 1024;  // PDF readers look for %%EOF in the last 1024 bytes

// The first and the last bytes of a stream that arrives in pieces.
struct Ends {
    std::string head, tail;
    std::uint64_t bytes_seen = 0;
    void add(std::span<const std::uint8_t> bytes) {
        bytes_seen += bytes.size();
        const auto* c = reinterpret_cast<const char*>(bytes.data());
        if (head.size() < 8) head.append(c, std::min<std::size_t>(8 - head.size(), bytes.size()));
        tail.append(c, bytes.size());
        if (tail.size() > 2 * kTail) tail.erase(0, tail.size() - kTail);
    }
    bool pdf() const {
        return looksLikePdf(head, tail.size() > kTail ? tail.substr(tail.size() - kTail) : tail);
    }
};

std::string lastLine(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    const auto nl = text.rfind('\n');
    return nl == std::string::npos ? text : text.substr(nl + 1);
}

}  // namespace

bool looksLikePdf(const std::string& head, const std::string& tail) {
    return head.rfind("%PDF-", 0) == 0 && tail.find("%%EOF") != std::string::npos;
}

Result<ReportPdf> writeReportPdf(const std::string& html_path, const std::string& pdf_path,
                                 const std::string& tool, const WriteFaults& faults) {
    ReportPdf r;
    if (tool.empty()) return r;
    const auto program = findProgram(tool);
    if (!program) {
        r.note = "no report.pdf: '" + tool +
                 "' is not installed (Debian: apt install weasyprint); report.html holds the same "
                 "report";
        return r;
    }
    SafeFileWriter file(pdf_path, faults);
    if (Status s = file.open(); !s.isOk()) return s;
    // The copy on the medium must be a whole PDF too; checked on the read-back's last piece,
    // before the file gets its final name.
    auto read_back = std::make_shared<Ends>();
    auto total = std::make_shared<std::uint64_t>(0);
    file.setReadBackCheck([read_back, total](std::span<const std::uint8_t> bytes) {
        read_back->add(bytes);
        if (read_back->bytes_seen < *total || read_back->pdf()) return std::string();
        return std::string("it reads back from the medium as no PDF (header or trailer changed)");
    });
    Ends written;
    Status write_error;
    auto run = runTool(
        {*program, "--quiet", html_path, "-"},
        [&](std::span<const std::uint8_t> bytes) {
            written.add(bytes);
            write_error = file.write(bytes);
            return write_error.isOk() ? std::string() : write_error.message();
        },
        kTimeoutS);
    if (!write_error.isOk()) return write_error;  // the medium, not the program
    if (!run.isOk()) {
        r.note = "no report.pdf: " + run.status().message();
        return r;
    }
    r.seconds = run->seconds;
    if (run->timed_out || !run->exited || run->exit_code != 0) {
        r.note = "no report.pdf: " + *program + " " +
                 (run->timed_out ? "did not finish within " + std::to_string(int(kTimeoutS)) + " s"
                  : run->exited  ? "failed (exit code " + std::to_string(run->exit_code) + ")"
                                 : "was killed") +
                 (run->stderr_tail.empty() ? "" : ": " + lastLine(run->stderr_tail));
        return r;
    }
    if (!written.pdf()) {
        r.note = "no report.pdf: " + *program + " wrote no complete PDF (" +
                 std::to_string(file.bytesWritten()) +
                 " bytes without the %PDF- header or the %%EOF trailer)";
        return r;
    }
    *total = file.bytesWritten();
    if (Status s = file.commit(); !s.isOk()) return s;
    r.written = true;
    r.bytes = file.bytesWritten();
    return r;
}

}  // namespace handscan::exporter
