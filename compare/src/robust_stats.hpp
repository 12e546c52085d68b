#pragma once
// Order statistics the photo pipeline takes of pixel samples (a cloth's colour, a region's
// responses): one definition, so every median in compare/ is the same element.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace foldcast::compare::detail {

// The element at index q (size - 1), rounded down, of v sorted; v is reordered, not empty.
template <typename T>
T quantile(std::vector<T>& v, double q) {
    const auto k = v.begin() + static_cast<std::ptrdiff_t>(q * double(v.size() - 1));
    std::nth_element(v.begin(), k, v.end());
    return *k;
}

// The element at index size / 2 of v sorted (the upper one of an even count); v not empty.
template <typename T>
T median(std::vector<T> v) {
    const auto k = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), k, v.end());
    return *k;
}

}  // namespace foldcast::compare::detail
