#include "stress_workload.hpp"

#include <string>
#include <thread>
#include <vector>

#include "handscan/shm/text_field.hpp"

namespace handscan::shm::stress {
namespace {

using Clock = std::chrono::steady_clock;

PoseRecord poseOf(std::uint64_t k) {
    PoseRecord p;
    p.t_ns = static_cast<std::int64_t>(k);
    for (int i = 0; i < 3; ++i) p.position_m[i] = static_cast<double>(k) * (i + 1);
    for (int i = 0; i < 4; ++i) p.orientation_xyzw[i] = static_cast<double>(k) + i;
    for (int i = 0; i < 6; ++i)
        p.covariance_diag[i] = static_cast<float>(k % 1000003) + static_cast<float>(i);
    p.vio_dof_mask = static_cast<std::uint8_t>(k & 0x3F);
    p.scan_dof_mask = static_cast<std::uint8_t>((k >> 6) & 0x3F);
    return p;
}

bool poseConsistent(const PoseRecord& p) {
    const auto k = static_cast<std::uint64_t>(p.t_ns);
    const PoseRecord e = poseOf(k);
    for (int i = 0; i < 3; ++i)
        if (p.position_m[i] != e.position_m[i]) return false;
    for (int i = 0; i < 4; ++i)
        if (p.orientation_xyzw[i] != e.orientation_xyzw[i]) return false;
    for (int i = 0; i < 6; ++i)
        if (p.covariance_diag[i] != e.covariance_diag[i]) return false;
    return p.vio_dof_mask == e.vio_dof_mask && p.scan_dof_mask == e.scan_dof_mask;
}

StatusBlock statusOf(std::uint64_t k) {
    StatusBlock s;
    s.t_ns = static_cast<std::int64_t>(k);
    s.sensor_count = kMaxSensors;
    for (std::size_t i = 0; i < kMaxSensors; ++i) {
        setText(s.sensors[i].name, "s" + std::to_string(k));
        setText(s.sensors[i].last_error, std::string(50 + k % 50, static_cast<char>('a' + k % 26)));
        s.sensors[i].rate_hz = static_cast<float>(k % 100000);
    }
    s.elapsed_s = static_cast<double>(k);
    s.distance_m = 2.0 * static_cast<double>(k);
    s.point_count = 3 * k;
    setText(s.message, std::to_string(k));
    return s;
}

bool statusConsistent(const StatusBlock& s) {
    const auto k = static_cast<std::uint64_t>(s.t_ns);
    const StatusBlock e = statusOf(k);
    for (std::size_t i = 0; i < kMaxSensors; ++i) {
        if (getText(s.sensors[i].name) != getText(e.sensors[i].name)) return false;
        if (getText(s.sensors[i].last_error) != getText(e.sensors[i].last_error)) return false;
        if (s.sensors[i].rate_hz != e.sensors[i].rate_hz) return false;
    }
    return s.elapsed_s == e.elapsed_s && s.distance_m == e.distance_m &&
           s.point_count == e.point_count && getText(s.message) == getText(e.message);
}

// Point i of a scan: x = i (exact in float below 2^24), y = 1000 + i % 7, colour from i.
DisplayPoint pointOf(std::uint64_t i) {
    DisplayPoint p;
    p.x_m = static_cast<float>(i);
    p.y_m = 1000.0f + static_cast<float>(i % 7);
    p.z_m = -static_cast<float>(i);
    p.r = static_cast<std::uint8_t>(i);
    p.g = static_cast<std::uint8_t>(i >> 8);
    p.b = static_cast<std::uint8_t>(i >> 16);
    p.intensity = static_cast<std::uint8_t>(i * 7);
    return p;
}

bool pointIs(const DisplayPoint& p, std::uint64_t i) {
    const DisplayPoint e = pointOf(i);
    return p.x_m == e.x_m && p.y_m == e.y_m && p.z_m == e.z_m && p.r == e.r && p.g == e.g &&
           p.b == e.b && p.intensity == e.intensity;
}

}  // namespace

void runWriter(LiveMapWriter& writer, std::chrono::milliseconds duration,
               std::uint64_t points_per_scan) {
    const auto end = Clock::now() + duration;
    std::uint64_t k = 1;
    std::uint64_t scan_points = 0;
    std::vector<DisplayPoint> chunk;
    while (Clock::now() < end) {
        for (int i = 0; i < 8; ++i) writer.publishPose(poseOf(k++));
        writer.setStatus(statusOf(k));
        if (scan_points >= points_per_scan) {
            writer.newScan();
            scan_points = 0;
        }
        chunk.clear();
        const std::uint64_t n = 1 + k % 257;
        for (std::uint64_t i = 0; i < n; ++i) chunk.push_back(pointOf(scan_points + i));
        if (writer.appendPoints(chunk).isOk()) scan_points += n;
        while (auto cmd = writer.pollCommand()) {
            writer.ack(cmd->seq, CommandState::kDone,
                       "ack " + std::to_string(cmd->seq) + " " + cmd->argument);
        }
    }
}

ReaderStats runReader(LiveMapReader& reader, std::chrono::milliseconds duration) {
    ReaderStats st;
    const auto end = Clock::now() + duration;
    MapCursor cursor;
    MapDelta delta;
    std::uint64_t last_nonce = 0;
    std::uint64_t next_pose = 0;
    std::vector<PoseRecord> poses;
    std::vector<std::uint64_t> pending;
    std::uint64_t iteration = 0;
    while (Clock::now() < end) {
        ++iteration;
        const Connection c = reader.poll();
        if (c != Connection::kConnected && c != Connection::kClosed && c != Connection::kStale) {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            continue;
        }
        if (reader.writerNonce() != last_nonce) {
            last_nonce = reader.writerNonce();
            ++st.nonces_seen;
            pending.clear();  // commands to the previous writer are lost by design
            next_pose = 0;
        }
        if (auto s = reader.readStatus()) {
            ++st.status_reads;
            if (s->t_ns != 0 && !statusConsistent(*s)) ++st.torn;
        }
        poses.clear();
        reader.readPoses(next_pose, poses);
        if (auto p = reader.latestPose()) poses.push_back(*p);
        for (const PoseRecord& p : poses) {
            ++st.pose_reads;
            if (!poseConsistent(p)) ++st.torn;
        }
        const std::uint64_t before = cursor.points;
        if (reader.readMap(cursor, delta, 4096)) {
            if (delta.reset) ++st.resets;
            const std::uint64_t first = delta.reset ? 0 : before;
            for (std::size_t i = 0; i < delta.points.size(); ++i) {
                ++st.points_checked;
                if (!pointIs(delta.points[i], first + i)) ++st.bad_points;
            }
        }
        if (c == Connection::kConnected && pending.empty() &&
            iteration % 8 == 0) {  // one in flight, as a UI does
            auto seq =
                reader.sendCommand(CommandType::kExport, "/media/usb" + std::to_string(iteration));
            if (seq) {
                ++st.commands_sent;
                pending.push_back(*seq);
            }
        }
        for (auto it = pending.begin(); it != pending.end();) {
            auto r = reader.commandResult(*it);
            if (r && static_cast<CommandState>(r->state) == CommandState::kDone) {
                ++st.commands_answered;
                if (getText(r->message).rfind("ack " + std::to_string(*it) + " /media/usb", 0) != 0)
                    ++st.bad_answers;
                it = pending.erase(it);
            } else if (!r && r.status().code() == StatusCode::kNotFound) {
                ++st.commands_lost;
                it = pending.erase(it);
            } else {
                ++it;
            }
        }
    }
    return st;
}

}  // namespace handscan::shm::stress
