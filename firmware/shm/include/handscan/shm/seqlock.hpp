// Lock-free access to the shared region without any lock held across processes (Boehm,
// "Can seqlocks get along with programming language memory models?", 2012): the writer makes the
// counter odd, publishes with a release fence, stores the payload, and makes the counter even
// again; a reader copies the payload and accepts it only if the counter was even and unchanged
// around the copy. Payload words are copied with relaxed atomics, so concurrent access is
// defined behaviour (and ThreadSanitizer-clean) even while a reader copies a record being
// rewritten; the counter check then throws the torn copy away.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace handscan::shm {

inline std::atomic_ref<std::uint64_t> atomicWord(std::uint64_t& word) {
    return std::atomic_ref<std::uint64_t>(word);
}
inline std::atomic_ref<std::int64_t> atomicWord(std::int64_t& word) {
    return std::atomic_ref<std::int64_t>(word);
}

// Copies `bytes` (a multiple of 8, both sides 8-byte aligned) word by word with relaxed atomics.
inline void loadWordsRelaxed(void* dst, const void* src, std::size_t bytes) {
    auto* d = static_cast<std::uint64_t*>(dst);
    const auto* s = static_cast<const std::uint64_t*>(src);
    for (std::size_t i = 0; i < bytes / 8; ++i) d[i] = __atomic_load_n(s + i, __ATOMIC_RELAXED);
}
inline void storeWordsRelaxed(void* dst, const void* src, std::size_t bytes) {
    auto* d = static_cast<std::uint64_t*>(dst);
    const auto* s = static_cast<const std::uint64_t*>(src);
    for (std::size_t i = 0; i < bytes / 8; ++i) __atomic_store_n(d + i, s[i], __ATOMIC_RELAXED);
}

template <typename T>
void loadRelaxed(T& out, const T& shared) {
    static_assert(std::is_trivially_copyable_v<T> && sizeof(T) % 8 == 0 && alignof(T) >= 4);
    loadWordsRelaxed(&out, &shared, sizeof(T));
}
template <typename T>
void storeRelaxed(T& shared, const T& value) {
    static_assert(std::is_trivially_copyable_v<T> && sizeof(T) % 8 == 0 && alignof(T) >= 4);
    storeWordsRelaxed(&shared, &value, sizeof(T));
}

// Single-writer seqlock write of `value` into `shared` guarded by `lock`.
template <typename T>
void seqlockWrite(std::uint64_t& lock, T& shared, const T& value) {
    auto l = atomicWord(lock);
    const std::uint64_t s = l.load(std::memory_order_relaxed);
    l.store(s + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    storeRelaxed(shared, value);
    l.store(s + 2, std::memory_order_release);
}

// One attempt to read; false when the writer was (or may have been) inside its write.
template <typename T>
bool seqlockTryRead(std::uint64_t& lock, const T& shared, T& out) {
    auto l = atomicWord(lock);
    const std::uint64_t s1 = l.load(std::memory_order_acquire);
    if (s1 & 1u) return false;
    loadRelaxed(out, shared);
    std::atomic_thread_fence(std::memory_order_acquire);
    return l.load(std::memory_order_relaxed) == s1;
}

// Retries a bounded number of times: a writer never stays inside its write for long, and a dead
// writer (odd counter forever) must not hang the reader.
template <typename T>
bool seqlockRead(std::uint64_t& lock, const T& shared, T& out, int attempts = 1000) {
    for (int i = 0; i < attempts; ++i) {
        if (seqlockTryRead(lock, shared, out)) return true;
    }
    return false;
}

}  // namespace handscan::shm
