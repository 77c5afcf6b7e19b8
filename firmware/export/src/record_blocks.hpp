// Fixed-size point records are encoded block by block into a small scratch that stays in the CPU
// cache (8192 points, 200-300 KiB), and each block is appended to the file's large I/O buffer:
// one tight loop per block, no per-point calls into the file, no allocation after the first block.
#pragma once

#include <algorithm>
#include <span>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/export/safe_file.hpp"
#include "handscan/journal/map_point.hpp"

namespace handscan::exporter {

// `encode(point, out)` writes one record of kRecordBytes and returns false when the point cannot
// be stored; then `reject(point)` says why, and nothing of that block is written.
template <std::size_t kRecordBytes, typename Encode, typename Reject>
Status writeRecords(SafeFileWriter& file, std::vector<std::uint8_t>& scratch,
                    std::span<const journal::MapPoint> points, Encode&& encode, Reject&& reject) {
    constexpr std::size_t kBlockPoints = 8192;
    scratch.resize(kBlockPoints * kRecordBytes);
    for (std::size_t first = 0; first < points.size(); first += kBlockPoints) {
        const std::span<const journal::MapPoint> block =
            points.subspan(first, std::min(kBlockPoints, points.size() - first));
        std::uint8_t* out = scratch.data();
        for (const journal::MapPoint& p : block) {
            if (!encode(p, out)) return reject(p);
            out += kRecordBytes;
        }
        if (Status s = file.write(
                std::span<const std::uint8_t>(scratch.data(), block.size() * kRecordBytes));
            !s.isOk())
            return s;
    }
    return Status::ok();
}

}  // namespace handscan::exporter
