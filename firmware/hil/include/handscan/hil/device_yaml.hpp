// The device.yaml `handscan hil` gives the daemon: the recording's own configuration (the one the
// simulator or the recording device ran with: latencies, node ids, rates) with each device's
// transport pointed at its fake.
#pragma once

#include <map>
#include <string>

#include "handscan/core/status.hpp"

namespace handscan::hil {

// `source` with the values of "section.key" entries replaced (comments and every other line
// kept). Fails naming the first override whose key is not in `source`.
[[nodiscard]] Result<std::string> overrideYaml(const std::string& source,
                                               const std::map<std::string, std::string>& values);

}  // namespace handscan::hil
