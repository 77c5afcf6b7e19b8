// Two threads hammer the queue; run under the `tsan` preset for ThreadSanitizer.
#include "handscan/core/spsc_queue.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace handscan {
namespace {

TEST(SpscQueue, FifoAndFull) {
    SpscQueue<int> q(3);
    EXPECT_EQ(q.capacity(), 4u);
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(q.tryPush(i));
    EXPECT_FALSE(q.tryPush(99));  // full: producer is told, never blocks
    for (int i = 0; i < 4; ++i) EXPECT_EQ(q.tryPop().value(), i);
    EXPECT_FALSE(q.tryPop().has_value());
}

struct Payload {
    std::uint64_t seq;
    std::vector<std::uint64_t> body;  // heap data: a torn move would show as a mismatch
};

TEST(SpscQueue, TwoThreadsHammerInOrderWithoutLoss) {
    constexpr std::uint64_t kCount = 200'000;
    SpscQueue<Payload> q(64);
    std::thread producer([&] {
        for (std::uint64_t i = 0; i < kCount;) {
            if (q.tryPush(Payload{i, {i, i * 3, i * 7}}))
                ++i;
            else
                std::this_thread::yield();
        }
    });
    std::uint64_t expected = 0;
    std::uint64_t mismatches = 0;
    while (expected < kCount) {
        auto item = q.tryPop();
        if (!item) {
            std::this_thread::yield();
            continue;
        }
        if (item->seq != expected || item->body.size() != 3 || item->body[1] != expected * 3 ||
            item->body[2] != expected * 7) {
            ++mismatches;
        }
        ++expected;
    }
    producer.join();
    EXPECT_EQ(mismatches, 0u);
    EXPECT_FALSE(q.tryPop().has_value());
}

}  // namespace
}  // namespace handscan
