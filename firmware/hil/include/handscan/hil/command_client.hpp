// The UI's side of the daemon's shared-memory command channel, as tools and tests drive it:
// send a command and wait for its final answer, wait for a status, find a sensor's status.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "handscan/shm/live_map_reader.hpp"

namespace handscan::hil {

// Sends `type` and waits up to `timeout_s` for a final state (done, failed, rejected); every
// state seen on the way is appended to `seen`. A command the daemon never answers comes back
// kPending with a message saying so.
shm::CommandAck sendCommand(shm::LiveMapReader& reader, shm::CommandType type,
                            const std::string& argument = {}, double timeout_s = 20.0,
                            std::vector<shm::CommandState>* seen = nullptr);

// Polls the status block until `pred` holds; nullopt after `timeout_s`.
std::optional<shm::StatusBlock> waitForStatus(
    shm::LiveMapReader& reader, const std::function<bool(const shm::StatusBlock&)>& pred,
    double timeout_s);

// The status of sensor `name` in a status block, if listed.
const shm::SensorStatus* findSensor(const shm::StatusBlock& s, const std::string& name);
bool sensorConnected(const shm::StatusBlock& s, const std::string& name);

}  // namespace handscan::hil
