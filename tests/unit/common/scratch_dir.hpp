// A per-test scratch directory under the system temp directory, removed when the test ends, with
// an optional small tmpfs mounted inside it: a real filesystem that fills up, for disk-full tests.
#pragma once

#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace handscan::testing {

class ScratchDir {
public:
    // `prefix` + pid + the running test's name, so parallel tests and test binaries never meet.
    explicit ScratchDir(const std::string& prefix)
        : path_(std::filesystem::temp_directory_path() /
                (prefix + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() {
        if (mounted_) ::umount2(disk().c_str(), MNT_DETACH);
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    const std::filesystem::path& path() const { return path_; }

    // Mounts a tmpfs of `size` (mount(8) syntax, e.g. "8m") at path()/disk and returns that
    // path; empty when this process may not mount (the caller skips its test).
    std::filesystem::path mountSmallDisk(const std::string& size) {
        std::filesystem::create_directories(disk());
        if (::mount("tmpfs", disk().c_str(), "tmpfs", 0, ("size=" + size).c_str()) != 0) return {};
        mounted_ = true;
        return disk();
    }

private:
    std::filesystem::path disk() const { return path_ / "disk"; }

    std::filesystem::path path_;
    bool mounted_ = false;
};

}  // namespace handscan::testing
