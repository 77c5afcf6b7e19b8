// The layering rules of STYLE.md and DESIGN.md as checks over two graphs:
//  - the include graph of the source tree (every #include of every .hpp/.cpp/.h, project headers
//    resolved to their files, followed transitively), and
//  - the link graph CMake writes at configure time (cmake/HandscanLinkGraph.cmake).
// Each check returns the violations it found, each naming the file (or target), the chain of
// includes (or links) that breaks the rule, and the rule; an empty list means the rule holds.
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace handscan::layering {

struct Include {
    std::string text;  // as written: "handscan/core/time.hpp" or <linux/can.h> without brackets
    bool angled = false;
    int line = 0;
};

// Source files by path relative to the tree's root ("drivers/motor/src/canopen.cpp").
class IncludeGraph {
public:
    // Reads every source file under root/<dir> for each of `dirs` (build folders skipped).
    static IncludeGraph scan(const std::filesystem::path& root,
                             const std::vector<std::string>& dirs);
    // For tests of the rules: files given as path -> content.
    static IncludeGraph fromFiles(const std::map<std::string, std::string>& files);

    const std::map<std::string, std::vector<Include>>& files() const { return includes_; }
    // The project file an include names, "" for a system or unknown header. Quoted includes are
    // looked up beside the including file, in its component's src/, then as include/<text>.
    std::string resolve(const std::string& from, const Include& inc) const;
    // Every file and system header `file` reaches, each with the include chain that reaches it
    // first ("a.cpp -> b.hpp -> <linux/can.h>").
    std::map<std::string, std::string> reach(const std::string& file) const;

private:
    std::map<std::string, std::vector<Include>> includes_;
    std::map<std::string, std::string> by_include_path_;  // "handscan/core/x.hpp" -> file
};

struct Violation {
    std::string where;  // file or target
    std::string chain;  // how it reaches what it must not
    std::string rule;
};
std::string describe(const std::vector<Violation>& violations);

// (a) pipeline/ reaches no project file outside pipeline/ and firmware/core/ (no driver, no
//     transport, no other firmware/ header).
std::vector<Violation> checkPipelineIncludes(const IncludeGraph& g);
// (b) A driver's codec (every file of drivers/<device>/ except the device layer: the state
//     machines over injected transports and the fakes, kDeviceLayerFiles) reaches no transport
//     header (drivers/transport/).
std::vector<Violation> checkCodecIncludes(const IncludeGraph& g);
// (b) Only drivers/transport/ reaches <linux/can.h>, <linux/videodev2.h>, <gpiod.h>, <libusb.h>
//     or a socket header; checked for the shipped code (drivers, firmware, pipeline, ui).
std::vector<Violation> checkSystemDeviceHeaders(const IncludeGraph& g);
// (c) ui/ reaches only ui/, the shared-memory protocol (firmware/shm/) and firmware/core/.
std::vector<Violation> checkUiIncludes(const IncludeGraph& g);
// (d) No shipped code reaches the simulator or the evaluation (tools/) except the development
//     host's subcommands (firmware/cli/dev/).
std::vector<Violation> checkToolsIncludes(const IncludeGraph& g);

// Device-layer files of the drivers (stems; any folder named fake/ counts too). They may use
// the transport interfaces; everything else in a driver folder is codec and may not.
extern const std::set<std::string> kDeviceLayerFiles;

// The link graph: target -> (source folder, direct link dependencies).
struct LinkTarget {
    std::string type;
    std::string dir;  // relative to the tree's root, "-" for imported targets
    std::vector<std::string> links;
};
class LinkGraph {
public:
    static LinkGraph parse(const std::string& text);
    static LinkGraph read(const std::filesystem::path& file);
    bool has(const std::string& target) const { return targets_.count(target) != 0; }
    const LinkTarget& at(const std::string& target) const { return targets_.at(target); }
    // Every target `target` links, directly or not, with the chain that reaches it first.
    std::map<std::string, std::string> reach(const std::string& target) const;

private:
    std::map<std::string, LinkTarget> targets_;
};

// (d) The device's binaries link no simulator or evaluation code: nothing from tools/, no Embree,
//     no tinyobjloader, in the closure of each of `binaries`.
std::vector<Violation> checkDeviceLinks(const LinkGraph& g,
                                        const std::vector<std::string>& binaries);
// (a)/(c) The pipeline's libraries link only the core and each other; the UI links only the shm
//     protocol and the core (of our own targets).
std::vector<Violation> checkPipelineAndUiLinks(const LinkGraph& g);

}  // namespace handscan::layering
