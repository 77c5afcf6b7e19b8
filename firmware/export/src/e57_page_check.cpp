#include "e57_page_check.hpp"

#include <algorithm>
#include <cstring>

#include "crc32c.hpp"
#include "e57_format.hpp"

namespace handscan::exporter::e57 {

std::string PageChecker::checkPage(const std::uint8_t* page) {
    const std::uint64_t index = pages_++;
    if (failed_) return {};
    const std::uint32_t stored = getCrcBigEndian(page + kPagePayload);
    const std::uint32_t actual = crc32c({page, kPagePayload});
    if (stored == actual) return {};
    failed_ = true;
    char msg[160];
    std::snprintf(
        msg, sizeof msg,
        "E57 page %llu (bytes %llu..%llu) is corrupt: CRC-32C 0x%08x stored, 0x%08x "
        "computed",
        static_cast<unsigned long long>(index), static_cast<unsigned long long>(index * kPageBytes),
        static_cast<unsigned long long>(index * kPageBytes + kPageBytes - 1), stored, actual);
    return msg;
}

std::string PageChecker::feed(std::span<const std::uint8_t> bytes) {
    std::string first;
    auto note = [&](std::string m) {
        if (first.empty()) first = std::move(m);
    };
    if (partial_fill_ > 0) {
        const std::size_t n = std::min(bytes.size(), kPageBytes - partial_fill_);
        std::memcpy(partial_.data() + partial_fill_, bytes.data(), n);
        partial_fill_ += n;
        bytes = bytes.subspan(n);
        if (partial_fill_ < kPageBytes) return first;
        note(checkPage(partial_.data()));
        partial_fill_ = 0;
    }
    for (; bytes.size() >= kPageBytes; bytes = bytes.subspan(kPageBytes))
        note(checkPage(bytes.data()));
    std::memcpy(partial_.data(), bytes.data(), bytes.size());
    partial_fill_ = bytes.size();
    return first;
}

std::string PageChecker::finish() const {
    if (partial_fill_ == 0) return {};
    return "E57 file ends " + std::to_string(partial_fill_) + " bytes into page " +
           std::to_string(pages_) + ": not a whole number of 1024-byte pages (truncated?)";
}

}  // namespace handscan::exporter::e57
