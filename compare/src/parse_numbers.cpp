#include <charconv>
#include <cmath>

#include "foldcast/compare/folds.hpp"

namespace foldcast::compare {

std::vector<double> parse_numbers(const std::string& text, size_t count, const std::string& flag) {
    std::vector<double> values;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = std::min(text.find(',', start), text.size());
        std::string token = text.substr(start, comma - start);
        while (!token.empty() && token.front() == ' ') token.erase(token.begin());
        while (!token.empty() && token.back() == ' ') token.pop_back();
        double v = 0.0;
        const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
        if (token.empty() || ec != std::errc() || ptr != token.data() + token.size() || !std::isfinite(v))
            throw InputError(flag + " '" + text + "': '" + token + "' is not a number; expected " +
                             std::to_string(count) + " comma-separated numbers");
        values.push_back(v);
        start = comma + 1;
    }
    if (values.size() != count)
        throw InputError(flag + " '" + text + "': expected " + std::to_string(count) + " comma-separated numbers, got " +
                         std::to_string(values.size()));
    return values;
}

SupportPixels parse_supports(const std::string& text, const std::string& flag) {
    const auto v = parse_numbers(text, 4, flag);
    return {Eigen::Vector2d(v[0], v[1]), Eigen::Vector2d(v[2], v[3])};
}

}  // namespace foldcast::compare
