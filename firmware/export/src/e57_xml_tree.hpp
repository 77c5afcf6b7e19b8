// The XML section of an E57 file, parsed with libxml2 into E57File's scans (ASTM E2807 8.4:
// e57Root, data3D/vectorChild, points prototype; our handscan:trajectory extension).
#pragma once

#include <string>

#include "handscan/core/status.hpp"
#include "handscan/export/e57_reader.hpp"

namespace handscan::exporter::e57 {

// Fills `file`'s guid and scans from the XML text; `where` names the file in errors.
Status parseXml(const std::string& xml, const std::string& where, E57File& file);

}  // namespace handscan::exporter::e57
