// `handscan info FILE.e57`: an E57 file's pages (every CRC-32C checked), GUID, and per scan its
// sensor, record count, prototype fields, decoded bounds, share of coloured points and trajectory.
#pragma once

#include <ostream>
#include <string>

namespace handscan::cli {

// 0 when the file reads, 3 when a page's CRC-32C does not match, 1 on any other error.
int printE57Info(const std::string& path, std::ostream& out);

}  // namespace handscan::cli
