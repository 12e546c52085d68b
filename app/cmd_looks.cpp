// foldcast looks: list the fabric looks, or show one with every value.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "foldcast/looks.hpp"
#include "foldcast/looks/look_json.hpp"

namespace foldcast::app {

namespace {
struct LooksOptions {
    bool json = false;
    std::string show_name;
    bool show_json = false;
};

int list_looks(const LooksOptions& options) {
    const auto library = looks::Library::load_default();
    if (options.json) {
        nlohmann::json report = {{"directory", library.directory().string()},
                                 {"looks", nlohmann::json::array()}};
        for (const auto& name : library.names()) report["looks"].push_back(library.get(name));
        std::cout << report.dump(2) << "\n";
        return 0;
    }
    std::printf("%-18s %-6s %6s %6s %9s  %s\n", "look", "weave", "gsm", "t_mm", "E_MPa",
                "description");
    for (const auto& name : library.names()) {
        const auto& look = library.get(name);
        std::printf("%-18s %-6s %6.0f %6.2f %9.3g  %s\n", name.c_str(),
                    looks::weave_name(look.appearance.weave), look.mechanics.gsm,
                    look.mechanics.thickness_mm, look.mechanics.young_mpa,
                    look.description.c_str());
    }
    std::printf("(%zu looks in %s; `foldcast looks show NAME` prints every value)\n",
                library.names().size(), library.directory().c_str());
    return 0;
}

int show_look(const LooksOptions& options) {
    const auto library = looks::Library::load_default();
    const auto& look = library.get(options.show_name);
    if (options.show_json || options.json) {
        const nlohmann::json report = look;
        std::cout << report.dump(2) << "\n";
    } else {
        std::cout << looks::format_look_toml(look);
    }
    return 0;
}
}  // namespace

Command looks_command(CLI::App& app) {
    auto options = std::make_shared<LooksOptions>();
    CLI::App* sub = app.add_subcommand(
        "looks", "List the fabric looks (mechanics + appearance) shipped in looks/data "
                 "(or $FOLDCAST_LOOKS_DIR)");
    sub->add_flag("--json", options->json, "Print every look with all its values as JSON");
    CLI::App* show = sub->add_subcommand("show", "Print one look's values (TOML, or JSON with --json)");
    show->add_option("name", options->show_name, "Look name (see `foldcast looks`)")->required();
    show->add_flag("--json", options->show_json, "Print the look as JSON");

    return Command{sub, [options, show] {
                       return show->parsed() ? show_look(*options) : list_looks(*options);
                   }};
}

}  // namespace foldcast::app
