// USB stick discovery against a fake /proc/self/mountinfo, sysfs and udev database.
#include "handscan/export/usb_target.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "export_test_support.hpp"
#include "handscan/export/exporter.hpp"

namespace handscan::exporter::testing {
namespace {

namespace fs = std::filesystem;

class UsbTargetTest : public ExportTest {
protected:
    // A fake system: an internal NVMe root, a USB stick (removable=1) at <dir>/media/stick, and a
    // USB disk that says removable=0 but udev knows is on USB at <dir>/media/disk.
    SystemPaths fakeSystem(bool with_stick, bool with_udev_disk) {
        const fs::path sys = dir_ / "sys";
        auto blockdev = [&](const std::string& majmin, const std::string& disk,
                            const std::string& part, const char* removable) {
            const fs::path devdir = sys / "devices" / "pci0" / "block" / disk;
            fs::create_directories(devdir / part);
            std::ofstream(devdir / "removable") << removable << "\n";
            fs::create_directories(sys / "dev" / "block");
            fs::create_directory_symlink(devdir / part, sys / "dev" / "block" / majmin);
        };
        blockdev("259:1", "nvme0n1", "nvme0n1p1", "0");
        std::ofstream mi(dir_ / "mountinfo");
        mi << "22 1 259:1 / / rw,relatime shared:1 - ext4 /dev/nvme0n1p1 rw\n";
        mi << "30 22 0:5 / /proc rw shared:5 - proc proc rw\n";
        if (with_stick) {
            blockdev("8:17", "sdb", "sdb1", "1");
            fs::create_directories(dir_ / "media" / "stick");
            mi << "40 22 8:17 / " << (dir_ / "media" / "stick").string()
               << " rw,nosuid - vfat /dev/sdb1 rw\n";
        }
        if (with_udev_disk) {
            blockdev("8:33", "sdc", "sdc1", "0");
            fs::create_directories(dir_ / "udev");
            std::ofstream(dir_ / "udev" / "b8:33")
                << "S:disk/by-id/usb-Disk\nE:ID_BUS=usb\nE:ID_TYPE=disk\n";
            fs::create_directories(dir_ / "media" / "my disk");
            mi << "41 22 8:33 / " << (dir_ / "media").string()
               << "/my\\040disk rw - exfat /dev/sdc1 rw\n";
        }
        return {(dir_ / "mountinfo").string(), sys.string(), (dir_ / "udev").string()};
    }
};

TEST_F(UsbTargetTest, FindsTheRemovableStickAndNotInternalStorage) {
    const SystemPaths paths = fakeSystem(true, false);
    const auto volumes = listVolumes(paths);
    ASSERT_EQ(volumes.size(), 2u);  // proc is not a block device
    EXPECT_FALSE(volumes[0].removable);
    EXPECT_TRUE(volumes[1].removable);
    auto stick = findUsbStick(paths);
    ASSERT_TRUE(stick.isOk()) << stick.status().message();
    EXPECT_EQ(stick->device, "/dev/sdb1");
    EXPECT_EQ(stick->mount_point, (dir_ / "media" / "stick").string());
}

TEST_F(UsbTargetTest, UdevUsbBusCountsAsRemovableAndMountPointsUnescape) {
    const SystemPaths paths = fakeSystem(false, true);
    auto stick = findUsbStick(paths);
    ASSERT_TRUE(stick.isOk()) << stick.status().message();
    EXPECT_EQ(stick->device, "/dev/sdc1");
    EXPECT_EQ(stick->mount_point, (dir_ / "media" / "my disk").string());
}

TEST_F(UsbTargetTest, NoStickMeansAClearErrorAndNoExport) {
    const SystemPaths paths = fakeSystem(false, false);
    const std::string journal = makeJournal(10);
    auto r = exportToUsb(journal, {}, paths);
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().message(),
              "no USB stick found: insert a stick (FAT32, exFAT or ext4), wait for it to mount, "
              "and try again");
}

TEST_F(UsbTargetTest, ExportToUsbWritesOntoTheStick) {
    const SystemPaths paths = fakeSystem(true, false);
    const std::string journal = makeJournal(50);
    auto r = exportToUsb(journal, {{"las"}, 0.0, "scan1", {}, {}, true, ""}, paths);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r->directory, (dir_ / "media" / "stick" / "scan1").string());
    EXPECT_TRUE(fs::exists(dir_ / "media" / "stick" / "scan1" / "cloud.las"));
}

}  // namespace
}  // namespace handscan::exporter::testing
