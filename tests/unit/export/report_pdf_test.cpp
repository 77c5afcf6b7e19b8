// report.pdf beside report.html: made by weasyprint where it is installed; a missing, failing or
// misbehaving program leaves the export successful, without a PDF, and says why.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "export_test_support.hpp"
#include "handscan/export/exporter.hpp"

namespace handscan::exporter::testing {
namespace {

namespace fs = std::filesystem;

class ReportPdf : public ExportTest {
protected:
    Result<ExportReport> exportWith(const std::string& tool) {
        ExportOptions opt;
        opt.formats = {"ply"};
        opt.scan_name = "scan";
        opt.pdf_tool = tool;
        const std::string journal = makeJournal(2000);
        target_ = dir_ / "target";
        fs::create_directories(target_);
        return exportScan(journal, target_.string(), opt);
    }
    fs::path out() const { return target_ / "scan"; }
    fs::path target_;
    // No report.pdf and no partial file of it.
    void expectNoPdf() const {
        EXPECT_TRUE(fs::exists(out() / "report.html"));
        EXPECT_FALSE(fs::exists(out() / "report.pdf"));
        EXPECT_FALSE(fs::exists(out() / ".report.pdf.partial"));
    }
};

bool haveWeasyprint() { return ::access("/usr/bin/weasyprint", X_OK) == 0; }

TEST_F(ReportPdf, WrittenBesideTheHtmlWhereWeasyprintIsInstalled) {
    if (!haveWeasyprint()) GTEST_SKIP() << "weasyprint is not installed (tools/install-deps)";
    auto r = exportWith("weasyprint");
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_TRUE(r->notes.empty()) << r->notes.front();
    const fs::path pdf = out() / "report.pdf";
    ASSERT_TRUE(fs::exists(pdf));
    EXPECT_EQ(r->files.back(), pdf.string());
    const auto bytes = readFile(pdf.string());
    ASSERT_GT(bytes.size(), 1000u);
    EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 5), "%PDF-");
    const std::string tail(bytes.end() - 64, bytes.end());
    EXPECT_NE(tail.find("%%EOF"), std::string::npos);
    EXPECT_GT(r->pdf_seconds, 0.0);
}

TEST_F(ReportPdf, AMissingProgramIsANoteNotAFailure) {
    auto r = exportWith("/nonexistent/weasyprint");
    ASSERT_TRUE(r.isOk()) << r.status().message();
    ASSERT_EQ(r->notes.size(), 1u);
    EXPECT_NE(r->notes[0].find("'/nonexistent/weasyprint' is not installed"), std::string::npos)
        << r->notes[0];
    EXPECT_NE(r->notes[0].find("apt install weasyprint"), std::string::npos);
    expectNoPdf();
}

TEST_F(ReportPdf, AFailingProgramIsNamedWithItsExitCode) {
    auto r = exportWith("false");
    ASSERT_TRUE(r.isOk()) << r.status().message();
    ASSERT_EQ(r->notes.size(), 1u);
    EXPECT_NE(r->notes[0].find("failed (exit code 1)"), std::string::npos) << r->notes[0];
    expectNoPdf();
}

TEST_F(ReportPdf, OutputThatIsNoPdfIsNotKept) {
    auto r = exportWith("echo");  // prints its arguments and exits 0
    ASSERT_TRUE(r.isOk()) << r.status().message();
    ASSERT_EQ(r->notes.size(), 1u);
    EXPECT_NE(r->notes[0].find("wrote no complete PDF"), std::string::npos) << r->notes[0];
    expectNoPdf();
}

TEST_F(ReportPdf, NoProgramNoPdfNoNote) {
    auto r = exportWith("");
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_TRUE(r->notes.empty());
    expectNoPdf();
}

}  // namespace
}  // namespace handscan::exporter::testing
