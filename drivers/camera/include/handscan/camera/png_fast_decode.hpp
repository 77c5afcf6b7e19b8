// The PNG files png_payload.cpp writes (8-bit grey or grey+alpha, not interlaced, chunks IHDR,
// IDAT and IEND only) decoded without libpng: the chunks' CRCs checked and the IDAT stream
// inflated with libdeflate (its adler32 checked), then the rows unfiltered here (PNG spec,
// section 9: None, Sub, Up, Average, Paeth). Replay decodes a tracking-camera frame every 20 ms
// of recording, and libpng's zlib inflate plus its row-by-row read cost 2.2 ms of each
// 640 x 512 frame (2.2 s of a 20 s replay with every module; see tests/bench/camera).
//
// Anything outside that subset (another chunk, bit depth, colour type, interlacing) or anything
// that fails to decode returns false, and the caller reads the file with libpng, whose error
// message then says what is wrong: this is a shortcut for the files we write, not a second
// PNG reader to maintain.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace handscan::camera {

// Decodes `png` into `pixels` (width * channels * height bytes) when the file is an 8-bit
// grey (channels 1) or grey+alpha (channels 2) image of exactly width x height pixels in the
// subset above. Returns false otherwise; `pixels` is then unspecified.
bool decodePlainPng(std::span<const std::uint8_t> png, std::uint32_t width, std::uint32_t height,
                    int channels, std::vector<std::uint8_t>& pixels);

}  // namespace handscan::camera
