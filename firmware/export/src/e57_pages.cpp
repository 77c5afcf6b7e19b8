#include "e57_pages.hpp"

#include <algorithm>
#include <cstring>

#include "crc32c.hpp"
#include "e57_format.hpp"

namespace handscan::exporter::e57 {

PageFramer::PageFramer(SafeFileWriter& file) : file_(file), logical_(kPagePayload) {}

Status PageFramer::append(std::span<const std::uint8_t> bytes) {
    while (!bytes.empty()) {
        std::uint8_t* page = stage_.data() + stage_pages_ * kPageBytes;
        const std::size_t n = std::min<std::size_t>(bytes.size(), kPagePayload - page_fill_);
        std::memcpy(page + page_fill_, bytes.data(), n);
        page_fill_ += n;
        logical_ += n;
        bytes = bytes.subspan(n);
        if (page_fill_ == kPagePayload) {
            putCrcBigEndian(page + kPagePayload, crc32c({page, kPagePayload}));
            page_fill_ = 0;
            if (++stage_pages_ == kStagePages) {
                if (Status s = flushPages(); !s.isOk()) return s;
            }
        }
    }
    return Status::ok();
}

Status PageFramer::appendZeros(std::size_t n) {
    static constexpr std::array<std::uint8_t, 1024> kZeros{};
    while (n > 0) {
        const std::size_t k = std::min(n, kZeros.size());
        if (Status s = append({kZeros.data(), k}); !s.isOk()) return s;
        n -= k;
    }
    return Status::ok();
}

Status PageFramer::finish() {
    if (page_fill_ > 0) {
        if (Status s = appendZeros(kPagePayload - page_fill_); !s.isOk()) return s;
    }
    return flushPages();
}

std::uint64_t PageFramer::physicalLength() const { return physicalOf(logical_); }

Status PageFramer::flushPages() {
    const std::size_t bytes = stage_pages_ * kPageBytes;
    stage_pages_ = 0;
    return file_.write({stage_.data(), bytes});
}

}  // namespace handscan::exporter::e57
