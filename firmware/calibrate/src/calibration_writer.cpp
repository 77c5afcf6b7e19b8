#include "handscan/calibrate/calibration_writer.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace handscan::calibrate {
namespace {

// Roll, pitch, yaw (deg) with R = Rz(y) Ry(p) Rx(r); exact for any R but pitch +-90 exactly.
Eigen::Vector3d rpyDeg(const Eigen::Matrix3d& R) {
    const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
    const double roll = std::atan2(R(2, 1), R(2, 2));
    const double yaw = std::atan2(R(1, 0), R(0, 0));
    return Eigen::Vector3d(roll, pitch, yaw) * 180.0 / M_PI;
}

std::string transform(const char* key, const Eigen::Isometry3d& T) {
    const Eigen::Vector3d t = T.translation();
    const Eigen::Vector3d rpy = rpyDeg(T.linear());
    return fmt::format(
        "{}:\n  translation: [{:.9f}, {:.9f}, {:.9f}]\n  rpy_deg: [{:.9f}, {:.9f}, {:.9f}]\n", key,
        t.x(), t.y(), t.z(), rpy.x(), rpy.y(), rpy.z());
}

}  // namespace

std::string camchainPathOf(const std::string& calibration_yaml) {
    try {
        const YAML::Node root = YAML::LoadFile(calibration_yaml);
        if (!root["camchain"].IsDefined()) return "";
        const std::string name = root["camchain"].as<std::string>();
        if (name.empty()) return "";
        return (std::filesystem::path(calibration_yaml).parent_path() / name).string();
    } catch (const YAML::Exception&) {
        return "";  // loadCalibration() has already read it; this cannot fail after that
    }
}

Status writeCalibrationYaml(const std::string& path, const Calibration& c,
                            const std::string& camchain, const std::vector<std::string>& comments) {
    std::string text;
    for (const std::string& line : comments) text += "# " + line + "\n";
    text += transform("T_shaft_laser", c.T_shaft_laser);
    text += transform("T_camera_shaftbase", c.T_camera_shaftbase);
    text +=
        fmt::format("encoder_zero_offset_deg: {:.9f}\n", c.encoder_zero_offset_rad * 180.0 / M_PI);
    if (c.xsens_frame_latency_ms || c.motor_tpdo_latency_ms) {
        text += "time_offsets:\n";
        if (c.xsens_frame_latency_ms)
            text += fmt::format("  xsens_frame_latency_ms: {:.6f}\n", *c.xsens_frame_latency_ms);
        if (c.motor_tpdo_latency_ms)
            text += fmt::format("  motor_tpdo_latency_ms: {:.6f}\n", *c.motor_tpdo_latency_ms);
    }
    if (!camchain.empty()) {
        namespace fs = std::filesystem;
        const fs::path dir = fs::absolute(fs::path(path)).parent_path();
        text += "camchain: " +
                fs::absolute(camchain).lexically_normal().lexically_relative(dir).string() + "\n";
    }
    const std::string tmp = path + ".tmp";
    {
        std::ofstream os(tmp, std::ios::trunc);
        os << text;
        if (!os.flush())
            return {StatusCode::kIoError, path + ": cannot write the calibration (" + tmp +
                                              "); check the folder exists and is writable"};
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec)
        return {StatusCode::kIoError, path + ": cannot replace the calibration: " + ec.message()};
    return Status::ok();
}

}  // namespace handscan::calibrate
