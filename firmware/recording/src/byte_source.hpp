// Random-access reading of a recording: a file (read piecewise, so multi-gigabyte recordings do
// not have to fit in memory) or a buffer already in memory.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::recording::detail {

class ByteSource {
public:
    virtual ~ByteSource() = default;
    virtual std::uint64_t size() const = 0;
    // Replaces `out` with bytes [offset, offset + n); fails if they are not all there.
    [[nodiscard]] virtual Status readAt(std::uint64_t offset, std::size_t n,
                                        std::vector<std::uint8_t>& out) = 0;
};

[[nodiscard]] Result<std::unique_ptr<ByteSource>> openFileSource(const std::string& path);
std::unique_ptr<ByteSource> memorySource(std::vector<std::uint8_t> bytes);

}  // namespace handscan::recording::detail
