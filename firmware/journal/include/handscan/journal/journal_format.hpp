// On-disk layout of the map journal: one append-only file of self-checking chunks, so that a power
// cut or kill -9 leaves a readable prefix. Every chunk is
//
//   ChunkHeader (40 bytes, little-endian) | payload (payload_bytes)
//
// Chunk kinds: metadata (JSON), points (28-byte records), trajectory (64-byte poses), per-sweep
// statistics (SweepRecord, each prefixed by its own length and layout so later fields can be
// appended; journals from before them simply have none), end of scan.
//
// with a CRC32 (zlib) over the payload and another over the header's first 36 bytes. A reader
// accepts chunks in order until the first one that is truncated or fails a check; everything
// before it is intact because each chunk is fdatasync'ed before the next is started.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "handscan/journal/map_point.hpp"
#include "handscan/journal/sweep_record.hpp"

namespace handscan::journal {

constexpr std::uint32_t kChunkMagic = 0x434A5348;  // "HSJC" little-endian
constexpr std::uint16_t kFormatVersion = 1;
constexpr std::size_t kChunkHeaderBytes = 40;
constexpr std::size_t kPointRecordBytes = 28;
constexpr std::size_t kPoseRecordBytes = 64;

enum class ChunkKind : std::uint16_t {
    kMetadata = 1,
    kPoints = 2,
    kTrajectory = 3,
    kEndOfScan = 4,
    kSweepStats = 5,
};

struct ChunkHeader {
    std::uint32_t magic = kChunkMagic;
    std::uint16_t version = kFormatVersion;
    ChunkKind kind = ChunkKind::kPoints;
    std::uint64_t sequence = 0;  // 0, 1, 2, ... in file order
    std::uint32_t record_count = 0;
    std::uint32_t payload_bytes = 0;
    double t_last_s = 0.0;  // newest time inside (points / poses), for "lost at most"
    std::uint32_t payload_crc = 0;
    std::uint32_t header_crc = 0;  // over the 36 bytes before it
};

std::vector<std::uint8_t> encodeHeader(
    const ChunkHeader& header);  // fills both CRCs' slots as given
// Decodes and checks magic, version and header CRC. False when any fails.
bool decodeHeader(std::span<const std::uint8_t> bytes, ChunkHeader& out);

std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t seed = 0);

void encodePoints(std::span<const MapPoint> points, std::vector<std::uint8_t>& out);
void decodePoints(std::span<const std::uint8_t> payload, std::vector<MapPoint>& out);
// Into `out` (sized by the caller: no allocation, no initialisation of what is overwritten).
void decodePoints(std::span<const std::uint8_t> payload, std::span<MapPoint> out);
void encodePoses(std::span<const TrajectoryPose> poses, std::vector<std::uint8_t>& out);
void decodePoses(std::span<const std::uint8_t> payload, std::vector<TrajectoryPose>& out);
// Per-sweep records: u16 record bytes, u16 layout, the fields (kSweepRecordBytes with these two in
// layout 1; a later layout appends after them), and last the tracking reason's text (its length
// at record byte 25). A newer layout's longer record is read for the fields known.
constexpr std::uint16_t kSweepRecordLayout = 1;
constexpr std::size_t kSweepRecordBytes = 168;
void encodeSweeps(std::span<const SweepRecord> sweeps, std::vector<std::uint8_t>& out);
// Appends every whole record; empty when all were, else what the first bad one is and where
// ("record 3 at payload byte 504: ...") - the records before it are kept.
std::string decodeSweeps(std::span<const std::uint8_t> payload, std::vector<SweepRecord>& out);

}  // namespace handscan::journal
