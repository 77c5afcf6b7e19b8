#include "layering_rules.hpp"

#include <deque>
#include <fstream>
#include <regex>
#include <sstream>

namespace handscan::layering {
namespace fs = std::filesystem;
namespace {

bool startsWith(const std::string& s, const std::string& prefix) {
    return s.compare(0, prefix.size(), prefix) == 0;
}

bool isSource(const fs::path& p) {
    const std::string e = p.extension().string();
    return e == ".hpp" || e == ".cpp" || e == ".h" || e == ".cc";
}

std::vector<Include> parseIncludes(const std::string& text) {
    static const std::regex kInclude(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
    std::vector<Include> out;
    std::istringstream in(text);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
        ++n;
        std::smatch m;
        if (std::regex_search(line, m, kInclude)) out.push_back({m[2].str(), m[1].str() == "<", n});
    }
    return out;
}

// "drivers/motor/src/x.cpp" -> "drivers/motor"; the folder holding include/ and src/.
std::string componentDir(const std::string& file) {
    for (const char* marker : {"/src/", "/include/"}) {
        const auto at = file.find(marker);
        if (at != std::string::npos) return file.substr(0, at);
    }
    return fs::path(file).parent_path().string();
}

std::string stem(const std::string& file) { return fs::path(file).stem().string(); }

// Files of a folder (and its sub-folders).
std::vector<std::string> under(const IncludeGraph& g, const std::string& dir) {
    std::vector<std::string> out;
    for (const auto& [file, _] : g.files())
        if (startsWith(file, dir)) out.push_back(file);
    return out;
}

// Runs `allowed` over everything `file` reaches; one violation per disallowed target.
template <typename Allowed>
void checkReach(const IncludeGraph& g, const std::string& file, const std::string& rule,
                Allowed allowed, std::vector<Violation>& out) {
    for (const auto& [target, chain] : g.reach(file))
        if (!allowed(target)) out.push_back({file, chain, rule});
}

bool isSystem(const std::string& target) { return startsWith(target, "<"); }

}  // namespace

const std::set<std::string> kDeviceLayerFiles = {
    // camera: the V4L2 ioctl sequence, the recording tap on the capture thread, the replay double
    "camera_device", "frame_record_tap", "replay_v4l2_device",
    // gpio: the panel over the line interface (a transport), and its fake line layer
    "gpio_lines", "gpio_panel", "fake_gpio_chip",
    // hokuyo, xsens: the state machines over a ByteStream; the xsens driver picks serial or USB
    "hokuyo_device", "xsens_device", "xsens_driver",
    // motor: CANopen master and device over a CanBus, the CAN bus doubles, and the device.yaml
    // section turned into the device's configuration and its emulated bus (motor_setup)
    "canopen_master", "motor_device", "motor_setup", "node_emulators", "paced_can_bus",
    "virtual_can_buses"};

IncludeGraph IncludeGraph::fromFiles(const std::map<std::string, std::string>& files) {
    IncludeGraph g;
    for (const auto& [path, text] : files) {
        g.includes_[path] = parseIncludes(text);
        const auto at = path.find("/include/");
        if (at != std::string::npos) g.by_include_path_[path.substr(at + 9)] = path;
    }
    return g;
}

IncludeGraph IncludeGraph::scan(const fs::path& root, const std::vector<std::string>& dirs) {
    std::map<std::string, std::string> files;
    for (const std::string& dir : dirs) {
        if (!fs::exists(root / dir)) continue;
        for (auto it = fs::recursive_directory_iterator(root / dir);
             it != fs::recursive_directory_iterator(); ++it) {
            const std::string name = it->path().filename().string();
            if (it->is_directory() && (startsWith(name, "build") || startsWith(name, "."))) {
                it.disable_recursion_pending();
                continue;
            }
            if (!it->is_regular_file() || !isSource(it->path())) continue;
            std::ifstream in(it->path());
            std::stringstream text;
            text << in.rdbuf();
            files[fs::relative(it->path(), root).generic_string()] = text.str();
        }
    }
    return fromFiles(files);
}

std::string IncludeGraph::resolve(const std::string& from, const Include& inc) const {
    if (!inc.angled) {
        const fs::path here = fs::path(from).parent_path();
        for (const fs::path& p :
             {here / inc.text, fs::path(componentDir(from)) / "src" / inc.text}) {
            const std::string s = p.lexically_normal().generic_string();
            if (includes_.count(s)) return s;
        }
    }
    const auto it = by_include_path_.find(inc.text);
    return it == by_include_path_.end() ? std::string() : it->second;
}

std::map<std::string, std::string> IncludeGraph::reach(const std::string& file) const {
    std::map<std::string, std::string> chains;
    std::deque<std::string> todo{file};
    chains[file] = file;
    while (!todo.empty()) {
        const std::string f = todo.front();
        todo.pop_front();
        const auto it = includes_.find(f);
        if (it == includes_.end()) continue;
        for (const Include& inc : it->second) {
            const std::string r = resolve(f, inc);
            const std::string key =
                r.empty() ? (inc.angled ? "<" + inc.text + ">" : "\"" + inc.text + "\"") : r;
            if (chains.count(key)) continue;
            chains[key] = chains[f] + " -> " + key + " (line " + std::to_string(inc.line) + ")";
            if (!r.empty()) todo.push_back(r);
        }
    }
    chains.erase(file);
    return chains;
}

std::string describe(const std::vector<Violation>& violations) {
    std::string s;
    for (const Violation& v : violations) s += v.where + ": " + v.rule + "\n    " + v.chain + "\n";
    return s;
}

std::vector<Violation> checkPipelineIncludes(const IncludeGraph& g) {
    std::vector<Violation> out;
    for (const std::string& f : under(g, "pipeline/")) {
        checkReach(
            g, f,
            "pipeline/ depends on the core only: no driver, transport or other firmware/ header "
            "(STYLE.md layering; hand decoded samples in)",
            [](const std::string& t) {
                return isSystem(t) || startsWith(t, "\"") || startsWith(t, "pipeline/") ||
                       startsWith(t, "firmware/core/");
            },
            out);
    }
    return out;
}

std::vector<Violation> checkCodecIncludes(const IncludeGraph& g) {
    std::vector<Violation> out;
    for (const std::string& f : under(g, "drivers/")) {
        if (startsWith(f, "drivers/transport/") || f.find("/fake/") != std::string::npos ||
            kDeviceLayerFiles.count(stem(f)))
            continue;
        checkReach(
            g, f,
            "a driver codec includes no transport header (plain frame and buffer types live in "
            "firmware/core: can_frame.hpp, v4l2_types.hpp); device-layer files are listed in "
            "tests/unit/layering kDeviceLayerFiles",
            [](const std::string& t) { return !startsWith(t, "drivers/transport/"); }, out);
    }
    return out;
}

std::vector<Violation> checkSystemDeviceHeaders(const IncludeGraph& g) {
    static const std::regex kDeviceHeader(
        R"(^<(linux/can\.h|linux/can/.*|linux/videodev2\.h|gpiod\.h|libusb\.h|libusb-1\.0/libusb\.h|sys/socket\.h|sys/un\.h|netinet/.*|arpa/.*|netdb\.h|net/if\.h)>$)");
    std::vector<Violation> out;
    for (const std::string dir : {"drivers/", "firmware/", "pipeline/", "ui/"}) {
        for (const std::string& f : under(g, dir)) {
            if (startsWith(f, "drivers/transport/src/")) continue;
            checkReach(
                g, f,
                "only drivers/transport/src includes kernel device, libgpiod, libusb or socket "
                "headers (STYLE.md layering)",
                [](const std::string& t) { return !std::regex_match(t, kDeviceHeader); }, out);
        }
    }
    return out;
}

std::vector<Violation> checkUiIncludes(const IncludeGraph& g) {
    std::vector<Violation> out;
    for (const std::string& f : under(g, "ui/")) {
        checkReach(
            g, f, "ui/ depends only on the shared-memory protocol (firmware/shm) and the core",
            [](const std::string& t) {
                return isSystem(t) || startsWith(t, "\"") || startsWith(t, "ui/") ||
                       startsWith(t, "firmware/shm/") || startsWith(t, "firmware/core/");
            },
            out);
    }
    return out;
}

std::vector<Violation> checkToolsIncludes(const IncludeGraph& g) {
    std::vector<Violation> out;
    for (const std::string dir : {"drivers/", "firmware/", "pipeline/", "ui/"}) {
        for (const std::string& f : under(g, dir)) {
            if (startsWith(f, "firmware/cli/dev/")) continue;
            checkReach(
                g, f,
                "shipped code includes no simulator or evaluation header (tools/); only "
                "firmware/cli/dev/ (HANDSCAN_WITH_DEV_TOOLS) may",
                [](const std::string& t) { return !startsWith(t, "tools/"); }, out);
        }
    }
    return out;
}

LinkGraph LinkGraph::parse(const std::string& text) {
    LinkGraph g;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string name, colon, dep;
        LinkTarget t;
        if (!(ls >> name >> t.type >> t.dir >> colon) || colon != ":") continue;
        while (ls >> dep) t.links.push_back(dep);
        g.targets_[name] = std::move(t);
    }
    return g;
}

LinkGraph LinkGraph::read(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    return parse(text.str());
}

std::map<std::string, std::string> LinkGraph::reach(const std::string& target) const {
    std::map<std::string, std::string> chains{{target, target}};
    std::deque<std::string> todo{target};
    while (!todo.empty()) {
        const std::string t = todo.front();
        todo.pop_front();
        const auto it = targets_.find(t);
        if (it == targets_.end()) continue;
        for (const std::string& d : it->second.links) {
            if (chains.count(d)) continue;
            chains[d] = chains[t] + " -> " + d;
            todo.push_back(d);
        }
    }
    chains.erase(target);
    return chains;
}

std::vector<Violation> checkDeviceLinks(const LinkGraph& g,
                                        const std::vector<std::string>& binaries) {
    std::vector<Violation> out;
    for (const std::string& b : binaries) {
        if (!g.has(b)) {
            out.push_back({b, "(not in the link graph)", "the device binary must exist"});
            continue;
        }
        for (const auto& [dep, chain] : g.reach(b)) {
            const bool from_tools = g.has(dep) && startsWith(g.at(dep).dir, "tools/");
            const bool dev_library = dep.find("embree") != std::string::npos ||
                                     dep.find("tinyobjloader") != std::string::npos;
            if (from_tools || dev_library)
                out.push_back({b, chain,
                               "the device's binaries link no simulator or evaluation code "
                               "(tools/, Embree, tinyobjloader)"});
        }
    }
    return out;
}

std::vector<Violation> checkPipelineAndUiLinks(const LinkGraph& g) {
    std::vector<Violation> out;
    // Our own targets: those built from a folder of this tree.
    const auto ours = [&](const std::string& t) { return g.has(t) && g.at(t).dir != "-"; };
    for (const std::string& name : {std::string("handscan_imu"), std::string("handscan_scan"),
                                    std::string("handscan_lio"), std::string("handscan_fusion"),
                                    std::string("handscan_colour"), std::string("handscan_ui")}) {
        if (!g.has(name)) continue;
        const bool ui = name == "handscan_ui";
        for (const auto& [dep, chain] : g.reach(name)) {
            if (!ours(dep)) continue;
            const std::string& dir = g.at(dep).dir;
            const bool ok = ui ? (dir == "ui" || dir == "firmware/shm" || dir == "firmware/core")
                               : (startsWith(dir, "pipeline/") || dir == "firmware/core");
            if (!ok)
                out.push_back({name, chain,
                               ui ? "the UI links only the shm protocol and the core"
                                  : "the pipeline links only the core and pipeline libraries"});
        }
    }
    return out;
}

}  // namespace handscan::layering
