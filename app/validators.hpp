#pragma once
// CLI11 validators the built-in ones lack: CLI::Range lets NaN through (every comparison
// with NaN is false), and a library's own parsers should reject flag values at parse time.
#include <CLI/CLI.hpp>
#include <cmath>
#include <functional>
#include <string>

#include "foldcast/core/error.hpp"

namespace foldcast::app {

// A finite number in [lo, hi] (either may be infinite: no bound on that side); `allowed`
// replaces the generated description ("a number in (0, 1]").
inline CLI::Validator finite_in(double lo, double hi, std::string allowed = {}) {
    if (allowed.empty())
        allowed = std::isinf(lo) && std::isinf(hi) ? std::string("a finite number")
                  : std::isinf(hi)
                      ? "a finite number >= " + CLI::detail::to_string(lo)
                      : "a finite number in [" + CLI::detail::to_string(lo) + ", " + CLI::detail::to_string(hi) + "]";
    return CLI::Validator(
        [lo, hi, allowed](std::string& text) -> std::string {
            double v = 0.0;
            if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
            if (!std::isfinite(v) || v < lo || v > hi) return "'" + text + "' is not allowed; expected " + allowed;
            return {};
        },
        allowed, "FINITE");
}

// For unsigned options: CLI11 would read "-1" into an unsigned integer as its largest value.
inline const CLI::Validator non_negative_integer(
    [](std::string& text) {
        return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos
                   ? std::string()
                   : std::string("'" + text + "' must be a whole number >= 0");
    },
    "UINT");

// A library's own parser as a validator: the library reports what is wrong with the value in
// its own terms, CLI11 puts the flag's name in front ("--aov: AOV list ..."), and the value is
// rejected at parse time with exit 2 like every other bad flag.
inline CLI::Validator library_validator(std::function<void(const std::string&)> parse, std::string description) {
    return CLI::Validator(
        [parse = std::move(parse)](std::string& value) -> std::string {
            try {
                parse(value);
            } catch (const InputError& e) {
                return e.what();
            }
            return {};
        },
        std::move(description));
}

}  // namespace foldcast::app
