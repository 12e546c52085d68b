#pragma once
// The turntable's temporal filter: each traced frame is averaged with where its surface
// points lie in the frames around it, before the spatial denoiser, so that the denoiser
// starts from several frames' samples (less noise, less blur) and what is left of the
// noise changes less from frame to frame (flicker).
//
// The motion is known exactly: between turntable frames the garment and its supports turn
// about the vertical axis through the studio's centre while the camera, lights and backdrop
// stay.  A pixel's first hit (camera ray at depth d) is turned by the frames' difference in
// turn for garment pixels, kept for backdrop pixels, projected into the other frame and read
// there bilinearly; a tap counts only where that frame's first hit agrees in what it is
// (cloth or backdrop), depth, shading normal and albedo, and in luminance to within the two
// pixels' noise and a tenth (moving highlights and shadow edges do not).  The window is centred (frames
// f-k and f+k count only together), so shading that changes linearly with the turn averages
// back to frame f's own value instead of lagging.  Illumination (colour / albedo) is what is
// averaged; frame f's own albedo is multiplied back, so the weave stays sharp.
#include <vector>

#include "foldcast/render/render.hpp"

namespace foldcast::render {

// One frame as the filter reads it: its traced image and the first-hit features it was rendered with (RenderResult::features), at the garment's turn.
struct TemporalFrame {
    Image beauty;  // RGBA linear, as traced (not denoised)
    PixelFeatures features;
    double turn_deg = 0.0;  // StudioSetup::garment_points' turn
};

// Frames on each side of the filtered one that the window holds.
constexpr int kTemporalRadius = 2;

// The filtered RGBA of the middle frame of `window`, which holds frames f-r .. f+r in
// turntable order (r = window.size() / 2), all of one size and rendered with `camera`;
// `turn_centre` is a point on the turn's vertical axis (StudioSetup::turn_centre).  With
// `denoise_after`, the average then goes through the spatial denoiser (denoise.hpp) with
// its reduced variance.  Each output pixel depends only on the inputs: the same for any
// thread count.
Image temporal_filter(const std::vector<const TemporalFrame*>& window, const Camera& camera, const Vec3f& turn_centre,
                      bool denoise_after, int threads);

}  // namespace foldcast::render
