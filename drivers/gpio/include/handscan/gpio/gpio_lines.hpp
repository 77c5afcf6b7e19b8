// The GPIO line interface the panel's state machine is written against, under the gpio driver's
// names. The interface and its libgpiod implementation are transports
// (handscan/transport/gpio_lines.hpp, drivers/transport/src/gpiod_lines.cpp); the fake line layer
// for tests is fake_gpio_chip.hpp.
#pragma once

#include "handscan/transport/gpio_lines.hpp"

namespace handscan::gpio {

using transport::Bias;
using transport::eventTimeToMonotonic;
using transport::GpioChip;
using transport::GpioInput;
using transport::GpioOutput;
using transport::InputRequest;
using transport::openGpiodChip;

}  // namespace handscan::gpio
