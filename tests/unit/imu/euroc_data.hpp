// Loaders for the EuRoC MAV captures in ../shared/data/imu/euroc (see its SOURCE.txt): imu0
// data.csv (t ns, gyro xyz rad/s, accel xyz m/s^2) and state_groundtruth_estimate0 data.csv
// (t ns, p, q wxyz, v, b_w, b_a). Tests skip when the directory is absent.
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/imu/nav_state.hpp"

namespace handscan::imu::testing {

inline std::string eurocDir() { return std::string(HANDSCAN_SHARED_DATA_DIR) + "/imu/euroc"; }

inline std::vector<std::vector<double>> readCsvRows(const std::string& path,
                                                    std::vector<TimeNs>* times) {
    std::vector<std::vector<double>> rows;
    std::ifstream f(path);
    std::string line;
    while (std::getline(f, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::stringstream ss(line);
        std::string cell;
        std::getline(ss, cell, ',');
        times->push_back(std::stoll(cell));
        std::vector<double> r;
        while (std::getline(ss, cell, ',')) r.push_back(std::stod(cell));
        rows.push_back(std::move(r));
    }
    return rows;
}

inline std::vector<ImuSample> readEurocImu(const std::string& path) {
    std::vector<TimeNs> t;
    const auto rows = readCsvRows(path, &t);
    std::vector<ImuSample> out(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        out[i].t_host = t[i];
        out[i].gyro_radps_imu = {rows[i][0], rows[i][1], rows[i][2]};
        out[i].accel_mps2_imu = {rows[i][3], rows[i][4], rows[i][5]};
    }
    return out;
}

struct EurocGroundTruth {
    NavState state;
    ImuBiases biases;
};

inline std::vector<EurocGroundTruth> readEurocGroundTruth(const std::string& path) {
    std::vector<TimeNs> t;
    const auto rows = readCsvRows(path, &t);
    std::vector<EurocGroundTruth> out(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const auto& r = rows[i];
        out[i].state.t = t[i];
        out[i].state.p_world_imu = {r[0], r[1], r[2]};
        out[i].state.R_world_imu =
            Eigen::Quaterniond(r[3], r[4], r[5], r[6]).normalized().toRotationMatrix();
        out[i].state.v_world_imu = {r[7], r[8], r[9]};
        out[i].biases.gyro_radps = {r[10], r[11], r[12]};
        out[i].biases.accel_mps2 = {r[13], r[14], r[15]};
    }
    return out;
}

}  // namespace handscan::imu::testing
