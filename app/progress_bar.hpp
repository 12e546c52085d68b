#pragma once
#include <mutex>
#include <string>

#include "foldcast/core/progress.hpp"

namespace foldcast::app {

// A one-line progress bar on stderr, redrawn at most every whole percent, when stderr is a
// terminal; otherwise (a log file, CI) one line per stage at each 10 %; silent when quiet.
class ProgressBar {
public:
    explicit ProgressBar(bool quiet);
    ~ProgressBar();
    ProgressFn callback();
    bool on_terminal() const { return terminal_; }

private:
    void draw(std::string_view stage, double fraction);
    bool quiet_;
    bool terminal_;
    std::mutex mutex_;
    std::string stage_;
    int last_percent_ = -1;
};

}  // namespace foldcast::app
