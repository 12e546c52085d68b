#include "progress_bar.hpp"

#include <algorithm>
#include <cstdio>

namespace foldcast::app {

ProgressBar::~ProgressBar() {
    if (last_percent_ >= 0) std::fputc('\n', stderr);
}

ProgressFn ProgressBar::callback() {
    if (quiet_) return {};
    return [this](std::string_view stage, double fraction) { draw(stage, fraction); };
}

void ProgressBar::draw(std::string_view stage, double fraction) {
    const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0);
    std::lock_guard lock(mutex_);
    if (percent == last_percent_ && stage == stage_) return;
    if (stage != stage_ && last_percent_ >= 0) std::fputc('\n', stderr);
    stage_ = stage;
    last_percent_ = percent;
    constexpr int kWidth = 40;
    const int filled = percent * kWidth / 100;
    std::fprintf(stderr, "\r%-10.*s [%.*s%*s] %3d%%", static_cast<int>(stage.size()), stage.data(),
                 filled, "########################################", kWidth - filled, "", percent);
    std::fflush(stderr);
}

}  // namespace foldcast::app
