// handscan: the command-line tool (info, config check, sim, decode, replay, eval, export, ...).
#include <algorithm>
#include <exception>
#include <map>

#include "command_registry.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/log.hpp"

namespace handscan::cli {

std::vector<Command>& commandRegistry() {
    static std::vector<Command> commands;
    return commands;
}

}  // namespace handscan::cli

int main(int argc, char** argv) {
    using namespace handscan;
    CLI::App app{"handscan: handheld laser scanner firmware tool"};
    app.require_subcommand(1);
    int verbosity = 0;
    bool quiet = false;
    app.add_flag("-v,--verbose", verbosity, "More logging (repeat for trace)");
    app.add_flag("-q,--quiet", quiet, "Only warnings and errors");

    auto& registry = cli::commandRegistry();
    std::sort(registry.begin(), registry.end(),
              [](const auto& a, const auto& b) { return a.name < b.name; });
    std::map<CLI::App*, std::function<int()>> runs;
    for (auto& cmd : registry) {
        CLI::App* sub = app.add_subcommand(cmd.name, cmd.description);
        runs[sub] = cmd.setup(*sub);
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    initLogging("handscan", quiet ? -1 : verbosity);
    try {
        for (CLI::App* sub : app.get_subcommands()) return runs.at(sub)();
    } catch (const ConfigError& e) {
        log().error("{}", e.what());
        return 2;
    } catch (const std::exception& e) {
        log().error("{}", e.what());
        return 1;
    }
    return 0;
}
