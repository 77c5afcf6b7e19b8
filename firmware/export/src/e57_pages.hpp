// Cuts a stream of E57 logical bytes into 1024-byte physical pages, each ending in the CRC-32C of
// its 1020 payload bytes, and hands whole pages to the safe file. Page 0 (the file header) is
// reserved in the file and written last; the stream starts on page 1.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "handscan/core/status.hpp"
#include "handscan/export/safe_file.hpp"

namespace handscan::exporter::e57 {

class PageFramer {
public:
    explicit PageFramer(SafeFileWriter& file);
    Status append(std::span<const std::uint8_t> logical_bytes);
    Status appendZeros(std::size_t n);
    // Pads the current page with zeros and writes out every page.
    Status finish();
    std::uint64_t logicalOffset() const { return logical_; }  // where the next byte lands
    std::uint64_t physicalLength() const;                     // after finish()

private:
    Status flushPages();

    static constexpr std::size_t kStagePages = 64;  // 64 KiB to the safe file at a time
    SafeFileWriter& file_;
    std::array<std::uint8_t, kStagePages * 1024> stage_{};
    std::size_t stage_pages_ = 0;  // complete pages in stage_
    std::size_t page_fill_ = 0;    // payload bytes in the page being filled
    std::uint64_t logical_;
};

}  // namespace handscan::exporter::e57
