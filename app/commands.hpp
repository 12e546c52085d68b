#pragma once
// Each subcommand lives in its own app/cmd_*.cpp: it declares its options on the CLI11
// subcommand and returns the function that runs it after parsing.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace foldcast::app {

// For unsigned options: CLI11 would read "-1" into an unsigned integer as its largest value.
inline const CLI::Validator non_negative_integer(
    [](std::string& text) {
        return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos
                   ? std::string()
                   : std::string("'" + text + "' must be a whole number >= 0");
    },
    "UINT");

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

}  // namespace foldcast::app
