// foldcast looks: list the fabric looks, show one with every value, or draw the swatch sheet.
#include <charconv>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "validators.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/looks/looks.hpp"
#include "foldcast/looks/look_json.hpp"
#include "foldcast/batch/swatches.hpp"
#include "foldcast/looks/look_keys.hpp"
#include "progress_bar.hpp"
#include "resource_estimates.hpp"

namespace foldcast::app {

namespace {
struct LooksOptions {
    bool json = false;
    std::string show_name;
    bool show_json = false;
    std::string swatches;  // OUT.png
    std::vector<std::string> only;
    std::string tile = "240x300";
    batch::SwatchOptions swatch;
    bool quiet = false;
    bool force = false;
};

// "240x300" -> (240, 300), each side 16-4096 pixels; throws InputError naming the flag.
std::pair<int, int> parse_tile(const std::string& text) {
    const std::size_t x = text.find('x');
    int w = 0, h = 0;
    auto side = [&](std::size_t from, std::size_t to, int& value) {
        const char* end = text.data() + to;
        const auto [at, ec] = std::from_chars(text.data() + from, end, value);
        return from < to && ec == std::errc() && at == end && value >= 16 && value <= 4096;
    };
    if (x == std::string::npos || !side(0, x, w) || !side(x + 1, text.size(), h))
        throw InputError("--tile '" + text + "': expected WIDTHxHEIGHT, each 16 to 4096 pixels, e.g. 240x300");
    return {w, h};
}

int draw_swatches(LooksOptions& options) {
    check_writable(options.swatches);  // fail before minutes of rendering
    const auto library = looks::Library::load_default();
    options.swatch.looks = options.only;
    std::tie(options.swatch.tile_width, options.swatch.tile_height) = parse_tile(options.tile);
    const auto& s = options.swatch;
    const std::size_t tiles = s.looks.empty() ? library.names().size() : s.looks.size();
    check_swatch_work(static_cast<long long>(tiles), s.tile_width, s.tile_height, s.spp,
                      "looks --swatches " + options.swatches + " (" + std::to_string(tiles) + " tiles of " +
                          options.tile + " at --spp " + std::to_string(s.spp) + ")",
                      options.force);
    ProgressBar bar(options.quiet);
    const auto sheet = batch::render_swatch_sheet(library, options.swatch, bar.callback());
    batch::write_swatch_sheet(options.swatches, sheet);
    if (options.json) {
        nlohmann::json report = {{"file", options.swatches},        {"width", sheet.width},
                                 {"height", sheet.height},          {"spp", options.swatch.spp},
                                 {"seconds", sheet.stats.seconds},  {"rays", sheet.stats.rays},
                                 {"tiles", nlohmann::json::array()}};
        for (const auto& tile : sheet.tiles)
            report["tiles"].push_back({{"look", tile.look}, {"folds", tile.folds}, {"gsm", tile.gsm}});
        std::cout << report.dump() << "\n";
    } else {
        std::fprintf(stderr, "wrote %s (%dx%d, %zu looks)\n", options.swatches.c_str(), sheet.width, sheet.height,
                     sheet.tiles.size());
    }
    return 0;
}

int list_looks(const LooksOptions& options) {
    const auto library = looks::Library::load_default();
    if (options.json) {
        nlohmann::json report = {{"directory", library.directory().string()}, {"looks", nlohmann::json::array()}};
        for (const auto& name : library.names()) report["looks"].push_back(library.get(name));
        std::cout << report.dump(2) << "\n";
        return 0;
    }
    std::printf("%-18s %-6s %6s %6s %9s  %s\n", "look", "weave", "gsm", "t_mm", "E_MPa", "description");
    for (const auto& name : library.names()) {
        const auto& look = library.get(name);
        std::printf("%-18s %-6s %6.0f %6.2f %9.3g  %s\n", name.c_str(), looks::weave_name(look.appearance.weave),
                    look.mechanics.gsm, look.mechanics.thickness_mm, look.mechanics.young_mpa,
                    look.description.c_str());
    }
    std::printf("(%zu looks in %s; `foldcast looks show NAME` prints every value)\n", library.names().size(),
                library.directory().c_str());
    return 0;
}

int show_look(const LooksOptions& options) {
    const auto library = looks::Library::load_default();
    const looks::Look look = library.find(options.show_name);
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
    CLI::App* sub = app.add_subcommand("looks",
                                       "List the fabric looks (mechanics + appearance) shipped in looks/data "
                                       "(or $FOLDCAST_LOOKS_DIR)");
    sub->add_flag("--json", options->json,
                  "Print every look with all its values as JSON (with --swatches: the sheet's report)");
    sub->add_option("--swatches", options->swatches,
                    "Draw every look draped the same way side by side, labelled, into OUT.png");
    sub->add_option("--only", options->only, "With --swatches: just these looks, in this order")->delimiter(',');
    sub->add_option("--tile", options->tile, "With --swatches: each tile's size in pixels")->capture_default_str();
    sub->add_option("--columns", options->swatch.columns, "With --swatches: tiles per row (0 = auto)")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    sub->add_option("--spp", options->swatch.spp, "With --swatches: samples per pixel")
        ->check(CLI::Range(1, 1 << 16))
        ->capture_default_str();
    sub->add_flag("--denoise", options->swatch.denoise, "With --swatches: denoise each tile (as render --denoise)");
    sub->add_option("--noise-threshold", options->swatch.noise_threshold,
                    "With --swatches: adaptive sampling, as render --noise-threshold (0 = off)")
        ->check(finite_in(0.0, 1.0))
        ->capture_default_str();
    sub->add_option("--seed", options->swatch.seed, "With --swatches: random seed")
        ->capture_default_str()
        ->check(non_negative_integer);
    sub->add_option("--threads", options->swatch.threads,
                    "With --swatches: render threads (default all cores; same image for any count)")
        ->check(CLI::Range(1, 1024));
    sub->add_option("--width-m", options->swatch.width_m, "With --swatches: cloth width (m)")->capture_default_str();
    sub->add_option("--height-m", options->swatch.height_m, "With --swatches: cloth height (m)")->capture_default_str();
    sub->add_option("--inset-m", options->swatch.inset_m, "With --swatches: support inset (m)")->capture_default_str();
    sub->add_flag("-q,--quiet", options->quiet, "With --swatches: no progress bar");
    sub->add_flag("--force", options->force,
                  "With --swatches: render even when the memory or time estimate exceeds this machine's");
    CLI::App* show = sub->add_subcommand("show", "Print one look's values (TOML, or JSON with --json)");
    show->add_option("name", options->show_name, "Look name (see `foldcast looks`) or a look .toml file")->required();
    show->add_flag("--json", options->show_json, "Print the look as JSON");
    CLI::App* keys = sub->add_subcommand("keys", "Print every key a look file may hold (the tables of docs/looks.md)");

    return Command{sub, [options, show, keys] {
                       if (show->parsed()) return show_look(*options);
                       if (keys->parsed()) {
                           std::cout << looks::look_keys_markdown();
                           return 0;
                       }
                       if (!options->swatches.empty()) return draw_swatches(*options);
                       return list_looks(*options);
                   }};
}

}  // namespace foldcast::app
