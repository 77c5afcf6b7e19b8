// Subcommands of the `handscan` tool register themselves from their own cmd_<name>.cpp file, so a
// new subcommand never edits main.cpp. A subcommand's setup adds its options and a callback; the
// callback returns the process exit code.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace handscan::cli {

struct Command {
    std::string name;
    std::string description;
    // Adds options to `sub` and returns the function to run when the subcommand is chosen.
    std::function<std::function<int()>(CLI::App& sub)> setup;
};

std::vector<Command>& commandRegistry();

struct RegisterCommand {
    RegisterCommand(std::string name, std::string description,
                    std::function<std::function<int()>(CLI::App&)> setup) {
        commandRegistry().push_back({std::move(name), std::move(description), std::move(setup)});
    }
};

}  // namespace handscan::cli
