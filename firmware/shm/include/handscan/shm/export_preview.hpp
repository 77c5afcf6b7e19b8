// Where the pipeline leaves the picture of the last export's map for the UI's export screen: a
// PNG beside the live-map region in /dev/shm (tmpfs: shared by the daemon and the UI whatever their
// users, gone at reboot), named after the region, because the USB stick the export went to is
// unmounted as soon as it is safe to remove. Written by the export (exporter::ExportOptions::
// preview_png: the scan report's map from above) before the export status says done.
#pragma once

#include <string>
#include <string_view>

namespace handscan::shm {

inline std::string exportPreviewPath(std::string_view region_name) {
    while (!region_name.empty() && region_name.front() == '/') region_name.remove_prefix(1);
    return "/dev/shm/" + std::string(region_name) + "-export-preview.png";
}

}  // namespace handscan::shm
