// The transport of the live map: a POSIX shared-memory object (shm_open + mmap) or, for tests that
// want writer and readers in one address space (ThreadSanitizer sees both sides), an anonymous
// shared mapping. Only this file's implementation makes syscalls; the writer and reader above it
// work on bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "handscan/core/status.hpp"

namespace handscan::shm {

class SharedRegion {
public:
    // Identity of the object behind a name: a writer restart creates a new object (new inode),
    // which readers notice by comparing identities.
    struct Identity {
        std::uint64_t device = 0;
        std::uint64_t inode = 0;
        bool operator==(const Identity&) const = default;
    };

    // Replaces any object of that name by a fresh, zero-filled one of `bytes` bytes. Readers that
    // still map the old object keep valid memory and move over when they see the new identity.
    static Result<std::shared_ptr<SharedRegion>> create(const std::string& name, std::size_t bytes);
    // Maps an existing object read-write (readers write command requests).
    static Result<std::shared_ptr<SharedRegion>> open(const std::string& name);
    // Identity of the object currently behind `name`, kNotFound if there is none.
    static Result<Identity> identityOf(const std::string& name);
    static void unlink(const std::string& name);
    static std::uint64_t currentProcessId();
    // False once process `pid` has exited (and been reaped); true while it runs or cannot be told.
    static bool processExists(std::uint64_t pid);
    // A zero-filled MAP_SHARED|MAP_ANONYMOUS mapping (shared across fork(), no name).
    static Result<std::shared_ptr<SharedRegion>> anonymous(std::size_t bytes);

    ~SharedRegion();
    SharedRegion(const SharedRegion&) = delete;
    SharedRegion& operator=(const SharedRegion&) = delete;

    std::byte* data() const { return data_; }
    std::size_t size() const { return size_; }
    const std::string& name() const { return name_; }
    Identity identity() const { return identity_; }

private:
    SharedRegion(std::byte* data, std::size_t size, std::string name, Identity id)
        : data_(data), size_(size), name_(std::move(name)), identity_(id) {}
    std::byte* data_;
    std::size_t size_;
    std::string name_;
    Identity identity_;
};

// Checks a name for shm_open: "/" followed by 1..250 characters without another "/".
Status validateRegionName(const std::string& name);

}  // namespace handscan::shm
