#include "handscan/core/config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include "handscan/core/realtime.hpp"
#include "handscan/core/se3.hpp"

#ifndef HANDSCAN_SOURCE_CONFIG_DIR
#define HANDSCAN_SOURCE_CONFIG_DIR "config"
#endif

namespace handscan {
namespace {

// Walks a YAML document, checking each field; remembers the dotted key path for messages.
class Validator {
public:
    explicit Validator(std::string file) : file_(std::move(file)) {}

    [[noreturn]] void fail(const YAML::Node& node, const std::string& key,
                           const std::string& expected, const std::string& found) const {
        std::ostringstream os;
        os << file_;
        if (node.IsDefined() && node.Mark().line >= 0) os << ':' << node.Mark().line + 1;
        os << ": " << key << ": expected " << expected << ", got " << found;
        throw ConfigError(os.str());
    }

    static std::string show(const YAML::Node& node) {
        if (!node.IsDefined() || node.IsNull()) return "nothing";
        if (node.IsScalar()) return "'" + node.Scalar() + "'";
        if (node.IsSequence()) return "a list of " + std::to_string(node.size());
        return "a mapping";
    }

    // Rejects keys the schema does not know (a typo must not silently fall back to a default).
    void onlyKeys(const YAML::Node& map, const std::string& prefix,
                  const std::set<std::string>& known) const {
        if (!map.IsMap())
            fail(map, prefix.empty() ? "(top level)" : prefix, "a mapping", show(map));
        for (const auto& kv : map) {
            const std::string k = kv.first.as<std::string>();
            if (!known.count(k)) {
                std::string list;
                for (const auto& s : known) list += (list.empty() ? "" : ", ") + s;
                fail(kv.first, join(prefix, k), "one of the keys {" + list + "}",
                     "unknown key '" + k + "'");
            }
        }
    }

    static std::string join(const std::string& prefix, const std::string& key) {
        return prefix.empty() ? key : prefix + "." + key;
    }

    YAML::Node section(const YAML::Node& parent, const std::string& prefix, const std::string& key,
                       bool required = false) const {
        YAML::Node n = parent[key];
        if (!n.IsDefined()) {
            if (required) fail(parent, join(prefix, key), "a mapping", "nothing (missing)");
            return n;
        }
        if (!n.IsMap()) fail(n, join(prefix, key), "a mapping", show(n));
        return n;
    }

    void integer(const YAML::Node& parent, const std::string& prefix, const std::string& key,
                 int& out, long lo, long hi) const {
        const YAML::Node n = parent[key];
        if (!n.IsDefined()) return;  // default stays
        const std::string expected =
            "an integer in " + std::to_string(lo) + ".." + std::to_string(hi);
        long v = 0;
        if (!n.IsScalar() || !parseLong(n.Scalar(), v))
            fail(n, join(prefix, key), expected, show(n));
        if (v < lo || v > hi) fail(n, join(prefix, key), expected, n.Scalar());
        out = static_cast<int>(v);
    }

    void number(const YAML::Node& parent, const std::string& prefix, const std::string& key,
                double& out, double lo, double hi) const {
        const YAML::Node n = parent[key];
        if (!n.IsDefined()) return;
        std::ostringstream e;
        e << "a number in " << lo << ".." << hi;
        double v = 0;
        if (!n.IsScalar() || !parseDouble(n.Scalar(), v))
            fail(n, join(prefix, key), e.str(), show(n));
        if (!(v >= lo && v <= hi)) fail(n, join(prefix, key), e.str(), n.Scalar());
        out = v;
    }

    void text(const YAML::Node& parent, const std::string& prefix, const std::string& key,
              std::string& out, const std::set<std::string>& allowed = {}) const {
        const YAML::Node n = parent[key];
        if (!n.IsDefined()) return;
        std::string expected = "a non-empty string";
        if (!allowed.empty()) {
            expected = "one of";
            for (const auto& a : allowed) expected += " '" + a + "'";
        }
        if (!n.IsScalar() || n.Scalar().empty()) fail(n, join(prefix, key), expected, show(n));
        if (!allowed.empty() && !allowed.count(n.Scalar()))
            fail(n, join(prefix, key), expected, show(n));
        out = n.Scalar();
    }

    void boolean(const YAML::Node& parent, const std::string& prefix, const std::string& key,
                 bool& out) const {
        const YAML::Node n = parent[key];
        if (!n.IsDefined()) return;
        bool v = false;
        if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v))
            fail(n, join(prefix, key), "true or false", show(n));
        out = v;
    }

    std::vector<double> numbers(const YAML::Node& n, const std::string& key, std::size_t min_count,
                                std::size_t max_count) const {
        std::ostringstream e;
        if (min_count == max_count)
            e << "a list of " << min_count << " numbers";
        else
            e << "a list of " << min_count << ".." << max_count << " numbers";
        if (!n.IsSequence() || n.size() < min_count || n.size() > max_count)
            fail(n, key, e.str(), show(n));
        std::vector<double> out;
        for (const auto& item : n) {
            double v = 0;
            if (!item.IsScalar() || !parseDouble(item.Scalar(), v) || !std::isfinite(v))
                fail(item, key, e.str(), "element " + show(item));
            out.push_back(v);
        }
        return out;
    }

    // A rigid transform as a 4x4 row-major list of lists (Kalibr) whose rotation is orthonormal.
    Eigen::Isometry3d rigid(const YAML::Node& n, const std::string& key) const {
        if (!n.IsSequence() || n.size() != 4)
            fail(n, key, "a 4x4 matrix (list of 4 rows)", show(n));
        Eigen::Matrix4d M;
        for (int r = 0; r < 4; ++r) {
            const auto row = numbers(n[r], key + "[" + std::to_string(r) + "]", 4, 4);
            for (int c = 0; c < 4; ++c) M(r, c) = row[c];
        }
        const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
        const double ortho_err = (R * R.transpose() - Eigen::Matrix3d::Identity()).norm();
        if (ortho_err > 1e-3 || R.determinant() < 0.0) {
            std::ostringstream f;
            f << "a rotation with |R R^T - I| = " << ortho_err << " and det " << R.determinant();
            fail(n, key, "a rigid transform (orthonormal rotation, det +1)", f.str());
        }
        if (M.row(3).transpose() != Eigen::Vector4d(0, 0, 0, 1))
            fail(n[3], key, "last row [0, 0, 0, 1]", show(n[3]));
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = orthonormalize(R);
        T.translation() = M.topRightCorner<3, 1>();
        return T;
    }

    // A rigid transform written compactly as {translation: [x y z], rpy_deg: [r p y]}.
    Eigen::Isometry3d pose(const YAML::Node& parent, const std::string& prefix,
                           const std::string& key) const {
        const YAML::Node n = parent[key];
        const std::string k = join(prefix, key);
        if (!n.IsDefined())
            fail(parent, k, "a transform {translation, rpy_deg}", "nothing (missing)");
        onlyKeys(n, k, {"translation", "rpy_deg"});
        const auto t = numbers(n["translation"], k + ".translation", 3, 3);
        const auto rpy = numbers(n["rpy_deg"], k + ".rpy_deg", 3, 3);
        for (int i = 0; i < 3; ++i) {
            if (std::abs(t[i]) > 10.0)
                fail(n["translation"], k + ".translation", "metres within +-10",
                     std::to_string(t[i]));
        }
        const double d2r = M_PI / 180.0;
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = (Eigen::AngleAxisd(rpy[2] * d2r, Eigen::Vector3d::UnitZ()) *
                      Eigen::AngleAxisd(rpy[1] * d2r, Eigen::Vector3d::UnitY()) *
                      Eigen::AngleAxisd(rpy[0] * d2r, Eigen::Vector3d::UnitX()))
                         .toRotationMatrix();
        T.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
        return T;
    }

    static bool parseLong(const std::string& s, long& v) {
        char* end = nullptr;
        errno = 0;
        v = std::strtol(s.c_str(), &end, 10);
        return errno == 0 && end != s.c_str() && *end == '\0';
    }
    static bool parseDouble(const std::string& s, double& v) {
        char* end = nullptr;
        v = std::strtod(s.c_str(), &end);
        return end != s.c_str() && *end == '\0';
    }

private:
    std::string file_;
};

YAML::Node loadYaml(const std::string& path) {
    if (!std::filesystem::exists(path))
        throw ConfigError(path + ": cannot open: file does not exist");
    try {
        YAML::Node root = YAML::LoadFile(path);
        if (!root.IsDefined() || root.IsNull())
            throw ConfigError(path + ":1: (top level): expected a mapping, got an empty file");
        return root;
    } catch (const YAML::ParserException& e) {
        throw ConfigError(path + ":" + std::to_string(e.mark.line + 1) +
                          ": YAML syntax error: " + e.msg);
    } catch (const YAML::BadFile&) {
        throw ConfigError(path + ": cannot open: permission denied or not a file");
    }
}

void loadCamera(const Validator& v, const YAML::Node& root, const std::string& key,
                CameraConfig& c) {
    const YAML::Node n = v.section(root, "", key);
    if (!n.IsDefined()) return;
    v.onlyKeys(
        n, key,
        {"enabled", "device", "width", "height", "fps", "format", "exposure_ms", "readout_ms"});
    v.boolean(n, key, "enabled", c.enabled);
    v.text(n, key, "device", c.device);
    v.integer(n, key, "width", c.width, 16, 8192);
    v.integer(n, key, "height", c.height, 16, 8192);
    v.number(n, key, "fps", c.fps, 0.1, 500.0);
    v.text(n, key, "format", c.format, {"GREY", "YUYV", "MJPEG"});
    v.number(n, key, "exposure_ms", c.exposure_ms, 0.01, 1000.0);
    v.number(n, key, "readout_ms", c.readout_ms, 0.0, 1000.0);
}

CameraIntrinsics loadKalibrCamera(const Validator& v, const YAML::Node& n, const std::string& key) {
    CameraIntrinsics cam;
    v.onlyKeys(n, key,
               {"camera_model", "intrinsics", "distortion_model", "distortion_coeffs", "resolution",
                "T_cam_imu", "T_cn_cnm1", "timeshift_cam_imu", "rostopic", "cam_overlaps"});
    v.text(n, key, "camera_model", cam.camera_model, {"pinhole", "omni"});
    const auto intr = v.numbers(n["intrinsics"], key + ".intrinsics", 4, 5);
    if (intr[0] <= 0 || intr[1] <= 0)
        v.fail(n["intrinsics"], key + ".intrinsics", "positive focal lengths fu fv",
               std::to_string(intr[0]) + ", " + std::to_string(intr[1]));
    for (int i = 0; i < 4; ++i) cam.intrinsics[i] = intr[intr.size() - 4 + i];
    v.text(n, key, "distortion_model", cam.distortion_model, {"equidistant", "radtan", "none"});
    const std::size_t want = cam.distortion_model == "none" ? 0 : 4;
    cam.distortion_coeffs =
        v.numbers(n["distortion_coeffs"], key + ".distortion_coeffs", want, want);
    const auto res = v.numbers(n["resolution"], key + ".resolution", 2, 2);
    if (res[0] < 16 || res[1] < 16 || res[0] > 8192 || res[1] > 8192)
        v.fail(n["resolution"], key + ".resolution", "width and height in 16..8192",
               std::to_string(int(res[0])) + "x" + std::to_string(int(res[1])));
    cam.resolution = {static_cast<int>(res[0]), static_cast<int>(res[1])};
    if (n["T_cam_imu"].IsDefined()) cam.T_cam_imu = v.rigid(n["T_cam_imu"], key + ".T_cam_imu");
    v.number(n, key, "timeshift_cam_imu", cam.timeshift_cam_imu_s, -1.0, 1.0);
    return cam;
}

void parseRealtime(const YAML::Node& root, const Validator& v, RealtimeConfig& out) {
    const YAML::Node n = v.section(root, "", "realtime");
    if (!n.IsDefined()) return;
    v.onlyKeys(n, "realtime", {"device_priority", "pipeline_priority", "lock_memory"});
    v.integer(n, "realtime", "device_priority", out.device_priority, 0, 99);
    v.integer(n, "realtime", "pipeline_priority", out.pipeline_priority, 0, 99);
    v.boolean(n, "realtime", "lock_memory", out.lock_memory);
}

}  // namespace

DeviceConfig loadDeviceConfig(const std::string& path) {
    const YAML::Node root = loadYaml(path);
    const Validator v(path);
    v.onlyKeys(root, "",
               {"hokuyo", "xsens", "motor", "tracking_camera", "colour_camera", "gpio", "storage",
                "realtime"});
    DeviceConfig c;
    c.source_file = path;
    if (auto n = v.section(root, "", "hokuyo"); n.IsDefined()) {
        v.onlyKeys(
            n, "hokuyo",
            {"host", "port", "connect_timeout_s", "reconnect_max_backoff_s", "frame_latency_ms"});
        v.number(n, "hokuyo", "frame_latency_ms", c.hokuyo.frame_latency_ms, 0.0, 100.0);
        v.text(n, "hokuyo", "host", c.hokuyo.host);
        v.integer(n, "hokuyo", "port", c.hokuyo.port, 1, 65535);
        v.number(n, "hokuyo", "connect_timeout_s", c.hokuyo.connect_timeout_s, 0.01, 60.0);
        v.number(n, "hokuyo", "reconnect_max_backoff_s", c.hokuyo.reconnect_max_backoff_s, 0.01,
                 600.0);
    }
    if (auto n = v.section(root, "", "xsens"); n.IsDefined()) {
        v.onlyKeys(
            n, "xsens",
            {"transport", "serial_path", "baud", "rate_hz", "delta_q_v", "frame_latency_ms"});
        v.text(n, "xsens", "transport", c.xsens.transport, {"serial", "usb"});
        v.text(n, "xsens", "serial_path", c.xsens.serial_path);
        v.integer(n, "xsens", "baud", c.xsens.baud, 9600, 4000000);
        static const std::set<int> bauds{9600,   19200,  38400,  57600,   115200,
                                         230400, 460800, 921600, 2000000, 4000000};
        if (!bauds.count(c.xsens.baud))
            v.fail(n["baud"], "xsens.baud",
                   "one of 9600 19200 38400 57600 115200 230400 460800 921600 2000000 4000000",
                   n["baud"].Scalar());
        v.integer(n, "xsens", "rate_hz", c.xsens.rate_hz, 1, 2000);
        v.boolean(n, "xsens", "delta_q_v", c.xsens.delta_q_v);
        v.number(n, "xsens", "frame_latency_ms", c.xsens.frame_latency_ms, 0.0, 100.0);
    }
    if (auto n = v.section(root, "", "motor"); n.IsDefined()) {
        v.onlyKeys(n, "motor",
                   {"can_interface", "encoder_node_id", "drive_node_id", "encoder_counts_per_rev",
                    "tpdo_period_ms", "heartbeat_timeout_s", "target_speed_rev_s", "sweep_boundary",
                    "tpdo_latency_ms"});
        v.text(n, "motor", "can_interface", c.motor.can_interface);
        v.integer(n, "motor", "encoder_node_id", c.motor.encoder_node_id, 1, 127);
        v.integer(n, "motor", "drive_node_id", c.motor.drive_node_id, 1, 127);
        v.integer(n, "motor", "encoder_counts_per_rev", c.motor.encoder_counts_per_rev, 4, 1 << 30);
        v.integer(n, "motor", "tpdo_period_ms", c.motor.tpdo_period_ms, 1, 1000);
        v.number(n, "motor", "heartbeat_timeout_s", c.motor.heartbeat_timeout_s, 0.01, 60.0);
        v.number(n, "motor", "target_speed_rev_s", c.motor.target_speed_rev_s, 0.05, 10.0);
        v.text(n, "motor", "sweep_boundary", c.motor.sweep_boundary, {"half", "full"});
        v.number(n, "motor", "tpdo_latency_ms", c.motor.tpdo_latency_ms, 0.0, 100.0);
        if (c.motor.encoder_node_id == c.motor.drive_node_id)
            v.fail(n["drive_node_id"], "motor.drive_node_id",
                   "a node id different from encoder_node_id",
                   std::to_string(c.motor.drive_node_id));
    }
    loadCamera(v, root, "tracking_camera", c.tracking_camera);
    loadCamera(v, root, "colour_camera", c.colour_camera);
    if (auto n = v.section(root, "", "gpio"); n.IsDefined()) {
        v.onlyKeys(n, "gpio",
                   {"chip", "start_button_line", "export_button_line", "led_ready_line",
                    "led_scanning_line", "led_fault_line", "led_exporting_line", "debounce_ms"});
        v.text(n, "gpio", "chip", c.gpio.chip);
        for (auto [key, field] : {std::pair{"start_button_line", &c.gpio.start_button_line},
                                  {"export_button_line", &c.gpio.export_button_line},
                                  {"led_ready_line", &c.gpio.led_ready_line},
                                  {"led_scanning_line", &c.gpio.led_scanning_line},
                                  {"led_fault_line", &c.gpio.led_fault_line},
                                  {"led_exporting_line", &c.gpio.led_exporting_line}}) {
            v.integer(n, "gpio", key, *field, 0, 1023);
        }
        v.number(n, "gpio", "debounce_ms", c.gpio.debounce_ms, 0.0, 1000.0);
    }
    if (auto n = v.section(root, "", "storage"); n.IsDefined()) {
        v.onlyKeys(n, "storage", {"journal_dir", "recording_dir", "min_free_gib", "record_scans"});
        v.text(n, "storage", "journal_dir", c.storage.journal_dir);
        v.text(n, "storage", "recording_dir", c.storage.recording_dir);
        v.number(n, "storage", "min_free_gib", c.storage.min_free_gib, 0.0, 1e6);
        v.boolean(n, "storage", "record_scans", c.storage.record_scans);
    }
    RealtimeConfig realtime;  // validated with the rest; loadRealtimeConfig() hands it out
    parseRealtime(root, v, realtime);
    return c;
}

RealtimeConfig loadRealtimeConfig(const std::string& path) {
    const YAML::Node root = loadYaml(path);
    RealtimeConfig realtime;
    parseRealtime(root, Validator(path), realtime);
    return realtime;
}

void loadCamchain(const std::string& path, Calibration& calibration) {
    const YAML::Node root = loadYaml(path);
    const Validator v(path);
    v.onlyKeys(root, "", {"cam0", "cam1"});
    if (!root["cam0"].IsDefined()) v.fail(root, "cam0", "the tracking camera", "nothing (missing)");
    calibration.tracking = loadKalibrCamera(v, root["cam0"], "cam0");
    if (root["cam1"].IsDefined()) {
        calibration.colour = loadKalibrCamera(v, root["cam1"], "cam1");
        if (root["cam1"]["T_cn_cnm1"].IsDefined())
            calibration.T_colour_tracking = v.rigid(root["cam1"]["T_cn_cnm1"], "cam1.T_cn_cnm1");
    }
}

Calibration loadCalibration(const std::string& path) {
    const YAML::Node root = loadYaml(path);
    const Validator v(path);
    v.onlyKeys(root, "",
               {"T_shaft_laser", "T_camera_shaftbase", "encoder_zero_offset_deg", "time_offsets",
                "camchain"});
    Calibration c;
    c.source_file = path;
    c.T_shaft_laser = v.pose(root, "", "T_shaft_laser");
    c.T_camera_shaftbase = v.pose(root, "", "T_camera_shaftbase");
    double zero_deg = 0.0;
    v.number(root, "", "encoder_zero_offset_deg", zero_deg, -360.0, 360.0);
    c.encoder_zero_offset_rad = zero_deg * M_PI / 180.0;
    if (auto n = v.section(root, "", "time_offsets"); n.IsDefined()) {
        // The same ranges as device.yaml's keys they replace.
        v.onlyKeys(n, "time_offsets", {"xsens_frame_latency_ms", "motor_tpdo_latency_ms"});
        for (auto [key, field] : {std::pair{"xsens_frame_latency_ms", &c.xsens_frame_latency_ms},
                                  {"motor_tpdo_latency_ms", &c.motor_tpdo_latency_ms}}) {
            if (!n[key].IsDefined()) continue;
            double ms = 0.0;
            v.number(n, "time_offsets", key, ms, 0.0, 100.0);
            *field = ms;
        }
    }
    std::string camchain;
    v.text(root, "", "camchain", camchain);
    if (!camchain.empty()) {
        const std::filesystem::path p = std::filesystem::path(path).parent_path() / camchain;
        if (!std::filesystem::exists(p))
            v.fail(root["camchain"], "camchain", "an existing Kalibr camchain file",
                   "'" + p.string() + "' (missing)");
        loadCamchain(p.string(), c);
    }
    return c;
}

DeviceConfig withCalibratedLatencies(DeviceConfig device, const Calibration& calibration) {
    if (calibration.xsens_frame_latency_ms)
        device.xsens.frame_latency_ms = *calibration.xsens_frame_latency_ms;
    if (calibration.motor_tpdo_latency_ms)
        device.motor.tpdo_latency_ms = *calibration.motor_tpdo_latency_ms;
    return device;
}

std::string defaultConfigDir() {
    if (const char* env = std::getenv("HANDSCAN_CONFIG_DIR")) return env;
    if (std::filesystem::exists("/etc/handscan/device.yaml")) return "/etc/handscan";
    return HANDSCAN_SOURCE_CONFIG_DIR;
}

}  // namespace handscan
