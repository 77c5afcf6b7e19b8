// Checks the CRC-32C of every 1024-byte page of an E57 file fed in pieces of any size, from the
// start of the file: the export's read-back from the medium and the reader both use it.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace handscan::exporter::e57 {

class PageChecker {
public:
    // Empty when every complete page so far is intact, else which page is not (once).
    std::string feed(std::span<const std::uint8_t> bytes);
    // After the last feed: empty when the file ended on a page boundary.
    std::string finish() const;
    std::uint64_t pages() const { return pages_; }

private:
    std::string checkPage(const std::uint8_t* page);
    std::array<std::uint8_t, 1024> partial_{};
    std::size_t partial_fill_ = 0;
    std::uint64_t pages_ = 0;
    bool failed_ = false;
};

}  // namespace handscan::exporter::e57
