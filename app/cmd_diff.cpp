// foldcast diff A B: image comparison for visual regression with idiff's conventions and
// exit statuses (0 pass, 1 warning, 2 failure, 3 size mismatch, 4 unreadable file): this
// subcommand's own contract, different from the 0/1/2 of the others.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "foldcast/compare/diff.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"

namespace foldcast::app {
namespace {

struct DiffOptions {
    std::string reference, test, heat_map_path, heat_map_kind = "flip", allow_failures_text = "0";
    compare::DiffThresholds th;
    bool json = false;
};

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

int report_error(const DiffOptions& o, compare::DiffVerdict verdict, const std::string& message) {
    std::fprintf(stderr, "foldcast diff: %s\n", message.c_str());
    if (o.json) {
        nlohmann::json j{{"reference", o.reference},
                         {"test", o.test},
                         {"verdict", compare::verdict_name(verdict)},
                         {"exit_code", static_cast<int>(verdict)},
                         {"error", message}};
        std::printf("%s\n", j.dump(2).c_str());
    }
    return static_cast<int>(verdict);
}

int run_diff(const DiffOptions& o) {
    compare::validate(o.th);
    if (!o.heat_map_path.empty()) {
        try {  // the heat-map must not replace the images it compares
            check_not_input(o.heat_map_path, o.reference, "-o");
            check_not_input(o.heat_map_path, o.test, "-o");
        } catch (const InputError& e) {
            return report_error(o, compare::DiffVerdict::unreadable, e.what());
        }
    }
    compare::Image a, b;
    try {
        a = compare::read_image(o.reference);
        b = compare::read_image(o.test);
    } catch (const compare::UnreadableImage& e) {
        return report_error(o, compare::DiffVerdict::unreadable, e.what());
    }
    compare::DiffReport r;
    compare::Image heat;
    const bool want_heat = !o.heat_map_path.empty();
    const auto kind = o.heat_map_kind == "abs" ? compare::HeatMapKind::abs_error : compare::HeatMapKind::flip;
    try {
        r = compare::diff_images(a, b, o.th, want_heat ? &heat : nullptr, kind);
    } catch (const compare::SizeMismatch& e) {
        return report_error(o, compare::DiffVerdict::size_mismatch, e.what());
    }
    if (want_heat) {
        try {
            compare::write_image(o.heat_map_path, heat);
        } catch (const InputError& e) {
            // idiff files every problem with files (input or output) under status 4.
            return report_error(o, compare::DiffVerdict::unreadable, e.what());
        }
    }
    if (o.json) {
        nlohmann::json j{{"reference", o.reference},
                         {"test", o.test},
                         {"width", r.width},
                         {"height", r.height},
                         {"channels", r.channels},
                         {"mean_abs_error", r.mean_abs_error},
                         {"max_abs_error", r.max_abs_error},
                         {"max_at", {{"x", r.max_x}, {"y", r.max_y}, {"channel", r.max_channel}}},
                         {"rms_error", r.rms_error},
                         {"psnr_db", number_or_null(r.psnr_db)},
                         {"ssim", r.ssim},
                         {"ssim_on", "Rec.709 luma of the stored values; Gaussian 11x11 sigma 1.5; valid region"},
                         {"flip_mean", r.flip_mean},
                         {"flip_max", r.flip_max},
                         {"warn_pixels", r.warn_pixels},
                         {"warn_percent", r.warn_percent},
                         {"fail_pixels", r.fail_pixels},
                         {"fail_percent", r.fail_percent},
                         {"fail_share", r.fail_percent / 100.0},
                         {"nan_values", r.nan_values},
                         {"thresholds",
                          {{"fail", o.th.fail},
                           {"failpercent", o.th.fail_percent},
                           {"hardfail", number_or_null(o.th.hard_fail)},
                           {"warn", o.th.warn},
                           {"warnpercent", o.th.warn_percent},
                           {"hardwarn", number_or_null(o.th.hard_warn)},
                           {"allowfailures", o.th.allow_failures}}},
                         {"verdict", compare::verdict_name(r.verdict)},
                         {"exit_code", static_cast<int>(r.verdict)}};
        if (want_heat) j["heat_map"] = o.heat_map_path;
        std::printf("%s\n", j.dump(2).c_str());
    } else {
        std::printf("Comparing \"%s\" and \"%s\"\n", o.reference.c_str(), o.test.c_str());
        std::printf("  Mean error = %g\n  RMS error = %g\n  Peak SNR = %g\n", r.mean_abs_error, r.rms_error, r.psnr_db);
        std::printf("  Max error  = %g @ (%d, %d, channel %d)\n", r.max_abs_error, r.max_x, r.max_y, r.max_channel);
        std::printf("  SSIM (luma) = %.6f\n  FLIP mean = %.6f  max = %.6f\n", r.ssim, r.flip_mean, r.flip_max);
        std::printf("  %lld pixels (%.3g%%) over %g\n", r.warn_pixels, r.warn_percent, o.th.warn);
        std::printf("  %lld pixels (%.3g%%) over %g\n", r.fail_pixels, r.fail_percent, o.th.fail);
        if (r.nan_values > 0) std::printf("  %lld values are NaN in one image or both\n", r.nan_values);
        std::printf("%s\n", compare::verdict_name(r.verdict));
    }
    return static_cast<int>(r.verdict);
}

}  // namespace

Command diff_command(CLI::App& app) {
    auto o = std::make_shared<DiffOptions>();
    CLI::App* sub =
        app.add_subcommand("diff",
                           "Compare two images like OpenImageIO's idiff. Exit status: 0 pass, 1 warning, 2 failure, "
                           "3 size mismatch, 4 unreadable file.");
    sub->add_option("reference", o->reference, "Reference (golden) image")->required();
    sub->add_option("test", o->test, "Image to check")->required();
    sub->add_option("-o,--output", o->heat_map_path, "Write a heat-map of the differences (PNG)");
    sub->add_option("--heatmap", o->heat_map_kind,
                    "Heat-map content: flip (perceptual) or abs (max |A-B|, scaled to the largest)")
        ->check(CLI::IsMember({"flip", "abs"}))
        ->capture_default_str();
    sub->add_option("--fail", o->th.fail, "A pixel fails when any channel differs by more than this (values in [0,1])")
        ->capture_default_str();
    sub->add_option("--failpercent", o->th.fail_percent, "FAILURE when more than this percentage of pixels fail")
        ->capture_default_str();
    sub->add_option("--hardfail", o->th.hard_fail, "FAILURE when any difference exceeds this (default: infinity)");
    sub->add_option("--warn", o->th.warn, "A pixel warns when any channel differs by more than this")
        ->capture_default_str();
    sub->add_option("--warnpercent", o->th.warn_percent, "WARNING when more than this percentage of pixels warn")
        ->capture_default_str();
    sub->add_option("--hardwarn", o->th.hard_warn, "WARNING when any difference exceeds this (default: infinity)");
    // Read as text: CLI11 would clamp 99999999999999999999 to the largest long long silently.
    sub->add_option("--allowfailures", o->allow_failures_text,
                    "PASS whenever at most this many pixels fail (idiff's rule)")
        ->capture_default_str();
    sub->add_flag("--json", o->json, "Print one JSON object with the metrics and the verdict");
    return {sub, [o] {
                const std::string& text = o->allow_failures_text;
                const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), o->th.allow_failures);
                if (ec != std::errc() || end != text.data() + text.size() || o->th.allow_failures < 0)
                    throw InputError("--allowfailures '" + text +
                                     "': must be a whole number from 0 to 9223372036854775807");
                return run_diff(*o);
            }};
}

}  // namespace foldcast::app
