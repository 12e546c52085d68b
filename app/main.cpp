// foldcast: one executable, git-style subcommands.  Only argument parsing lives in app/;
// the work is done by the libraries.  Exit status: 0 ok, 1 failed check, 2 usage or input
// error.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cerrno>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <vector>

#include "commands.hpp"
#include "foldcast/compare/image.hpp"
#include "input_domains.hpp"
#include "foldcast/core/error.hpp"

namespace {
// One line of ours instead of libstdc++'s "filesystem error: ..." text: the path and the
// system's reason.  A path that cannot be followed or found is the user's input (exit 2);
// anything else (a full disk, an I/O error) is a runtime failure (exit 1).
int report_filesystem_error(const std::filesystem::filesystem_error& e) {
    const std::string path = e.path1().empty() ? std::string("a path") : "'" + e.path1().string() + "'";
    std::fprintf(stderr, "foldcast: %s: %s\n", path.c_str(), e.code().message().c_str());
    const int code = e.code().value();
    const bool input = e.code().category() == std::generic_category() || e.code().category() == std::system_category();
    return input && (code == ELOOP || code == ENOENT || code == ENOTDIR || code == EISDIR || code == EACCES ||
                     code == ENAMETOOLONG || code == EEXIST || code == EINVAL)
               ? 2
               : 1;
}
}  // namespace

int main(int argc, char** argv) {
    foldcast::compare::silence_library_logging();  // our one line, not OpenCV's (or FFmpeg's) first
    CLI::App app{"foldcast: cloth folds, garment animation codec and garment renderer"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "foldcast 0.1.0");
    std::vector<foldcast::app::Command> commands;
    commands.push_back(foldcast::app::looks_command(app));
    commands.push_back(foldcast::app::drape_command(app));
    commands.push_back(foldcast::app::diff_command(app));
    commands.push_back(foldcast::app::folds_command(app));
    commands.push_back(foldcast::app::overlay_command(app));
    commands.push_back(foldcast::app::encode_command(app));
    commands.push_back(foldcast::app::decode_command(app));
    commands.push_back(foldcast::app::export_command(app));
    commands.push_back(foldcast::app::serve_command(app));
    commands.push_back(foldcast::app::render_command(app));
    commands.push_back(foldcast::app::turntable_command(app));
    commands.push_back(foldcast::app::preview_command(app));
    commands.push_back(foldcast::app::batch_command(app));
    foldcast::app::apply_input_domains(app);

    // CLI11 would answer "A subcommand is required" to a misspelt one: name it instead.
    bool known_name = false;
    if (argc > 1)
        for (const auto& command : commands) known_name = known_name || command.sub->check_name(argv[1]);
    if (argc > 1 && argv[1][0] != '-' && !known_name) {
        std::string known;
        for (const auto& command : commands) known += (known.empty() ? "" : ", ") + command.sub->get_name();
        std::fprintf(stderr, "foldcast: unknown subcommand '%s' (known: %s)\n", argv[1], known.c_str());
        std::fprintf(stderr, "Run with --help for usage.\n");
        return 2;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "foldcast: %s\n", e.what());
        std::fprintf(stderr, "Run with --help for usage.\n");
        return 2;
    }

    try {
        for (const auto& command : commands)
            if (command.sub->parsed()) return command.run();
    } catch (const foldcast::InputError& e) {
        std::fprintf(stderr, "foldcast: %s\n", e.what());
        return 2;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "foldcast: error: out of memory (the work needs more memory than this process may use)\n");
        return 1;
    } catch (const std::filesystem::filesystem_error& e) {
        return report_filesystem_error(e);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "foldcast: error: %s\n", e.what());
        return 1;
    }
    return 2;
}
