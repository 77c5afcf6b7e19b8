#include "handscan/core/status.hpp"

#include <gtest/gtest.h>

namespace handscan {
namespace {

Result<int> parsePositive(int v) {
    if (v <= 0)
        return Status(StatusCode::kInvalidArgument,
                      "value must be positive, got " + std::to_string(v));
    return v;
}

TEST(Status, ResultCarriesValueOrError) {
    const auto good = parsePositive(3);
    ASSERT_TRUE(good.isOk());
    EXPECT_EQ(*good, 3);
    const auto bad = parsePositive(-1);
    ASSERT_FALSE(bad.isOk());
    EXPECT_EQ(bad.status().code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(bad.status().message(), "value must be positive, got -1");
    EXPECT_STREQ(toString(StatusCode::kChecksumError), "checksum error");
}

}  // namespace
}  // namespace handscan
