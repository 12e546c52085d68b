#pragma once
// Each subcommand lives in its own app/cmd_*.cpp: it declares its options on the CLI11
// subcommand and returns the function that runs it after parsing.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "validators.hpp"

namespace foldcast::app {

struct Command {
    CLI::App* sub = nullptr;
    std::function<int()> run;  // returns the exit status: 0 ok, 1 failed check
};

Command looks_command(CLI::App& app);
Command drape_command(CLI::App& app);
Command diff_command(CLI::App& app);
Command folds_command(CLI::App& app);
Command overlay_command(CLI::App& app);
Command encode_command(CLI::App& app);
Command decode_command(CLI::App& app);
Command serve_command(CLI::App& app);
Command render_command(CLI::App& app);
Command turntable_command(CLI::App& app);
Command preview_command(CLI::App& app);
Command batch_command(CLI::App& app);
Command export_command(CLI::App& app);

}  // namespace foldcast::app
