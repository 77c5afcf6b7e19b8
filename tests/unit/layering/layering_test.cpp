// The layering of STYLE.md / DESIGN.md checked on this tree: the include graph of every source
// file and the link graph CMake wrote for this build. Each rule is first shown to catch a
// deliberately bad tree or graph, then run on the real one; a failure lists every offending file
// with the include (or link) chain that breaks the rule.
#include <gtest/gtest.h>

#include <cstdlib>

#include "layering_rules.hpp"

namespace handscan::layering {
namespace {

const std::vector<std::string> kSourceDirs = {"drivers", "firmware", "pipeline", "ui", "tools"};

const IncludeGraph& tree() {
    static const IncludeGraph g = IncludeGraph::scan(HANDSCAN_SOURCE_DIR, kSourceDirs);
    return g;
}

// This build's link graph, or another build's (tools/check-device-build checks the `device`
// preset's build with HANDSCAN_LINK_GRAPH=build/device/link_graph.txt).
std::string linkGraphPath() {
    const char* other = std::getenv("HANDSCAN_LINK_GRAPH");
    return other ? other : std::string(HANDSCAN_BINARY_DIR) + "/link_graph.txt";
}

const LinkGraph& links() {
    static const LinkGraph g = LinkGraph::read(linkGraphPath());
    return g;
}

// A small tree that breaks every include rule once, beside files that keep them.
IncludeGraph badTree() {
    return IncludeGraph::fromFiles({
        {"firmware/core/include/handscan/core/time.hpp", "#pragma once\n#include <cstdint>\n"},
        {"firmware/shm/include/handscan/shm/layout.hpp", "#include \"handscan/core/time.hpp\"\n"},
        {"firmware/journal/include/handscan/journal/journal_writer.hpp", "#pragma once\n"},
        {"drivers/transport/include/handscan/transport/can_bus.hpp",
         "#include \"handscan/core/time.hpp\"\n"},
        {"drivers/transport/src/socketcan.cpp",
         "#include \"handscan/transport/can_bus.hpp\"\n#include <linux/can.h>\n"},
        {"drivers/camera/include/handscan/camera/image_convert.hpp",
         "#include \"handscan/core/time.hpp\"\n"},
        // codec -> transport (through a header of its own): rule (b)
        {"drivers/motor/include/handscan/motor/canopen.hpp",
         "#include \"handscan/transport/can_bus.hpp\"\n"},
        {"drivers/motor/src/canopen.cpp", "#include \"handscan/motor/canopen.hpp\"\n"},
        // device layer -> transport: allowed
        {"drivers/motor/src/motor_device.cpp", "#include \"handscan/transport/can_bus.hpp\"\n"},
        // a driver with a syscall header outside the transport: rule (b)
        {"drivers/gpio/src/gpiod_lines.cpp", "  #  include <gpiod.h>\n"},
        // pipeline -> driver codec: rule (a)
        {"pipeline/colour/src/colouriser.cpp",
         "#include \"handscan/camera/image_convert.hpp\"\n#include \"local.hpp\"\n"},
        {"pipeline/colour/src/local.hpp", "#include \"handscan/core/time.hpp\"\n"},
        // pipeline -> other firmware/: rule (a)
        {"pipeline/scan/src/map.cpp", "#include \"handscan/journal/journal_writer.hpp\"\n"},
        // ui -> shm -> core: allowed; ui -> journal: rule (c)
        {"ui/src/ok.cpp", "#include \"handscan/shm/layout.hpp\"\n"},
        {"ui/src/bad.cpp", "#include <handscan/journal/journal_writer.hpp>\n"},
        // shipped code -> tools/: rule (d); the dev-host subcommand may
        {"tools/sim/include/handscan/sim/simulator.hpp", "#pragma once\n"},
        {"firmware/cli/cmd_info.cpp", "#include \"handscan/sim/simulator.hpp\"\n"},
        {"firmware/cli/dev/cmd_sim.cpp", "#include \"handscan/sim/simulator.hpp\"\n"},
    });
}

bool mentions(const std::vector<Violation>& v, const std::string& where, const std::string& what) {
    for (const Violation& x : v)
        if (x.where == where && x.chain.find(what) != std::string::npos) return true;
    return false;
}

TEST(LayeringRules, ResolveIncludesTransitivelyWithTheirChain) {
    const IncludeGraph g = badTree();
    const auto r = g.reach("drivers/motor/src/canopen.cpp");
    ASSERT_TRUE(r.count("drivers/transport/include/handscan/transport/can_bus.hpp"));
    ASSERT_TRUE(r.count("firmware/core/include/handscan/core/time.hpp"));
    EXPECT_EQ(r.at("firmware/core/include/handscan/core/time.hpp"),
              "drivers/motor/src/canopen.cpp -> drivers/motor/include/handscan/motor/canopen.hpp "
              "(line 1) -> drivers/transport/include/handscan/transport/can_bus.hpp (line 1) -> "
              "firmware/core/include/handscan/core/time.hpp (line 1)");
    EXPECT_TRUE(r.count("<cstdint>"));
    EXPECT_TRUE(
        g.reach("pipeline/colour/src/colouriser.cpp").count("pipeline/colour/src/local.hpp"));
}

TEST(LayeringRules, EachRuleCatchesItsViolationAndOnlyThat) {
    const IncludeGraph g = badTree();
    const auto a = checkPipelineIncludes(g);
    EXPECT_TRUE(mentions(a, "pipeline/colour/src/colouriser.cpp", "handscan/camera/image_convert"))
        << describe(a);
    EXPECT_TRUE(mentions(a, "pipeline/scan/src/map.cpp", "journal_writer.hpp")) << describe(a);
    EXPECT_EQ(a.size(), 2u) << describe(a);

    const auto b = checkCodecIncludes(g);
    EXPECT_TRUE(mentions(b, "drivers/motor/src/canopen.cpp", "transport/can_bus.hpp"))
        << describe(b);
    EXPECT_TRUE(mentions(b, "drivers/motor/include/handscan/motor/canopen.hpp", "can_bus.hpp"));
    EXPECT_FALSE(mentions(b, "drivers/motor/src/motor_device.cpp", "can_bus.hpp"));
    EXPECT_EQ(b.size(), 2u) << describe(b);

    const auto sys = checkSystemDeviceHeaders(g);
    EXPECT_TRUE(mentions(sys, "drivers/gpio/src/gpiod_lines.cpp", "<gpiod.h>")) << describe(sys);
    EXPECT_EQ(sys.size(), 1u) << describe(sys);  // drivers/transport/src/socketcan.cpp may

    const auto c = checkUiIncludes(g);
    EXPECT_TRUE(mentions(c, "ui/src/bad.cpp", "journal_writer.hpp")) << describe(c);
    EXPECT_EQ(c.size(), 1u) << describe(c);

    const auto d = checkToolsIncludes(g);
    EXPECT_TRUE(mentions(d, "firmware/cli/cmd_info.cpp", "tools/sim")) << describe(d);
    EXPECT_EQ(d.size(), 1u) << describe(d);
}

TEST(LayeringRules, LinkRulesCatchSimulatorAndForeignLibraries) {
    const LinkGraph g = LinkGraph::parse(
        "handscan_core STATIC_LIBRARY firmware/core : Eigen3::Eigen\n"
        "handscan_camera STATIC_LIBRARY drivers/camera : handscan_core\n"
        "handscan_colour STATIC_LIBRARY pipeline/colour : handscan_core handscan_camera\n"
        "handscan_shm STATIC_LIBRARY firmware/shm : handscan_core\n"
        "handscan_ui STATIC_LIBRARY ui : handscan_shm glfw\n"
        "handscan_sim STATIC_LIBRARY tools/sim : handscan_core embree\n"
        "embree SHARED_LIBRARY - : \n"
        "handscan-ui EXECUTABLE ui : handscan_ui\n"
        "handscan-pipeline EXECUTABLE firmware/pipeline_daemon : handscan_colour handscan_sim\n"
        "handscan EXECUTABLE firmware/cli : handscan_colour\n");
    const auto d = checkDeviceLinks(g, {"handscan-pipeline", "handscan-ui", "handscan"});
    EXPECT_TRUE(mentions(d, "handscan-pipeline", "handscan_sim")) << describe(d);
    EXPECT_TRUE(mentions(d, "handscan-pipeline", "handscan_sim -> embree")) << describe(d);
    EXPECT_EQ(d.size(), 2u) << describe(d);
    EXPECT_EQ(checkDeviceLinks(g, {"handscan-missing"}).size(), 1u);

    const auto p = checkPipelineAndUiLinks(g);
    EXPECT_TRUE(mentions(p, "handscan_colour", "handscan_camera")) << describe(p);
    EXPECT_EQ(p.size(), 1u) << describe(p);
}

// ---- the real tree --------------------------------------------------------------------------

TEST(Layering, TheTreeIsScanned) {
    // A scan that found nothing would pass every rule.
    EXPECT_GT(tree().files().size(), 300u);
    EXPECT_TRUE(tree().files().count("pipeline/colour/src/colouriser.cpp"));
    EXPECT_TRUE(tree().files().count("drivers/transport/src/socketcan.cpp"));
}

TEST(Layering, PipelineDependsOnTheCoreOnly) {
    const auto v = checkPipelineIncludes(tree());
    EXPECT_TRUE(v.empty()) << describe(v);
}

TEST(Layering, DriverCodecsIncludeNoTransport) {
    const auto v = checkCodecIncludes(tree());
    EXPECT_TRUE(v.empty()) << describe(v);
}

TEST(Layering, OnlyTransportsIncludeDeviceAndSocketHeaders) {
    const auto v = checkSystemDeviceHeaders(tree());
    EXPECT_TRUE(v.empty()) << describe(v);
}

TEST(Layering, UiDependsOnTheShmProtocolAndCoreOnly) {
    const auto v = checkUiIncludes(tree());
    EXPECT_TRUE(v.empty()) << describe(v);
}

TEST(Layering, ShippedCodeIncludesNoSimulatorOrEvaluation) {
    const auto v = checkToolsIncludes(tree());
    EXPECT_TRUE(v.empty()) << describe(v);
}

TEST(Layering, LinkGraphWasWritten) {
    ASSERT_TRUE(links().has("handscan_core"))
        << linkGraphPath() << " is missing or empty: re-run cmake";
    ASSERT_TRUE(links().has("@device-cli"));
}

TEST(Layering, DeviceBinariesLinkNoSimulatorOrEvaluation) {
    // `@device-cli` is what the `handscan` tool links without HANDSCAN_WITH_DEV_TOOLS, as the
    // device's build (cmake --preset device) makes it; tools/test also builds that preset.
    std::vector<std::string> binaries = {"handscan-pipeline", "@device-cli"};
    if (links().has("handscan_ui")) binaries.push_back("handscan-ui");
    // In a build without the development tools the tool itself is the device's.
    if (!links().has("handscan_sim")) binaries.push_back("handscan");
    const auto v = checkDeviceLinks(links(), binaries);
    EXPECT_TRUE(v.empty()) << describe(v);
}

TEST(Layering, DevHostToolLinksTheSimulator) {
    // On a development host `handscan sim` / `handscan eval` keep working: the rule above is
    // about the device build, not a simulator that went missing.
    if (!links().has("handscan_sim")) GTEST_SKIP() << "built without the simulator";
    const auto r = links().reach("handscan");
    EXPECT_TRUE(r.count("handscan_sim"));
    EXPECT_TRUE(r.count("handscan_eval"));
}

TEST(Layering, PipelineAndUiLibrariesLinkOnlyTheirLayers) {
    const auto v = checkPipelineAndUiLinks(links());
    EXPECT_TRUE(v.empty()) << describe(v);
}

}  // namespace
}  // namespace handscan::layering
