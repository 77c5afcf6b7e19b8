#include "handscan/hil/command_client.hpp"

#include <chrono>
#include <thread>

#include "handscan/shm/text_field.hpp"

namespace handscan::hil {

shm::CommandAck sendCommand(shm::LiveMapReader& reader, shm::CommandType type,
                            const std::string& argument, double timeout_s,
                            std::vector<shm::CommandState>* seen) {
    shm::CommandAck last;
    reader.poll();
    auto seq = reader.sendCommand(type, argument);
    if (!seq.isOk()) {
        shm::setText(last.message, seq.status().message());
        last.state = static_cast<std::uint32_t>(shm::CommandState::kRejected);
        return last;
    }
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
        reader.poll();
        if (auto r = reader.commandResult(*seq); r.isOk()) {
            last = *r;
            const auto s = static_cast<shm::CommandState>(r->state);
            if (seen && (seen->empty() || seen->back() != s)) seen->push_back(s);
            if (s != shm::CommandState::kPending && s != shm::CommandState::kAccepted &&
                s != shm::CommandState::kInProgress)
                return last;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    shm::setText(last.message, std::string("no final answer to ") + shm::toString(type));
    return last;
}

std::optional<shm::StatusBlock> waitForStatus(
    shm::LiveMapReader& reader, const std::function<bool(const shm::StatusBlock&)>& pred,
    double timeout_s) {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
        reader.poll();
        if (auto s = reader.readStatus(); s && pred(*s)) return s;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return std::nullopt;
}

const shm::SensorStatus* findSensor(const shm::StatusBlock& s, const std::string& name) {
    for (std::uint32_t i = 0; i < s.sensor_count && i < shm::kMaxSensors; ++i) {
        if (shm::getText(s.sensors[i].name) == name) return &s.sensors[i];
    }
    return nullptr;
}

bool sensorConnected(const shm::StatusBlock& s, const std::string& name) {
    const shm::SensorStatus* x = findSensor(s, name);
    return x && x->connected;
}

}  // namespace handscan::hil
