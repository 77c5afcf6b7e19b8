// The XML section of an E57 file (ASTM E2807 section 8.4, the E57 element tree): e57Root with the
// file's GUID and version, and one Data3D (data3D/vectorChild) for the scan with its sensor, pose,
// bounds, limits and the points' CompressedVector prototype; the trajectory as extension data.
#pragma once

#include <cstdint>
#include <string>

#include "handscan/export/point_formats.hpp"

namespace handscan::exporter::e57 {

struct ScanXml {
    std::string file_guid, scan_guid, name, description;
    std::string sensor_vendor, sensor_model, sensor_serial, software_version;
    double creation_gps_s = 0.0;  // seconds since 1980-01-06 (E57 DateTime)
    std::uint64_t points = 0;
    std::uint64_t points_offset = 0;  // physical offset of the points' section
    Bounds bounds;
    std::uint16_t intensity_min = 0, intensity_max = 0;
    std::uint64_t trajectory_poses = 0;  // 0: no trajectory section
    std::uint64_t trajectory_offset = 0;
    double coordinate_scale = 0.0;  // > 0: cartesianX/Y/Z are ScaledInteger of this scale
    std::int64_t coordinate_raw_min = 0, coordinate_raw_max = 0;
};

std::string scanXml(const ScanXml& scan);

// "{8-4-4-4-12}" random (version 4) GUID, as E57 writers use.
std::string randomGuid();

}  // namespace handscan::exporter::e57
