#include "progress_bar.hpp"

#include <algorithm>
#include <cstdio>
#include <unistd.h>

namespace foldcast::app {

ProgressBar::ProgressBar(bool quiet) : quiet_(quiet), terminal_(isatty(STDERR_FILENO) == 1) {}

ProgressBar::~ProgressBar() {
    if (last_percent_ >= 0 && terminal_) std::fputc('\n', stderr);
}

ProgressFn ProgressBar::callback() {
    if (quiet_) return {};
    return [this](std::string_view stage, double fraction) { draw(stage, fraction); };
}

void ProgressBar::draw(std::string_view stage, double fraction) {
    int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0);
    if (!terminal_) percent -= percent % 10;  // a log gets a line per 10 %, not per redraw
    std::lock_guard lock(mutex_);
    if (percent == last_percent_ && stage == stage_) return;
    if (stage != stage_ && last_percent_ >= 0 && terminal_) std::fputc('\n', stderr);
    stage_ = stage;
    last_percent_ = percent;
    if (!terminal_) {
        std::fprintf(stderr, "%.*s %d%%\n", static_cast<int>(stage.size()), stage.data(), percent);
        return;
    }
    constexpr int kWidth = 40;
    const int filled = percent * kWidth / 100;
    std::fprintf(stderr, "\r%-10.*s [%.*s%*s] %3d%%", static_cast<int>(stage.size()), stage.data(), filled,
                 "########################################", kWidth - filled, "", percent);
    std::fflush(stderr);
}

}  // namespace foldcast::app
