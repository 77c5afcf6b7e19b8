// libgpiod needs a GPIO chip (or gpio-sim): skipped when none exists.
#include <gtest/gtest.h>

#include <filesystem>

#include "handscan/gpio/gpio_lines.hpp"

namespace handscan::gpio {
namespace {

TEST(Gpiod, OpensTheFirstChipAndNamesAMissingOne) {
    auto missing = openGpiodChip("no-such-gpiochip");
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.status().message().find("no-such-gpiochip"), std::string::npos);
    if (!std::filesystem::exists("/dev/gpiochip0"))
        GTEST_SKIP() << "no /dev/gpiochip0 on this machine";
    auto chip = openGpiodChip("gpiochip0");
    ASSERT_TRUE(chip) << chip.status().message();
    EXPECT_EQ((*chip)->describe(), "gpio gpiochip0");
}

}  // namespace
}  // namespace handscan::gpio
