// Lock-free single-producer / single-consumer ring buffer for samples between a driver thread and
// the pipeline thread. Wait-free for both sides; capacity is rounded up to a power of two. The
// producer never blocks: when full, tryPush fails and the caller counts a drop (a real-time
// driver must not stall on a slow consumer).
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <new>
#include <optional>
#include <utility>

namespace handscan {

template <typename T>
class SpscQueue {
public:
    explicit SpscQueue(std::size_t capacity) {
        std::size_t cap = 2;
        while (cap < capacity) cap <<= 1;
        mask_ = cap - 1;
        slots_ = std::make_unique<std::optional<T>[]>(cap);
    }
    SpscQueue(const SpscQueue&) = delete;
    SpscQueue& operator=(const SpscQueue&) = delete;

    std::size_t capacity() const { return mask_ + 1; }

    // Producer side only.
    template <typename U>
    bool tryPush(U&& value) {
        const std::size_t head = head_.load(std::memory_order_relaxed);
        if (head - tail_cache_ > mask_) {
            tail_cache_ = tail_.load(std::memory_order_acquire);
            if (head - tail_cache_ > mask_) return false;  // full
        }
        slots_[head & mask_].emplace(std::forward<U>(value));
        head_.store(head + 1, std::memory_order_release);
        return true;
    }

    // Consumer side only.
    std::optional<T> tryPop() {
        const std::size_t tail = tail_.load(std::memory_order_relaxed);
        if (tail == head_cache_) {
            head_cache_ = head_.load(std::memory_order_acquire);
            if (tail == head_cache_) return std::nullopt;  // empty
        }
        std::optional<T>& slot = slots_[tail & mask_];
        std::optional<T> out(std::move(*slot));
        slot.reset();
        tail_.store(tail + 1, std::memory_order_release);
        return out;
    }

    // Approximate (exact when called from either side while the other is idle).
    std::size_t size() const {
        return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire);
    }

private:
    static constexpr std::size_t kLine =
        64;  // keep producer and consumer indices on separate lines
    std::size_t mask_ = 0;
    std::unique_ptr<std::optional<T>[]> slots_;
    alignas(kLine) std::atomic<std::size_t> head_{0};  // written by the producer
    std::size_t tail_cache_ = 0;                       // producer's view of tail
    alignas(kLine) std::atomic<std::size_t> tail_{0};  // written by the consumer
    std::size_t head_cache_ = 0;                       // consumer's view of head
};

}  // namespace handscan
