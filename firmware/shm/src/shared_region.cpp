// shm_open / mmap transport of the live map.
#include "handscan/shm/shared_region.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace handscan::shm {
namespace {

std::string errnoText(int err) { return std::strerror(err); }

class FdCloser {
public:
    explicit FdCloser(int fd) : fd_(fd) {}
    ~FdCloser() {
        if (fd_ >= 0) ::close(fd_);
    }
    FdCloser(const FdCloser&) = delete;
    FdCloser& operator=(const FdCloser&) = delete;

private:
    int fd_;
};

}  // namespace

Status validateRegionName(const std::string& name) {
    if (name.size() < 2 || name.size() > 250 || name[0] != '/' ||
        name.find('/', 1) != std::string::npos) {
        return {StatusCode::kInvalidArgument,
                "shared-memory name '" + name +
                    "': expected '/' followed by 1..249 characters without '/'"};
    }
    return Status::ok();
}

Result<std::shared_ptr<SharedRegion>> SharedRegion::create(const std::string& name,
                                                           std::size_t bytes) {
    if (Status s = validateRegionName(name); !s) return s;
    // A fresh object every time: old readers keep their (now nameless) mapping valid and notice
    // the new identity; nobody ever sees the region resized under them.
    if (::shm_unlink(name.c_str()) != 0 && errno != ENOENT) {
        return Status{StatusCode::kIoError, "shm_unlink(" + name + "): " + errnoText(errno) +
                                                " (remove /dev/shm" + name +
                                                " or pick another --shm-name)"};
    }
    const int fd = ::shm_open(name.c_str(), O_RDWR | O_CREAT | O_EXCL, 0660);
    if (fd < 0) {
        return Status{StatusCode::kIoError, "shm_open(" + name + ", create): " + errnoText(errno)};
    }
    FdCloser closer(fd);
    if (::ftruncate(fd, static_cast<off_t>(bytes)) != 0) {
        const int err = errno;
        ::shm_unlink(name.c_str());
        return Status{StatusCode::kNoSpace, "ftruncate(" + name + ", " + std::to_string(bytes) +
                                                " bytes): " + errnoText(err) +
                                                " (is /dev/shm full?)"};
    }
    struct stat st {};
    ::fstat(fd, &st);
    void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED) {
        const int err = errno;
        ::shm_unlink(name.c_str());
        return Status{StatusCode::kIoError, "mmap(" + name + "): " + errnoText(err)};
    }
    return std::shared_ptr<SharedRegion>(new SharedRegion(
        static_cast<std::byte*>(p), bytes, name,
        Identity{static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino)}));
}

Result<std::shared_ptr<SharedRegion>> SharedRegion::open(const std::string& name) {
    if (Status s = validateRegionName(name); !s) return s;
    const int fd = ::shm_open(name.c_str(), O_RDWR, 0);
    if (fd < 0) {
        const int err = errno;
        return Status{err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError,
                      "shm_open(" + name + "): " + errnoText(err)};
    }
    FdCloser closer(fd);
    struct stat st {};
    if (::fstat(fd, &st) != 0)
        return Status{StatusCode::kIoError, "fstat(" + name + "): " + errnoText(errno)};
    if (st.st_size <= 0)
        return Status{StatusCode::kTruncated,
                      "shared memory " + name + " is empty (writer starting?)"};
    const auto bytes = static_cast<std::size_t>(st.st_size);
    void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED)
        return Status{StatusCode::kIoError, "mmap(" + name + "): " + errnoText(errno)};
    return std::shared_ptr<SharedRegion>(new SharedRegion(
        static_cast<std::byte*>(p), bytes, name,
        Identity{static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino)}));
}

Result<SharedRegion::Identity> SharedRegion::identityOf(const std::string& name) {
    const int fd = ::shm_open(name.c_str(), O_RDONLY, 0);
    if (fd < 0) {
        const int err = errno;
        return Status{err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError,
                      "shm_open(" + name + "): " + errnoText(err)};
    }
    FdCloser closer(fd);
    struct stat st {};
    if (::fstat(fd, &st) != 0)
        return Status{StatusCode::kIoError, "fstat(" + name + "): " + errnoText(errno)};
    return Identity{static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino)};
}

void SharedRegion::unlink(const std::string& name) { ::shm_unlink(name.c_str()); }

std::uint64_t SharedRegion::currentProcessId() { return static_cast<std::uint64_t>(::getpid()); }

bool SharedRegion::processExists(std::uint64_t pid) {
    // Signal 0 checks existence only; EPERM means it exists under another user.
    return pid != 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH);
}

Result<std::shared_ptr<SharedRegion>> SharedRegion::anonymous(std::size_t bytes) {
    void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED)
        return Status{StatusCode::kIoError,
                      "mmap(anonymous, " + std::to_string(bytes) + "): " + errnoText(errno)};
    return std::shared_ptr<SharedRegion>(
        new SharedRegion(static_cast<std::byte*>(p), bytes, "", Identity{}));
}

SharedRegion::~SharedRegion() { ::munmap(data_, size_); }

}  // namespace handscan::shm
