// foldcast diff against OpenImageIO's idiff on the same image pairs: exit statuses and
// fail counts over 12 option sets.  Its own executable, labelled `slow` (it starts ~24
// processes; it still runs in CI), so the unit label stays fast.
#include <gtest/gtest.h>

#include <cctype>
#include <nlohmann/json.hpp>

#include "compare_test_util.hpp"
#include "diff_cli_util.hpp"
#include "foldcast/compare/image.hpp"
#include "test_paths.hpp"

using namespace foldcast;
using namespace foldcast::test;
namespace fs = std::filesystem;

namespace {

bool have_idiff() { return run_command("command -v idiff >/dev/null 2>&1").exit_code == 0; }

struct IdiffResult {
    int exit_code;
    long long warn_pixels = -1, fail_pixels = -1;
};

IdiffResult run_idiff(const std::string& args, const fs::path& a, const fs::path& b) {
    const CommandResult r = run_command("idiff -v " + args + " " + quoted(a) + " " + quoted(b) + " 2>/dev/null");
    IdiffResult out{r.exit_code};
    // "  N pixels (P%) over T" twice: warnings first, then failures.  (Parsed by hand: GCC 12
    // warns falsely inside std::regex under the sanitizer build's -O2 -Werror.)
    std::vector<long long> counts;
    const std::string marker = " pixels (";
    for (size_t at = r.out.find(marker); at != std::string::npos; at = r.out.find(marker, at + 1)) {
        size_t start = at;
        while (start > 0 && std::isdigit(static_cast<unsigned char>(r.out[start - 1]))) --start;
        if (start < at) counts.push_back(std::stoll(r.out.substr(start, at - start)));
    }
    if (counts.size() >= 2) {
        out.warn_pixels = counts[0];
        out.fail_pixels = counts[1];
    }
    return out;
}

}  // namespace

TEST(DiffCli, AgreesWithIdiffOnExitCodesAndFailCounts) {
    if (!have_idiff()) GTEST_SKIP() << "idiff (openimageio-tools) not installed";
    const fs::path dir = temp_dir();
    const fs::path a = dir / "a.png", b = dir / "b.png", same = dir / "same.png";
    write_pair(a, b, 3, 0.2, 40);  // noise of 3/255 on 20 % of the pixels, one spike of 40/255
    write_pair(a, same, 0, 0.0, 0);
    // Thresholds avoid ties with multiples of 1/255 (idiff compares in float).
    const std::vector<std::string> cases = {
        "",                                                             // defaults: any change fails
        "--fail 0.02",                                                  // only the spike fails
        "--fail 0.02 --failpercent 1",                                  // 1 of 3072 allowed
        "--fail 0.02 --failpercent 1 --warn 0.005 --warnpercent 50",    // noise warns, share allowed
        "--fail 0.02 --failpercent 1 --warn 0.005 --warnpercent 5",     // too many warnings
        "--fail 0.5 --hardfail 0.1",                                    // the spike exceeds hardfail
        "--fail 0.5 --warn 0.5 --hardwarn 0.1",                         // ... or hardwarn
        "--fail 0.12 --hardfail 0.1",                                   // the spike fails and is over hardfail
        "--fail 0.1 --failpercent 1 --hardfail 0.12",                   // within failpercent, over hardfail
        "--fail 0.1 --failpercent 1 --hardfail 0.2",                    // warning only
        "--fail 0.002 --failpercent 30 --warn 0.002 --warnpercent 30",  // all within allowances
        "--fail 0.002 --allowfailures 700",                             // idiff's allowance by count
    };
    for (const std::string& args : cases) {
        std::string idiff_args;  // idiff spells its options with one dash
        for (size_t i = 0; i < args.size(); ++i)
            if (!(args[i] == '-' && i + 1 < args.size() && args[i + 1] == '-')) idiff_args.push_back(args[i]);
        const IdiffResult reference = run_idiff(idiff_args, a, b);
        int code = -1;
        const nlohmann::json ours = run_ours(args, a, b, &code);
        EXPECT_EQ(code, reference.exit_code) << "options: " << args;
        EXPECT_EQ(ours["fail_pixels"].get<long long>(), reference.fail_pixels) << "options: " << args;
        EXPECT_EQ(ours["warn_pixels"].get<long long>(), reference.warn_pixels) << "options: " << args;
    }
    int code = -1;
    run_ours("", a, same, &code);
    EXPECT_EQ(code, 0);
    EXPECT_EQ(run_idiff("", a, same).exit_code, 0);
}
