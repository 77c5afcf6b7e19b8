#include "handscan/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "handscan/core/se3.hpp"
#include "handscan/sim/random.hpp"

namespace handscan::sim {
namespace {

// Z-Y-X Euler (yaw psi, pitch theta, roll phi) -> rotation.
Eigen::Matrix3d rotZYX(double yaw, double pitch, double roll) {
    return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
        .toRotationMatrix();
}

}  // namespace

Eigen::Matrix3d Trajectory::deviceFromCamera() {
    Eigen::Matrix3d R;
    // columns: camera x (right) = -F y, camera y (down) = -F z, camera z (forward) = F x
    R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    return R;
}

Trajectory::Trajectory(double dt, std::vector<Vector6d> control, double duration)
    : dt_(dt), c_(std::move(control)) {
    const double last = c_.empty() ? 0.0 : dt_ * static_cast<double>(c_.size() - 1);
    duration_ = duration < 0.0 ? last : std::min(duration, last);
}

double Trajectory::duration() const { return duration_; }

BodyState Trajectory::at(double t) const {
    BodyState s;
    s.t = t;
    if (c_.empty()) return s;
    const double u = std::clamp(t, 0.0, duration()) / dt_;
    const auto n = static_cast<long>(c_.size());
    long i = static_cast<long>(std::floor(u));
    double x = u - static_cast<double>(i);
    if (i >= n - 1) {
        i = n - 1;
        x = 0.0;
    }
    // Uniform cubic B-spline basis over control points i-1 .. i+2 (indices clamped at the ends).
    const double x2 = x * x, x3 = x2 * x, m = 1.0 - x;
    const double b[4] = {m * m * m / 6.0, (3 * x3 - 6 * x2 + 4) / 6.0,
                         (-3 * x3 + 3 * x2 + 3 * x + 1) / 6.0, x3 / 6.0};
    const double d[4] = {-m * m / 2.0, (3 * x2 - 4 * x) / 2.0, (-3 * x2 + 2 * x + 1) / 2.0,
                         x2 / 2.0};
    const double dd[4] = {m, 3 * x - 2, -3 * x + 1, x};
    Vector6d p = Vector6d::Zero(), v = Vector6d::Zero(), a = Vector6d::Zero();
    for (int k = 0; k < 4; ++k) {
        const Vector6d& c = c_[static_cast<std::size_t>(std::clamp(i - 1 + k, 0L, n - 1))];
        p += b[k] * c;
        v += d[k] * c;
        a += dd[k] * c;
    }
    v /= dt_;
    a /= dt_ * dt_;
    const double psi = p[3], th = p[4], ph = p[5];
    const double dpsi = v[3], dth = v[4], dph = v[5];
    const double ddpsi = a[3], ddth = a[4], ddph = a[5];
    const double sth = std::sin(th), cth = std::cos(th), sph = std::sin(ph), cph = std::cos(ph);
    // Body rates of a Z-Y-X Euler sequence and their exact time derivatives.
    const Eigen::Vector3d w_f(dph - dpsi * sth, dth * cph + dpsi * cth * sph,
                              -dth * sph + dpsi * cth * cph);
    const Eigen::Vector3d al_f(ddph - ddpsi * sth - dpsi * dth * cth,
                               ddth * cph - dth * dph * sph + ddpsi * cth * sph -
                                   dpsi * dth * sth * sph + dpsi * dph * cth * cph,
                               -ddth * sph - dth * dph * cph + ddpsi * cth * cph -
                                   dpsi * dth * sth * cph - dpsi * dph * cth * sph);
    const Eigen::Matrix3d R_fc = deviceFromCamera();
    s.T_world_body.linear() = rotZYX(psi, th, ph) * R_fc;
    s.T_world_body.translation() = p.head<3>();
    s.v_world = v.head<3>();
    s.a_world = a.head<3>();
    s.omega_body = R_fc.transpose() * w_f;
    s.alpha_body = R_fc.transpose() * al_f;
    return s;
}

double Trajectory::peakAngularRate(double step) const {
    double peak = 0.0;
    for (double t = 0.0; t <= duration(); t += step) peak = std::max(peak, at(t).omega_body.norm());
    return peak;
}

double Trajectory::pathLength(double step) const {
    double len = 0.0;
    Eigen::Vector3d prev = at(0.0).T_world_body.translation();
    for (double t = step; t <= duration(); t += step) {
        const Eigen::Vector3d p = at(t).T_world_body.translation();
        len += (p - prev).norm();
        prev = p;
    }
    return len;
}

namespace {

// Chaikin corner cutting on a closed polygon: converges to a quadratic B-spline that stays
// inside the polygon's corners (walkers cut corners, and door approaches stay straight).
std::vector<Eigen::Vector3d> chaikinClosed(std::vector<Eigen::Vector3d> p, int iterations) {
    for (int it = 0; it < iterations; ++it) {
        std::vector<Eigen::Vector3d> q;
        q.reserve(2 * p.size());
        for (std::size_t i = 0; i < p.size(); ++i) {
            const Eigen::Vector3d& a = p[i];
            const Eigen::Vector3d& b = p[(i + 1) % p.size()];
            q.push_back(0.75 * a + 0.25 * b);
            q.push_back(0.25 * a + 0.75 * b);
        }
        p = std::move(q);
    }
    return p;
}

double smootherstep(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * x * (x * (6 * x - 15) + 10);
}

// Moving average over +-half samples (several passes approximate a Gaussian).
void smooth(std::vector<double>& v, int half, int passes) {
    std::vector<double> tmp(v.size());
    for (int p = 0; p < passes; ++p) {
        double sum = 0.0;
        const long n = static_cast<long>(v.size());
        auto at = [&](long i) { return v[static_cast<std::size_t>(std::clamp(i, 0L, n - 1))]; };
        for (long i = -half; i <= half; ++i) sum += at(i);
        for (long i = 0; i < n; ++i) {
            tmp[static_cast<std::size_t>(i)] = sum / (2 * half + 1);
            sum += at(i + half + 1) - at(i - half);
        }
        v.swap(tmp);
    }
}

}  // namespace

WalkPlan makeWalk(const std::vector<Eigen::Vector3d>& loop, const WalkOptions& o) {
    WalkPlan plan;
    const double ds = 0.02;
    // 1. Smooth closed path, resampled by arc length, starting at the point nearest loop[0].
    const std::vector<Eigen::Vector3d> curve = chaikinClosed(loop, 6);
    std::vector<Eigen::Vector3d> pts;
    {
        std::size_t start = 0;
        for (std::size_t i = 0; i < curve.size(); ++i)
            if ((curve[i] - loop[0]).norm() < (curve[start] - loop[0]).norm()) start = i;
        std::vector<Eigen::Vector3d> ring;
        for (std::size_t k = 0; k <= curve.size(); ++k)
            ring.push_back(curve[(start + k) % curve.size()]);
        pts.push_back(ring[0]);
        double carry = 0.0;
        for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
            const Eigen::Vector3d seg = ring[i + 1] - ring[i];
            const double len = seg.norm();
            double at = ds - carry;
            while (at <= len) {
                pts.push_back(ring[i] + seg * (at / len));
                at += ds;
            }
            carry = len - (at - ds);
        }
    }
    // Another start on the same loop: the resampled lap turned by the fraction.
    if (const double f = o.start_fraction - std::floor(o.start_fraction); f > 0.0) {
        const auto k =
            static_cast<std::ptrdiff_t>(std::llround(f * static_cast<double>(pts.size())));
        std::rotate(pts.begin(), pts.begin() + std::min<std::ptrdiff_t>(k, std::ssize(pts) - 1),
                    pts.end());
    }
    const std::size_t m = pts.size();
    const double L = ds * static_cast<double>(m);
    auto P = [&](double s) {  // position at arc length s (periodic), linear between samples
        double u = std::fmod(s, L) / ds;
        if (u < 0) u += static_cast<double>(m);
        const std::size_t i = static_cast<std::size_t>(u) % m;
        const double f = u - std::floor(u);
        return Eigen::Vector3d((1 - f) * pts[i] + f * pts[(i + 1) % m]);
    };
    // 2. Speed limits along one lap: curvature (lateral acceleration) and stairs.
    std::vector<double> vlim(m);
    for (std::size_t i = 0; i < m; ++i) {
        const double s = ds * static_cast<double>(i);
        const Eigen::Vector3d a = P(s - 0.1), b = P(s), c = P(s + 0.1);
        const Eigen::Vector2d t0 = (b - a).head<2>().normalized(),
                              t1 = (c - b).head<2>().normalized();
        const double kappa =
            std::abs(std::atan2(t0.x() * t1.y() - t0.y() * t1.x(), t0.dot(t1))) / 0.1;
        const double slope = std::abs(c.z() - a.z()) / 0.2;
        double v = kappa > 1e-6 ? std::sqrt(o.lateral_accel_mps2 / kappa) : 10.0;
        if (slope > 0.15) v = std::min(v, 0.6);  // stairs
        vlim[i] = v;
    }
    const double walk_time = o.duration_s - o.still_start_s - o.still_end_s;
    // 3. Speed profile over `laps` laps for a cruise speed; returns the walking time.
    auto profile = [&](double cruise, int laps, std::vector<double>& v) {
        const std::size_t n = m * static_cast<std::size_t>(laps) + 1;
        v.assign(n, 0.0);
        for (std::size_t i = 0; i < n; ++i) v[i] = std::min(cruise, vlim[i % m]);
        smooth(v, 15, 3);
        const double acc = 0.5;
        v[0] = 0.0;
        for (std::size_t i = 1; i < n; ++i)
            v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2 * acc * ds));
        v[n - 1] = 0.0;
        for (std::size_t i = n - 1; i-- > 0;)
            v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2 * acc * ds));
        double t = 0.0;
        for (std::size_t i = 1; i < n; ++i) t += 2 * ds / (v[i] + v[i - 1] + 1e-9);
        return t;
    };
    std::vector<double> v;
    int laps = std::max(1, static_cast<int>(std::floor(walk_time * 0.9 / L)));
    double cruise = 1.0;
    plan.closed = walk_time > 0 && profile(o.speed_max_mps, 1, v) <= walk_time;
    if (plan.closed) {
        while (laps > 1 && profile(o.speed_max_mps, laps, v) > walk_time) --laps;
        double lo = 0.2, hi = o.speed_max_mps;
        for (int it = 0; it < 50; ++it) {
            cruise = 0.5 * (lo + hi);
            (profile(cruise, laps, v) > walk_time ? lo : hi) = cruise;
        }
        cruise = hi;
    }
    (void)profile(cruise, laps, v);
    plan.laps = laps;
    plan.cruise_speed_mps = cruise;
    // Cumulative time at each arc-length sample.
    std::vector<double> tcum(v.size(), 0.0);
    for (std::size_t i = 1; i < v.size(); ++i)
        tcum[i] = tcum[i - 1] + 2 * ds / (v[i] + v[i - 1] + 1e-9);
    const double S = ds * static_cast<double>(v.size() - 1);
    auto sOfT = [&](double t) {  // arc length walked after t seconds of walking
        if (t <= 0) return 0.0;
        if (t >= tcum.back()) return S;
        const auto it = std::upper_bound(tcum.begin(), tcum.end(), t);
        const std::size_t i = static_cast<std::size_t>(it - tcum.begin()) - 1;
        const double f = (t - tcum[i]) / (tcum[i + 1] - tcum[i]);
        return ds * (static_cast<double>(i) + f);
    };
    const double t_walk_end =
        o.still_start_s + (plan.closed ? tcum.back() : walk_time + o.still_end_s);
    // 4. Control points every dt: position along the path plus gait, heading plus looking around.
    const double dt = 0.04;
    Rng phase_rng(o.seed, "walk");
    const double ph1 = phase_rng.uniform(0, 6.28), ph2 = phase_rng.uniform(0, 6.28),
                 ph3 = phase_rng.uniform(0, 6.28);
    // Three control points past the end keep the spline's last interval free of clamping.
    const std::size_t count = static_cast<std::size_t>(std::ceil(o.duration_s / dt)) + 4;
    auto build = [&](double aggressive_gain) {
        std::vector<Vector6d> c(count);
        double prev_yaw = 0.0;
        for (std::size_t k = 0; k < count; ++k) {
            const double t = dt * static_cast<double>(k);
            const double s = sOfT(t - o.still_start_s);
            // Gate: 0 while still, 1 while walking (smooth), scales every walking motion.
            const double g =
                smootherstep((t - o.still_start_s) / 1.5) * smootherstep((t_walk_end - t) / 1.5);
            const Eigen::Vector3d pos = P(s);
            const Eigen::Vector3d ahead = P(s + 0.5) - P(s);
            double yaw = std::atan2(ahead.y(), ahead.x());
            if (k > 0) yaw = prev_yaw + std::remainder(yaw - prev_yaw, 2 * std::numbers::pi);
            prev_yaw = yaw;
            const double gait = 2 * std::numbers::pi * s / 0.7;  // one bounce per 0.7 m step
            const Eigen::Vector3d left(-std::sin(yaw), std::cos(yaw), 0.0);
            Vector6d cp;
            cp.head<3>() = pos + g * (0.015 * -std::cos(gait) * Eigen::Vector3d::UnitZ() +
                                      0.02 * std::sin(gait / 2) * left);
            double y = yaw + g * 0.35 * std::sin(2 * std::numbers::pi * t / 7.3 + ph1);
            double p = -0.12 + g * (0.15 * std::sin(2 * std::numbers::pi * t / 9.1 + ph2) +
                                    0.02 * std::sin(gait));
            double r = g * 0.04 * std::sin(gait / 2 + ph3);
            if (o.style == MotionStyle::kAggressive) {
                y += aggressive_gain * g * 0.9 * std::sin(2 * std::numbers::pi * 0.9 * t + ph1);
                p += aggressive_gain * g * 0.5 * std::sin(2 * std::numbers::pi * 1.3 * t + ph2);
                r += aggressive_gain * g * 0.5 * std::sin(2 * std::numbers::pi * 1.1 * t + ph3);
            }
            cp[3] = y;
            cp[4] = p;
            cp[5] = r;
            c[k] = cp;
        }
        return c;
    };
    plan.trajectory = Trajectory(dt, build(1.0), o.duration_s);
    if (o.style == MotionStyle::kAggressive) {
        // Scale the violent rotation until the peak rate is the requested one (Figure 30: 370
        // deg/s).
        double gain = 1.0;
        const double target = o.peak_rate_dps * std::numbers::pi / 180.0;
        for (int it = 0; it < 6; ++it) {
            const double peak = plan.trajectory.peakAngularRate(0.005);
            gain *= target / peak;
            plan.trajectory = Trajectory(dt, build(gain), o.duration_s);
        }
    }
    return plan;
}

Result<Trajectory> loadTum(const std::string& path) {
    std::ifstream in(path);
    if (!in) return Status{StatusCode::kNotFound, path + ": cannot open TUM trajectory"};
    struct Pose {
        double t;
        Eigen::Vector3d p;
        Eigen::Quaterniond q;
    };
    std::vector<Pose> poses;
    std::string line;
    int lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ss(line);
        Pose p;
        double qx, qy, qz, qw;
        if (!(ss >> p.t >> p.p.x() >> p.p.y() >> p.p.z() >> qx >> qy >> qz >> qw)) {
            return Status{StatusCode::kInvalidArgument,
                          path + ":" + std::to_string(lineno) +
                              ": expected 't x y z qx qy qz qw', got '" + line + "'"};
        }
        p.q = Eigen::Quaterniond(qw, qx, qy, qz);
        if (std::abs(p.q.norm() - 1.0) > 1e-3) {
            return Status{StatusCode::kInvalidArgument,
                          path + ":" + std::to_string(lineno) + ": quaternion not unit"};
        }
        p.q.normalize();
        if (!poses.empty() && p.t <= poses.back().t) {
            return Status{StatusCode::kInvalidArgument,
                          path + ":" + std::to_string(lineno) + ": time not increasing"};
        }
        poses.push_back(p);
    }
    if (poses.size() < 2)
        return Status{StatusCode::kInvalidArgument, path + ": needs at least two poses"};
    const double dt = 0.01;
    const double t0 = poses.front().t, T = poses.back().t - t0;
    const Eigen::Matrix3d R_fc = Trajectory::deviceFromCamera();
    std::vector<Vector6d> c;
    std::size_t j = 0;
    double py = 0, pr = 0;
    for (double t = 0.0; t <= T + 1e-9; t += dt) {
        while (j + 2 < poses.size() && poses[j + 1].t - t0 < t) ++j;
        const Pose& a = poses[j];
        const Pose& b = poses[j + 1];
        const double f = std::clamp((t + t0 - a.t) / (b.t - a.t), 0.0, 1.0);
        const Eigen::Matrix3d R_wf = (a.q.slerp(f, b.q)).toRotationMatrix() * R_fc.transpose();
        // Z-Y-X Euler angles, unwrapped against the previous sample.
        double yaw = std::atan2(R_wf(1, 0), R_wf(0, 0));
        const double pitch = std::asin(std::clamp(-R_wf(2, 0), -1.0, 1.0));
        double roll = std::atan2(R_wf(2, 1), R_wf(2, 2));
        if (!c.empty()) {
            yaw = py + std::remainder(yaw - py, 2 * std::numbers::pi);
            roll = pr + std::remainder(roll - pr, 2 * std::numbers::pi);
        }
        py = yaw;
        pr = roll;
        Vector6d cp;
        cp << (1 - f) * a.p + f * b.p, yaw, pitch, roll;
        c.push_back(cp);
    }
    return Trajectory(dt, std::move(c));
}

}  // namespace handscan::sim
