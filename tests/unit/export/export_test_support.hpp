// Shared fixture: a temp directory with a small journal in it.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace handscan::exporter::testing {

// The whole file's bytes (empty when it cannot be read).
std::vector<std::uint8_t> readFile(const std::string& path);

// Tests that are not about report.pdf give ExportOptions{formats, voxel, name, {}, {}, true, ""}:
// report.html, no PDF (its program runs for a second; report_pdf_test.cpp covers it).
class ExportTest : public ::testing::Test {
protected:
    void SetUp() override;
    void TearDown() override;
    // Writes `n` points on a 1 m grid line with colours (i, 2i, 3i) mod 256 into a new journal.
    std::string makeJournal(std::size_t n, const std::string& name = "journal.hsj");
    // A tmpfs of `size` mounted at a new directory; empty string when mounting is not permitted.
    std::string mountTmpfs(const std::string& size, bool read_only = false);

    std::filesystem::path dir_;
    std::vector<std::string> mounts_;
};

}  // namespace handscan::exporter::testing
