#pragma once
// The frames a temporally filtered turntable holds: frame f's output needs the traced
// frames f-r .. f+r (turntable order, wrapping round: frame 0's neighbours are the last
// frames, so the loop has no seam), each traced once per run and dropped when no later
// output needs it.  An output depends only on those traced frames, so a range A:B renders
// the same frames as the whole turntable (it traces the r frames beyond each end too).
#include <functional>
#include <map>
#include <memory>
#include <optional>

#include "foldcast/render/temporal_filter.hpp"

namespace foldcast::batch {

struct TracedFrame {
    render::TemporalFrame frame;
    render::RenderStats stats;
};

class TemporalWindow {
public:
    using TraceFn = std::function<TracedFrame(int frame)>;
    // Outputs frames up to `last` (exclusive) of a turntable of `total` frames.
    TemporalWindow(int total, int last, int radius, TraceFn trace);

    struct Output {
        render::RenderResult result;  // the filtered image, frame f's raw; rays and mean_spp
                                      // summed over the frames traced for it
        int traced = 0;               // frames traced for it (0 to 2r+1)
    };
    // Frame f's output; call for f = first, first+1, ... in order.  With keep_raw its raw is
    // frame f as traced (before any filter).
    Output output(int f, const render::Camera& camera, const Vec3f& turn_centre, bool denoise, bool keep_raw,
                  int threads);

private:
    int wrap(int f) const { return ((f % total_) + total_) % total_; }
    bool needed_after(int g, int f) const;

    int total_, last_, radius_;
    TraceFn trace_;
    std::map<int, std::shared_ptr<TracedFrame>> held_;
};

}  // namespace foldcast::batch
