#include "temporal_window.hpp"

#include <utility>
#include <vector>

namespace foldcast::batch {

TemporalWindow::TemporalWindow(int total, int last, int radius, TraceFn trace)
    : total_(total), last_(last), radius_(radius), trace_(std::move(trace)) {}

// Whether traced frame g is in the window of some output after f.
bool TemporalWindow::needed_after(int g, int f) const {
    for (int o = f + 1; o < last_; ++o)
        for (int k = -radius_; k <= radius_; ++k)
            if (wrap(o + k) == g) return true;
    return false;
}

TemporalWindow::Output TemporalWindow::output(int f, const render::Camera& camera, const Vec3f& turn_centre,
                                              bool denoise, bool keep_raw, int threads) {
    Output out;
    render::RenderResult& result = out.result;
    std::vector<const render::TemporalFrame*> window;
    for (int k = -radius_; k <= radius_; ++k) {
        const int g = wrap(f + k);
        auto it = held_.find(g);
        if (it == held_.end()) {
            it = held_.emplace(g, std::make_shared<TracedFrame>(trace_(g))).first;
            // Every traced frame is counted once, with the output that first needed it.
            result.stats.rays += it->second->stats.rays;
            result.stats.mean_spp += it->second->stats.mean_spp;
            ++out.traced;
        }
        window.push_back(&it->second->frame);
    }
    result.beauty = render::temporal_filter(window, camera, turn_centre, denoise, threads);
    if (keep_raw) result.raw = held_.at(wrap(f))->frame.beauty;
    for (auto it = held_.begin(); it != held_.end();) it = needed_after(it->first, f) ? std::next(it) : held_.erase(it);
    return out;
}

}  // namespace foldcast::batch
