#pragma once
#include <mutex>
#include <string>

#include "foldcast/core/progress.hpp"

namespace foldcast::app {

// A one-line progress bar on stderr, redrawn at most every whole percent; silent when quiet.
class ProgressBar {
public:
    explicit ProgressBar(bool quiet) : quiet_(quiet) {}
    ~ProgressBar();
    ProgressFn callback();

private:
    void draw(std::string_view stage, double fraction);
    bool quiet_;
    std::mutex mutex_;
    std::string stage_;
    int last_percent_ = -1;
};

}  // namespace foldcast::app
