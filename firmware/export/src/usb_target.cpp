#include "handscan/export/usb_target.hpp"

#include <sys/statvfs.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace handscan::exporter {
namespace {

namespace fs = std::filesystem;

std::string readFirstLine(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    std::getline(in, line);
    return line;
}

// mountinfo escapes spaces etc. as \040.
std::string unescape(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '\\' && i + 3 < s.size()) {
            const std::string oct = s.substr(i + 1, 3);
            if (oct.size() == 3 &&
                std::all_of(oct.begin(), oct.end(), [](char c) { return c >= '0' && c <= '7'; })) {
                out.push_back(static_cast<char>(std::stoi(oct, nullptr, 8)));
                i += 3;
                continue;
            }
        }
        out.push_back(s[i]);
    }
    return out;
}

bool isRemovable(const SystemPaths& paths, unsigned major, unsigned minor) {
    const std::string id = std::to_string(major) + ":" + std::to_string(minor);
    // udev: ID_BUS=usb marks USB mass storage even when the stick claims removable=0.
    std::ifstream udev(fs::path(paths.udev_data) / ("b" + id));
    for (std::string line; std::getline(udev, line);) {
        if (line == "E:ID_BUS=usb" || line == "E:ID_USB_DRIVER=usb-storage") return true;
    }
    // sysfs: /sys/dev/block/M:m -> .../block/sdb/sdb1; `removable` lives on the disk.
    std::error_code ec;
    const fs::path dev = fs::canonical(fs::path(paths.sysfs) / "dev" / "block" / id, ec);
    if (ec) return false;
    for (const fs::path& p : {dev, dev.parent_path()}) {
        if (fs::exists(p / "removable")) return readFirstLine(p / "removable") == "1";
    }
    return false;
}

}  // namespace

std::vector<MountedVolume> listVolumes(const SystemPaths& paths) {
    std::vector<MountedVolume> out;
    std::ifstream in(paths.mountinfo);
    for (std::string line; std::getline(in, line);) {
        // id parent major:minor root mount-point options [optional...] - fstype source
        // super-options
        std::istringstream is(line);
        std::string id, parent, majmin, root, mount_point, options;
        is >> id >> parent >> majmin >> root >> mount_point >> options;
        std::string tok;
        while (is >> tok && tok != "-") {
        }
        std::string fstype, source, super_options;
        is >> fstype >> source >> super_options;
        if (source.rfind("/dev/", 0) != 0) continue;  // only block devices
        MountedVolume v;
        v.mount_point = unescape(mount_point);
        v.device = source;
        v.fs_type = fstype;
        if (std::sscanf(majmin.c_str(), "%u:%u", &v.major, &v.minor) != 2) continue;
        v.read_only = options.rfind("ro", 0) == 0 && (options.size() == 2 || options[2] == ',');
        v.removable = isRemovable(paths, v.major, v.minor);
        struct statvfs vfs {};
        if (::statvfs(v.mount_point.c_str(), &vfs) == 0)
            v.free_bytes = static_cast<std::uint64_t>(vfs.f_bavail) * vfs.f_frsize;
        out.push_back(v);
    }
    return out;
}

Result<MountedVolume> volumeOf(const std::string& path, const SystemPaths& paths) {
    std::error_code ec;
    const std::string abs = fs::weakly_canonical(fs::absolute(path), ec).string();
    const MountedVolume* best = nullptr;
    const auto volumes = listVolumes(paths);
    for (const MountedVolume& v : volumes) {
        const bool prefix =
            abs == v.mount_point || (abs.rfind(v.mount_point, 0) == 0 &&
                                     (v.mount_point == "/" || abs[v.mount_point.size()] == '/'));
        if (prefix && (!best || v.mount_point.size() > best->mount_point.size())) best = &v;
    }
    if (!best) return Status(StatusCode::kNotFound, path + ": not on a mounted block device");
    return *best;
}

Result<MountedVolume> findUsbStick(const SystemPaths& paths) {
    std::vector<MountedVolume> sticks;
    for (const MountedVolume& v : listVolumes(paths)) {
        if (v.removable && !v.read_only) sticks.push_back(v);
    }
    if (sticks.empty()) {
        return Status(StatusCode::kNotFound,
                      "no USB stick found: insert a stick (FAT32, exFAT or ext4), wait for it to "
                      "mount, and try again");
    }
    return *std::max_element(sticks.begin(), sticks.end(), [](const auto& a, const auto& b) {
        return a.free_bytes < b.free_bytes;
    });
}

}  // namespace handscan::exporter
