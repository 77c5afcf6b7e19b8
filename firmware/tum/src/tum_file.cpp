#include "handscan/tum/tum_file.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace handscan::tum {

Result<Trajectory> parseTum(const std::string& text, const std::string& name) {
    Trajectory out;
    std::istringstream in(text);
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream ls(line);
        double v[8];
        for (double& x : v) {
            if (!(ls >> x)) {
                return Status(
                    StatusCode::kInvalidArgument,
                    fmt::format("{}:{}: expected 8 numbers 't tx ty tz qx qy qz qw', got '{}'",
                                name, line_no, line));
            }
        }
        Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
        const double n = q.norm();
        if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-2) {
            return Status(
                StatusCode::kInvalidArgument,
                fmt::format("{}:{}: quaternion norm {} is not 1; is the order qx qy qz qw?", name,
                            line_no, n));
        }
        StampedPose p;
        p.t_s = v[0];
        p.T.linear() = q.normalized().toRotationMatrix();
        p.T.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
        if (!out.empty() && p.t_s <= out.back().t_s) {
            return Status(
                StatusCode::kInvalidArgument,
                fmt::format("{}:{}: time {} is not after the previous pose's {}; sort the file",
                            name, line_no, p.t_s, out.back().t_s));
        }
        out.push_back(p);
    }
    return out;
}

Result<Trajectory> readTum(const std::string& path) {
    std::ifstream f(path);
    if (!f)
        return Status(StatusCode::kNotFound, fmt::format("{}: cannot open TUM trajectory", path));
    std::stringstream ss;
    ss << f.rdbuf();
    return parseTum(ss.str(), path);
}

std::string formatTumLine(const StampedPose& p) {
    const Eigen::Quaterniond q(p.T.linear());
    const Eigen::Vector3d& t = p.T.translation();
    return fmt::format("{:.9f} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f} {:.9f}\n", p.t_s, t.x(),
                       t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
}

Status writeTum(const std::string& path, const Trajectory& trajectory) {
    std::ofstream f(path);
    if (!f)
        return Status(StatusCode::kIoError, fmt::format("{}: cannot create TUM trajectory", path));
    f << "# t tx ty tz qx qy qz qw\n";
    for (const auto& p : trajectory) f << formatTumLine(p);
    f.flush();
    if (!f) return Status(StatusCode::kIoError, fmt::format("{}: write failed (disk full?)", path));
    return Status::ok();
}

}  // namespace handscan::tum
