#include "input_domains.hpp"

#include <string>

#include "foldcast/looks/looks.hpp"
#include "validators.hpp"

namespace foldcast::app {
namespace {

struct FlagDomain {
    const char* command;
    const char* flag;
    double lo, hi;
    const char* unit;
};

// Cloth: a garment or curtain panel (width and height as garment.width_m, height_m in a
// scene), fabrics from chiffon to heavy canvas with a wide margin; pictures in pixels.
constexpr FlagDomain kDomains[] = {
    {"drape", "--width-m", 0.01, 20.0, "m"},
    {"drape", "--height-m", 0.01, 20.0, "m"},
    {"drape", "--inset-m", 0.0, 10.0, "m"},
    {"drape", "--support-drop-m", -20.0, 20.0, "m"},
    {"drape", "--supports", 2, 65, ""},
    {"drape", "--thickness-mm", 0.01, 50.0, "mm"},
    {"drape", "--young-mpa", 1e-3, 1e5, "MPa"},
    {"drape", "--gsm", 1.0, 5000.0, "g/m^2"},
    {"drape", "--weight-n-mm2", 1e-9, 1e-4, "N/mm^2"},
    {"drape", "--poisson", 0.0, 0.5, ""},
    {"drape", "--load-constant", 0.01, 1e4, ""},
    {"drape", "--frames", 1, 100000, "frames"},
    {"drape", "--fps", 0.01, 1000.0, "frames/s"},
    {"drape", "--sway-m", 0.0, 20.0, "m"},
    {"drape", "--sway-period-s", 0.01, 3600.0, "s"},
    {"looks", "--width-m", 0.01, 20.0, "m"},
    {"looks", "--height-m", 0.01, 20.0, "m"},
    {"looks", "--inset-m", 0.0, 10.0, "m"},
    {"overlay", "--width-m", 0.01, 20.0, "m"},
    {"overlay", "--height-m", 0.01, 20.0, "m"},
    {"overlay", "--inset-m", 0.0, 10.0, "m"},
    {"overlay", "--thickness-mm", 0.01, 50.0, "mm"},
    {"overlay", "--young-mpa", 1e-3, 1e5, "MPa"},
    {"overlay", "--gsm", 1.0, 5000.0, "g/m^2"},
    {"overlay", "--poisson", 0.0, 0.5, ""},
    {"overlay", "--load-constant", 0.01, 1e4, ""},
    {"overlay", "--scale-px-per-m", 1e-3, 1e7, "px/m"},
    {"overlay", "--supports", -1e6, 1e6, "px"},
    {"overlay", "--corners", -1e6, 1e6, "px"},
    {"folds", "--supports", -1e6, 1e6, "px"},
    {"folds", "--min-length-px", 0.0, 1e6, "px"},
    {"encode", "--max-error-m", 1e-9, 1e3, "m"},
    {"encode", "--fps", 1e-3, 1e6, "frames/s"},
    {"encode", "--keep", 1e-9, 1.0, ""},
    {"serve", "--port", 0, 65535, ""},
    {"serve", "--throttle-kbps", 1.0, 1e7, "kbit/s"},
    {"render", "--noise-threshold", 0.0, 1.0, ""},
    {"turntable", "--noise-threshold", 0.0, 1.0, ""},
    {"looks", "--noise-threshold", 0.0, 1.0, ""},
    {"diff", "--failpercent", 0.0, 100.0, "%"},
    {"diff", "--warnpercent", 0.0, 100.0, "%"},
};

// Flags that name a look, a file or a folder: checked at parse time, so that the refusal
// names the flag ("--mask: File does not exist: m.png"), not only the value.
enum class Names { look, file, folder };
struct NamingFlag {
    const char* command;
    const char* flag;
    Names names;
};
constexpr NamingFlag kNamingFlags[] = {
    {"drape", "--look", Names::look},       {"overlay", "--look", Names::look}, {"decode", "--look", Names::look},
    {"looks", "--only", Names::look},       {"folds", "--mask", Names::file},   {"overlay", "--mask", Names::file},
    {"turntable", "--join", Names::folder},
};

CLI::Validator naming_check(Names names) {
    if (names == Names::file) return CLI::ExistingFile;
    if (names == Names::folder) return CLI::ExistingDirectory;
    return library_validator([](const std::string& look) { looks::Library::load_default().find(look); }, "LOOK");
}

std::string range_text(const FlagDomain& d) {
    std::string text =
        "a finite number in [" + CLI::detail::to_string(d.lo) + ", " + CLI::detail::to_string(d.hi) + "]";
    if (*d.unit) text += std::string(" ") + d.unit;
    return text + " (docs/inputs.md)";
}

const CLI::Validator kNotEmpty(
    [](std::string& text) { return text.empty() ? std::string("an empty value is not allowed") : std::string(); }, "");

void require_values(CLI::App& app) {
    for (CLI::Option* option : app.get_options())
        if (option->get_type_size() != 0) option->check(kNotEmpty);
    for (CLI::App* sub : app.get_subcommands({})) require_values(*sub);
}

}  // namespace

void apply_input_domains(CLI::App& app) {
    for (const FlagDomain& d : kDomains) {
        CLI::App* sub = app.get_subcommand(d.command);
        sub->get_option(d.flag)->check(finite_in(d.lo, d.hi, range_text(d)));
    }
    for (const NamingFlag& n : kNamingFlags)
        app.get_subcommand(n.command)->get_option(n.flag)->check(naming_check(n.names));
    require_values(app);
}

}  // namespace foldcast::app
