#include "handscan/hil/device_yaml.hpp"

#include <set>
#include <sstream>

namespace handscan::hil {

Result<std::string> overrideYaml(const std::string& source,
                                 const std::map<std::string, std::string>& values) {
    std::istringstream in(source);
    std::ostringstream out;
    std::set<std::string> done;
    std::string section, line;
    while (std::getline(in, line)) {
        const std::size_t indent = line.find_first_not_of(' ');
        const std::size_t colon = line.find(':');
        if (indent == std::string::npos || line[indent] == '#' || colon == std::string::npos) {
            out << line << '\n';
            continue;
        }
        const std::string key = line.substr(indent, colon - indent);
        if (indent == 0) {
            section = key;
            out << line << '\n';
            continue;
        }
        const auto it = values.find(section + "." + key);
        if (it == values.end()) {
            out << line << '\n';
            continue;
        }
        out << line.substr(0, colon) << ": " << it->second << '\n';
        done.insert(it->first);
    }
    for (const auto& [k, v] : values) {
        if (done.count(k) == 0)
            return Status(StatusCode::kInvalidArgument,
                          "device.yaml: no key " + k + " to point at the fake device");
    }
    return out.str();
}

}  // namespace handscan::hil
