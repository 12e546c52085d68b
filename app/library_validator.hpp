#pragma once
// A library's own parser as a CLI11 validator: the library reports what is wrong with the
// value in its own terms, CLI11 puts the flag's name in front ("--aov: AOV list ..."), and
// the value is rejected at parse time with exit 2 like every other bad flag.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "foldcast/core/error.hpp"

namespace foldcast::app {

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
