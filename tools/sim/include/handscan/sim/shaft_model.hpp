// The spinning shaft: the motor turns the laser at ~1 rev/s with a speed ripple (cogging once and
// twice per revolution), so the angle is not a straight line in time and the encoder matters.
//   theta(t) = theta0 + w t + a1 sin(w t + p1) + a2 sin(2 w t + p2)
// The laser's pose: T_W_L(t) = T_W_C(t) * T_C_B * Rz(theta(t)) * T_S_L (calibration.yaml), and the
// encoder reads theta + encoder_zero_offset (so shaft angle = encoder angle - offset).
#pragma once

#include <cmath>
#include <numbers>

namespace handscan::sim {

struct ShaftConfig {
    double speed_rev_s = 1.0;
    double ripple1 = 0.02;  // fraction of the speed, once per revolution
    double ripple2 = 0.01;  // twice per revolution
    double phase1 = 0.7;
    double phase2 = 2.1;
    double theta0 = 0.3;
};

class ShaftModel {
public:
    explicit ShaftModel(const ShaftConfig& c) : c_(c), w_(2.0 * std::numbers::pi * c.speed_rev_s) {}
    double angle(double t) const {
        return c_.theta0 + w_ * t + c_.ripple1 * std::sin(w_ * t + c_.phase1) +
               c_.ripple2 / 2.0 * std::sin(2.0 * w_ * t + c_.phase2);
    }
    double speed(double t) const {
        return w_ * (1.0 + c_.ripple1 * std::cos(w_ * t + c_.phase1) +
                     c_.ripple2 * std::cos(2.0 * w_ * t + c_.phase2));
    }

private:
    ShaftConfig c_;
    double w_;
};

}  // namespace handscan::sim
