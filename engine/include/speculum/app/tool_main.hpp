// The command-line tools' main(): parse with CLI11, run, and map what went wrong to the exit
// status contract (docs/design.md section 6): 0 done (and --help), 2 bad arguments, the Error's
// own status (3 bad input, 4 no device), 1 for anything else, reported as an internal error.
// Every message starts with the tool's name. Header-only, so that a tool needs no extra library.
#pragma once

#include "speculum/core.hpp"

#include <CLI/CLI.hpp>

#include <exception>
#include <functional>
#include <iostream>
#include <string>

namespace speculum::app {

inline int toolMain(const std::string& name, CLI::App& cli, int argc, char** argv, const std::function<int()>& run) {
    try {
        cli.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return cli.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << name << ": " << e.what() << " (see --help)\n";
        return static_cast<int>(ExitCode::BadArguments);
    }
    try {
        return run();
    } catch (const Error& e) {
        std::cerr << name << ": " << e.what() << "\n";
        return static_cast<int>(e.code());
    } catch (const std::exception& e) {
        std::cerr << name << ": internal error: " << e.what() << "\n";
        return static_cast<int>(ExitCode::Failure);
    }
}

}  // namespace speculum::app
