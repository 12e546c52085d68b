#pragma once
// What the flag and key batteries share: the digit-run check on refusals and running the
// cases on the CI machine's two cores, failures collected in case order of finishing.
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace foldcast::test {

// The longest run of digits in `text` (a double printed with %f has 309).
inline std::size_t longest_digit_run(const std::string& text) {
    std::size_t longest = 0, run = 0;
    for (char c : text) {
        run = std::isdigit(static_cast<unsigned char>(c)) ? run + 1 : 0;
        longest = std::max(longest, run);
    }
    return longest;
}

// Runs check(i) for every i < count on two threads; returns the non-empty answers.
inline std::vector<std::string> run_on_two_threads(std::size_t count,
                                                   const std::function<std::string(std::size_t)>& check) {
    std::atomic<std::size_t> next{0};
    std::mutex mutex;
    std::vector<std::string> failures;
    auto work = [&] {
        for (std::size_t i; (i = next++) < count;) {
            const std::string wrong = check(i);
            if (!wrong.empty()) {
                std::lock_guard lock(mutex);
                failures.push_back(wrong);
            }
        }
    };
    std::thread a(work), b(work);
    a.join();
    b.join();
    return failures;
}

}  // namespace foldcast::test
