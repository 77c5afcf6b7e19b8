// Finds where a USB stick is mounted, and tells removable media from internal storage: the
// mount table gives each mount's device number; sysfs says whether that block device (or the
// disk it is a partition of) is `removable`, and udev's database whether it hangs on USB
// (ID_BUS=usb: many sticks report removable=0). Paths are injectable for tests.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::exporter {

struct SystemPaths {
    std::string mountinfo = "/proc/self/mountinfo";
    std::string sysfs = "/sys";
    std::string udev_data = "/run/udev/data";
};

struct MountedVolume {
    std::string mount_point;
    std::string device;  // /dev/sdb1
    std::string fs_type;
    unsigned major = 0, minor = 0;
    bool read_only = false;
    bool removable = false;  // sysfs removable flag or udev ID_BUS=usb
    std::uint64_t free_bytes = 0;
};

// Every mounted block device, with its removable flag.
std::vector<MountedVolume> listVolumes(const SystemPaths& paths = {});
// The volume holding `path` (the longest mount point that is a prefix of it).
Result<MountedVolume> volumeOf(const std::string& path, const SystemPaths& paths = {});
// The one removable, writable volume to export to (the one with most free space if several).
Result<MountedVolume> findUsbStick(const SystemPaths& paths = {});

}  // namespace handscan::exporter
